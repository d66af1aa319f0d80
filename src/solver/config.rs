//! The settings of a run: [`SimConfig`] with its time integrator, position correction and
//! surface tension.

use super::escape;
use super::plan::PlanInputs;
use crate::math::Vector;
use crate::model::pair_terms::PairTermSettings;
use crate::model::{DensityEquation, GradientMoment, SurfaceTensionModel};
use crate::physics::damping_zone::DampingZone;

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

    /// The Shu–Osher `(a, b)` of [`Integrator::stages`] in f64 (those are their f32 roundings),
    /// for the state the run keeps in f64: a floating body (`boundary::rigid_body`), whose
    /// centre would drift by `(a + b − 1) |c|` a stage with the f32 values.
    pub fn stage_weights_f64(self) -> &'static [(f64, f64)] {
        match self {
            Integrator::SymplecticEuler => &[(0.0, 1.0)],
            Integrator::Rk3 => &[(0.0, 1.0), (0.75, 0.25), (1.0 / 3.0, 2.0 / 3.0)],
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
    /// Each velocity solve starts from the increments of the same integrator stage's solve at the
    /// last step (`Backend::warm_start_velocity_solve`). Off by default: it takes a quarter to a
    /// third fewer iterations, but the resting tank's pressure sensors then read 2–8 % low
    /// (docs/method.md, "The velocity solve").
    pub warm_start: bool,
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
            warm_start: false,
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
    /// The force stage's optional pair terms the scene switches on, with their coefficients
    /// (`kernels/pair_terms.table`).
    pub pair_terms: PairTermSettings,
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
    /// The factor on the artificial viscosity's α between fluid and solid particles
    /// (dimensionless, `physics::artificial_viscosity::DEFAULT_WALL_FACTOR` by default).
    pub artificial_viscosity_wall_factor: f64,
    /// `δ` of [F19]'s density diffusion (dimensionless): the continuity equation replaces the
    /// summation (18) (`model::DensityEquation`); `None` without the `density_diffusion` effect.
    pub density_diffusion: Option<f64>,
    /// The periodic axes (`crate::periodic`): the domain is one period along each; the plan
    /// then wraps positions once a step (`Stage::WrapPositions`).
    pub periodic: crate::periodic::PeriodicAxes,
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
    /// The damping zone (`physics::damping_zone`): the plan's `damping_zone` stage relaxes the
    /// fluid's velocity there; `None`: no zone, no stage.
    pub damping_zone: Option<DampingZone<D>>,
    /// The first moment `κ` the pressure force (16) divides by: the lattice's, or measured on
    /// the particles every integrator stage (`physics::gradient_moment`).
    pub gradient_moment: GradientMoment,
}

impl<const D: usize> SimConfig<D> {
    /// What the stage plan (`solver::plan`) depends on: the models these settings switch on,
    /// whether there are solids and whether some move. The one place a setting becomes a
    /// plan choice; `StepParams` takes its values from the same settings
    /// (`Simulation::params_at`).
    pub fn plan_inputs(&self, solids: bool, moving_solids: bool) -> PlanInputs {
        PlanInputs {
            pair_terms: self.pair_terms.terms(),
            rotating_frame: self.angular_velocity.is_some(),
            surface_tension: self.surface_tension.map(|s| s.model),
            solids,
            moving_solids,
            integrator: self.integrator,
            corrected: self.correction.is_some(),
            density: match self.density_diffusion {
                Some(_) => DensityEquation::ContinuityFourtakas2019,
                None => DensityEquation::Summation,
            },
            damping_zone: self.damping_zone.is_some(),
            periodic: self.periodic,
            gradient_moment: self.gradient_moment,
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
