//! The plan's vocabulary: the model choices a plan carries to the backends (which force terms,
//! which wall model, which surface-tension model) and the step's parameters (`params`). Both the
//! solver, which builds the plan, and the backends, which run it, import it from here; so do the
//! scene and the boundary code, without depending on a backend.

pub mod pair_terms;
pub mod params;

use crate::physics::multiphase::Phases;
use pair_terms::PairTerms;
use serde::Deserialize;

/// Which terms the force stage computes; a term a scene does not ask for is compiled out
/// (the CPU backend monomorphises the force loop on them, the CUDA backend launches the entry
/// compiled for them).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ForceTerms {
    /// The optional per-pair terms besides the pressure force (16) (`kernels/pair_terms.table`).
    pub pair: PairTerms,
    /// Coriolis and centrifugal forces of a rotating frame ([B67] §3.2,
    /// `physics::rotating_frame`).
    pub rotating_frame: bool,
}

impl ForceTerms {
    /// The entry of the generated `forces` family (`kernels/launch.table`,
    /// `forces{terms}{rotating}{phases}`) for these terms and `phases`.
    pub fn entry(self, phases: Phases) -> usize {
        self.pair.bits() as usize
            + PairTerms::SETS * (usize::from(self.rotating_frame) + 2 * usize::from(phases == Phases::Multi))
    }
}

/// How the fluid's density evolves (the `density_diffusion` effect chooses).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum DensityEquation {
    /// Eq. (18): summed over the neighbours at every stage (`Stage::Density`).
    #[default]
    Summation,
    /// The continuity equation with [F19] density diffusion of strength
    /// `StepParams::density_diffusion` (`physics::density_diffusion`): the rate
    /// (`Stage::DensityRate`) integrated with positions and velocities
    /// (`Stage::IntegrateDensity`), so density is state, not a function of positions.
    ContinuityFourtakas2019,
}

/// The first moment `κ` of the spiky gradient the pressure force (16) divides by
/// (`StepParams::pressure_gradient_scale = 1/κ`, `physics::gradient_moment`); scene
/// `solver.gradient_moment`, in `snake_case`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GradientMoment {
    /// The initial square lattice's (`physics::lattice::lattice_gradient_moment`), fixed for the
    /// run: the `wcsph` default, whose pressure comes from the density (19).
    Lattice,
    /// Measured on the particles at every integrator stage (`Stage::GradientMoment`): the
    /// `corrected` default, whose pressure is the one that holds the particles where they are,
    /// so its scale is the gradient operator's as the particles stand.
    Measured,
}

impl GradientMoment {
    /// The name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            GradientMoment::Lattice => "lattice",
            GradientMoment::Measured => "measured",
        }
    }
}

/// How the pressure of solid particles is set (`Stage::WallPressure`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WallModel {
    /// `max(`[A12] extrapolation, eq. (19) of the wall's own summed density`)`: the weakly
    /// compressible solver, whose clamped pressure gives lone splash particles no pressure.
    ExtrapolatedOrSummed,
    /// [A12] extrapolation only: the `corrected` solver, where eq. (19) with a real `C` would be
    /// stiff and the position correction (23) keeps fluid out of walls instead.
    Extrapolated,
}

/// The surface-tension model (`fluid.surface_tension_model`), evaluated by the `surface_tension`
/// stage.
///
/// `#[repr(u32)]` as a field of `StepParams`; `kernels/sph.cuh` names the same values
/// `SPH_SURFACE_*`.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SurfaceTensionModel {
    /// The capillary stress `σ δ (I − N̂N̂ᵀ)` of the surface layers, the conservative form of the
    /// continuum surface force (`physics::surface_stress`); the default: the bulk carries no
    /// stress of its own, so the core of a drop holds the Laplace pressure in its EOS pressure.
    #[default]
    SurfaceStress = 0,
    /// [AAT13] pair cohesion and curvature between all fluid particles within `h`
    /// (`physics::surface_tension`): momentum-conserving pair by pair, but its bulk pressure
    /// (≈ 5σ/h) jams small drops (tests/physics/surface_tension.rs).
    Akinci = 1,
}

impl SurfaceTensionModel {
    /// The name used in scene files (`"surface_stress"`, `"akinci"`).
    pub fn name(self) -> &'static str {
        match self {
            SurfaceTensionModel::SurfaceStress => "surface_stress",
            SurfaceTensionModel::Akinci => "akinci",
        }
    }
}
