//! Scene loading: TOML scene files, command-line overrides, validation and
//! initial particle generation.
//!
//! The pipeline is
//! `text --parse--> toml::Table --overrides--> SceneFile --validate--> Scene`,
//! followed by [`generate()`] (particles) or [`count_particles`] (counts only).
//! Every problem found on the way is reported as a [`Problem`] naming the key
//! path (`fluid_box[1].max`) and its location in the file (or the `--set`
//! override that produced it). Validation collects all problems it finds.
//!
//! All physical quantities are SI: lengths in m, times in s, velocities in
//! m/s, densities in kg/m^3, dynamic viscosity in Pa s.

use std::path::{Path, PathBuf};

use crate::geometry::Volume;

pub use crate::boundary::motion::{Motion, Piston, Sway};

pub(crate) mod count;
pub mod floating;
pub mod generate;
pub mod initial_state;
pub mod magnitude;
pub mod overrides;
mod problem;
pub mod progress;
pub mod read;
pub mod references;
pub mod schema;
pub mod trim;
pub mod validate;

pub use generate::{
    Fitted, GenerationReport, Layout, ParticleCounts, SolidParticles, count_particles, fluid_rest_density,
    generate, generate_reported, wall_layers,
};
pub use overrides::apply_overrides;
pub(crate) use problem::{KeyPath, Seg, SpanIndex};
pub use problem::{Location, Problem, SceneError};
use problem::{line_col, locate, toml_problem};
pub use read::MAX_SCENE_BYTES;
pub use references::{
    MissingReason, REFERENCE_DIR_ENV, ReferenceLocation, SkippedReference, locate_references, reference_dir,
    skipped_references,
};
pub use schema::{Effect, Integrator, ProbeKind, SceneFile, SolidShape, SolverKind};
pub use trim::{Body, MIN_GAP, Trimmed};
pub use validate::{
    BASE_BYTES, ParticleBytes, frame_bytes_per_particle, particle_bytes, run_bytes, scene_particle_bytes,
    solver_particle_bytes, validate,
};

/// A validated scene with all defaults resolved. Floats are `f64`, SI units.
///
/// Every vector (`domain`, box corners, velocities, gravity) has exactly
/// `dimension` entries, all finite; every box has `min < max` on every axis.
/// Build it with [`load_scene`], [`parse_scene`] or [`validate()`].
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Optional scene name from the file.
    pub name: Option<String>,
    /// Spatial dimension, 2 or 3.
    pub dimension: usize,
    /// Enabled effects, without duplicates, in file order.
    pub effects: Vec<Effect>,
    /// Simulation domain \[m\]; all particles lie inside it.
    pub domain: Aabb,
    /// Initial particle spacing dx \[m\].
    pub spacing: f64,
    /// Kernel support radius h \[m\] (resolved from `smoothing_ratio * spacing`
    /// or given directly as `smoothing_length`); `1 <= h / dx <= 5`.
    pub smoothing_length: f64,
    /// Rest density rho0 \[kg/m^3\].
    pub rho0: f64,
    /// Numerical speed of sound c0 \[m/s\].
    pub sound_speed: f64,
    /// The force stage's optional pair terms with their coefficients (`kernels/pair_terms.table`):
    /// a term is on iff its [`Effect::Pair`] is enabled.
    pub pair_terms: crate::model::pair_terms::PairTermSettings,
    /// Gravitational acceleration \[m/s^2\]; `Some` iff [`Effect::Gravity`] is enabled.
    pub gravity: Option<Vec<f64>>,
    /// Gravity ramp-in time \[s\] (0 = full gravity from t = 0).
    pub gravity_ramp: f64,
    /// Angular velocity `Ω` \[rad/s\] of the rotating frame, always 3 components (2D: `(0, 0, Ω)`
    /// from a number, `(Ω_x, Ω_y, 0)` from 2 entries); `Some` iff [`Effect::RotatingFrame`] is on.
    pub angular_velocity: Option<[f64; 3]>,
    /// A point on the rotation axis \[m\], `dimension` entries (the origin by default).
    pub rotation_centre: Vec<f64>,
    /// Surface tension `σ` \[N/m\] (2D: per unit depth); `Some` iff [`Effect::SurfaceTension`]
    /// is on.
    pub surface_tension: Option<f64>,
    /// The surface-tension model (`fluid.surface_tension_model`, default `surface_stress`);
    /// meaningful only with [`Effect::SurfaceTension`].
    pub surface_tension_model: crate::model::SurfaceTensionModel,
    /// The factor on the artificial viscosity's α between fluid and solid particles
    /// (`fluid.artificial_viscosity_wall_factor`, default 1); meaningful only with the
    /// `artificial_viscosity` effect.
    pub artificial_viscosity_wall_factor: f64,
    /// δ of the density diffusion (`fluid.density_diffusion`, dimensionless); `Some` iff
    /// [`Effect::DensityDiffusion`] is on.
    pub density_diffusion: Option<f64>,
    /// The fluid's initial state (`fluid.initial_state`, default uniform).
    pub initial_state: initial_state::InitialState,
    /// Initial fluid blocks, in file order (non-empty, non-overlapping).
    pub fluid_boxes: Vec<FluidBox>,
    /// Solid bodies, in file order, with unique names.
    pub solids: Vec<Solid>,
    /// Pressure scheme, integrator and position-correction settings (`[solver]`).
    pub solver: SolverSettings,
    /// Fixed time step \[s\]; `None` means adaptive.
    pub dt: Option<f64>,
    /// CFL number in (0, 1].
    pub cfl: f64,
    /// Simulated time \[s\].
    pub end_time: f64,
    /// Time between particle frames \[s\] (default `end_time / 50`).
    pub output_interval: f64,
    /// Whether particle frames are written.
    pub write_frames: bool,
    /// Whether the free surface (eq. (25)) is written at every frame time.
    pub write_surface: bool,
    /// Support radius of that surface's eq. (25) in particle spacings (`[output]
    /// surface_radius`, default [`crate::surface::DEFAULT_RADIUS`]).
    pub surface_radius: f64,
    /// Storage of the arrays of frames and surfaces (`[output] encoding`, default zlib).
    pub output_encoding: crate::output::Encoding,
    /// Whether frames hold only the fluid particles (`[output] fluid_only`, default false).
    pub fluid_only: bool,
    /// Probes (`[[probe]]`), in file order, with unique names.
    pub probes: Vec<Probe>,
    /// The damping zone (`[damping_zone]`), if any.
    pub damping_zone: Option<DampingZoneSpec>,
    /// The periodic axes (`[periodic]`, `crate::periodic`); none without the table.
    pub periodic: crate::periodic::PeriodicAxes,
    /// Inflow and outflow planes (`[[open_boundary]]`, `boundary::open`), in file order.
    pub open_boundaries: Vec<OpenBoundarySpec>,
    /// How a run across ranks cuts the domain (`[ranks]`).
    pub ranks: RankSettings,
}

/// How a run split across ranks cuts its domain (`[ranks]`, `distributed::decomposition`);
/// a run on one rank ignores it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RankSettings {
    /// The cut at the start and at every rebalance (default: bisection).
    pub method: crate::distributed::Method,
    /// When the regions are cut again (default: above an imbalance of 0.1).
    pub rebalance: crate::distributed::Rebalance,
}

impl Default for RankSettings {
    fn default() -> Self {
        Self {
            method: crate::distributed::Method::Bisection,
            rebalance: crate::distributed::Rebalance::Above(0.1),
        }
    }
}

/// A validated `[[open_boundary]]` (`boundary::open`).
#[derive(Debug, Clone, PartialEq)]
pub struct OpenBoundarySpec {
    /// Inflow or outflow.
    pub kind: schema::OpenBoundaryKind,
    /// The normal's axis.
    pub axis: usize,
    /// `+1` when the normal into the fluid is `+e_axis`, `−1` otherwise.
    pub inward: f64,
    /// Lower corner of the section \[m\]; along `axis`, the plane.
    pub min: Vec<f64>,
    /// Upper corner of the section \[m\]; along `axis`, the plane.
    pub max: Vec<f64>,
    /// Buffer depth in spacings.
    pub layers: u32,
    /// Inflow: mean velocity \[m/s\]; outflow: zeros.
    pub velocity: Vec<f64>,
    /// Inflow: the profile across the section.
    pub profile: crate::boundary::open::Profile,
    /// Inflow: free-surface height \[m\] on the last axis, if given.
    pub level: Option<f64>,
    /// Inflow: the velocity's rise time \[s\] (`(1 − cos(π t/T))/2`), if given.
    pub ramp: Option<f64>,
}

impl OpenBoundarySpec {
    /// The boundary as `boundary::open` uses it (f32, `D` components), at spacing `dx` \[m\].
    pub fn boundary<const D: usize>(&self, dx: f64) -> crate::boundary::open::OpenBoundary<D> {
        use crate::boundary::open::{Flow, OpenBoundary};
        let vector = |v: &[f64]| crate::math::Vector::<D>::from_fn(|k, _| v[k] as crate::math::Real);
        OpenBoundary {
            flow: match self.kind {
                schema::OpenBoundaryKind::Inflow => Flow::Inflow {
                    velocity: vector(&self.velocity),
                    profile: self.profile,
                    level: self.level.map(|l| l as crate::math::Real),
                    ramp: self.ramp,
                },
                schema::OpenBoundaryKind::Outflow => Flow::Outflow,
            },
            axis: self.axis,
            inward: self.inward as crate::math::Real,
            min: vector(&self.min),
            max: vector(&self.max),
            depth: (f64::from(self.layers) * dx) as crate::math::Real,
        }
    }
}

/// A validated `[damping_zone]` (`physics::damping_zone`).
#[derive(Debug, Clone, PartialEq)]
pub struct DampingZoneSpec {
    /// Where the damping starts \[m\], `dimension` entries.
    pub start: Vec<f64>,
    /// Where it reaches full strength \[m\], `dimension` entries, not `start`.
    pub end: Vec<f64>,
    /// `β` \[1/s\], > 0.
    pub strength: f64,
}

impl DampingZoneSpec {
    /// The default `strength` \[1/s\]: DualSPHysics' `redumax`.
    pub const DEFAULT_STRENGTH: f64 = 10.0;

    /// The zone as the `damping_zone` stage uses it (f32, `D` components).
    pub fn zone<const D: usize>(&self) -> crate::physics::damping_zone::DampingZone<D> {
        crate::physics::damping_zone::DampingZone::new(&self.start, &self.end, self.strength)
    }
}

impl Scene {
    /// Whether `effect` is enabled.
    pub fn has(&self, effect: Effect) -> bool {
        self.effects.contains(&effect)
    }

    /// Number of particle layers L of container walls: `ceil(h / dx - 1e-9)`.
    pub fn wall_layers(&self) -> u64 {
        wall_layers(self.smoothing_length, self.spacing)
    }
}

/// The resolved `[solver]` settings other than time (`dt`, `cfl` and `end_time` are
/// [`Scene`] fields).
///
/// For [`SolverKind::Wcsph`] the `corrected`-only fields (`delta`, `max_iterations`,
/// `strict`, `relaxation`, `warm_start`) hold their defaults and are unused.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    /// Pressure scheme.
    pub kind: SolverKind,
    /// Time integrator.
    pub integrator: Integrator,
    /// Density-error tolerance delta of eq. (24), in (0, 0.1].
    pub delta: f64,
    /// Most position-correction iterations per step, in [1, 100000].
    pub max_iterations: u32,
    /// Whether failing to meet `delta` within `max_iterations` is an error.
    pub strict: bool,
    /// Relaxation factor omega of the position correction, in (0, 1].
    pub relaxation: f64,
    /// Whether the velocity solves start warm (`solver::Correction::warm_start`).
    pub warm_start: bool,
    /// What a fluid particle outside the domain does (`solver::escape`).
    pub on_escape: crate::solver::escape::EscapePolicy,
    /// The moment `κ` the pressure force divides by (`model::GradientMoment`).
    pub gradient_moment: crate::model::GradientMoment,
}

impl SolverSettings {
    /// Default `delta` (the solver's, `solver::Correction`).
    pub const DEFAULT_DELTA: f64 = crate::solver::Correction::DEFAULT_DELTA;
    /// Default `max_iterations`.
    pub const DEFAULT_MAX_ITERATIONS: u32 = crate::solver::Correction::DEFAULT_MAX_ITERATIONS;
    /// Default `relaxation`.
    pub const DEFAULT_RELAXATION: f64 = crate::solver::Correction::DEFAULT_RELAXATION;

    /// The default integrator of `kind`: symplectic Euler for `wcsph`, RK3 for `corrected`.
    pub fn default_integrator(kind: SolverKind) -> Integrator {
        match kind {
            SolverKind::Wcsph => Integrator::SymplecticEuler,
            SolverKind::Corrected => Integrator::Rk3,
        }
    }

    /// The default gradient moment of `kind`: measured for `corrected`, whose pressure is the
    /// one that holds the particles as they stand; the lattice's for `wcsph`, whose pressure
    /// is the density's (19) (measured, its resting tank reads 3.4 % low on the wall 0.4 m deep, where
    /// the clamped surface row carries no pressure; docs/method.md).
    pub fn default_gradient_moment(kind: SolverKind) -> crate::model::GradientMoment {
        match kind {
            SolverKind::Wcsph => crate::model::GradientMoment::Lattice,
            SolverKind::Corrected => crate::model::GradientMoment::Measured,
        }
    }

    /// `kind` with every other setting at its default.
    pub fn defaults(kind: SolverKind) -> Self {
        SolverSettings {
            kind,
            integrator: Self::default_integrator(kind),
            delta: Self::DEFAULT_DELTA,
            max_iterations: Self::DEFAULT_MAX_ITERATIONS,
            strict: false,
            relaxation: Self::DEFAULT_RELAXATION,
            warm_start: false,
            on_escape: Default::default(),
            gradient_moment: Self::default_gradient_moment(kind),
        }
    }
}

/// A quantity measured during the run (`[[probe]]`).
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    /// Unique name among probes (`[A-Za-z0-9_-]+`).
    pub name: String,
    /// What is measured.
    pub kind: ProbeKind,
    /// Axis index, `0..dimension` (`"x"` = 0, `"y"` = 1, `"z"` = 2).
    pub axis: usize,
    /// Coordinate \[m\] subtracted from the measurement: a front is reported as the largest
    /// fluid coordinate along `axis` minus `origin`.
    pub origin: f64,
    /// Force probes: index of the measured solid in `Scene::solids`.
    pub solid: Option<usize>,
    /// Pressure, level, velocity and flow-rate probes: where they measure \[m\], `dimension`
    /// entries (a flow rate: the section's centre).
    pub point: Option<Vec<f64>>,
    /// Flow-rate probes: the section's extents \[m\] along the other axes, in increasing order.
    pub size: Option<Vec<f64>>,
    /// Reference data to compare with, if any.
    pub reference: Option<ProbeReference>,
    /// What area a pressure sensor reads (a point unless it has a `diameter`).
    pub sensor: Sensor,
    /// How each recorded sample combines the per-step values.
    pub averaging: Averaging,
}

/// The face of a pressure sensor (`probe.diameter`, `probe.normal`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sensor {
    /// The interpolated value at `point`.
    Point,
    /// The mean over a segment (2D) or disc (3D) of `diameter` \[m\] centred on `point`, in
    /// the plane normal to axis `normal` (`probe::interpolate::face_average`).
    Face {
        /// Diameter \[m\] > 0.
        diameter: f64,
        /// Index of the axis normal to the face.
        normal: usize,
    },
}

/// How a probe's recorded sample combines the values of the steps since the previous one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Averaging {
    /// The value at the sampling time (front, and point probes without `sampling_rate`).
    Instant,
    /// The time-weighted mean over the sampling interval (force probes without
    /// `sampling_rate`: the per-step force of particle methods is noisy).
    Interval,
    /// The time-weighted mean over the last `window` \[s\] = `1/sampling_rate`, as a
    /// transducer of that rate reads.
    Window(f64),
}

/// Normalised reference curves for a [`Probe`] (`[probe.reference]`).
#[derive(Debug, Clone, PartialEq)]
pub struct ProbeReference {
    /// The CSV file as the scene names it: relative to the reference directory, or absolute
    /// (see [`references`]).
    pub file: PathBuf,
    /// Where the file was found, once [`locate_references`] has looked it up.
    pub location: ReferenceLocation,
    /// Series (columns) to compare with; empty means all series of the file.
    pub series: Vec<String>,
    /// Length scale \[m\] > 0 of the normalisation (front: a of Z = x / a and
    /// T = t sqrt(g / a); pressure, level, velocity: H of T = t sqrt(g/H), p/(ρ0 g H), level/H,
    /// u/sqrt(g H)); `None`: compared in seconds and SI units (always for a force).
    pub length: Option<f64>,
    /// Pressure, level and velocity: the file's `(time, value)` columns.
    pub columns: Option<(String, String)>,
    /// `(T0, T1)`, T0 < T1: where the error is measured (front: normalised times; force: \[s\]).
    pub time_range: (f64, f64),
}

impl ProbeReference {
    /// Default `time_range`.
    pub const DEFAULT_TIME_RANGE: (f64, f64) = (1.0, 3.0);
}

/// An axis-aligned box `[min, max]` \[m\], `dimension` entries each.
#[derive(Debug, Clone, PartialEq)]
pub struct Aabb {
    /// Lower corner \[m\].
    pub min: Vec<f64>,
    /// Upper corner \[m\].
    pub max: Vec<f64>,
}

/// A volume of fluid particles (`[[fluid_box]]`): a box, or another shape's [`Volume`].
#[derive(Debug, Clone, PartialEq)]
pub struct FluidBox {
    /// The box filled with fluid \[m\]; for another shape (and a rotated box) the axis-aligned
    /// box that bounds [`FluidBox::volume`].
    pub region: Aabb,
    /// Initial velocity \[m/s\] (zero unless given).
    pub velocity: Vec<f64>,
    /// Initial over-compression c in [0, 1) (0 unless given): the box is filled on a lattice of
    /// spacing [`FluidBox::lattice_spacing`], so the fluid starts near `(1 + c) rho0`.
    pub compression: f64,
    /// Fraction in [0, 1] of the box's particles that get a coincident twin (0 unless given);
    /// see [`FluidBox::has_twin`].
    pub coincident: f64,
    /// Rest density of the box's phase \[kg/m^3\] (`[[fluid_box]] rho0`); `None`: `fluid.rho0`.
    /// `Some` only with [`Effect::Multiphase`].
    pub rho0: Option<f64>,
    /// The volume filled at `t = 0` \[m\]: [`Volume::Aabb`] (equal to `region`) for an
    /// unrotated box, filled as `generate`'s module doc says of fluid boxes; another shape is
    /// filled as a shaped solid (its lattice points inside, at spacing `dx`), with
    /// `compression` and `coincident` zero.
    pub volume: Volume,
}

impl FluidBox {
    /// Lattice spacing \[m\] of the box for scene spacing `dx` \[m\] in `dim` dimensions:
    /// `dx / (1 + c)^(1/dim)`, so a volume holds `1 + c` times the particles of the `dx`
    /// lattice (exactly `dx` when `c = 0`).
    pub fn lattice_spacing(&self, dx: f64, dim: usize) -> f64 {
        if self.compression == 0.0 {
            dx
        } else {
            dx / (1.0 + self.compression).powf(1.0 / dim as f64)
        }
    }

    /// Whether lattice particle `k` of the box (axis 0 fastest) gets a coincident twin:
    /// `floor((k + 1) f) > floor(k f)`, which spreads `floor(n f)` twins evenly over `n`
    /// particles (every particle when `f = 1`, none when `f = 0`).
    pub fn has_twin(&self, k: u64) -> bool {
        let f = self.coincident;
        ((k + 1) as f64 * f).floor() > (k as f64 * f).floor()
    }

    /// Number of twins among `n` lattice particles: `floor(n f)`.
    pub fn twins(&self, n: u64) -> u64 {
        (n as f64 * self.coincident).floor() as u64
    }
}

/// A solid body made of boundary particles.
#[derive(Debug, Clone, PartialEq)]
pub struct Solid {
    /// Unique name (`[A-Za-z0-9_-]+`).
    pub name: String,
    /// The shape the scene names.
    pub shape: SolidShape,
    /// The filled box, or the inside of the container \[m\]; for the other shapes (and a
    /// rotated box) the axis-aligned box that bounds [`Solid::volume`].
    pub region: Aabb,
    /// Container without lid (always `false` for [`SolidShape::Box`]).
    pub open_top: bool,
    /// Prescribed rigid translation (`motion = {...}`) of its kind; `None` for a fixed solid.
    pub motion: Option<Motion>,
    /// A floating body the fluid moves (`floating = {...}`); `None` unless given. Exclusive with
    /// `motion`.
    pub floating: Option<floating::Floating>,
    /// The volume the solid fills at `t = 0` \[m\]: [`Volume::Aabb`] for an unrotated box and
    /// for a container's inside (which its walls surround), else the shape's own volume.
    pub volume: Volume,
}

/// Reads, overrides, deserializes and validates the scene file at `path`.
///
/// `sets` are `KEY=VALUE` overrides (see [`apply_overrides`]). Probe reference files are
/// left as the scene names them ([`locate_references`] looks them up). Errors: the
/// file is missing, a directory or unreadable ([`SceneError::Io`]); larger than
/// [`MAX_SCENE_BYTES`] ([`SceneError::TooLarge`], found before reading); not UTF-8,
/// bad TOML, schema mismatch or invalid values ([`SceneError::Invalid`]).
pub fn load_scene(path: &Path, sets: &[String]) -> Result<Scene, SceneError> {
    let bytes = read::read_scene_bytes(path)?;
    let origin = path.display().to_string();
    let text = match String::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) => {
            let bytes = e.as_bytes();
            let good = e.utf8_error().valid_up_to();
            let prefix = bytes.get(..good).unwrap_or_default();
            let prefix = std::str::from_utf8(prefix).unwrap_or_default();
            let (line, column) = line_col(prefix, prefix.len());
            return Err(SceneError::Invalid {
                origin,
                problems: vec![Problem {
                    key: String::new(),
                    location: Location::Line { line, column },
                    reason: format!("file is not valid UTF-8 (bad byte at offset {good})"),
                }],
            });
        }
    };
    let dir = path.parent().unwrap_or(Path::new(""));
    parse_scene_in(&text, &origin, sets, dir)
}

/// Parses scene `text` (named `origin` in messages), applies the `sets`
/// overrides, deserializes and validates it. Probe reference files are left as the scene
/// names them ([`locate_references`] looks them up); mesh files are read relative to the
/// current directory.
pub fn parse_scene(text: &str, origin: &str, sets: &[String]) -> Result<Scene, SceneError> {
    parse_scene_in(text, origin, sets, Path::new(""))
}

/// [`parse_scene`] for a scene whose file lies in `dir`: a mesh solid's relative `file` is
/// taken from there ([`parse_scene`]: from the current directory).
pub fn parse_scene_in(text: &str, origin: &str, sets: &[String], dir: &Path) -> Result<Scene, SceneError> {
    let invalid = |problems: Vec<Problem>| SceneError::Invalid {
        origin: origin.to_string(),
        problems,
    };
    let original = SpanIndex::build(text);
    let mut table: toml::Table = match text.parse() {
        Ok(t) => t,
        Err(e) => {
            let here = |path: &KeyPath| locate(path, text, &original, &[]);
            return Err(invalid(vec![toml_problem(&e, text, &original, &here, true)]));
        }
    };
    let override_paths = match apply_overrides(&mut table, sets) {
        Ok(()) => overrides::override_paths(sets),
        Err(e) => return Err(invalid(e.problems().to_vec())),
    };
    let locate = |path: &KeyPath| locate(path, text, &original, &override_paths);

    let file: SceneFile = if sets.is_empty() {
        toml::from_str(text).map_err(|e| invalid(vec![toml_problem(&e, text, &original, &locate, true)]))?
    } else {
        // Deserialize the overridden table from its re-serialized text, map
        // error spans to key paths there, and key paths back to the file.
        let canonical = toml::to_string(&table).map_err(|e| {
            invalid(vec![Problem {
                key: String::new(),
                location: Location::Unknown,
                reason: format!("cannot re-serialize the overridden scene: {e}"),
            }])
        })?;
        let index = SpanIndex::build(&canonical);
        toml::from_str(&canonical)
            .map_err(|e| invalid(vec![toml_problem(&e, &canonical, &index, &locate, false)]))?
    };
    validate::validate_raw(&file, dir).map_err(|raw| {
        invalid(
            raw.into_iter()
                .map(|r| Problem {
                    key: r.path.to_string(),
                    location: locate(&r.path),
                    reason: r.reason,
                })
                .collect(),
        )
    })
}
