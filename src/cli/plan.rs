//! `sph plan SCENE`: what a run of the scene simulates, step by step.
//!
//! Prints the stage plan (`solver::plan`, built from the scene's effects, solids and solver)
//! with each stage's equation and the particle fields it reads and writes (`Stage::equation`,
//! `Stage::reads`, `Stage::writes`), the steps the driver runs inside a stage (the correction
//! loop's sweep, the no-penetration guard: `Stage::sub_stages`), the start-up settle, and what
//! the run does after each step (probes, output files). A term the scene does not ask for is
//! not printed because it does not run.

use crate::fields::Field;
use crate::model::SurfaceTensionModel;
use crate::model::pair_terms::PairTerm;
use crate::run::{correction, plan_inputs};
use crate::scene::{Effect, ProbeKind, Scene, load_scene};
use crate::solver::Integrator;
use crate::solver::plan::plan;
use crate::solver::stage::{Stage, SubStage};
use crate::solver::step::{RESORT_DRIFT, VELOCITY_SOLVE_CAP};
use anyhow::Context;
use std::fmt::Write;
use std::path::Path;

/// Validates the scene and prints its plan.
pub fn print_plan(path: &Path, sets: &[String]) -> anyhow::Result<()> {
    let scene = load_scene(path, sets).with_context(|| format!("planning scene {}", path.display()))?;
    print!("{}", render(&scene, &path.display().to_string()));
    Ok(())
}

/// Field names joined by commas; every field reads as "every field (reorder)".
fn fields(list: &[Field]) -> String {
    if list.len() == Field::ALL.len() {
        return "every field (reorder)".into();
    }
    if list.is_empty() {
        return "no particle field".into();
    }
    list.iter().map(|f| f.name()).collect::<Vec<_>>().join(", ")
}

/// A vector as `(a, b)`.
fn vector(v: &[f64]) -> String {
    let parts: Vec<String> = v.iter().map(|c| format!("{c}")).collect();
    format!("({})", parts.join(", "))
}

/// The calibrated constant the run will use for `sigma`, as `Simulation::new` calibrates it:
/// the surface stress's `σ'` (`physics::surface_stress`) or [AAT13]'s `γ`
/// (`physics::surface_tension`); NaN where the scene's kernel cannot be built.
fn surface_tension_constant(scene: &Scene, sigma: f64) -> f64 {
    use crate::physics::lattice::{lattice_gradient_moment, lattice_mass};
    use crate::physics::{surface_stress::calibrated_stress, surface_tension::gamma_for_surface_tension};
    use crate::smoothing::Smoothing;
    fn constant<const D: usize>(scene: &Scene, k: &Smoothing<D>, sigma: f64) -> f64 {
        let (dx, rho0) = (scene.spacing, scene.rho0);
        let m = f64::from(lattice_mass(k, dx, rho0) as f32);
        match scene.surface_tension_model {
            SurfaceTensionModel::SurfaceStress => {
                let scale = 1.0 / lattice_gradient_moment(k, dx, rho0);
                calibrated_stress(k, dx, m, rho0, scale, sigma)
            }
            SurfaceTensionModel::Akinci => gamma_for_surface_tension(k, dx, rho0, m, sigma),
        }
    }
    let h = scene.smoothing_length as f32;
    match scene.dimension {
        2 => Smoothing::<2>::new(h).map_or(f64::NAN, |k| constant(scene, &k, sigma)),
        _ => Smoothing::<3>::new(h).map_or(f64::NAN, |k| constant(scene, &k, sigma)),
    }
}

/// One effect with its parameters.
fn effect(scene: &Scene, e: Effect) -> String {
    match e {
        Effect::Gravity => {
            let g = scene.gravity.as_deref().map(vector).unwrap_or_default();
            if scene.gravity_ramp > 0.0 {
                format!("gravity g = {g} m/s^2, ramped in over {} s", scene.gravity_ramp)
            } else {
                format!("gravity g = {g} m/s^2")
            }
        }
        Effect::Pair(term) => {
            let unit = match term.unit() {
                "" => String::new(),
                u => format!(" {u}"),
            };
            let value = scene.pair_terms.get(term).unwrap_or(0.0);
            let reach = match term {
                PairTerm::ArtificialViscosity => format!(
                    ", times {} between fluid and solid particles",
                    scene.artificial_viscosity_wall_factor
                ),
                _ => String::new(),
            };
            format!("{} {} = {value}{unit}{reach}", term.name(), term.symbol())
        }
        Effect::RotatingFrame => format!(
            "rotating_frame Omega = {} rad/s about the axis through {} m: Coriolis and centrifugal force",
            vector(&scene.angular_velocity.unwrap_or_default()),
            vector(&scene.rotation_centre)
        ),
        Effect::SurfaceTension => {
            let sigma = scene.surface_tension.unwrap_or(0.0);
            let constant = surface_tension_constant(scene, sigma);
            match scene.surface_tension_model {
                SurfaceTensionModel::SurfaceStress => format!(
                    "surface_tension sigma = {sigma} N/m, model surface_stress: capillary stress of the surface layers with artificial stress (no adhesion to solids), sigma' = {constant:.4e} from the lattice slab"
                ),
                SurfaceTensionModel::Akinci => format!(
                    "surface_tension sigma = {sigma} N/m, model akinci: [AAT13] cohesion and curvature between fluid particles (no adhesion to solids), gamma = {constant:.4e} from the lattice slab"
                ),
            }
        }
        Effect::DensityDiffusion => format!(
            "density_diffusion delta = {}: density integrated by the continuity equation with Fourtakas et al. (2019) diffusion, instead of summed (18)",
            scene.density_diffusion.unwrap_or(0.0)
        ),
        Effect::Multiphase => {
            let mut phases: Vec<f64> = vec![scene.rho0];
            for fb in &scene.fluid_boxes {
                if let Some(r) = fb.rho0 {
                    if !phases.contains(&r) {
                        phases.push(r);
                    }
                }
            }
            let used: Vec<String> = phases
                .iter()
                .filter(|&&r| {
                    scene
                        .fluid_boxes
                        .iter()
                        .any(|fb| fb.rho0.unwrap_or(scene.rho0) == r)
                })
                .map(|r| format!("{r}"))
                .collect();
            format!(
                "multiphase rest densities {} kg/m^3 (one sound speed): [HA06] number density and volume-form pressure force",
                used.join(", ")
            )
        }
    }
}

/// The plan printout of a validated scene; `origin` names it in the heading.
pub fn render(scene: &Scene, origin: &str) -> String {
    let inputs = plan_inputs(scene);
    let stages = plan(inputs);
    let solids = inputs.solids;
    let mut out = String::new();
    let (rounds, integrator) = match inputs.integrator {
        Integrator::SymplecticEuler => (1, "symplectic Euler, 1 integrator stage per step"),
        Integrator::Rk3 => (3, "SSP-RK3, 3 integrator stages per step at t + (0, 1, 1/2) dt"),
    };
    // Writing to a String cannot fail; the results are ignored below for that reason.
    let _ = writeln!(
        out,
        "scene {origin}: {}D, solver {}, {integrator}",
        scene.dimension,
        scene.solver.kind.name()
    );
    let effects: Vec<String> = scene.effects.iter().map(|&e| effect(scene, e)).collect();
    let _ = writeln!(
        out,
        "effects: {}",
        if effects.is_empty() {
            "none".into()
        } else {
            effects.join("; ")
        }
    );
    if !scene.has(Effect::Gravity) {
        let _ = writeln!(
            out,
            "  (no gravity: the body force (6) in the forces stage is zero)"
        );
    }
    let solid_names: Vec<String> = scene
        .solids
        .iter()
        .map(|s| match s.motion {
            Some(_) => format!("{} (moving)", s.name),
            None => s.name.clone(),
        })
        .collect();
    let _ = writeln!(
        out,
        "solids: {}",
        if solid_names.is_empty() {
            "none".into()
        } else {
            solid_names.join(", ")
        }
    );
    let c = correction(scene);
    if let Some(c) = &c {
        let _ = writeln!(out, "\nfirst step only:");
        let _ = writeln!(
            out,
            "  settle                   (23)-(24)                    the correction loop below on the initial state, moving particles without giving them velocity"
        );
        let _ = writeln!(
            out,
            "      delta = {:e}, at most {} sweeps, relaxation {}",
            c.delta, c.max_iterations, c.relaxation
        );
    }
    let multiphase = scene.has(Effect::Multiphase);
    let _ = writeln!(out, "\neach integrator stage ({rounds} per step), in order:");
    for (k, stage) in stages.iter().enumerate() {
        stage_lines(&mut out, k + 1, stage, &stages, multiphase);
        let subs = stage.sub_stages(solids);
        if subs.is_empty() {
            continue;
        }
        let _ = match (stage, &c) {
            (Stage::Correction, Some(c)) => writeln!(
                out,
                "      each sweep, until the compression is below delta = {:e} (at most {} sweeps{}):",
                c.delta,
                c.max_iterations,
                if c.strict { ", else an error" } else { "" }
            ),
            _ => writeln!(out, "      then:"),
        };
        for sub in subs {
            sub_stage_lines(&mut out, sub, &stages, multiphase);
        }
        let velocity = stage.velocity_sub_stages(solids);
        if let (false, Some(c)) = (velocity.is_empty(), &c) {
            let _ = writeln!(
                out,
                "      then, once converged, the velocity solve, each sweep until its residual is below delta \
                 (at most {} sweeps):",
                VELOCITY_SOLVE_CAP.min(c.max_iterations)
            );
            for sub in velocity {
                sub_stage_lines(&mut out, sub, &stages, multiphase);
            }
        }
    }
    let _ = writeln!(out, "\nafter each step:");
    let probe_interval = crate::probe::ProbeLog::interval_for(scene);
    for p in &scene.probes {
        let axis = ["x", "y", "z"].get(p.axis).copied().unwrap_or("?");
        let point = p.point.as_deref().map(vector).unwrap_or_default();
        let what = match (p.kind, p.solid.and_then(|s| scene.solids.get(s))) {
            (ProbeKind::Moment, Some(s)) => format!("moment on {} about {point} m along {axis}", s.name),
            (_, Some(s)) => format!("{} on {} along {axis}", p.kind.name(), s.name),
            (ProbeKind::Pressure, None) => match p.sensor {
                crate::scene::Sensor::Point => format!("pressure at {point} m"),
                crate::scene::Sensor::Face { diameter, normal } => format!(
                    "pressure over {diameter} m wide, normal to {}, centred on {point} m",
                    ["x", "y", "z"].get(normal).copied().unwrap_or("?")
                ),
            },
            (ProbeKind::Level, None) => format!("level above {point} m along {axis}"),
            (ProbeKind::Velocity, None) => format!("velocity along {axis} at {point} m"),
            (ProbeKind::FlowRate, None) => format!(
                "flow rate along {axis} through {} m centred on {point} m",
                p.size.as_deref().map(vector).unwrap_or_default()
            ),
            _ => format!("{} along {axis}", p.kind.name()),
        };
        let _ = writeln!(
            out,
            "  probe {:<14} {what}, recorded every {probe_interval} s{}{}",
            p.name,
            match p.averaging {
                crate::scene::Averaging::Window(w) => format!(", each the mean over the last {w} s"),
                _ => String::new(),
            },
            if p.reference.is_some() {
                ", compared with its reference data"
            } else {
                ""
            }
        );
    }
    let _ = writeln!(
        out,
        "  steps.csv            every step: time step, its limit, extremes"
    );
    if solids {
        let _ = writeln!(out, "  forces.csv           every step: force on each solid");
    }
    if scene.write_frames {
        let _ = writeln!(
            out,
            "  frames               every {} s: position, velocity, density, pressure, kind, id of {} (.vtu, {})",
            scene.output_interval,
            if scene.fluid_only {
                "the fluid"
            } else {
                "every particle"
            },
            scene.output_encoding.name()
        );
    }
    if scene.write_surface {
        let _ = writeln!(
            out,
            "  surface              every {} s: free surface (25) (.vtp, {})",
            scene.output_interval,
            scene.output_encoding.name()
        );
    }
    out
}

/// The lines of one plan stage: number, name, equation, description, fields; with the
/// `multiphase` effect, the variant the stage runs.
fn stage_lines(out: &mut String, number: usize, stage: &Stage, plan: &[Stage], multiphase: bool) {
    let variant = stage.multiphase().filter(|_| multiphase);
    let _ = writeln!(
        out,
        "  {number:>2}. {:<18} {:<28} {}",
        stage.name(),
        stage.equation(),
        stage.description()
    );
    if let Some(v) = variant {
        let _ = writeln!(out, "      multiphase: {} -- {}", v.equation, v.description);
    }
    let _ = writeln!(
        out,
        "      reads {} -> writes {}",
        fields(&stage.reads_in(plan, multiphase)),
        fields(&stage.writes_in(plan))
    );
}

/// The lines of one step the driver runs inside a stage.
fn sub_stage_lines(out: &mut String, sub: SubStage, plan: &[Stage], multiphase: bool) {
    let variant = sub.multiphase().filter(|_| multiphase);
    let description = match sub {
        SubStage::SortByCell => {
            format!("re-sort, only once particles drifted {RESORT_DRIFT} h since the last sort")
        }
        _ => sub.description().to_string(),
    };
    let _ = writeln!(
        out,
        "      - {:<19} {:<25} {description}",
        sub.name(),
        sub.equation()
    );
    if let Some(v) = variant {
        let _ = writeln!(out, "          multiphase: {} -- {}", v.equation, v.description);
    }
    let _ = writeln!(
        out,
        "          reads {} -> writes {}",
        fields(&sub.reads_in(plan, multiphase)),
        fields(sub.writes())
    );
}
