//! Backends: the memory and the loops. One method per stage of the solver's plan
//! (`solver::stage::Stage`); the driver (`solver::step`) walks the plan and calls them, so the
//! CPU and CUDA backends cannot diverge in the order of stages.

pub mod cpu;
pub mod params;

use crate::fields::Fields;
use crate::grid::GridError;
use params::StepParams;

/// Which terms the force stage computes; a term a scene does not ask for is compiled out
/// (the CPU backend monomorphises the force loop on these flags).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ForceTerms {
    /// Eq. (17), the viscous force.
    pub viscosity: bool,
    /// Monaghan's artificial viscosity ([M92]).
    pub artificial_viscosity: bool,
}

/// Extremes of the fluid state needed by the time-step choice and the state guards.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StateExtremes {
    /// Largest fluid speed [m/s].
    pub max_speed: f64,
    /// Largest fluid acceleration magnitude [m/s²].
    pub max_acceleration: f64,
    /// Largest `|ρ − ρ0|/ρ0` over fluid particles.
    pub max_abs_density_error: f64,
    /// Mean `|ρ − ρ0|/ρ0` over fluid particles.
    pub mean_abs_density_error: f64,
    /// Largest compression `max(ρ − ρ0, 0)/ρ0` over fluid particles (PAPER.md note 6).
    pub max_compression: f64,
    /// Mean compression over fluid particles.
    pub mean_compression: f64,
    /// First particle (current order) with a non-finite field, and the field's name.
    pub non_finite: Option<(usize, &'static str)>,
    /// First fluid particle (current order) outside the domain box.
    pub escaped: Option<usize>,
}

/// The stages a backend runs. Each method is one `Stage` of the plan.
pub trait Backend<const D: usize> {
    /// Short name for reports (`"cpu"`, `"cuda"`).
    fn name(&self) -> &'static str;
    /// Section 3: hash particles to cells of size `h`, radix-sort, reorder every field.
    fn sort_by_cell(&mut self, fields: &mut Fields<D>, h: f32) -> Result<(), GridError>;
    /// Eq. (18): density of fluid particles by summation.
    fn density(&mut self, fields: &mut Fields<D>, params: &StepParams<D>);
    /// Eq. (19): pressure of fluid particles.
    fn equation_of_state(&mut self, fields: &mut Fields<D>, params: &StepParams<D>);
    /// Boundary: pressure and density of solid particles ([A12] eq. 27).
    fn wall_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>);
    /// Eqs. (15)–(17) and (6): acceleration of fluid particles.
    fn forces(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, terms: ForceTerms);
    /// Fig. 4: total force [N] (per unit depth in 2D) of the fluid on each of `solids` solids.
    fn solid_forces(&mut self, fields: &Fields<D>, params: &StepParams<D>, solids: usize) -> Vec<[f64; 3]>;
    /// Extremes of speed, acceleration and density error, and the first non-finite value.
    fn state_extremes(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> StateExtremes;
    /// Semi-implicit (symplectic) Euler: `u += a dt`, then `x += u dt`, fluid only; `dt` [s].
    fn integrate(&mut self, fields: &mut Fields<D>, dt: f32);
}

pub mod cuda;

/// Which backend runs the stages.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BackendKind {
    /// The rayon CPU reference backend.
    #[default]
    Cpu,
    /// The CUDA backend (`--features cuda`, NVIDIA GPU).
    Cuda,
}

/// Errors of backend selection and setup.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BackendError {
    /// The backend cannot run here; the reason says why.
    #[error("backend {backend} is unavailable: {reason}")]
    Unavailable {
        /// Backend name.
        backend: &'static str,
        /// Why it cannot run.
        reason: String,
    },
}
