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

use std::path::{Path, PathBuf};

use crate::model::pair_terms::{CoefficientRule, PairTermSettings};

use super::count::{self, axis_name};
use super::generate::{fmt_box, intersection, outside_axis, solid_extent};
use super::schema::{
    BoxFile, Effect, MotionFile, ProbeFile, ProbeKind, SceneFile, SolidShape, SolverFile, SolverKind,
};
use super::{
    Aabb, FluidBox, KeyPath, Location, Probe, ProbeReference, Problem, RankSettings, Scene, SceneError,
    Solid, SolverSettings, Sway,
};
use crate::boundary::motion::Motion;

mod floating;
mod geometry;
mod keys;
mod memory;
mod motion;
mod open;
mod periodic;
mod ranks;
use ranks::check_ranks;
mod probe_extents;
mod probes;
mod sea;
mod solids;
mod step_bounds;
mod wave_maker;

use geometry::{check_box, check_geometry};
use keys::{
    artificial_viscosity_wall_factor, check_name, check_solver, density_diffusion, initial_state,
    rotating_frame,
};
use memory::check_counts;
pub use memory::{
    BASE_BYTES, ParticleBytes, frame_bytes_per_particle, particle_bytes, run_bytes, scene_particle_bytes,
    solver_particle_bytes,
};
use probes::check_probe;
pub use step_bounds::{CORRECTED_FLOW_FACTOR, CORRECTED_GRAVITY_FACTOR, corrected_step_bound};
use step_bounds::{check_acoustic_step, check_corrected_step};

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

/// Validates `file` without source positions (problem locations are
/// [`Location::Unknown`], origin `"scene"`).
///
/// The particle-memory check compares the estimated peak ([`run_bytes`]) with
/// [`crate::memory::limit`] (the least of `MemAvailable`, the cgroup's limit and `ulimit -v`),
/// or with `isize::MAX` if none can be read; counts above `u32::MAX` are always rejected.
pub fn validate(file: &SceneFile) -> Result<Scene, SceneError> {
    validate_raw(file, Path::new("")).map_err(|raw| SceneError::Invalid {
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

/// Validates `file`, returning every problem with its key path; a mesh file's relative path is
/// taken from `dir` (the scene file's directory).
pub(crate) fn validate_raw(file: &SceneFile, dir: &Path) -> Result<Scene, Vec<RawProblem>> {
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
    let has_grav = effects.contains(&Effect::Gravity);
    // The pair terms' coefficients (`kernels/pair_terms.table`): each required iff its effect
    // is on.
    let mut pair_terms = PairTermSettings::none();
    for (term, value) in f.pair_term_coefficients() {
        let key = fp.k(term.name());
        let on = effects.contains(&Effect::Pair(term));
        match (value, on) {
            (Some(v), true) => {
                let checked = match term.rule() {
                    CoefficientRule::NonNegative => c.non_negative(key, v),
                    CoefficientRule::Positive => c.positive(key, v),
                };
                if let Some(v) = checked {
                    pair_terms = pair_terms.with(term, v);
                }
            }
            (None, true) => c.err(
                key,
                format!("required because effect \"{}\" is enabled", term.name()),
            ),
            (Some(_), false) => c.err(
                key,
                format!(
                    "given but effect \"{}\" is not enabled (add it to `effects` or remove this key)",
                    term.name()
                ),
            ),
            (None, false) => {}
        }
    }
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
    let density_diffusion = density_diffusion(&mut c, &fp, f, &effects);
    let artificial_viscosity_wall_factor = artificial_viscosity_wall_factor(&mut c, &fp, f, &effects);
    let initial_state = initial_state(&mut c, &fp, f, &effects, gravity_ramp);

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
        let volume = solids::check_fluid_shape(&mut c, &path, fb, dim, dir);
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
        match (volume, velocity, compression, coincident, rho0) {
            (Some((region, volume)), Some(velocity), Some(compression), Some(coincident), Some(rho0)) => {
                fluid_boxes.push(FluidBox {
                    region,
                    velocity,
                    compression,
                    coincident,
                    rho0,
                    volume,
                })
            }
            _ => boxes_ok = false,
        }
    }

    // [[solid]]
    let mut solids = Vec::new();
    // |g| [m/s²] for a piston's dispersion relation.
    let g_norm = gravity
        .as_ref()
        .map(|g| g.iter().map(|x| x * x).sum::<f64>().sqrt());
    for i in 0..file.solid.len() {
        match solids::check_solid(&mut c, file, i, dim, dir, g_norm) {
            Some(s) => solids.push(s),
            None => boxes_ok = false,
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
    if let Some(settings) = solver {
        if settings.kind == SolverKind::Corrected && effects.contains(&Effect::DensityDiffusion) {
            c.err(
                fp.k("density_diffusion"),
                "effect \"density_diffusion\" needs solver.kind = \"wcsph\": the corrected solver sets density by positions (the summation its correction drives to rho0), so there is no density to integrate".into(),
            );
        }
    }
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

    let damping_zone = match &file.damping_zone {
        Some(z) => motion::check_damping_zone(&mut c, z, dim).map(Some),
        None => Some(None),
    };

    let periodic = match &file.periodic {
        Some(p) => periodic::check_periodic(&mut c, p, dim, domain.as_ref(), spacing, h),
        None => Some(crate::periodic::PeriodicAxes::NONE),
    };

    let ranks = file
        .ranks
        .as_ref()
        .map_or(Some(RankSettings::default()), |r| check_ranks(&mut c, r));

    let mut open_boundaries = Vec::new();
    let mut open_ok = true;
    for (i, b) in file.open_boundary.iter().enumerate() {
        match open::check_open_boundary(&mut c, i, b, dim, spacing, h) {
            Some(b) => open_boundaries.push(b),
            None => open_ok = false,
        }
    }

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
            pair_terms,
            gravity,
            gravity_ramp: gravity_ramp?,
            angular_velocity,
            rotation_centre: rotation_centre?,
            surface_tension,
            surface_tension_model,
            artificial_viscosity_wall_factor: artificial_viscosity_wall_factor?,
            density_diffusion,
            initial_state,
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
            damping_zone: damping_zone?,
            periodic: periodic?,
            open_boundaries,
            ranks: ranks?,
        })
    })();
    match resolved {
        Some(scene) if boxes_ok && probes_ok && open_ok => {
            // Geometry is checked even when other keys have problems, so
            // that everything is reported at once.
            check_geometry(&mut c, &scene);
            wave_maker::check_wave_makers(&mut c, &scene);
            probe_extents::check_probe_extents(&mut c, &scene);
            open::check_open_geometry(&mut c, &scene);
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

/// A number as a person reads it in one line: plain in [1e-4, 1e9), else in exponent form
/// (`1e308`, not 309 digits).
pub(crate) fn num(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e9).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}
