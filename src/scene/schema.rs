//! The scene file as deserialized from TOML, before validation.
//!
//! Every struct denies unknown fields, so a misspelt key is an error that
//! names the key. Values here are unchecked; see [`super::validate()`] for the
//! rules and [`super::Scene`] for the resolved, validated form.

use crate::model::pair_terms::{PairTerm, with_pair_term_keys};
use serde::Deserialize;

#[path = "schema_motion.rs"]
mod motion;
pub use motion::{DampingZoneFile, MotionFile, MotionKind, SeaFile, SeaKind};

#[path = "schema_floating.rs"]
mod floating;
pub use floating::{ContactFile, FloatingFile, HingeFile, MooringFile};

#[path = "schema_periodic.rs"]
mod periodic;
pub use periodic::{AxisName, PeriodicFile};

#[path = "schema_ranks.rs"]
mod ranks;
pub use ranks::{DecompositionName, RanksFile, RebalanceFile};

#[path = "schema_open.rs"]
mod open;
pub use open::{OpenBoundaryFile, OpenBoundaryKind};

#[path = "schema_shape.rs"]
mod shape;
pub use shape::{AxisFile, NumberOrVector, SolidShape};

/// A physical effect switched on in a scene (`effects = [...]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Effect {
    /// Body force `fluid.gravity` \[m/s^2\], optionally ramped in over `fluid.gravity_ramp` \[s\].
    Gravity,
    /// An optional pair term of the force stage (`kernels/pair_terms.table`), named as the
    /// term, with its coefficient under the same key in `[fluid]`: `viscosity` (eq. 17, dynamic
    /// viscosity \[Pa s\]), `artificial_viscosity` ([M92], alpha).
    Pair(PairTerm),
    /// Coriolis and centrifugal forces of a frame rotating at `fluid.angular_velocity`
    /// \[rad/s\] about the axis through `fluid.rotation_centre` \[m\]
    /// (`physics::rotating_frame`).
    RotatingFrame,
    /// Surface tension `fluid.surface_tension` \[N/m\] between fluid particles, by the model
    /// `fluid.surface_tension_model`: the capillary stress of the surface layers
    /// (`physics::surface_stress`, the default) or [AAT13]'s cohesion and curvature forces
    /// (`physics::surface_tension`).
    SurfaceTension,
    /// Fluid phases of different rest densities: a `[[fluid_box]]` may set its own `rho0`
    /// \[kg/m^3\]; density, equation of state, pressure force and position correction use each
    /// particle's own rest density (`physics::multiphase`, Hu & Adams 2006).
    Multiphase,
    /// The continuity equation with Fourtakas et al. (2019)'s density diffusion
    /// `fluid.density_diffusion` (δ, dimensionless) in place of the summation (18): density is
    /// integrated in time (`physics::density_diffusion`). `wcsph` only.
    DensityDiffusion,
}

impl Effect {
    /// Every effect, in the order `sph plan` and error messages list them.
    pub fn all() -> Vec<Effect> {
        let mut all = vec![Effect::Gravity];
        all.extend(PairTerm::ALL.map(Effect::Pair));
        all.extend([
            Effect::RotatingFrame,
            Effect::SurfaceTension,
            Effect::Multiphase,
            Effect::DensityDiffusion,
        ]);
        all
    }

    /// The name used in scene files (`"gravity"`, `"viscosity"`).
    pub fn name(self) -> &'static str {
        match self {
            Effect::Gravity => "gravity",
            Effect::Pair(term) => term.name(),
            Effect::RotatingFrame => "rotating_frame",
            Effect::SurfaceTension => "surface_tension",
            Effect::Multiphase => "multiphase",
            Effect::DensityDiffusion => "density_diffusion",
        }
    }

    /// The effect named `name` in a scene file.
    pub fn from_name(name: &str) -> Option<Effect> {
        Effect::all().into_iter().find(|e| e.name() == name)
    }
}

impl<'de> Deserialize<'de> for Effect {
    /// An effect's name; anything else is serde's `unknown variant` error listing the names.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let name = String::deserialize(deserializer)?;
        static NAMES: std::sync::OnceLock<Vec<&'static str>> = std::sync::OnceLock::new();
        Effect::from_name(&name).ok_or_else(|| {
            let names = NAMES.get_or_init(|| Effect::all().into_iter().map(Effect::name).collect());
            serde::de::Error::unknown_variant(&name, names)
        })
    }
}

/// The pressure scheme (`solver.kind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolverKind {
    /// Weakly compressible SPH with a stiff equation of state.
    Wcsph,
    /// Incompressible SPH with iterative position correction until the density error is
    /// below `solver.delta` (eqs. 23–24).
    Corrected,
}

impl SolverKind {
    /// The name used in scene files (`"wcsph"`, `"corrected"`).
    pub fn name(self) -> &'static str {
        match self {
            SolverKind::Wcsph => "wcsph",
            SolverKind::Corrected => "corrected",
        }
    }
}

/// The time integrator (`solver.integrator`): the solver's own type.
pub use crate::solver::Integrator;

/// What a `[[probe]]` measures (`probe.kind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProbeKind {
    /// The fluid front: the largest fluid coordinate along `axis`, minus `origin` \[m\].
    Front,
    /// The force of the fluid on the solid `solid` along `axis` \[N\] (\[N/m\] in 2D).
    Force,
    /// The fluid pressure at `point` \[Pa\] (on a solid's surface or inside the fluid), by a
    /// Shepard-normalised SPH interpolation (`probe::interpolate`).
    Pressure,
    /// A wave gauge: the height \[m\] of the free surface above `point` along `axis` (default
    /// the vertical, the last axis), where the kernel-summed particle volume falls below 1/2.
    Level,
    /// The fluid velocity's component along `axis` at `point` \[m/s\].
    Velocity,
    /// The volume flux along `axis` through the segment (2D, \[m²/s\]) or rectangle (3D,
    /// \[m³/s\]) centred on `point`, of extents `size` along the other axes.
    FlowRate,
    /// The moment about `point` of the fluid's force on the solid `solid`, its component along
    /// `axis` (default `"z"`) \[N m\]; in 2D only the out-of-plane moment, `axis = "z"`
    /// \[N m/m\]. Averaged over each sampling interval as a force.
    Moment,
}

impl ProbeKind {
    /// The name used in scene files (`"front"`).
    pub fn name(self) -> &'static str {
        match self {
            ProbeKind::Front => "front",
            ProbeKind::Force => "force",
            ProbeKind::Pressure => "pressure",
            ProbeKind::Level => "level",
            ProbeKind::Velocity => "velocity",
            ProbeKind::FlowRate => "flow_rate",
            ProbeKind::Moment => "moment",
        }
    }

    /// Whether it reads the loads on a solid (`Simulation::solid_forces`, `solid_moments`)
    /// rather than the particle fields.
    pub fn reads_solids(self) -> bool {
        matches!(self, ProbeKind::Force | ProbeKind::Moment)
    }
}

/// The whole scene file (top-level table).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Optional human-readable scene name.
    pub name: Option<String>,
    /// Spatial dimension, 2 or 3 (signed so that bad values reach validation).
    pub dimension: i64,
    /// Enabled effects; absent means none. Duplicates are an error.
    #[serde(default)]
    pub effects: Vec<Effect>,
    /// The simulation domain \[m\].
    pub domain: BoxFile,
    /// Particle resolution.
    pub particles: ParticlesFile,
    /// Fluid material.
    pub fluid: FluidFile,
    /// Initial fluid regions (`[[fluid_box]]`); at least one is required.
    #[serde(default)]
    pub fluid_box: Vec<FluidBoxFile>,
    /// Solid bodies (`[[solid]]`); zero or more.
    #[serde(default)]
    pub solid: Vec<SolidFile>,
    /// Time integration.
    pub solver: SolverFile,
    /// Output control; optional.
    pub output: Option<OutputFile>,
    /// Measurements taken during the run (`[[probe]]`); zero or more.
    #[serde(default)]
    pub probe: Vec<ProbeFile>,
    /// A zone where the fluid's velocity is relaxed towards zero (`[damping_zone]`, a wave
    /// flume's absorber); absent: none, and the step pays nothing.
    pub damping_zone: Option<DampingZoneFile>,
    /// Periodic boundaries along some axes (`[periodic]`); absent: none.
    pub periodic: Option<PeriodicFile>,
    /// Inflow and outflow planes (`[[open_boundary]]`); zero or more.
    #[serde(default)]
    pub open_boundary: Vec<OpenBoundaryFile>,
    /// How a run across ranks cuts the domain (`[ranks]`); absent: bisection, rebalanced above
    /// an imbalance of 0.1.
    pub ranks: Option<RanksFile>,
}

/// An axis-aligned box `[min, max]` \[m\].
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxFile {
    /// Lower corner \[m\], `dimension` entries.
    pub min: Vec<f64>,
    /// Upper corner \[m\], `dimension` entries, strictly greater than `min`.
    pub max: Vec<f64>,
}

/// `[particles]`: resolution and kernel size.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticlesFile {
    /// Initial particle spacing dx \[m\], > 0.
    pub spacing: f64,
    /// h / dx, in [1, 5]; exactly one of this and `smoothing_length`.
    pub smoothing_ratio: Option<f64>,
    /// Kernel support radius h \[m\]; exactly one of this and `smoothing_ratio`.
    pub smoothing_length: Option<f64>,
}

with_pair_term_keys! {
/// `[fluid]`: material constants and body force; one key per optional pair term of the force
/// stage (`kernels/pair_terms.table`), its coefficient, required iff its effect is on.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidFile {
    /// Rest density \[kg/m^3\], > 0.
    pub rho0: f64,
    /// Numerical speed of sound \[m/s\], > 0.
    pub sound_speed: f64,
    /// Gravitational acceleration \[m/s^2\]; required iff the `gravity` effect is on.
    pub gravity: Option<Vec<f64>>,
    /// Time over which gravity is ramped in \[s\], >= 0; only with the `gravity` effect.
    pub gravity_ramp: Option<f64>,
    /// Angular velocity of the frame \[rad/s\]; required iff the `rotating_frame` effect is on.
    /// 3D: 3 entries. 2D: a number (rotation about the out-of-plane axis) or 2 entries (an axis
    /// in the plane: a vertical slice through the axis of a rotating tank, see
    /// `physics::rotating_frame` for what the slice drops).
    pub angular_velocity: Option<AngularVelocityFile>,
    /// A point on the rotation axis \[m\], `dimension` entries; default the origin; only with the
    /// `rotating_frame` effect.
    pub rotation_centre: Option<Vec<f64>>,
    /// Surface tension σ \[N/m\] (2D: per unit depth), > 0; required iff the `surface_tension`
    /// effect is on.
    pub surface_tension: Option<f64>,
    /// The surface-tension model, `"surface_stress"` (default) or `"akinci"`; only with the
    /// `surface_tension` effect.
    pub surface_tension_model: Option<crate::model::SurfaceTensionModel>,
    /// The factor on the artificial viscosity's α between fluid and solid particles, >= 0
    /// (default 1, DualSPHysics' `ViscoBoundFactor`); only with the `artificial_viscosity` effect.
    pub artificial_viscosity_wall_factor: Option<f64>,
    /// The fluid's initial state, `"uniform"` (default: `ρ0`, no pressure) or `"hydrostatic"`
    /// (the pressure of a resting column, `scene::initial_state`); hydrostatic needs the
    /// `gravity` effect without a ramp.
    pub initial_state: Option<crate::scene::initial_state::InitialState>,
    /// δ of the density diffusion (dimensionless, >= 0, typically 0.1); required iff the
    /// `density_diffusion` effect is on.
    pub density_diffusion: Option<f64>,
}
}

/// `fluid.angular_velocity`: a number (2D, about the out-of-plane axis) or a vector.
#[derive(Debug, Clone, PartialEq)]
pub enum AngularVelocityFile {
    /// `Ω` \[rad/s\] about the out-of-plane axis (2D only).
    Scalar(f64),
    /// `Ω` \[rad/s\] as a vector: 3 entries in 3D, 2 (in the plane) in 2D.
    Vector(Vec<f64>),
}

impl<'de> Deserialize<'de> for AngularVelocityFile {
    /// A number or an array of numbers; anything else is an error saying so (an untagged enum
    /// would only say that no variant matched).
    fn deserialize<De: serde::Deserializer<'de>>(deserializer: De) -> Result<Self, De::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = AngularVelocityFile;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number [rad/s] (2D: about the out-of-plane axis) or an array of numbers")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Self::Value, E> {
                Ok(AngularVelocityFile::Scalar(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Self::Value, E> {
                Ok(AngularVelocityFile::Scalar(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Self::Value, E> {
                Ok(AngularVelocityFile::Scalar(v as f64))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> Result<Self::Value, A::Error> {
                Vec::<f64>::deserialize(serde::de::value::SeqAccessDeserializer::new(seq))
                    .map(AngularVelocityFile::Vector)
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// `[[fluid_box]]`: a volume of fluid particles on the lattice, a box unless `shape` says
/// otherwise; the shape keys are those of `[[solid]]` ([`SolidFile`]).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidBoxFile {
    /// `"box"` (default), `"cylinder"`, `"sphere"` or `"mesh"` (not `"container"`).
    pub shape: Option<SolidShape>,
    /// Box: lower corner \[m\]; required for a box.
    pub min: Option<Vec<f64>>,
    /// Box: upper corner \[m\]; required for a box.
    pub max: Option<Vec<f64>>,
    /// Initial velocity \[m/s\]; default zero.
    pub velocity: Option<Vec<f64>>,
    /// Initial over-compression c (dimensionless), in [0, 1); default 0. The box is filled on a
    /// lattice of spacing `dx / (1 + c)^(1/D)`, so it holds about `1 + c` times the particles,
    /// each with the mass of an uncompressed one: the fluid starts near `(1 + c) rho0` and the
    /// released pressure tests the solver's start. Below 1 because a doubled density is far
    /// beyond any compression a solver should meet.
    pub compression: Option<f64>,
    /// Fraction f in [0, 1] of the box's particles that get a twin at exactly the same position
    /// with the same velocity and mass; default 0. Particle k of the box (lattice order, x
    /// fastest) gets one iff `floor((k + 1) f) > floor(k f)`, so `floor(n f)` twins spread evenly
    /// over the box. Coincident particles have no pair direction: a test of the solvers' guard
    /// at `r = 0` (`grid::coincident_offset`).
    pub coincident: Option<f64>,
    /// Rest density of this box's fluid phase \[kg/m^3\], finite and > 0; default `fluid.rho0`.
    /// Only with the `multiphase` effect.
    pub rho0: Option<f64>,
    /// Box and mesh: rotation in degrees, as [`SolidFile::rotation`].
    pub rotation: Option<NumberOrVector>,
    /// Cylinder and sphere: centre \[m\], as [`SolidFile::centre`].
    pub centre: Option<Vec<f64>>,
    /// Cylinder and sphere: radius \[m\], > 0.
    pub radius: Option<f64>,
    /// 3D cylinder: length along its axis \[m\], > 0.
    pub length: Option<f64>,
    /// 3D cylinder: axis direction, as [`SolidFile::axis`].
    pub axis: Option<AxisFile>,
    /// Mesh: `.stl` or `.obj` file, relative to the scene file's directory (or absolute).
    pub file: Option<String>,
    /// Mesh: scale from file units to m, as [`SolidFile::scale`].
    pub scale: Option<NumberOrVector>,
    /// Mesh: translation \[m\] after scaling and rotating, 3 entries; default zero.
    pub translation: Option<Vec<f64>>,
}

/// `[[solid]]`: a rigid boundary body made of particles.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolidFile {
    /// Unique non-empty name of `[A-Za-z0-9_-]` characters.
    pub name: String,
    /// Box, container, cylinder, sphere or mesh.
    pub shape: SolidShape,
    /// Box and container: lower corner \[m\] (of the filled box, or of the container's inside).
    pub min: Option<Vec<f64>>,
    /// Box and container: upper corner \[m\] (of the filled box, or of the container's inside).
    pub max: Option<Vec<f64>>,
    /// Container only: no lid when true (default true). An error for the other shapes.
    pub open_top: Option<bool>,
    /// Prescribed rigid translation; absent means the solid is fixed (and costs nothing).
    pub motion: Option<MotionFile>,
    /// A floating body the fluid moves (`schema_floating`); exclusive with `motion`.
    pub floating: Option<FloatingFile>,
    /// Box and mesh: rotation in degrees, 2D a number (counter-clockwise), 3D `[α, β, γ]` about
    /// the fixed x, y, z axes applied in that order (`geometry` module doc). A box turns about
    /// its centre, a mesh about its file origin (before `translation`). Default none.
    pub rotation: Option<NumberOrVector>,
    /// Cylinder and sphere: centre \[m\], `dimension` entries (a 3D cylinder: the middle of its
    /// axis).
    pub centre: Option<Vec<f64>>,
    /// Cylinder and sphere: radius \[m\], > 0.
    pub radius: Option<f64>,
    /// 3D cylinder: length along its axis \[m\], > 0.
    pub length: Option<f64>,
    /// 3D cylinder: axis direction, `"x"`, `"y"`, `"z"` or a vector of 3 entries (not zero).
    pub axis: Option<AxisFile>,
    /// Mesh: path of an `.stl` (binary or ASCII) or `.obj` file, relative to the scene file's
    /// directory (or absolute).
    pub file: Option<String>,
    /// Mesh: scale from file units to m, a number or 3 per-axis factors, each > 0; default 1.
    pub scale: Option<NumberOrVector>,
    /// Mesh: translation \[m\] applied after scaling and rotating, 3 entries; default zero.
    pub translation: Option<Vec<f64>>,
}

/// `[solver]`: time integration.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverFile {
    /// Pressure scheme.
    pub kind: SolverKind,
    /// Time integrator; default `symplectic_euler` for `wcsph`, `rk3` for `corrected`.
    pub integrator: Option<Integrator>,
    /// `corrected` only: density-error tolerance of eq. (24), in (0, 0.1]; default 1e-4.
    pub delta: Option<f64>,
    /// `corrected` only: most correction iterations per step, in [1, 100000]; default 200
    /// (signed so that bad values reach validation).
    pub max_iterations: Option<i64>,
    /// `corrected` only: whether failing to meet `delta` within `max_iterations` is an error;
    /// default false.
    pub strict: Option<bool>,
    /// `corrected` only: relaxation factor omega of the position correction, in (0, 1];
    /// default 0.5.
    pub relaxation: Option<f64>,
    /// `corrected` only: whether each velocity solve starts from the increments of the same
    /// integrator stage's solve at the last step; default false (`solver::Correction`).
    pub warm_start: Option<bool>,
    /// The first moment of the spiky gradient the pressure force divides by: `lattice` (the
    /// initial lattice's, fixed) or `measured` (on the particles, every integrator stage);
    /// default `measured` for `corrected`, `lattice` for `wcsph` (`model::GradientMoment`).
    pub gradient_moment: Option<crate::model::GradientMoment>,
    /// Fixed time step \[s\] > 0; absent means adaptive.
    pub dt: Option<f64>,
    /// CFL number in (0, 1]; default 0.2.
    pub cfl: Option<f64>,
    /// Simulated time \[s\] > 0, and >= `dt` when `dt` is given.
    pub end_time: f64,
    /// What a fluid particle outside the domain does: `remove` (default: dropped, counted,
    /// the run goes on) or `stop` (the run ends naming it; strict conservation).
    pub on_escape: Option<crate::solver::escape::EscapePolicy>,
}

/// `[output]`: what to write and how often.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputFile {
    /// Time between particle frames \[s\] > 0; default `end_time / 50`.
    pub interval: Option<f64>,
    /// Whether to write particle frames; default true.
    pub frames: Option<bool>,
    /// Whether to write the free surface (eq. (25)) at every frame time as
    /// `surface/surface_NNNNN.vtp` (triangles in 3D, line segments in 2D), listed in
    /// `surface.pvd`; default false.
    pub surface: Option<bool>,
    /// Support radius R of eq. (25) for that surface, in particle spacings, > 0; default
    /// [`crate::surface::DEFAULT_RADIUS`] (independent of `smoothing_ratio`).
    pub surface_radius: Option<f64>,
    /// How the arrays of frames and surfaces are stored: `"zlib"` (compressed, the default),
    /// `"base64"` (the encoding vtkio and splashsurf read) or `"raw"` (uncompressed binary).
    pub encoding: Option<crate::output::Encoding>,
    /// Whether frames hold only the fluid particles (their `id`s unchanged); default false.
    pub fluid_only: Option<bool>,
}

/// `[[probe]]`: a quantity measured during the run.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeFile {
    /// Unique (among probes) non-empty name of `[A-Za-z0-9_-]` characters.
    pub name: String,
    /// What is measured.
    pub kind: ProbeKind,
    /// `"x"`, `"y"` or `"z"`, below `dimension`; default `"x"` (a level gauge: the last axis,
    /// the vertical). Not for a pressure probe. A moment: default `"z"`, the only one in 2D.
    pub axis: Option<String>,
    /// Where a pressure, level, velocity or flow-rate probe measures \[m\], `dimension` entries
    /// inside the domain (a level gauge: the foot of its line, e.g. on the floor; a flow rate:
    /// the section's centre). A moment (required there): the point it is taken about, anywhere.
    pub point: Option<Vec<f64>>,
    /// A flow-rate section's extents \[m\] along the axes other than `axis`, in increasing order
    /// (2D: one entry, 3D: two), each > 0; required for a flow rate, only there.
    pub size: Option<Vec<f64>>,
    /// Coordinate subtracted from the measurement \[m\], finite; default 0 (front only).
    pub origin: Option<f64>,
    /// Name of the solid whose force (or its moment) is measured (force and moment only,
    /// required there).
    pub solid: Option<String>,
    /// Reference data to compare with; optional.
    pub reference: Option<ProbeReferenceFile>,
    /// Pressure only: the sensor's diameter \[m\] > 0; the reading is the mean over a segment
    /// (2D) or disc (3D) of that diameter centred on `point`, normal to `normal`.
    pub diameter: Option<f64>,
    /// Pressure only, required with `diameter`: the axis (`"x"`, `"y"` or `"z"`) normal to the
    /// sensor's face.
    pub normal: Option<String>,
    /// A transducer's sampling rate \[Hz\] > 0 (not for a front): each sample is the mean of the
    /// per-step values over the last `1/sampling_rate` seconds.
    pub sampling_rate: Option<f64>,
}

/// `[probe.reference]`: a CSV of normalised reference curves.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbeReferenceFile {
    /// Path of the CSV file, non-empty; relative to the scene file's directory (checked when read).
    pub file: String,
    /// Series (columns) of the file to compare with; absent or empty means all.
    pub series: Option<Vec<String>>,
    /// Front: length scale a \[m\] > 0 for Z = x / a and T = t sqrt(g / a) (required there;
    /// not allowed for a force). Pressure, level, velocity (optional): the length H of
    /// T = t sqrt(g/H), p/(ρ0 g H), level/H and u/sqrt(g H); absent: seconds and SI values.
    pub length: Option<f64>,
    /// `[T0, T1]`, finite, T0 < T1: where the error is measured; front: normalised times,
    /// default `[1.0, 3.0]`; force: times \[s\], default `[0, end_time]`; pressure, level and
    /// velocity: in the reference's time unit, default all times.
    pub time_range: Option<Vec<f64>>,
    /// Pressure, level and velocity (required there): the file's time and value columns,
    /// `[time, value]`.
    pub columns: Option<Vec<String>>,
}
