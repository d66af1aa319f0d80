//! Parameters passed to every stage: the DualSPHysics `StInterParms` idea, one small struct
//! instead of loose arguments. `#[repr(C)]` so the CUDA backend can mirror it: `StepParams` in
//! `kernels/sph.cuh`.

use super::SurfaceTensionModel;
use super::pair_terms::PairCoefficients;
use crate::math::{Real, Vector};
use crate::periodic::{Periodic, PeriodicAxes};
use crate::physics::density::{DensityKernel, DensityWeight};
use crate::physics::multiphase::Phases;
use crate::smoothing::Smoothing;

/// Physical constants of a step, in SI units.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepParams<const D: usize> {
    /// Kernel support radius `h` [m].
    pub h: Real,
    /// Rest density `ρ0` [kg/m³].
    pub rho0: Real,
    /// Squared sound speed `C²` [m²/s²] of eq. (19).
    pub c2: Real,
    /// The coefficients of the force stage's optional pair terms (`kernels/pair_terms.table`);
    /// which terms a stage evaluates is the plan's `ForceTerms`, never these values.
    pub pair: PairCoefficients,
    /// Sound speed `C` [m/s] (used by the artificial viscosity).
    pub c: Real,
    /// `1/κ`: scale of the spiky gradient in the pressure force (16), see
    /// `physics::lattice::lattice_gradient_moment`.
    pub pressure_gradient_scale: Real,
    /// Gravity `g` [m/s²] at the current time (eq. 6); zero when the scene has no gravity.
    pub gravity: Vector<D>,
    /// Lower corner of the domain [m]; a fluid particle outside the domain stops the run.
    pub domain_min: Vector<D>,
    /// Upper corner of the domain [m].
    pub domain_max: Vector<D>,
    /// Angular velocity `Ω` [rad/s] of the rotating frame (`physics::rotating_frame`), always 3
    /// components (2D: `(0, 0, Ω)` about the out-of-plane axis, or in the plane); zero when the
    /// scene has no `rotating_frame` effect.
    pub angular_velocity: [Real; 3],
    /// A point `x_c` [m] on the rotation axis; zero when the scene has no rotating frame.
    pub rotation_centre: Vector<D>,
    /// `1/λ`: scale of the viscous force (17), see
    /// `physics::lattice::lattice_laplacian_moment`; multiplies `mu` wherever (17) is evaluated
    /// (1 when the scene has no viscosity).
    pub viscosity_scale: Real,
    /// [AAT13]'s `γ` of the surface tension (`physics::surface_tension`), in the units that make
    /// each of its terms a force; 0 when the scene has no `surface_tension` effect.
    pub surface_tension_gamma: Real,
    /// `σ'` [N/m] (2D: [N]) of the surface stress (`physics::surface_stress`), calibrated so that
    /// the model's surface tension is the scene's `σ`; 0 unless the scene's surface-tension model
    /// is `surface_stress`.
    pub surface_tension_sigma: Real,
    /// The initial particle spacing `dx` [m] (the reference distance of the surface stress's
    /// artificial stress, `physics::surface_stress::tensile_factor`).
    pub spacing: Real,
    /// The factor `c` of the spiky density `c W_spiky` (`corrected`,
    /// `physics::lattice::lattice_spiky_scale`); unused with poly6.
    pub density_spiky_scale: Real,
    /// The kernel of eq. (18) (`physics::density::density_kernel`): poly6 (20) for `wcsph`, the
    /// scaled spiky kernel for `corrected`.
    pub density_kernel: DensityKernel,
    /// The model the `surface_normals` and `surface_tension` stages evaluate (the scene's
    /// `fluid.surface_tension_model`; unused without the `surface_tension` effect).
    pub surface_tension_model: SurfaceTensionModel,
    /// 1 with the `rotating_frame` effect (the wall pressure adds the centrifugal acceleration,
    /// [B67] §3.2), 0 without it: `u32` as in `kernels/sph.cuh`.
    pub rotating_frame: u32,
    /// One fluid phase or several (the `multiphase` effect, [HA06]): which variant of the
    /// density, equation-of-state, pressure-force and correction stages both backends run.
    pub phases: Phases,
    /// `δ` of [F19]'s density diffusion (dimensionless, `physics::density_diffusion`), read by
    /// the `density_rate` stage, which only plans with the `density_diffusion` effect
    /// (`DensityEquation`); 0 without it.
    pub density_diffusion: Real,
    /// The factor on the artificial viscosity's `α` between a fluid and a solid particle
    /// (dimensionless, the scene's `fluid.artificial_viscosity_wall_factor`, default 1;
    /// `physics::artificial_viscosity::DEFAULT_WALL_FACTOR`).
    pub artificial_viscosity_wall_factor: Real,
    /// The periodic axes (`crate::periodic`, the scene's `[periodic]`): their period is the
    /// domain `[domain_min, domain_max)`; the neighbour search wraps and pair offsets take the
    /// minimum image along them. [`PeriodicAxes::NONE`] without periodic boundaries.
    pub periodic: PeriodicAxes,
}

impl<const D: usize> StepParams<D> {
    /// The kernel of eq. (18) with its factor.
    pub fn density_weight(&self) -> DensityWeight {
        DensityWeight {
            kernel: self.density_kernel,
            spiky_scale: self.density_spiky_scale,
        }
    }

    /// Whether the scene has the `rotating_frame` effect.
    pub fn rotating(&self) -> bool {
        self.rotating_frame != 0
    }

    /// The periodic axes with their period, the domain.
    pub fn periodic(&self) -> Periodic<D> {
        Periodic::new(self.periodic, self.domain_min, self.domain_max)
    }

    /// The kernels for this `h`.
    ///
    /// `h` was validated at construction (`Simulation::new`), so the dimension is supported.
    pub fn smoothing(&self) -> Smoothing<D> {
        // Invariant: Simulation::new only builds D = 2 or 3; other D never reach a stage.
        Smoothing::new(self.h).unwrap_or_else(|_| unreachable!("dimension checked at construction"))
    }
}
