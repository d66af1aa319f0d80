//! Progress guards: a scene must be able to finish. Validation refuses an end time, time step,
//! CFL number or output interval for which the run would loop without end or take longer than
//! anyone can wait.
//!
//! Why: each value alone is a finite positive number, yet `solver.dt = 1e-300`, `solver.cfl =
//! 1e-30`, `fluid.artificial_viscosity = 1e308` (a viscous limit of exactly 0 s) or
//! `output.interval = 1e-12` make a run that never ends, and `end_time = 1e30` one whose step no
//! longer changes the f64 time.
//!
//! The step is estimated with the solver's own rule ([`crate::solver::timestep::choose`]) from
//! the scene's values: the sound speed (`wcsph` only; the corrected solver has no acoustic
//! limit), the viscous limit of the pair terms' equivalent viscosities (`PairTerm::step_viscosity`,
//! the physical viscosity divided by its lattice moment, as the solver does), the force limit of
//! gravity, a fixed `solver.dt`, and as flow speed the largest of the fluid boxes' initial
//! speeds, the moving walls' speeds and the shallow-water speed `sqrt(|g| H)` of the tallest
//! fluid box (`H` its extent along gravity). At run time the flow decides the speed; the
//! estimate is the step of a moderate flow, so a scene refused here needs at least about the
//! steps stated. The run itself stops if its step stalls (`solver::StepError::Stalled`).

use super::magnitude::short;
use super::validate::RawProblem;
use super::{KeyPath, Scene, SolverKind};
use crate::model::pair_terms::PairTerm;
use crate::physics::lattice::lattice_laplacian_moment;
use crate::physics::pair::ViscousMedium;
use crate::smoothing::Smoothing;
use crate::solver::timestep::{self, TimeStepInputs, TimeStepLimit};

/// The most time steps a scene may need: 1e9. A 2D run of a few thousand particles takes about
/// 1 ms a step on a CPU, so 1e9 steps are weeks; beyond this a run is a mistake in `solver.dt`,
/// `solver.cfl`, the sound speed, the viscosities or `solver.end_time`, not a plan.
pub const MAX_STEPS: f64 = 1e9;

/// The most frame times a scene may have, `solver.end_time / output.interval`: 1e6. Each frame
/// time writes a frame (and, with `output.surface`, a surface) and the probes sample ten times
/// per interval; a million frames of even a small scene are terabytes.
pub const MAX_FRAMES: f64 = 1e6;

/// The progress problems of `scene` (empty when it can finish). Assumes the magnitudes passed
/// (`scene::magnitude`), so that the estimates are finite numbers.
pub(crate) fn check(scene: &Scene) -> Vec<RawProblem> {
    let mut problems = Vec::new();
    frames(scene, &mut problems);
    steps(scene, &mut problems);
    problems
}

/// `output.interval` against the end time: it must advance the f64 time at the end time and
/// make at most [`MAX_FRAMES`] frame times.
fn frames(scene: &Scene, problems: &mut Vec<RawProblem>) {
    let (end, interval) = (scene.end_time, scene.output_interval);
    let path = KeyPath::key("output").k("interval");
    if end + interval == end {
        problems.push(RawProblem::new(
            path,
            format!(
                "{} s is below the f64 resolution of the time at solver.end_time = {} s (t + interval == t), so the next frame time is never reached; use a larger output.interval",
                short(interval),
                short(end)
            ),
        ));
    } else if end / interval > MAX_FRAMES {
        problems.push(RawProblem::new(
            path,
            format!(
                "{} s makes solver.end_time / output.interval = {} s / {} s = {} frame times, more than the limit of {MAX_FRAMES:e} (scene::progress::MAX_FRAMES); use output.interval >= {} s",
                short(interval),
                short(end),
                short(interval),
                short((end / interval).ceil()),
                short(end / MAX_FRAMES)
            ),
        ));
    }
}

/// The estimated step against the end time: it must advance the f64 time at the end time and
/// make at most [`MAX_STEPS`] steps.
fn steps(scene: &Scene, problems: &mut Vec<RawProblem>) {
    let estimate = estimate(scene);
    let (dt, limit, end) = (estimate.dt, estimate.limit, scene.end_time);
    let stalls = timestep::stalls(dt, limit, 0.0, end);
    let count = end / dt;
    if !stalls && count <= MAX_STEPS {
        return;
    }
    let (path, how) = describe(scene, &estimate);
    let what = if stalls {
        format!(
            "does not advance the f64 time at solver.end_time = {} s (t + dt == t), so the run would never finish",
            short(end)
        )
    } else {
        format!(
            "makes about solver.end_time / dt = {} s / {} s = {} steps, more than the limit of {MAX_STEPS:e} (scene::progress::MAX_STEPS); it needs a step of at least {} s or a shorter solver.end_time",
            short(end),
            short(dt),
            short(count.ceil()),
            short(end / MAX_STEPS)
        )
    };
    problems.push(RawProblem::new(
        path,
        format!("the time step dt = {} s ({how}) {what}", short(dt)),
    ));
}

/// The estimated step and the inputs it came from.
struct Estimate {
    dt: f64,
    limit: TimeStepLimit,
    inputs: TimeStepInputs,
    /// Each pair term's share of `inputs.kinematic_viscosity` [m²/s], in table order.
    viscosities: Vec<(PairTerm, f64)>,
}

/// The step [`timestep::choose`] takes with the scene's values (see the module documentation).
fn estimate(scene: &Scene) -> Estimate {
    let (h, dx, d) = (scene.smoothing_length, scene.spacing, scene.dimension);
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let g = scene.gravity.as_deref().map_or(0.0, norm);
    let tallest = scene
        .fluid_boxes
        .iter()
        .map(|b| match scene.gravity.as_deref() {
            Some(gv) if g > 0.0 => (0..d)
                .map(|k| (b.region.max[k] - b.region.min[k]) * gv[k].abs() / g)
                .sum::<f64>(),
            _ => 0.0,
        })
        .fold(0.0, f64::max);
    let speed = scene
        .fluid_boxes
        .iter()
        .map(|b| norm(&b.velocity))
        .chain(
            scene
                .solids
                .iter()
                .filter_map(|s| s.motion.as_ref())
                .map(|m| m.max_speed()),
        )
        .fold((g * tallest).sqrt(), f64::max);
    // The lightest phase has the largest mu / rho0 (`Simulation::with_phases`).
    let lightest = scene
        .fluid_boxes
        .iter()
        .filter_map(|b| b.rho0)
        .fold(scene.rho0, f64::min);
    // Each pair term's equivalent kinematic viscosity, as the solver bounds its step.
    let medium = ViscousMedium {
        sound_speed: scene.sound_speed,
        h,
        dimension: d,
        lightest_rho0: lightest,
        viscosity_scale: 1.0 / laplacian_moment(d, h, dx, scene.rho0),
    };
    let viscosities: Vec<(PairTerm, f64)> = scene
        .pair_terms
        .iter()
        .map(|(term, c)| (term, term.step_viscosity(c, &medium)))
        .collect();
    let inputs = TimeStepInputs {
        h,
        sound_speed: match scene.solver.kind {
            SolverKind::Wcsph => scene.sound_speed,
            SolverKind::Corrected => 0.0,
        },
        cfl: scene.cfl,
        max_speed: speed,
        max_acceleration: g,
        kinematic_viscosity: scene.pair_terms.step_viscosity(&medium),
        fixed: scene.dt,
        // A floating solid's contact bounds only the steps in which it touches a solid
        // (`boundary::contact`): not the estimate's.
        contact_frequency: None,
        // The moorings bound every step.
        mooring_frequency: crate::scene::floating::rigid_bodies(scene)
            .iter()
            .flatten()
            .filter_map(|b| b.mooring_frequency(scene.dimension))
            .reduce(f64::max),
        remaining: f64::INFINITY,
    };
    let (dt, limit) = timestep::choose(&inputs);
    Estimate {
        dt,
        limit,
        inputs,
        viscosities,
    }
}

/// The lattice moment `λ` of the viscous Laplacian (`physics::lattice`), by which the solver
/// divides the viscosity; 1 if the kernel cannot be built.
fn laplacian_moment(dimension: usize, h: f64, dx: f64, rho0: f64) -> f64 {
    let lambda = match dimension {
        2 => Smoothing::<2>::new(h as f32).map(|k| lattice_laplacian_moment(&k, dx, rho0)),
        3 => Smoothing::<3>::new(h as f32).map(|k| lattice_laplacian_moment(&k, dx, rho0)),
        _ => Ok(1.0),
    };
    lambda.ok().filter(|l| *l > 0.0 && l.is_finite()).unwrap_or(1.0)
}

/// Whether a step `dt` [s] would do for a run of one second: it advances the time there and
/// makes at most [`MAX_STEPS`] steps.
fn fits_one_second(dt: f64, limit: TimeStepLimit) -> bool {
    !timestep::stalls(dt, limit, 0.0, 1.0) && 1.0 / dt <= MAX_STEPS
}

/// The key a step problem is reported at and the estimate in words. The key is
/// `solver.end_time` when the step would do for a run of one second (the end time is what is
/// out of proportion), else the value that set the step: `solver.dt`; `solver.cfl`, or the sound
/// speed when even CFL number 1 would not do; the dominant viscosity; gravity.
fn describe(scene: &Scene, e: &Estimate) -> (KeyPath, String) {
    let (key, how) = limit_key(scene, e);
    if fits_one_second(e.dt, e.limit) {
        (KeyPath::key("solver").k("end_time"), how)
    } else {
        (key, how)
    }
}

/// The key of the criterion that set the estimated step, and the estimate in words.
fn limit_key(scene: &Scene, e: &Estimate) -> (KeyPath, String) {
    let (fp, sp) = (KeyPath::key("fluid"), KeyPath::key("solver"));
    let i = &e.inputs;
    match e.limit {
        TimeStepLimit::Fixed | TimeStepLimit::EndTime => (sp.k("dt"), "the fixed solver.dt".into()),
        TimeStepLimit::SoundSpeed | TimeStepLimit::FlowSpeed => {
            let cfl = if scene.dt.is_some() { 1.0 } else { i.cfl };
            let how = format!(
                "CFL limit solver.cfl * h / (C + |u|) = {} * {} m / ({} m/s + {} m/s), fluid.sound_speed = {} m/s",
                short(cfl),
                short(i.h),
                short(i.sound_speed),
                short(i.max_speed),
                short(scene.sound_speed)
            );
            // A fixed step is cut at CFL number 1: then the sound speed set it; so it did when
            // even the largest CFL number, 1, gives too short a step.
            let at_cfl_one = e.dt / cfl;
            let sound = e.limit == TimeStepLimit::SoundSpeed;
            let key = if sound && (scene.dt.is_some() || !fits_one_second(at_cfl_one, e.limit)) {
                fp.k("sound_speed")
            } else {
                sp.k("cfl")
            };
            (key, how)
        }
        TimeStepLimit::Contact => (
            KeyPath::key("particles").k("spacing"),
            format!(
                "floating-body contact limit {} / omega_c, omega_c = sqrt({} g0 / dx) (boundary::contact)",
                short(crate::boundary::contact::CONTACT_STEP),
                short(crate::boundary::contact::CONTACT_STIFFNESS)
            ),
        ),
        TimeStepLimit::Mooring => (
            KeyPath::key("solid"),
            format!(
                "mooring limit {} / omega_m, omega_m^2 = sum k (1/M + r^2/I) over a floating solid's moorings",
                short(crate::boundary::contact::CONTACT_STEP)
            ),
        ),
        TimeStepLimit::Force => (
            fp.k("gravity"),
            format!("force limit 0.25 sqrt(h / |g|), h = {} m", short(i.h)),
        ),
        TimeStepLimit::Viscosity => {
            // The term that contributes most names the key.
            let largest =
                e.viscosities
                    .iter()
                    .fold(None, |best: Option<(PairTerm, f64)>, &(t, nu)| match best {
                        Some((_, b)) if b >= nu => best,
                        _ => Some((t, nu)),
                    });
            let key = fp.k(largest.map_or("viscosity", |(t, _)| t.name()));
            let parts: Vec<String> = e
                .viscosities
                .iter()
                .map(|(t, nu)| format!("fluid.{} ({} m^2/s)", t.name(), short(*nu)))
                .collect();
            (
                key,
                format!(
                    "viscous limit 0.125 (h/2)^2 / nu, h = {} m, nu = {} m^2/s from {}",
                    short(i.h),
                    short(i.kinematic_viscosity),
                    parts.join(" and ")
                ),
            )
        }
    }
}
