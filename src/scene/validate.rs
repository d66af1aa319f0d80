//! Validation of a deserialized [`SceneFile`] into a [`Scene`].
//!
//! All floats must be finite; every box needs `min < max` on every axis and
//! vectors need exactly `dimension` entries. Beyond the per-key rules,
//! validation checks that fluid boxes and solids (including container walls)
//! lie inside the domain, that fluid boxes overlap neither each other nor a
//! solid (the interior of a container is fine), and that the particle count
//! fits `u32` indices and the available memory. `corrected`-only solver keys
//! are an error with `wcsph`; probe names are unique and probe axes below
//! `dimension`. Values and their products must fit the solver's f32 arithmetic
//! (`scene::magnitude`) and the run must be able to finish (`scene::progress`).
//! All problems are collected.

use std::path::PathBuf;

use super::generate::{self, axis_name, fmt_box, intersection, outside_axis, solid_extent};
use super::schema::{
    BoxFile, Effect, MotionFile, ProbeFile, ProbeKind, SceneFile, SolidShape, SolverFile, SolverKind,
};
use super::{
    Aabb, FluidBox, KeyPath, Location, Probe, ProbeReference, Problem, Scene, SceneError, Solid,
    SolverSettings, Sway,
};

/// A problem with a structured key path (turned into a [`Problem`] later).
#[derive(Debug, Clone)]
pub(crate) struct RawProblem {
    pub(crate) path: KeyPath,
    pub(crate) reason: String,
}

impl RawProblem {
    pub(crate) fn new(path: KeyPath, reason: String) -> Self {
        RawProblem { path, reason }
    }
}

/// The resident memory of the process before particles \[B\]: the program, its libraries, the
/// worker threads' stacks and the allocator's arenas. Measured peak resident sets of the
/// smallest shipped scenes (a few hundred particles, `/usr/bin/time -f %M`): 6.6–8.4 MiB.
pub const BASE_BYTES: u64 = 7 << 20;

/// Estimated peak resident memory per particle \[B\] of a run in `dim` dimensions with
/// `solver`: the particle fields, SSP-RK3's start-of-step copies, the grid's keys, sort pairs
/// and cell ranges, the reorder scratch, and for `corrected` the correction's increments, the
/// velocity solve's saved fields, its Anderson window and its neighbour list (4 B per pair,
/// about 33 pairs per fluid particle in 3D at `h = 2 dx`).
///
/// Calibrated on peak resident sets (`/usr/bin/time -f %M`, Xeon 2-core VM, 3 ms of every
/// shipped scene, less [`BASE_BYTES`]): 3D `wcsph` 195–222 B (214,125 and 148,041
/// particles), 3D `corrected` 400–466 B, 2D `wcsph` about 160 B and `corrected` about 330 B
/// (scenes of 3–4 thousand particles, where the base dominates). The per-particle figure
/// varies by scene with the growth of the arrays built particle by particle.
pub fn bytes_per_particle(dim: usize, solver: crate::scene::SolverKind) -> u64 {
    use crate::scene::SolverKind;
    match (dim, solver) {
        (3, SolverKind::Wcsph) => 210,
        (3, SolverKind::Corrected) => 430,
        (_, SolverKind::Wcsph) => 170,
        (_, SolverKind::Corrected) => 340,
    }
}

/// The estimated peak resident memory \[B\] of a run of `particles` particles.
pub fn run_bytes(particles: u64, dim: usize, solver: crate::scene::SolverKind) -> Option<u64> {
    particles
        .checked_mul(bytes_per_particle(dim, solver))?
        .checked_add(BASE_BYTES)
}

/// Validates `file` without source positions (problem locations are
/// [`Location::Unknown`], origin `"scene"`).
///
/// The particle-memory check compares the estimated peak ([`run_bytes`]) with
/// [`crate::memory::limit`] (the least of `MemAvailable`, the cgroup's limit and `ulimit -v`),
/// or with `isize::MAX` if none can be read; counts above `u32::MAX` are always rejected.
pub fn validate(file: &SceneFile) -> Result<Scene, SceneError> {
    validate_raw(file).map_err(|raw| SceneError::Invalid {
        origin: "scene".into(),
        problems: raw
            .into_iter()
            .map(|r| Problem {
                key: r.path.to_string(),
                location: Location::Unknown,
                reason: r.reason,
            })
            .collect(),
    })
}

/// Collects problems.
struct Checker {
    problems: Vec<RawProblem>,
}

impl Checker {
    fn err(&mut self, path: KeyPath, reason: String) {
        self.problems.push(RawProblem { path, reason });
    }

    fn finite(&mut self, path: KeyPath, v: f64) -> Option<f64> {
        if v.is_finite() {
            Some(v)
        } else {
            self.err(path, format!("must be a finite number, got {}", num(v)));
            None
        }
    }

    fn positive(&mut self, path: KeyPath, v: f64) -> Option<f64> {
        let v = self.finite(path.clone(), v)?;
        if v > 0.0 {
            Some(v)
        } else {
            self.err(path, format!("must be > 0, got {}", num(v)));
            None
        }
    }

    fn non_negative(&mut self, path: KeyPath, v: f64) -> Option<f64> {
        let v = self.finite(path.clone(), v)?;
        if v >= 0.0 {
            Some(v)
        } else {
            self.err(path, format!("must be >= 0, got {}", num(v)));
            None
        }
    }

    fn vector(&mut self, path: KeyPath, v: &[f64], dim: Option<usize>) -> Option<Vec<f64>> {
        let dim = dim?;
        if v.len() != dim {
            self.err(
                path,
                format!("expected {dim} entries (dimension = {dim}), found {}", v.len()),
            );
            return None;
        }
        let mut ok = true;
        for (i, &x) in v.iter().enumerate() {
            ok &= self.finite(path.i(i), x).is_some();
        }
        ok.then(|| v.to_vec())
    }

    fn aabb(&mut self, path: &KeyPath, min: &[f64], max: &[f64], dim: Option<usize>) -> Option<Aabb> {
        let lo = self.vector(path.k("min"), min, dim);
        let hi = self.vector(path.k("max"), max, dim);
        let (lo, hi) = (lo?, hi?);
        let mut ok = true;
        for (k, (a, b)) in lo.iter().zip(&hi).enumerate() {
            if a >= b {
                ok = false;
                self.err(
                    path.k("max"),
                    format!(
                        "max must be greater than min on every axis, but on axis {} max = {b} <= min = {a}",
                        axis_name(k)
                    ),
                );
            }
        }
        ok.then_some(Aabb { min: lo, max: hi })
    }
}

fn in_range(c: &mut Checker, path: KeyPath, v: f64, lo: f64, hi: f64, lo_open: bool) -> Option<f64> {
    let v = c.finite(path.clone(), v)?;
    let low_ok = if lo_open { v > lo } else { v >= lo };
    if low_ok && v <= hi {
        Some(v)
    } else {
        let open = if lo_open { "(" } else { "[" };
        c.err(path, format!("must be in {open}{lo}, {hi}], got {}", num(v)));
        None
    }
}

/// Validates `file`, returning every problem with its key path.
pub(crate) fn validate_raw(file: &SceneFile) -> Result<Scene, Vec<RawProblem>> {
    let mut c = Checker { problems: Vec::new() };
    let dim = match file.dimension {
        2 => Some(2usize),
        3 => Some(3),
        d => {
            c.err(KeyPath::key("dimension"), format!("must be 2 or 3, got {d}"));
            None
        }
    };

    let mut effects: Vec<Effect> = Vec::new();
    for (i, &e) in file.effects.iter().enumerate() {
        if effects.contains(&e) {
            c.err(
                KeyPath::key("effects").i(i),
                format!("duplicate effect \"{}\"", e.name()),
            );
        } else {
            effects.push(e);
        }
    }

    let domain = check_box(&mut c, &KeyPath::key("domain"), &file.domain, dim);

    // [particles]
    let pp = KeyPath::key("particles");
    let p = &file.particles;
    let spacing = c.positive(pp.k("spacing"), p.spacing);
    let h = match (p.smoothing_ratio, p.smoothing_length) {
        (Some(_), Some(_)) => {
            c.err(
                pp.k("smoothing_length"),
                "give exactly one of particles.smoothing_ratio and particles.smoothing_length, not both"
                    .into(),
            );
            None
        }
        (None, None) => {
            c.err(
                pp.clone(),
                "one of smoothing_ratio (h / dx) or smoothing_length (h [m]) is required".into(),
            );
            None
        }
        (Some(r), None) => {
            let r = in_range(&mut c, pp.k("smoothing_ratio"), r, 1.0, 5.0, false);
            r.zip(spacing).map(|(r, dx)| r * dx)
        }
        (None, Some(h)) => {
            let h = c.positive(pp.k("smoothing_length"), h);
            match (h, spacing) {
                (Some(h), Some(dx)) if !(1.0..=5.0).contains(&(h / dx)) => {
                    c.err(
                        pp.k("smoothing_length"),
                        format!(
                            "smoothing_length / spacing must be in [1, 5], got {} / {} = {}",
                            num(h),
                            num(dx),
                            num(h / dx)
                        ),
                    );
                    None
                }
                (h, _) => h,
            }
        }
    };

    // [fluid]
    let fp = KeyPath::key("fluid");
    let f = &file.fluid;
    let rho0 = c.positive(fp.k("rho0"), f.rho0);
    let sound_speed = c.positive(fp.k("sound_speed"), f.sound_speed);
    let has_visc = effects.contains(&Effect::Viscosity);
    let has_grav = effects.contains(&Effect::Gravity);
    let viscosity = match (f.viscosity, has_visc) {
        (Some(v), true) => c.non_negative(fp.k("viscosity"), v),
        (None, true) => {
            c.err(
                fp.k("viscosity"),
                "required because effect \"viscosity\" is enabled".into(),
            );
            None
        }
        (Some(_), false) => {
            c.err(
                fp.k("viscosity"),
                "given but effect \"viscosity\" is not enabled (add it to `effects` or remove this key)"
                    .into(),
            );
            None
        }
        (None, false) => None,
    };
    let has_art = effects.contains(&Effect::ArtificialViscosity);
    let artificial_viscosity = match (f.artificial_viscosity, has_art) {
        (Some(v), true) => c.non_negative(fp.k("artificial_viscosity"), v),
        (None, true) => {
            c.err(
                fp.k("artificial_viscosity"),
                "required because effect \"artificial_viscosity\" is enabled".into(),
            );
            None
        }
        (Some(_), false) => {
            c.err(
                fp.k("artificial_viscosity"),
                "given but effect \"artificial_viscosity\" is not enabled (add it to `effects` or remove this key)"
                    .into(),
            );
            None
        }
        (None, false) => None,
    };
    let gravity = match (&f.gravity, has_grav) {
        (Some(g), true) => c.vector(fp.k("gravity"), g, dim),
        (None, true) => {
            c.err(
                fp.k("gravity"),
                "required because effect \"gravity\" is enabled".into(),
            );
            None
        }
        (Some(_), false) => {
            c.err(
                fp.k("gravity"),
                "given but effect \"gravity\" is not enabled (add it to `effects` or remove this key)".into(),
            );
            None
        }
        (None, false) => None,
    };
    let gravity_ramp = match (f.gravity_ramp, has_grav) {
        (Some(r), true) => c.non_negative(fp.k("gravity_ramp"), r),
        (Some(_), false) => {
            c.err(
                fp.k("gravity_ramp"),
                "given but effect \"gravity\" is not enabled".into(),
            );
            None
        }
        (None, _) => Some(0.0),
    };

    let (angular_velocity, rotation_centre) =
        rotating_frame(&mut c, &fp, f, effects.contains(&Effect::RotatingFrame), dim);
    let surface_tension = match (f.surface_tension, effects.contains(&Effect::SurfaceTension)) {
        (Some(sigma), true) => c.positive(fp.k("surface_tension"), sigma),
        (None, true) => {
            c.err(
                fp.k("surface_tension"),
                "required because effect \"surface_tension\" is enabled".into(),
            );
            None
        }
        (Some(_), false) => {
            c.err(
                fp.k("surface_tension"),
                "given but effect \"surface_tension\" is not enabled (add it to `effects` or remove this key)"
                    .into(),
            );
            None
        }
        (None, false) => None,
    };
    if f.surface_tension_model.is_some() && !effects.contains(&Effect::SurfaceTension) {
        c.err(
            fp.k("surface_tension_model"),
            "given but effect \"surface_tension\" is not enabled (add it to `effects` or remove this key)"
                .into(),
        );
    }
    let surface_tension_model = f.surface_tension_model.unwrap_or_default();

    // [[fluid_box]]
    if file.fluid_box.is_empty() {
        c.err(
            KeyPath::key("fluid_box"),
            "at least one [[fluid_box]] is required".into(),
        );
    }
    let mut fluid_boxes = Vec::new();
    let mut boxes_ok = true;
    for (i, fb) in file.fluid_box.iter().enumerate() {
        let path = KeyPath::key("fluid_box").i(i);
        let region = c.aabb(&path, &fb.min, &fb.max, dim);
        let velocity = match &fb.velocity {
            Some(v) => c.vector(path.k("velocity"), v, dim),
            None => dim.map(|d| vec![0.0; d]),
        };
        // Compression: [0, 1). A lattice `(1 + c)^(1/D)` times finer; 1 (double density) or
        // more is no longer a start a solver should recover from.
        let compression = match fb.compression {
            Some(v) => c.finite(path.k("compression"), v).and_then(|v| {
                if (0.0..1.0).contains(&v) {
                    Some(v)
                } else {
                    c.err(
                        path.k("compression"),
                        format!(
                            "must be in [0, 1) (the initial density is (1 + compression) rho0), got {}",
                            num(v)
                        ),
                    );
                    None
                }
            }),
            None => Some(0.0),
        };
        let coincident = match fb.coincident {
            Some(v) => in_range(&mut c, path.k("coincident"), v, 0.0, 1.0, false),
            None => Some(0.0),
        };
        // A phase's own rest density: only with the multiphase effect (without it every particle
        // has `fluid.rho0`, and a silently ignored key would hide a mistake).
        let rho0 = match (fb.rho0, effects.contains(&Effect::Multiphase)) {
            (Some(_), false) => {
                c.err(
                    path.k("rho0"),
                    "given but effect \"multiphase\" is not enabled (add it to `effects` or remove this key)"
                        .into(),
                );
                None
            }
            (Some(v), true) => c.positive(path.k("rho0"), v).map(Some),
            (None, _) => Some(None),
        };
        match (region, velocity, compression, coincident, rho0) {
            (Some(region), Some(velocity), Some(compression), Some(coincident), Some(rho0)) => fluid_boxes
                .push(FluidBox {
                    region,
                    velocity,
                    compression,
                    coincident,
                    rho0,
                }),
            _ => boxes_ok = false,
        }
    }

    // [[solid]]
    let mut solids = Vec::new();
    for (i, s) in file.solid.iter().enumerate() {
        let path = KeyPath::key("solid").i(i);
        let earlier: Vec<&str> = file.solid.iter().take(i).map(|o| o.name.as_str()).collect();
        let mut ok = check_name(&mut c, path.k("name"), &s.name, &earlier, "solid");
        let open_top = match (s.shape, s.open_top) {
            (SolidShape::Box, Some(_)) => {
                c.err(
                    path.k("open_top"),
                    "only allowed for shape = \"container\"".into(),
                );
                ok = false;
                false
            }
            (SolidShape::Box, None) => false,
            (SolidShape::Container, o) => o.unwrap_or(true),
        };
        let motion = match &s.motion {
            None => Some(None),
            Some(m) => check_motion(&mut c, &path.k("motion"), m, dim).map(Some),
        };
        match (c.aabb(&path, &s.min, &s.max, dim), motion) {
            (Some(region), Some(motion)) if ok => solids.push(Solid {
                name: s.name.clone(),
                shape: s.shape,
                region,
                open_top,
                motion,
            }),
            _ => boxes_ok = false,
        }
    }

    // [solver]
    let sp = KeyPath::key("solver");
    let sv = &file.solver;
    let dt = sv.dt.map(|dt| c.positive(sp.k("dt"), dt));
    let cfl = in_range(&mut c, sp.k("cfl"), sv.cfl.unwrap_or(0.2), 0.0, 1.0, true);
    let end_time = c.positive(sp.k("end_time"), sv.end_time);
    if let (Some(Some(dt)), Some(end)) = (dt, end_time) {
        if end < dt {
            c.err(
                sp.k("end_time"),
                format!("must be >= solver.dt = {}, got {}", num(dt), num(end)),
            );
        }
    }
    let solver = check_solver(&mut c, &sp, sv);
    if let (Some(Some(dt)), Some(settings), Some(h), Some(sound)) = (dt, solver, h, sound_speed) {
        check_acoustic_step(&mut c, &sp, dt, settings.kind, h, sound);
    }
    if let (Some(Some(dt)), Some(settings), Some(h)) = (dt, solver, h) {
        if settings.kind == SolverKind::Corrected {
            check_corrected_step(&mut c, &sp, dt, h, gravity.as_deref(), &fluid_boxes, &solids);
        }
    }

    // [[probe]]
    let mut probes = Vec::new();
    let mut probes_ok = true;
    for (i, pf) in file.probe.iter().enumerate() {
        match check_probe(&mut c, file, i, pf, dim, has_grav) {
            Some(p) => probes.push(p),
            None => probes_ok = false,
        }
    }

    // [output]
    let op = KeyPath::key("output");
    let out = file.output.as_ref();
    let interval = match out.and_then(|o| o.interval) {
        Some(i) => c.positive(op.k("interval"), i),
        None => end_time.map(|t| t / 50.0),
    };
    let write_frames = out.and_then(|o| o.frames).unwrap_or(true);
    let write_surface = out.and_then(|o| o.surface).unwrap_or(false);
    let surface_radius = match out.and_then(|o| o.surface_radius) {
        Some(r) => c.positive(op.k("surface_radius"), r),
        None => Some(crate::surface::DEFAULT_RADIUS),
    };
    let output_encoding = out.and_then(|o| o.encoding).unwrap_or_default();
    let fluid_only = out.and_then(|o| o.fluid_only).unwrap_or(false);

    let resolved = (|| {
        Some(Scene {
            name: file.name.clone(),
            dimension: dim?,
            effects,
            domain: domain?,
            spacing: spacing?,
            smoothing_length: h?,
            rho0: rho0?,
            sound_speed: sound_speed?,
            viscosity,
            artificial_viscosity,
            gravity,
            gravity_ramp: gravity_ramp?,
            angular_velocity,
            rotation_centre: rotation_centre?,
            surface_tension,
            surface_tension_model,
            fluid_boxes,
            solids,
            solver: solver?,
            dt: dt.flatten(),
            cfl: cfl?,
            end_time: end_time?,
            output_interval: interval?,
            write_frames,
            write_surface,
            surface_radius: surface_radius?,
            output_encoding,
            fluid_only,
            probes,
        })
    })();
    match resolved {
        Some(scene) if boxes_ok && probes_ok => {
            // Geometry is checked even when other keys have problems, so
            // that everything is reported at once.
            check_geometry(&mut c, &scene);
            // Values the f32 solver cannot hold, then values that cannot finish (whose
            // estimates need the magnitudes to hold).
            let magnitudes = super::magnitude::check(&scene);
            let representable = magnitudes.is_empty();
            c.problems.extend(magnitudes);
            if representable {
                c.problems.extend(super::progress::check(&scene));
            }
            if c.problems.is_empty() {
                Ok(scene)
            } else {
                Err(c.problems)
            }
        }
        _ => Err(c.problems),
    }
}

/// A fixed `solver.dt` \[s\] for `wcsph` must not exceed the acoustic bound `h / C` (support
/// radius over sound speed, CFL number 1): beyond it a pressure wave crosses more than a kernel
/// support per step, which no explicit scheme follows (the CFL condition; the adaptive step
/// uses a fifth of it by default). Adaptive steps and `corrected`
/// (no acoustic wave, eq. (19) unused) are not limited here; at run time a fixed step is also
/// cut to the force and viscous limits (`solver::timestep::choose`).
fn check_acoustic_step(c: &mut Checker, sp: &KeyPath, dt: f64, kind: SolverKind, h: f64, sound: f64) {
    let bound = h / sound;
    if kind == SolverKind::Wcsph && dt > bound {
        c.err(
            sp.k("dt"),
            format!(
                "{} s is above the acoustic stability bound h / C = {} m / {} m/s = {} s of solver.kind = \"wcsph\" (CFL number 1); use solver.dt <= {}, or remove solver.dt for an adaptive step",
                num(dt),
                num(h),
                num(sound),
                num(bound),
                num(bound)
            ),
        );
    }
}

/// Factor `k_g` of the gravity bound `k_g sqrt(h / |g|)` on a fixed `corrected` step. Measured
/// (docs/hard-cases.md) as the largest fixed step that keeps every hard-case invariant, over
/// `sqrt(h/|g|)`: `viscous_low_3d.toml` passes at 0.85 ms and fails the energy bound at 1 ms
/// (h = 0.04 m: 0.0133 and 0.0157); `large_dt_3d.toml` 2.5 ms (0.039), `large_dt_2d.toml`
/// 2.5 ms (h = 0.02 m: 0.055), `rest_2d.toml` 3.5 ms (0.078), `viscous_low_2d.toml` at least
/// 6 ms (0.13). 0.0125 stays below the smallest (`rest_3d.toml` fails at every step tried,
/// adaptive included: a known failure).
pub const CORRECTED_GRAVITY_FACTOR: f64 = 0.0125;

/// Factor `k_u` of the flow bound `k_u h / |u|max` on a fixed `corrected` step, `|u|max` the
/// largest initial fluid speed or moving-wall speed. Measured on `jet_2d.toml` (10 m/s, h =
/// 0.02 m): 0.25 h / |u| = 0.5 ms keeps every invariant, 0.3 h / |u| (0.6 ms) raises the energy
/// at the impact; `jet_3d.toml` (h = 0.04 m) passes at 0.25 and 0.3 h / |u|. A 12 × 12 lattice
/// block thrown at 1 m/s at a wall (h = 0.02 m, no gravity, with the no-penetration guard;
/// tests/correction.rs) stays in its box for 0.3 s at 0.05, 0.075, 0.1 and 0.15 h / |u|; at
/// 0.125, 0.2 and 0.25 the impact is violent enough that a particle went through the wall (steps
/// 25, 7 and 7) until the guard took each particle's step start into account, and since then the
/// correction stops unconverged (steps 28, 10 and 9). 0.1 is the largest factor below which every
/// measured step passed.
pub const CORRECTED_FLOW_FACTOR: f64 = 0.1;

/// The largest fixed `solver.dt` [s] that validation accepts for `solver.kind = "corrected"`:
/// `min(k_g sqrt(h / |g|), k_u h / |u|max)` over the terms that apply (gravity given and
/// non-zero; a fluid box or moving wall with a non-zero speed), `None` when neither applies.
/// `h` is the support radius [m], `gravity` [m/s²], the speeds from the fluid boxes' initial
/// velocities and the solids' `Sway::max_speed` [m/s]. The corrected solver has no acoustic
/// limit (its pressure does not come from eq. (19)); these are the measured limits of its
/// start-up and of impacts (`CORRECTED_GRAVITY_FACTOR`, `CORRECTED_FLOW_FACTOR`).
pub fn corrected_step_bound(
    h: f64,
    gravity: Option<&[f64]>,
    fluid_boxes: &[FluidBox],
    solids: &[Solid],
) -> Option<f64> {
    corrected_step_terms(h, gravity, fluid_boxes, solids)
        .map(|t| t.gravity.min(t.flow))
        .filter(|b| b.is_finite())
}

/// The two terms of [`corrected_step_bound`] with their inputs (infinite where absent).
struct CorrectedStepTerms {
    g: f64,
    gravity: f64,
    speed: f64,
    flow: f64,
}

fn corrected_step_terms(
    h: f64,
    gravity: Option<&[f64]>,
    fluid_boxes: &[FluidBox],
    solids: &[Solid],
) -> Option<CorrectedStepTerms> {
    let norm = |v: &[f64]| v.iter().map(|c| c * c).sum::<f64>().sqrt();
    let g = gravity.map(norm).unwrap_or(0.0);
    let speed = fluid_boxes
        .iter()
        .map(|b| norm(&b.velocity))
        .chain(
            solids
                .iter()
                .filter_map(|s| s.motion.as_ref())
                .map(Sway::max_speed),
        )
        .fold(0.0, f64::max);
    if !(g.is_finite() && speed.is_finite()) {
        return None;
    }
    let gravity = if g > 0.0 {
        CORRECTED_GRAVITY_FACTOR * (h / g).sqrt()
    } else {
        f64::INFINITY
    };
    let flow = if speed > 0.0 {
        CORRECTED_FLOW_FACTOR * h / speed
    } else {
        f64::INFINITY
    };
    Some(CorrectedStepTerms {
        g,
        gravity,
        speed,
        flow,
    })
}

/// A fixed `solver.dt` \[s\] for `corrected` must not exceed [`corrected_step_bound`]; the
/// error names the value, the bound, the terms it is made of and the fix.
fn check_corrected_step(
    c: &mut Checker,
    sp: &KeyPath,
    dt: f64,
    h: f64,
    gravity: Option<&[f64]>,
    fluid_boxes: &[FluidBox],
    solids: &[Solid],
) {
    let Some(t) = corrected_step_terms(h, gravity, fluid_boxes, solids) else {
        return;
    };
    let bound = t.gravity.min(t.flow);
    if dt <= bound {
        return;
    }
    // Six significant digits, rounded down so that the value shown is itself accepted; the
    // whole problem stays one readable line.
    let shown = |v: f64| {
        let scale = 10f64.powi(5 - v.log10().floor() as i32);
        num((v * scale).floor() / scale)
    };
    let mut terms = Vec::new();
    let mut inputs = vec![format!("h = {} m", num(h))];
    if t.gravity.is_finite() {
        terms.push(format!(
            "{CORRECTED_GRAVITY_FACTOR} sqrt(h / |g|) = {} s",
            shown(t.gravity)
        ));
        inputs.push(format!("|g| = {} m/s^2", num(t.g)));
    }
    if t.flow.is_finite() {
        terms.push(format!(
            "{CORRECTED_FLOW_FACTOR} h / |u|max = {} s",
            shown(t.flow)
        ));
        inputs.push(format!("|u|max = {} m/s", num(t.speed)));
    }
    let how = match terms.as_slice() {
        [one] => one.clone(),
        _ => format!("min({})", terms.join(", ")),
    };
    c.err(
        sp.k("dt"),
        format!(
            "{} s is above the largest fixed step of solver.kind = \"corrected\", {how} ({}); use a smaller solver.dt, or remove solver.dt for an adaptive step",
            num(dt),
            inputs.join(", ")
        ),
    );
}

/// Checks a solid or probe name: non-empty, `[A-Za-z0-9_-]` only, not among `earlier`
/// (the names of the preceding `what` tables). Reports at `path`; returns whether it is fine.
fn check_name(c: &mut Checker, path: KeyPath, name: &str, earlier: &[&str], what: &str) -> bool {
    if name.is_empty() {
        c.err(path, "must not be empty".into());
    } else if let Some(bad) = name
        .chars()
        .find(|ch| !(ch.is_ascii_alphanumeric() || *ch == '_' || *ch == '-'))
    {
        c.err(
            path,
            format!("may only contain A-Z, a-z, 0-9, '_' and '-', found {bad:?}"),
        );
    } else if let Some(j) = earlier.iter().position(|o| *o == name) {
        c.err(
            path,
            format!("duplicate {what} name \"{name}\" (already used by {what}[{j}])"),
        );
    } else {
        return true;
    }
    false
}

/// A solid's `motion` table (`schema::MotionFile`): finite amplitudes, not all zero, a positive
/// period, a non-negative ramp. The swept box is checked with the geometry.
fn check_motion(c: &mut Checker, path: &KeyPath, m: &MotionFile, dim: Option<usize>) -> Option<Sway> {
    let amplitude = c.vector(path.k("amplitude"), &m.amplitude, dim);
    if amplitude.as_ref().is_some_and(|a| a.iter().all(|&x| x == 0.0)) {
        c.err(
            path.k("amplitude"),
            "all entries are 0, so the solid would not move (remove `motion` for a fixed solid)".into(),
        );
        return None;
    }
    let period = c.positive(path.k("period"), m.period);
    let ramp = match m.ramp {
        Some(r) => c.non_negative(path.k("ramp"), r),
        None => Some(0.0),
    };
    Some(Sway {
        amplitude: amplitude?,
        period: period?,
        ramp: ramp?,
    })
}

/// The `[solver]` scheme settings; `corrected`-only keys are an error with `wcsph`.
fn check_solver(c: &mut Checker, sp: &KeyPath, sv: &SolverFile) -> Option<SolverSettings> {
    let mut settings = SolverSettings::defaults(sv.kind);
    if let Some(integrator) = sv.integrator {
        settings.integrator = integrator;
    }
    let corrected = sv.kind == SolverKind::Corrected;
    let mut ok = true;
    let given = [
        ("delta", sv.delta.is_some()),
        ("max_iterations", sv.max_iterations.is_some()),
        ("strict", sv.strict.is_some()),
        ("relaxation", sv.relaxation.is_some()),
    ];
    for (key, present) in given {
        if present && !corrected {
            c.err(
                sp.k(key),
                format!(
                    "only with solver.kind = \"corrected\" (solver.kind is \"{}\")",
                    sv.kind.name()
                ),
            );
            ok = false;
        }
    }
    if !ok {
        return None;
    }
    if let Some(d) = sv.delta {
        match in_range(c, sp.k("delta"), d, 0.0, 0.1, true) {
            Some(d) => settings.delta = d,
            None => ok = false,
        }
    }
    if let Some(n) = sv.max_iterations {
        match u32::try_from(n) {
            Ok(m) if (1..=100_000).contains(&m) => settings.max_iterations = m,
            _ => {
                c.err(
                    sp.k("max_iterations"),
                    format!("must be an integer in [1, 100000], got {n}"),
                );
                ok = false;
            }
        }
    }
    if let Some(strict) = sv.strict {
        settings.strict = strict;
    }
    if let Some(policy) = sv.on_escape {
        settings.on_escape = policy;
    }
    if let Some(w) = sv.relaxation {
        match in_range(c, sp.k("relaxation"), w, 0.0, 1.0, true) {
            Some(w) => settings.relaxation = w,
            None => ok = false,
        }
    }
    ok.then_some(settings)
}

/// Checks `probe[i]`; `has_grav` is whether the gravity effect is on.
fn check_probe(
    c: &mut Checker,
    file: &SceneFile,
    i: usize,
    pf: &ProbeFile,
    dim: Option<usize>,
    has_grav: bool,
) -> Option<Probe> {
    let path = KeyPath::key("probe").i(i);
    let earlier: Vec<&str> = file.probe.iter().take(i).map(|o| o.name.as_str()).collect();
    let mut ok = check_name(c, path.k("name"), &pf.name, &earlier, "probe");
    let axis_text = pf.axis.as_deref().unwrap_or("x");
    let axis = match (["x", "y", "z"].iter().position(|a| *a == axis_text), dim) {
        (Some(a), Some(d)) if a < d => Some(a),
        (Some(_), None) => None,
        (found, d) => {
            let allowed = if d == Some(2) {
                "\"x\" or \"y\""
            } else {
                "\"x\", \"y\" or \"z\""
            };
            let why = match (found, d) {
                (Some(_), Some(d)) => format!(" (dimension = {d})"),
                _ => String::new(),
            };
            c.err(
                path.k("axis"),
                format!("must be {allowed}{why}, got {axis_text:?}"),
            );
            None
        }
    };
    let origin = match pf.origin {
        Some(o) => c.finite(path.k("origin"), o),
        None => Some(0.0),
    };
    let force = pf.kind == ProbeKind::Force;
    let solid = match (&pf.solid, force) {
        (None, false) => Some(None),
        (Some(_), false) => {
            c.err(path.k("solid"), "only with kind = \"force\"".into());
            None
        }
        (None, true) => {
            c.err(
                path.k("solid"),
                "required with kind = \"force\": the solid's name".into(),
            );
            None
        }
        (Some(name), true) => match file.solid.iter().position(|s| &s.name == name) {
            Some(k) => Some(Some(k)),
            None => {
                c.err(path.k("solid"), format!("no solid named {name:?}"));
                None
            }
        },
    };
    if force && pf.origin.is_some() {
        c.err(path.k("origin"), "only with kind = \"front\"".into());
        ok = false;
    }
    let reference = match &pf.reference {
        None => Some(None),
        Some(r) => {
            let rp = path.k("reference");
            if !has_grav && !force {
                c.err(
                    rp.clone(),
                    "needs effect \"gravity\" (the reference time is T = t sqrt(g / a))".into(),
                );
                ok = false;
            }
            if r.file.trim().is_empty() {
                c.err(rp.k("file"), "must not be empty".into());
                ok = false;
            }
            let series = r.series.clone().unwrap_or_default();
            for (j, name) in series.iter().enumerate() {
                if name.trim().is_empty() {
                    c.err(rp.k("series").i(j), "must not be empty".into());
                    ok = false;
                } else if let Some(k) = series.iter().take(j).position(|o| o == name) {
                    c.err(
                        rp.k("series").i(j),
                        format!("duplicate series \"{name}\" (already at series[{k}])"),
                    );
                    ok = false;
                }
            }
            let length = match (r.length, force) {
                (Some(l), false) => c.positive(rp.k("length"), l),
                (None, false) => {
                    c.err(
                        rp.k("length"),
                        "required for a front: the column width a [m]".into(),
                    );
                    None
                }
                (Some(_), true) => {
                    c.err(rp.k("length"), "only for a front".into());
                    None
                }
                (None, true) => Some(0.0),
            };
            let time_range = match r.time_range.as_deref() {
                None if force => Some((0.0, file.solver.end_time)),
                None => Some(ProbeReference::DEFAULT_TIME_RANGE),
                Some(&[t0, t1]) => {
                    let t0 = c.finite(rp.k("time_range").i(0), t0);
                    let t1 = c.finite(rp.k("time_range").i(1), t1);
                    match (t0, t1) {
                        (Some(t0), Some(t1)) if t0 < t1 => Some((t0, t1)),
                        (Some(t0), Some(t1)) => {
                            c.err(
                                rp.k("time_range"),
                                format!("must be [T0, T1] with T0 < T1, got [{t0}, {t1}]"),
                            );
                            None
                        }
                        _ => None,
                    }
                }
                Some(other) => {
                    c.err(
                        rp.k("time_range"),
                        format!("expected 2 entries [T0, T1], found {}", other.len()),
                    );
                    None
                }
            };
            match (length, time_range) {
                (Some(length), Some(time_range)) => Some(Some(ProbeReference {
                    file: PathBuf::from(&r.file),
                    location: super::ReferenceLocation::Unlocated,
                    series,
                    length,
                    time_range,
                })),
                _ => None,
            }
        }
    };
    let probe = Probe {
        name: pf.name.clone(),
        kind: pf.kind,
        axis: axis?,
        origin: origin?,
        solid: solid?,
        reference: reference?,
    };
    ok.then_some(probe)
}

fn check_box(c: &mut Checker, path: &KeyPath, b: &BoxFile, dim: Option<usize>) -> Option<Aabb> {
    c.aabb(path, &b.min, &b.max, dim)
}

/// Domain containment, overlaps and particle-count / memory limits.
fn check_geometry(c: &mut Checker, scene: &Scene) {
    let dx = scene.spacing;
    let tol = 1e-6 * dx;
    let layers = scene.wall_layers();
    let domain = &scene.domain;
    for (i, fb) in scene.fluid_boxes.iter().enumerate() {
        if let Some(k) = outside_axis(&fb.region, domain, tol) {
            c.err(
                KeyPath::key("fluid_box").i(i),
                format!(
                    "fluid box {} extends outside the domain {} on axis {}",
                    fmt_box(&fb.region),
                    fmt_box(domain),
                    axis_name(k)
                ),
            );
        }
    }
    let extents: Vec<Aabb> = scene.solids.iter().map(|s| solid_extent(s, dx, layers)).collect();
    for (i, (s, ext)) in scene.solids.iter().zip(&extents).enumerate() {
        if let Some(m) = &s.motion {
            // The box the moving solid sweeps: |d_k(t)| <= |A_k| since |r sin| <= 1.
            let swept = Aabb {
                min: ext
                    .min
                    .iter()
                    .zip(&m.amplitude)
                    .map(|(x, a)| x - a.abs())
                    .collect(),
                max: ext
                    .max
                    .iter()
                    .zip(&m.amplitude)
                    .map(|(x, a)| x + a.abs())
                    .collect(),
            };
            if let Some(k) = outside_axis(&swept, domain, tol) {
                c.err(
                    KeyPath::key("solid").i(i).k("motion").k("amplitude"),
                    format!(
                        "solid \"{}\" sweeps {} while moving by ±{} m on axis {}, outside the domain {}",
                        s.name,
                        fmt_box(&swept),
                        num(m.amplitude[k].abs()),
                        axis_name(k),
                        fmt_box(domain)
                    ),
                );
                continue;
            }
        }
        if let Some(k) = outside_axis(ext, domain, tol) {
            let walls = match s.shape {
                SolidShape::Box => String::new(),
                SolidShape::Container => format!(" (including walls of {layers} layers x {dx} m)"),
            };
            c.err(
                KeyPath::key("solid").i(i),
                format!(
                    "solid \"{}\" occupies {}{walls}, outside the domain {} on axis {}",
                    s.name,
                    fmt_box(ext),
                    fmt_box(domain),
                    axis_name(k)
                ),
            );
        }
    }
    for (i, fb) in scene.fluid_boxes.iter().enumerate() {
        let path = KeyPath::key("fluid_box").i(i);
        for (s, ext) in scene.solids.iter().zip(&extents) {
            let Some(cut) = intersection(&fb.region, ext, tol) else {
                continue;
            };
            match s.shape {
                SolidShape::Box => c.err(
                    path.clone(),
                    format!(
                        "fluid box {} overlaps solid box \"{}\" {}",
                        fmt_box(&fb.region),
                        s.name,
                        fmt_box(&s.region)
                    ),
                ),
                SolidShape::Container => {
                    if outside_axis(&cut, &s.region, tol).is_some() {
                        c.err(
                            path.clone(),
                            format!(
                                "fluid box {} overlaps the walls of container \"{}\" (walls occupy {} minus the inside {})",
                                fmt_box(&fb.region),
                                s.name,
                                fmt_box(ext),
                                fmt_box(&s.region)
                            ),
                        );
                    }
                }
            }
        }
        for (j, other) in scene.fluid_boxes.iter().enumerate().take(i) {
            if intersection(&fb.region, &other.region, tol).is_some() {
                c.err(path.clone(), format!("fluid box overlaps fluid_box[{j}]"));
            }
        }
    }
    check_counts(c, scene);
}

fn check_counts(c: &mut Checker, scene: &Scene) {
    let dx = scene.spacing;
    let layers = scene.wall_layers();
    let mut total: Option<u64> = Some(0);
    let mut complete = true;
    for (i, fb) in scene.fluid_boxes.iter().enumerate() {
        let path = KeyPath::key("fluid_box").i(i);
        match generate::fluid_box_count(fb, dx, &path) {
            Ok(n) => total = total.and_then(|t| t.checked_add(n)),
            Err(p) => {
                c.problems.push(p);
                complete = false;
            }
        }
    }
    for (i, s) in scene.solids.iter().enumerate() {
        let path = KeyPath::key("solid").i(i);
        match generate::solid_count(s, dx, layers, &path) {
            Ok(n) => total = total.and_then(|t| t.checked_add(n)),
            Err(p) => {
                c.problems.push(p);
                complete = false;
            }
        }
    }
    if !complete {
        return;
    }
    let key = KeyPath::key("particles").k("spacing");
    let Some(total) = total else {
        c.err(
            key,
            format!("particle count overflows a 64-bit integer at spacing {dx} m"),
        );
        return;
    };
    let per = bytes_per_particle(scene.dimension, scene.solver.kind);
    let bytes = run_bytes(total, scene.dimension, scene.solver.kind);
    let bytes_txt = bytes.map_or_else(|| "more than 2^64".to_string(), |b| format!("{b}"));
    if total > u64::from(u32::MAX) {
        c.err(
            key,
            format!(
                "spacing {dx} m gives {total} particles (about {bytes_txt} bytes), more than the {} that u32 particle indices allow",
                u32::MAX
            ),
        );
        return;
    }
    let (limit, what) =
        crate::memory::limit().unwrap_or((isize::MAX as u64, "isize::MAX (no limit readable)"));
    if bytes.is_none_or(|b| b > limit) {
        c.err(
            key,
            format!(
                "spacing {dx} m gives {total} particles needing about {bytes_txt} bytes ({per} per particle and {BASE_BYTES} for the program), more than the {limit} bytes available ({what})"
            ),
        );
    }
}

/// A number as a person reads it in one line: plain in [1e-4, 1e9), else in exponent form
/// (`1e308`, not 309 digits).
pub(crate) fn num(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e9).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// `fluid.angular_velocity` as 3 components and `fluid.rotation_centre` (default the origin):
/// required / allowed iff the `rotating_frame` effect is on (`schema::FluidFile`).
fn rotating_frame(
    c: &mut Checker,
    fp: &KeyPath,
    f: &crate::scene::schema::FluidFile,
    on: bool,
    dim: Option<usize>,
) -> (Option<[f64; 3]>, Option<Vec<f64>>) {
    use crate::scene::schema::AngularVelocityFile;
    let key = fp.k("angular_velocity");
    let omega = match (&f.angular_velocity, on, dim) {
        (Some(_), false, _) => {
            c.err(
                key,
                "given but effect \"rotating_frame\" is not enabled (add it to `effects` or remove this key)"
                    .into(),
            );
            None
        }
        (None, true, _) => {
            c.err(
                key,
                "required because effect \"rotating_frame\" is enabled".into(),
            );
            None
        }
        (None, false, _) | (Some(_), true, None) => None,
        (Some(AngularVelocityFile::Scalar(w)), true, Some(2)) => c.finite(key, *w).map(|w| [0.0, 0.0, w]),
        (Some(AngularVelocityFile::Scalar(_)), true, Some(d)) => {
            c.err(
                key,
                format!(
                    "expected {d} entries (dimension = {d}); a single number (about the out-of-plane axis) is for 2D only"
                ),
            );
            None
        }
        (Some(AngularVelocityFile::Vector(v)), true, Some(d)) => c
            .vector(key, v, Some(d))
            .map(|v| [v[0], v[1], if d > 2 { v[2] } else { 0.0 }]),
    };
    let centre = match (&f.rotation_centre, on) {
        (Some(_), false) => {
            c.err(
                fp.k("rotation_centre"),
                "given but effect \"rotating_frame\" is not enabled".into(),
            );
            None
        }
        (Some(x), true) => c.vector(fp.k("rotation_centre"), x, dim),
        (None, _) => dim.map(|d| vec![0.0; d]),
    };
    (omega, centre)
}
