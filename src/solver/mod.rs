//! The solver: owns time and the order of stages; it never loops over particles itself.
//!
//! A [`Simulation`] holds the particle fields, the backend, the plan and the clock. The step
//! driver (`step.rs`) walks the plan and calls one backend method per stage.

pub mod anderson;
pub mod checkpoint;
pub mod escape;
pub mod plan;
pub mod stage;
pub mod step;
pub mod timestep;

use crate::backend::cpu::CpuBackend;
use crate::backend::params::StepParams;
use crate::backend::{Backend, BackendError, BackendKind, SurfaceTensionModel};
use crate::boundary::keep_out::KeepOutBox;
use crate::boundary::motion::{SolidKinematics, SolidReference, Sway};
use crate::fields::{FLUID, Fields};
use crate::math::{Real, Vector, sum_in_order};
use crate::physics::density::DensityWeight;
use crate::physics::gravity::gravity_at;
use crate::physics::lattice::{
    correction_stiffness, lattice_gradient_moment, lattice_laplacian_moment, lattice_mass,
    lattice_spiky_scale,
};
use crate::physics::multiphase::Phases;
use crate::physics::surface_stress::calibrated_stress;
use crate::physics::surface_tension::gamma_for_surface_tension;
use crate::smoothing::{Smoothing, UnsupportedDimension};
use stage::Stage;
use timestep::TimeStepLimit;

/// The time integrator (scene `solver.integrator`, in `snake_case`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Integrator {
    /// Semi-implicit (symplectic) Euler, one force evaluation per step.
    #[default]
    SymplecticEuler,
    /// Third-order strong-stability-preserving Runge–Kutta (Shu & Osher 1988), three stages;
    /// the paper's integrator (PAPER.md note 8).
    Rk3,
}

impl Integrator {
    /// The name used in scene files (`"symplectic_euler"`, `"rk3"`).
    pub fn name(self) -> &'static str {
        match self {
            Integrator::SymplecticEuler => "symplectic_euler",
            Integrator::Rk3 => "rk3",
        }
    }

    /// Shu–Osher stage coefficients `(a, b, τ/dt, t/dt)`: the stage state is
    /// `a y^n + b (y + dt L(y))`, it lies at time `t^n + τ` and the stage starts at `t^n + t·dt`.
    pub fn stages(self) -> &'static [(f32, f32, f64, f64)] {
        match self {
            Integrator::SymplecticEuler => &[(0.0, 1.0, 1.0, 0.0)],
            Integrator::Rk3 => &[
                (0.0, 1.0, 1.0, 0.0),
                (0.75, 0.25, 0.5, 1.0),
                (1.0 / 3.0, 2.0 / 3.0, 1.0, 0.5),
            ],
        }
    }

    /// Weight of stage `k`'s forces in the step: the step's impulse is `dt Σ_k w_k F_k`
    /// (SSP-RK3: 1/6, 1/6, 2/3).
    pub fn force_weights(self) -> &'static [f64] {
        match self {
            Integrator::SymplecticEuler => &[1.0],
            Integrator::Rk3 => &[1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0],
        }
    }

    /// Weight of stage `k`'s own state change in the step's final state (SSP-RK3: the change
    /// made to `y1` reaches `y^{n+1}` times 1/6, to `y2` times 2/3, to `y^{n+1}` times 1).
    pub fn correction_weights(self) -> &'static [f64] {
        match self {
            Integrator::SymplecticEuler => &[1.0],
            Integrator::Rk3 => &[1.0 / 6.0, 2.0 / 3.0, 1.0],
        }
    }
}

/// Settings of the position correction, eqs. (23)–(24) (scene `[solver]`, `kind = "corrected"`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Correction {
    /// Tolerance `δ` of (24) on the compression `max(ρ − ρ0, 0)/ρ0` (and, for particles that
    /// carry pressure, on the expansion: `physics::correction::residual`).
    pub delta: f64,
    /// Iteration cap per integrator stage.
    pub max_iterations: u32,
    /// Stop with `StepError::Unconverged` when the cap is hit (else warn and count).
    pub strict: bool,
    /// Relaxation `ω` in (0, 1] of the step scale (`physics::lattice::correction_stiffness`).
    pub relaxation: f64,
}

impl Correction {
    /// Default `delta`.
    pub const DEFAULT_DELTA: f64 = 1e-4;
    /// Default `max_iterations`.
    pub const DEFAULT_MAX_ITERATIONS: u32 = 200;
    /// Default `relaxation`.
    pub const DEFAULT_RELAXATION: f64 = 0.5;
}

impl Default for Correction {
    fn default() -> Self {
        Self {
            delta: Self::DEFAULT_DELTA,
            max_iterations: Self::DEFAULT_MAX_ITERATIONS,
            strict: false,
            relaxation: Self::DEFAULT_RELAXATION,
        }
    }
}

/// Physical and numerical settings of a run, resolved from a scene (SI units).
#[derive(Clone, Debug, PartialEq)]
pub struct SimConfig<const D: usize> {
    /// Initial particle spacing `dx` [m].
    pub spacing: f64,
    /// Kernel support radius `h` [m].
    pub h: f64,
    /// Rest density `ρ0` [kg/m³].
    pub rho0: f64,
    /// Sound speed `C` [m/s] of eq. (19).
    pub sound_speed: f64,
    /// Dynamic viscosity `μ` [Pa s]; `None` when the scene has no viscosity effect.
    pub viscosity: Option<f64>,
    /// Artificial-viscosity coefficient `α`; `None` when the scene has no such effect.
    pub artificial_viscosity: Option<f64>,
    /// Gravity `g` [m/s²]; `None` when the scene has no gravity effect.
    pub gravity: Option<Vector<D>>,
    /// Time over which gravity is ramped in [s] (0 = none).
    pub gravity_ramp: f64,
    /// Angular velocity `Ω` [rad/s] of the rotating frame (3 components, also in 2D:
    /// `physics::rotating_frame`); `None` when the scene has no `rotating_frame` effect.
    pub angular_velocity: Option<[f64; 3]>,
    /// A point `x_c` [m] on the rotation axis (unused without a rotating frame).
    pub rotation_centre: Vector<D>,
    /// Surface tension `σ` and its model; `None` when the scene has no `surface_tension` effect.
    pub surface_tension: Option<SurfaceTension>,
    /// Fixed time step [s], or `None` for adaptive.
    pub dt: Option<f64>,
    /// CFL number of the adaptive step.
    pub cfl: f64,
    /// Lower corner of the domain [m].
    pub domain_min: Vector<D>,
    /// Upper corner of the domain [m].
    pub domain_max: Vector<D>,
    /// Time integrator.
    pub integrator: Integrator,
    /// The position correction (23)–(24); `None` for the weakly compressible solver.
    pub correction: Option<Correction>,
    /// What a step does with a fluid particle outside the domain ([`escape`]).
    pub on_escape: escape::EscapePolicy,
}

/// Errors that stop a step. Each names the step, the time, the particle and the quantity.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StepError {
    /// A field became NaN or infinite.
    #[error("step {step}, t = {time:.6} s: particle {particle} has a non-finite {quantity}")]
    NonFinite {
        /// Step number.
        step: u64,
        /// Simulated time [s].
        time: f64,
        /// Particle id (index in the initial layout).
        particle: u32,
        /// Name of the field.
        quantity: &'static str,
    },
    /// A fluid particle left the domain box.
    #[error("step {step}, t = {time:.6} s: fluid particle {particle} left the domain at {position:?} m")]
    Escaped {
        /// Step number.
        step: u64,
        /// Simulated time [s].
        time: f64,
        /// Particle id (index in the initial layout).
        particle: u32,
        /// Its position [m].
        position: Vec<f64>,
    },
    /// The position correction hit its iteration cap in a `strict` scene.
    #[error(
        "step {step}, t = {time:.6} s, stage {stage}: the position correction did not reach delta = \
         {delta:e} in {iterations} iterations (residual {residual:.3e}); raise \
         solver.max_iterations, lower the time step, or drop solver.strict"
    )]
    Unconverged {
        /// Step number.
        step: u64,
        /// Simulated time [s].
        time: f64,
        /// Integrator stage (1-based).
        stage: usize,
        /// Iterations done.
        iterations: u32,
        /// Residual left (`physics::correction::residual`: compression, and expansion where
        /// pressure remains).
        residual: f64,
        /// The tolerance.
        delta: f64,
    },
    /// The chosen time step cannot advance the run: zero, not finite, or so small that the
    /// time does not change in f64 (`t + dt == t`, or `end + dt == end` for a step not cut to
    /// land on the end time, which the run could then never reach). Without this stop such a
    /// run loops for ever. `sph check` refuses the scene values that lead here in advance
    /// (`scene::progress`); this catches what only the flow decides.
    #[error(
        "step {step}, t = {time:e} s: the time step dt = {dt:e} s ({limit} limit) does not advance \
         the time in f64 (end time {end_time:e} s), so the run cannot finish; check solver.dt, \
         solver.cfl, fluid.sound_speed, fluid.viscosity and fluid.artificial_viscosity"
    )]
    Stalled {
        /// Step number.
        step: u64,
        /// Simulated time [s].
        time: f64,
        /// The step chosen [s].
        dt: f64,
        /// The criterion that chose it.
        limit: TimeStepLimit,
        /// The run's end time [s].
        end_time: f64,
    },
    /// The backend failed (a device launch or copy).
    #[error("step {step}: {source}")]
    Backend {
        /// Step number.
        step: u64,
        /// The backend's error.
        source: crate::backend::BackendError,
    },
    /// The neighbour grid could not be built.
    #[error("step {step}: {source}")]
    Grid {
        /// Step number.
        step: u64,
        /// The grid's error.
        source: crate::grid::GridError,
    },
}

/// Errors building a simulation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SetupError {
    /// Dimension other than 2 or 3.
    #[error(transparent)]
    Dimension(#[from] UnsupportedDimension),
    /// A numeric setting that cannot run (the scene validator normally catches these first).
    #[error("invalid setting {key}: {reason}")]
    Invalid {
        /// The setting.
        key: &'static str,
        /// Why.
        reason: String,
    },
}

/// The plan's inputs from the settings, whether there are solids and whether some move.
fn plan_inputs<const D: usize>(config: &SimConfig<D>, solids: bool, moving_solids: bool) -> plan::PlanInputs {
    plan::PlanInputs {
        viscosity: config.viscosity.is_some(),
        artificial_viscosity: config.artificial_viscosity.is_some(),
        rotating_frame: config.angular_velocity.is_some(),
        surface_tension: config.surface_tension.map(|s| s.model),
        solids,
        moving_solids,
        integrator: config.integrator,
        corrected: config.correction.is_some(),
    }
}

/// Simulated time and step count.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Clock {
    /// Simulated time [s].
    pub time: f64,
    /// Steps taken.
    pub step: u64,
}

/// What one step did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepReport {
    /// The step taken [s].
    pub dt: f64,
    /// The criterion that limited it.
    pub limit: TimeStepLimit,
    /// Extremes of the state at the start of the step.
    pub extremes: crate::backend::StateExtremes,
    /// Fluid particles removed at the start of the step for having left the domain
    /// ([`escape::EscapePolicy::Remove`]).
    pub removed: u64,
}

/// Density statistics over a run, from the state at the start of every step (fluid particles;
/// see `StateExtremes`).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunStats {
    /// Largest compression `max(ρ − ρ0, 0)/ρ0` seen.
    pub max_compression: f64,
    /// Sum over steps of the per-step mean compression.
    pub sum_mean_compression: f64,
    /// Largest free-surface deficit `max(ρ0 − ρ, 0)/ρ0` seen.
    #[serde(default)]
    pub max_surface_deficit: f64,
    /// Sum over steps of the per-step mean deficit.
    #[serde(default)]
    pub sum_mean_surface_deficit: f64,
    /// Position-correction statistics (`corrected` solver; zero otherwise).
    pub correction: CorrectionStats,
    /// Fluid particles the no-penetration guard put back out of a solid
    /// (`boundary::keep_out`): how often the guard, not the particle boundary, held the fluid.
    #[serde(default)]
    pub keep_out_pushes: u64,
    /// Fluid particles removed for having left the domain ([`escape`]).
    #[serde(default)]
    pub removed_particles: u64,
}

/// What the position correction did over a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CorrectionStats {
    /// Integrator stages corrected.
    pub stages: u64,
    /// Iterations summed over stages.
    pub iterations: u64,
    /// Most iterations in one stage.
    pub max_iterations: u32,
    /// Stages that hit the iteration cap.
    pub unconverged_stages: u64,
    /// Largest compression `max(ρ − ρ0, 0)/ρ0` left after a stage's correction.
    pub max_compression_after: f64,
    /// Largest loop residual left after a stage's correction (`physics::correction::residual`).
    pub max_residual_after: f64,
    /// Iterations of the last stage.
    pub last_iterations: u32,
    /// Velocity solves run (one after every stage whose positions converged).
    #[serde(default)]
    pub velocity_solves: u64,
    /// Velocity-solve iterations summed over solves.
    #[serde(default)]
    pub velocity_iterations: u64,
    /// Velocity solves given up (velocity and pressure restored).
    #[serde(default)]
    pub velocity_solves_given_up: u64,
}

impl CorrectionStats {
    /// Mean iterations per corrected stage.
    pub fn mean_iterations(&self) -> f64 {
        if self.stages == 0 {
            0.0
        } else {
            self.iterations as f64 / self.stages as f64
        }
    }

    /// Mean applications of the correction operators per corrected stage: position sweeps plus
    /// velocity-solve iterations (each one neighbour pass for the density and one for the
    /// pressure force), the work measure of issue targets and `docs/performance.md`.
    pub fn mean_operator_applications(&self) -> f64 {
        if self.stages == 0 {
            0.0
        } else {
            (self.iterations + self.velocity_iterations) as f64 / self.stages as f64
        }
    }

    /// Mean iterations per velocity solve.
    pub fn mean_velocity_iterations(&self) -> f64 {
        if self.velocity_solves == 0 {
            0.0
        } else {
            self.velocity_iterations as f64 / self.velocity_solves as f64
        }
    }
}

/// The `surface_tension` effect of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceTension {
    /// `σ` [N/m] (2D: per unit depth, [N]).
    pub sigma: f64,
    /// The surface stress (`physics::surface_stress`) or [AAT13]'s pair forces
    /// (`physics::surface_tension`).
    pub model: SurfaceTensionModel,
}

/// A running simulation in dimension `D` (2 or 3).
pub struct Simulation<const D: usize> {
    /// Particle fields (cell-sorted after the first step).
    pub fields: Fields<D>,
    backend: Box<dyn Backend<D> + Send>,
    /// Wall seconds per stage name since [`Simulation::time_stages`] turned timing on.
    stage_seconds: Option<Vec<(&'static str, f64)>>,
    /// Seconds the velocity solves of the current correction stage took, while stages are
    /// timed; moved into `stage_seconds` as `velocity_solve` when the stage ends.
    velocity_solve_seconds: f64,
    /// `fields` lags the backend's state (a device-resident backend ran stages since the last
    /// [`Simulation::sync_fields`]).
    fields_stale: bool,
    plan: Vec<Stage>,
    config: SimConfig<D>,
    solid_names: Vec<String>,
    /// `1/κ` of the pressure gradient (see `physics::lattice`).
    pressure_gradient_scale: Real,
    /// The kernel of eq. (18): poly6 for `wcsph`, the spiky kernel times its lattice factor for
    /// `corrected` (`physics::density`).
    density_weight: DensityWeight,
    /// `1/λ` of the viscous force (17) (`physics::lattice::lattice_laplacian_moment`); 1 when
    /// the scene has no viscosity.
    viscosity_scale: Real,
    /// [AAT13]'s `γ` for the scene's `σ`, calibrated on the lattice at set-up
    /// (`physics::surface_tension::gamma_for_surface_tension`); 0 without surface tension.
    surface_tension_gamma: Real,
    /// `σ'` of the surface stress, calibrated on the lattice at set-up
    /// (`physics::surface_stress::calibrated_stress`); 0 unless that is the model.
    surface_tension_sigma: Real,
    clock: Clock,
    stats: RunStats,
    /// Force of the fluid on each named solid at the last step [N] (2D: [N/m]).
    solid_force: Vec<[f64; 3]>,
    fluid_count: usize,
    /// `K` of the correction's step scale [m²] (`physics::lattice::correction_stiffness`).
    correction_stiffness: f64,
    /// The grid matches the positions (no move since the last sort beyond `RESORT_DRIFT`).
    grid_fresh: bool,
    /// The density field matches the positions.
    density_fresh: bool,
    /// The start-up settle ran ([`Simulation::settle`]).
    settled: bool,
    /// The current step stored its start positions (`Backend::store_step_start`, SSP-RK3): the
    /// no-penetration guard can tell from them which side a particle came from.
    step_start_stored: bool,
    /// The solids' volumes for the no-penetration guard (`boundary::keep_out`); empty: no guard.
    keep_out: Vec<KeepOutBox<D>>,
    /// Prescribed motion of each solid (`None`: fixed), in scene order.
    motions: Vec<Option<Sway>>,
    /// `x0` of the solid particles by id; empty unless a solid moves.
    solid_reference: SolidReference<D>,
    /// Kinematics of each solid at its last placement; empty unless a solid moves.
    solid_kinematics: Vec<SolidKinematics<D>>,
    /// Each solid's acceleration at its last placement [m/s²]; empty unless a solid moves.
    wall_acceleration: Vec<Vector<D>>,
    /// Time [s] the moving solids were last placed at, if they were since the fields were set.
    solids_placed_at: Option<f64>,
    /// Bound of the moving solids' speed [m/s] (`Sway::max_speed`), a flow speed for the time
    /// step; 0 when nothing moves.
    wall_speed: f64,
    /// The smallest rest density of any phase [kg/m³] (`config.rho0` unless
    /// [`Simulation::with_phases`] gave a lighter one): the viscous time-step limit uses the
    /// largest kinematic viscosity `μ/ρ0`.
    lightest_rho0: f64,
    /// One fluid phase, or several from [`Simulation::with_phases`] (`StepParams::phases`).
    phases: Phases,
}

impl<const D: usize> Simulation<D> {
    /// Builds a simulation from fluid particles (positions [m], velocities [m/s]) and named
    /// solids. Every particle gets the lattice mass (see `physics::lattice::lattice_mass`).
    pub fn new(
        config: SimConfig<D>,
        fluid_position: &[Vector<D>],
        fluid_velocity: &[Vector<D>],
        solids: &[(String, Vec<Vector<D>>)],
    ) -> Result<Self, SetupError> {
        let positive = |key: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(SetupError::Invalid {
                    key,
                    reason: format!("must be positive and finite, got {v}"),
                })
            }
        };
        positive("particles.spacing", config.spacing)?;
        positive("particles.smoothing_length", config.h)?;
        positive("fluid.rho0", config.rho0)?;
        positive("fluid.sound_speed", config.sound_speed)?;
        positive("solver.cfl", config.cfl)?;
        if let Some(st) = config.surface_tension {
            positive("fluid.surface_tension", st.sigma)?;
        }
        if fluid_position.len() != fluid_velocity.len() {
            return Err(SetupError::Invalid {
                key: "fluid_box",
                reason: "positions and velocities differ in length".into(),
            });
        }
        let kernel = Smoothing::<D>::new(config.h as Real)?;
        let mass = lattice_mass(&kernel, config.spacing, config.rho0) as Real;
        let kappa = lattice_gradient_moment(&kernel, config.spacing, config.rho0);
        // The corrected solver sums the kernel whose gradient its correction moves particles
        // along (`physics::density`); wcsph keeps the paper's poly6.
        let density_weight = if config.correction.is_some() {
            DensityWeight::spiky(lattice_spiky_scale(&kernel, config.spacing) as Real)
        } else {
            DensityWeight::POLY6
        };
        let stiffness = correction_stiffness(&kernel, config.spacing, config.rho0, kappa, density_weight);
        let viscosity_scale = if config.viscosity.is_some() {
            (1.0 / lattice_laplacian_moment(&kernel, config.spacing, config.rho0)) as Real
        } else {
            1.0
        };
        let (dx, m) = (config.spacing, f64::from(mass));
        let (surface_tension_gamma, surface_tension_sigma) = match config.surface_tension {
            None => (0.0, 0.0),
            Some(SurfaceTension {
                sigma,
                model: SurfaceTensionModel::Akinci,
            }) => (
                gamma_for_surface_tension(&kernel, dx, config.rho0, m, sigma) as Real,
                0.0,
            ),
            Some(SurfaceTension {
                sigma,
                model: SurfaceTensionModel::SurfaceStress,
            }) => (
                0.0,
                calibrated_stress(&kernel, dx, m, config.rho0, 1.0 / kappa, sigma) as Real,
            ),
        };
        if let Some(c) = &config.correction {
            positive("solver.delta", c.delta)?;
            positive("solver.relaxation", c.relaxation)?;
            if c.max_iterations == 0 {
                return Err(SetupError::Invalid {
                    key: "solver.max_iterations",
                    reason: "must be at least 1".into(),
                });
            }
        }
        let rho0 = config.rho0 as Real;
        let n = fluid_position.len() + solids.iter().map(|(_, xs)| xs.len()).sum::<usize>();
        let mut fields = Fields::with_capacity(n);
        for (x, u) in fluid_position.iter().zip(fluid_velocity) {
            fields.push(*x, *u, mass, rho0, FLUID);
        }
        for (k, (_, xs)) in solids.iter().enumerate() {
            for x in xs {
                fields.push(*x, Vector::zeros(), mass, rho0, k as u32 + 1);
            }
        }
        let plan = plan::plan(plan_inputs(&config, !solids.is_empty(), false));
        if plan.contains(&Stage::WallVelocity) {
            // [A12] no-slip walls: the viscous velocity of solids, only where it is used.
            fields.wall_velocity = vec![Vector::zeros(); fields.len()];
        }
        Ok(Self {
            fields,
            backend: Box::new(CpuBackend::new()),
            stage_seconds: None,
            velocity_solve_seconds: 0.0,
            fields_stale: false,
            plan,
            solid_names: solids.iter().map(|(n, _)| n.clone()).collect(),
            pressure_gradient_scale: (1.0 / kappa) as Real,
            density_weight,
            viscosity_scale,
            surface_tension_gamma,
            surface_tension_sigma,
            clock: Clock::default(),
            stats: RunStats::default(),
            solid_force: vec![[0.0; 3]; solids.len()],
            fluid_count: fluid_position.len(),
            correction_stiffness: stiffness,
            grid_fresh: false,
            density_fresh: false,
            settled: false,
            step_start_stored: false,
            keep_out: Vec::new(),
            motions: vec![None; solids.len()],
            solid_reference: SolidReference::default(),
            solid_kinematics: Vec::new(),
            wall_acceleration: Vec::new(),
            solids_placed_at: None,
            wall_speed: 0.0,
            lightest_rho0: config.rho0,
            phases: Phases::Single,
            config,
        })
    }

    /// Gives the solids their prescribed motions (`motions[k]` for solid `k`, `None`: fixed), as
    /// the scene's `[[solid]] motion` does. Call before the first step. When some solid moves,
    /// the plan gains the `move_solids` stage and the solid particles' current positions become
    /// their reference positions `x0`; when none does, nothing changes (no stage, no cost).
    ///
    /// # Errors
    /// [`SetupError::Invalid`] when `motions` does not have one entry per solid, a motion is not
    /// finite (period ≤ 0, negative ramp, non-finite or missing amplitude), or steps were taken.
    pub fn with_solid_motion(mut self, motions: Vec<Option<Sway>>) -> Result<Self, SetupError> {
        let invalid = |reason: String| SetupError::Invalid {
            key: "solid.motion",
            reason,
        };
        if motions.len() != self.solid_names.len() {
            return Err(invalid(format!(
                "{} motions for {} solids",
                motions.len(),
                self.solid_names.len()
            )));
        }
        if self.clock.step != 0 {
            return Err(invalid("motions must be given before the first step".into()));
        }
        for m in motions.iter().flatten() {
            let ok = m.period.is_finite()
                && m.period > 0.0
                && m.ramp.is_finite()
                && m.ramp >= 0.0
                && m.amplitude.len() == D
                && m.amplitude.iter().all(|a| a.is_finite());
            if !ok {
                return Err(invalid(format!("not a valid sway: {m:?}")));
            }
        }
        let moving = motions.iter().any(Option::is_some);
        self.plan = plan::plan(plan_inputs(&self.config, !self.solid_names.is_empty(), moving));
        self.wall_speed = motions.iter().flatten().map(Sway::max_speed).fold(0.0, f64::max);
        self.motions = motions;
        self.solids_placed_at = None;
        if !moving {
            self.solid_reference = SolidReference::default();
            self.solid_kinematics.clear();
            self.wall_acceleration.clear();
            return Ok(self);
        }
        // Solids are appended after the fluid: ids fluid_count.. in any current order.
        let f = &self.fields;
        let first_id = self.fluid_count as u32;
        let mut position = vec![Vector::zeros(); f.len() - self.fluid_count];
        for i in 0..f.len() {
            if f.kind[i] != FLUID {
                position[(f.id[i] - first_id) as usize] = f.position[i];
            }
        }
        self.solid_reference = SolidReference { first_id, position };
        self.solid_kinematics = vec![SolidKinematics::rest(); self.solid_names.len()];
        self.wall_acceleration = vec![Vector::zeros(); self.solid_names.len()];
        Ok(self)
    }

    /// Gives each fluid particle (in the order given to [`Simulation::new`]) the rest density
    /// `rest_density[k]` [kg/m³] of its phase: the `multiphase` effect (`physics::multiphase`).
    /// Each phase gets the lattice mass of its own `ρ0` (`physics::lattice::lattice_mass`), so it
    /// starts at its rest density; solids keep the scene's `ρ0` and mass. Allocates
    /// `Fields::rest_density` and sets the run's [`Phases::Multi`], on which the backends run the
    /// multiphase variants of density, equation of state, forces, wall pressure, correction and
    /// state extremes. Call
    /// before the first step. All phases share the sound speed `C` (see `physics::multiphase`).
    ///
    /// # Errors
    /// [`SetupError::Invalid`] when the count differs from the fluid particles', a density is not
    /// finite and positive, steps were taken, or a device backend already holds the fields.
    pub fn with_phases(mut self, rest_density: &[f64]) -> Result<Self, SetupError> {
        let invalid = |reason: String| SetupError::Invalid {
            key: "fluid_box.rho0",
            reason,
        };
        if rest_density.len() != self.fluid_count {
            return Err(invalid(format!(
                "{} rest densities for {} fluid particles",
                rest_density.len(),
                self.fluid_count
            )));
        }
        if self.clock.step != 0 || self.settled {
            return Err(invalid("phases must be given before the first step".into()));
        }
        if self.backend.holds_state() {
            // A device backend took its copy of the fields without the rest densities.
            return Err(invalid("phases must be given before `use_backend`".into()));
        }
        if let Some(bad) = rest_density.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
            return Err(invalid(format!("must be positive and finite, got {bad}")));
        }
        let kernel = Smoothing::<D>::new(self.config.h as Real)?;
        let mut masses: Vec<(f64, Real)> = Vec::new();
        let f = &mut self.fields;
        f.rest_density = vec![self.config.rho0 as Real; f.len()];
        for i in 0..f.len() {
            if f.kind[i] != FLUID {
                continue;
            }
            // Before the first step particle i has id i (`Fields::push`).
            let rho0 = rest_density[f.id[i] as usize];
            let mass = match masses.iter().find(|(r, _)| *r == rho0) {
                Some(&(_, m)) => m,
                None => {
                    let m = lattice_mass(&kernel, self.config.spacing, rho0) as Real;
                    masses.push((rho0, m));
                    m
                }
            };
            f.mass[i] = mass;
            f.density[i] = rho0 as Real;
            f.rest_density[i] = rho0 as Real;
        }
        self.lightest_rho0 = rest_density.iter().fold(self.config.rho0, |a, &b| a.min(b));
        self.phases = Phases::Multi;
        self.fields_stale = false;
        self.grid_fresh = false;
        self.density_fresh = false;
        Ok(self)
    }

    /// Whether the fluid has phases of their own rest densities (`Simulation::with_phases`).
    pub fn multiphase(&self) -> bool {
        self.phases == Phases::Multi
    }

    /// The prescribed motion of each solid (`None`: fixed), in scene order.
    pub fn solid_motions(&self) -> &[Option<Sway>] {
        &self.motions
    }

    /// The reference positions `x0` of the solid particles, by id (empty unless a solid moves).
    pub fn solid_reference(&self) -> &SolidReference<D> {
        &self.solid_reference
    }

    /// Displacement `d`, velocity `d'` and acceleration `d''` of each solid (scene order) at the
    /// time it was last placed (`Stage::MoveSolids`; [`Simulation::solids_placed_at`]); empty
    /// unless a solid moves. A fixed solid in a scene with moving ones has zero kinematics.
    pub fn solid_kinematics(&self) -> &[SolidKinematics<D>] {
        &self.solid_kinematics
    }

    /// The time [s] the moving solids were last placed at (`None` before the first placement and
    /// after a restore, or when nothing moves).
    pub fn solids_placed_at(&self) -> Option<f64> {
        self.solids_placed_at
    }

    /// Places every moving solid at time `time` [s] (stage `move_solids`): kinematics from the
    /// motions, then the backend moves the particles. Returns whether anything was done (not
    /// when the solids already stand at `time`).
    fn place_solids(&mut self, time: f64) -> bool {
        if self.solids_placed_at == Some(time) {
            return false;
        }
        for (k, m) in self.motions.iter().enumerate() {
            self.solid_kinematics[k] = m
                .as_ref()
                .map_or_else(SolidKinematics::rest, |m| m.kinematics::<D>(time));
            self.wall_acceleration[k] = self.solid_kinematics[k].acceleration;
        }
        self.backend
            .move_solids(&mut self.fields, &self.solid_reference, &self.solid_kinematics);
        self.solids_placed_at = Some(time);
        true
    }

    /// The plan each step walks.
    pub fn plan(&self) -> &[Stage] {
        &self.plan
    }

    /// [AAT13]'s `γ` the run uses for the scene's `σ` (`physics::surface_tension`); 0 without
    /// surface tension.
    pub fn surface_tension_gamma(&self) -> Real {
        self.surface_tension_gamma
    }

    /// The surface stress's `σ'` the run uses for the scene's `σ` (`physics::surface_stress`); 0
    /// unless the scene's surface-tension model is `surface_stress`.
    pub fn surface_stress_sigma(&self) -> Real {
        self.surface_tension_sigma
    }

    /// The settings of the run.
    pub fn config(&self) -> &SimConfig<D> {
        &self.config
    }

    /// Simulated time and step count.
    pub fn clock(&self) -> Clock {
        self.clock
    }

    /// Density-error statistics so far.
    pub fn stats(&self) -> RunStats {
        self.stats
    }

    /// Names of the solids, in scene order (solid `k` has `kind == k + 1`).
    pub fn solid_names(&self) -> &[String] {
        &self.solid_names
    }

    /// Force of the fluid on each solid during the last step [N] (per unit depth in 2D).
    pub fn solid_forces(&self) -> &[[f64; 3]] {
        &self.solid_force
    }

    /// Number of fluid particles.
    pub fn fluid_count(&self) -> usize {
        self.fluid_count
    }

    /// Backend name.
    pub fn backend_name(&self) -> &'static str {
        self.backend.name()
    }

    /// Which backend runs the stages.
    pub fn backend_kind(&self) -> BackendKind {
        self.backend.kind()
    }

    /// The device the backend runs on (`None` for the host's CPUs).
    pub fn backend_device(&self) -> Option<String> {
        self.backend.device()
    }

    /// Memory per run the backend's side holds [B]: host fields, grid and scratch for the CPU;
    /// device buffers for a device-resident backend.
    pub fn backend_bytes(&self) -> usize {
        if self.backend.holds_state() {
            self.backend.heap_bytes()
        } else {
            self.heap_bytes()
        }
    }

    /// Gives the solids' volumes to the no-penetration guard (`boundary::keep_out`), which then
    /// runs after every move; each box's `solid` indexes the solids given to [`Simulation::new`].
    /// Without it (the default) only the particle boundary keeps fluid out of solids.
    ///
    /// # Errors
    /// [`SetupError::Invalid`] when a box names a solid that does not exist or is not a box.
    pub fn set_keep_out(&mut self, boxes: Vec<KeepOutBox<D>>) -> Result<(), SetupError> {
        for b in &boxes {
            let finite = b
                .min
                .iter()
                .chain(b.max.iter())
                .chain(b.velocity.iter())
                .all(|c| c.is_finite());
            if b.solid as usize >= self.solid_names.len() || !finite || (0..D).any(|k| b.min[k] > b.max[k]) {
                return Err(SetupError::Invalid {
                    key: "solid",
                    reason: format!(
                        "a solid volume {b:?} is not a finite box of one of the {} solids",
                        self.solid_names.len()
                    ),
                });
            }
        }
        self.keep_out = boxes;
        Ok(())
    }

    /// Runs the stages on `kind` from now on (the CPU backend is the default). The CUDA backend
    /// takes a copy of the current fields into device memory.
    ///
    /// # Errors
    /// [`BackendError`] when the backend cannot run here (no `--features cuda`, no driver, no
    /// NVRTC, no GPU) or the upload fails.
    pub fn use_backend(&mut self, kind: BackendKind) -> Result<(), BackendError> {
        self.use_backend_from(|fields, params| match kind {
            BackendKind::Cpu => Ok(Box::new(CpuBackend::new())),
            BackendKind::Cuda => crate::backend::cuda::create(fields, params),
        })
    }

    /// Runs the stages from now on on the backend `make` builds from the current fields and
    /// parameters: [`Simulation::use_backend`] for a backend outside [`BackendKind`], such as
    /// the CUDA backend on the host shim (`backend::cuda::shim::Shim::backend`).
    ///
    /// # Errors
    /// What `make` returns, or [`BackendError::Device`] when the old backend's fields cannot be
    /// copied back first.
    pub fn use_backend_from(
        &mut self,
        make: impl FnOnce(&Fields<D>, &StepParams<D>) -> Result<Box<dyn Backend<D> + Send>, BackendError>,
    ) -> Result<(), BackendError> {
        self.sync_fields()?;
        self.backend = make(&self.fields, &self.step_params())?;
        self.grid_fresh = false;
        self.density_fresh = false;
        Ok(())
    }

    /// Waits until the backend has finished every stage launched so far (for timings).
    ///
    /// # Errors
    /// [`BackendError`] when a stage failed on the device.
    pub fn synchronize(&mut self) -> Result<(), BackendError> {
        self.backend.synchronize();
        self.backend.take_error().map_or(Ok(()), Err)
    }

    /// Turns per-stage timing on (from zero) or off. While on, each stage waits for the backend
    /// to finish (`Backend::synchronize`) so its time is its own; the step gets slightly slower.
    pub fn time_stages(&mut self, on: bool) {
        self.stage_seconds = on.then(Vec::new);
    }

    /// Wall seconds spent in each stage of the plan since timing was turned on, by stage name
    /// in plan order (the correction loop counts as `correct_positions`, the velocity solves
    /// after it as `velocity_solve`).
    pub fn stage_seconds(&self) -> &[(&'static str, f64)] {
        self.stage_seconds.as_deref().unwrap_or(&[])
    }

    /// Times `count` sweeps (one density pass, the equation of state and one force pass, the
    /// unit of the paper's Fig. 5, plus the surface-tension stages when the scene has them) on
    /// the current state after one untimed warm-up sweep, and
    /// returns the seconds per sweep. The fields keep the last sweep's density, pressure and
    /// acceleration; positions and velocities are unchanged.
    ///
    /// # Errors
    /// [`StepError::Grid`] or [`StepError::Backend`] when a stage fails.
    pub fn time_sweeps(&mut self, count: usize) -> Result<f64, StepError> {
        let step = self.clock.step;
        let params = self.step_params();
        let terms = crate::backend::ForceTerms {
            viscosity: self.config.viscosity.is_some(),
            artificial_viscosity: self.config.artificial_viscosity.is_some(),
            rotating_frame: self.config.angular_velocity.is_some(),
        };
        let (bk, f) = (&mut self.backend, &mut self.fields);
        bk.sort_by_cell(f, params.h)
            .map_err(|source| StepError::Grid { step, source })?;
        let surface_tension = self.config.surface_tension.is_some();
        let sweep = |bk: &mut Box<dyn Backend<D> + Send>, f: &mut Fields<D>| {
            bk.density(f, &params);
            bk.equation_of_state(f, &params);
            bk.forces(f, &params, terms);
            if surface_tension {
                bk.surface_normals(f, &params);
                bk.surface_tension(f, &params);
            }
        };
        sweep(bk, f);
        bk.synchronize();
        let start = std::time::Instant::now();
        for _ in 0..count {
            sweep(bk, f);
        }
        bk.synchronize();
        let seconds = start.elapsed().as_secs_f64() / count.max(1) as f64;
        self.grid_fresh = true;
        self.density_fresh = true;
        self.fields_stale = self.backend.holds_state();
        if let Some(source) = self.backend.take_error() {
            return Err(StepError::Backend { step, source });
        }
        Ok(seconds)
    }

    /// Brings `fields` up to date with the backend's state (a copy from the device for CUDA;
    /// nothing for the CPU). Call before reading `fields` after steps.
    ///
    /// # Errors
    /// [`BackendError::Device`] when the copy fails.
    pub fn sync_fields(&mut self) -> Result<(), BackendError> {
        if self.fields_stale {
            self.backend.download(&mut self.fields)?;
            self.fields_stale = false;
        }
        Ok(())
    }

    /// Bytes held by the particle fields, the grid and the scratch buffers.
    pub fn heap_bytes(&self) -> usize {
        self.fields.heap_bytes() + self.backend.heap_bytes()
    }

    /// Parameters for the stages at the current time.
    pub fn step_params(&self) -> StepParams<D> {
        self.params_at(self.clock.time)
    }

    /// Parameters for the stages at time `time` [s] (gravity is ramped in time).
    pub fn params_at(&self, time: f64) -> StepParams<D> {
        let c = &self.config;
        let g = c
            .gravity
            .map(|g| gravity_at(&g, time, c.gravity_ramp))
            .unwrap_or_else(Vector::zeros);
        StepParams {
            h: c.h as Real,
            rho0: c.rho0 as Real,
            c2: (c.sound_speed * c.sound_speed) as Real,
            mu: c.viscosity.unwrap_or(0.0) as Real,
            alpha: c.artificial_viscosity.unwrap_or(0.0) as Real,
            c: c.sound_speed as Real,
            pressure_gradient_scale: self.pressure_gradient_scale,
            gravity: g,
            domain_min: c.domain_min,
            domain_max: c.domain_max,
            angular_velocity: c.angular_velocity.map_or([0.0; 3], |w| w.map(|x| x as Real)),
            rotation_centre: if c.angular_velocity.is_some() {
                c.rotation_centre
            } else {
                Vector::zeros()
            },
            viscosity_scale: self.viscosity_scale,
            surface_tension_gamma: self.surface_tension_gamma,
            surface_tension_sigma: self.surface_tension_sigma,
            spacing: c.spacing as Real,
            density_spiky_scale: self.density_weight.spiky_scale,
            density_kernel: self.density_weight.kernel,
            surface_tension_model: c
                .surface_tension
                .as_ref()
                .map_or(SurfaceTensionModel::default(), |t| t.model),
            rotating_frame: u32::from(c.angular_velocity.is_some()),
            phases: self.phases,
        }
    }

    /// `1/λ`, the scale of the viscous force (17) on this scene's lattice
    /// (`physics::lattice::lattice_laplacian_moment`); 1 without viscosity.
    pub fn viscosity_scale(&self) -> Real {
        self.viscosity_scale
    }

    /// Total fluid mass [kg] (per unit depth in 2D), summed in f64.
    pub fn fluid_mass(&self) -> f64 {
        let f = &self.fields;
        sum_in_order(f.len(), |i| {
            [if f.kind[i] == FLUID {
                f64::from(f.mass[i])
            } else {
                0.0
            }]
        })[0]
    }

    /// Total fluid momentum [kg m/s] (per unit depth in 2D), summed in f64.
    pub fn fluid_momentum(&self) -> [f64; 3] {
        let f = &self.fields;
        sum_in_order(f.len(), |i| {
            if f.kind[i] != FLUID {
                return [0.0; 3];
            }
            let m = f64::from(f.mass[i]);
            let u = crate::math::to_xyz(&f.velocity[i]);
            [m * u[0], m * u[1], m * u[2]]
        })
    }
}
