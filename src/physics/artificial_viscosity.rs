//! Monaghan's artificial viscosity, an optional effect (`artificial_viscosity` in a scene).
//!
//! Not in the paper: its model has only the physical viscosity (17). Weakly compressible SPH with
//! summation density and low physical viscosity lets acoustic noise grow in violent flows (a dam
//! break with water's μ blows up here within 0.15 s); the standard remedy in SPH codes
//! (DualSPHysics uses α = 0.01 by default) is this bulk viscosity, active only between
//! approaching particles.
//!
//! References: [M92] J. J. Monaghan, "Smoothed particle hydrodynamics", Annu. Rev. Astron.
//! Astrophys. 30, 543–574 (1992), eq. (4.1).

use super::pair::{Pair, ViscousMedium};
use crate::math::{Real, Vector};
use crate::model::params::StepParams;

/// The default of the scene's `fluid.artificial_viscosity_wall_factor`: the factor on `α` between
/// a fluid and a solid particle (DualSPHysics' `ViscoBoundFactor`, default 1 there too).
///
/// Why a factor: at a wall the term is a bulk viscosity `≈ ρ α C |u_n|` on the fluid that
/// approaches it (5 kPa for α = 0.05, C = 35 m/s, 3 m/s), of the order of the stagnation pressure
/// `ρ u²/2` of an impact, so it takes a wall's impact load off the pressure that sensors read, and
/// along a floor it acts as a friction of the same order. Its purpose, damping acoustic noise in
/// the fluid, needs only the fluid pairs (docs/method.md, "Impact pressure").
pub const DEFAULT_WALL_FACTOR: f64 = 1.0;

/// [M92] eq. (4.1): acceleration [m/s²] of `i` due to `j`, `−m_j Π_ij ∇W_ij`, with
/// `Π_ij = −α C μ_ij / ρ̄_ij`, `μ_ij = ĥ u_ij·x_ij / (r² + 0.01 ĥ²)` for approaching particles
/// (`u_ij·x_ij < 0`, else 0), `ĥ = h/2` the smoothing length, `ρ̄_ij` the mean density.
///
/// Inputs: `alpha` (dimensionless), sound speed `c` [m/s], support radius `h` [m], `x_ij`
/// [m], `u_ij = u_i − u_j` [m/s], densities [kg/m³], `m_j` [kg], `grad_w` [1/m^(D+1)].
/// Symmetric in `i, j`, so the pair force is antisymmetric and momentum is conserved.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn artificial_viscous_acceleration<const D: usize>(
    alpha: Real,
    c: Real,
    h: Real,
    x_ij: &Vector<D>,
    u_ij: &Vector<D>,
    rho_i: Real,
    rho_j: Real,
    m_j: Real,
    grad_w: &Vector<D>,
) -> Vector<D> {
    let ux = u_ij.dot(x_ij);
    if ux >= 0.0 {
        return Vector::zeros();
    }
    let hs = 0.5 * h;
    let mu = hs * ux / (x_ij.norm_squared() + 0.01 * hs * hs);
    let pi = -alpha * c * mu / (0.5 * (rho_i + rho_j));
    grad_w * (-m_j * pi)
}

/// The kinematic viscosity [m²/s] the artificial viscosity amounts to in a continuum,
/// `ν = α C ĥ / (2 (D + 2))` (Monaghan 2005, section 4.3; `ĥ = h/2`), for the viscous time-step
/// limit. It matters for the `corrected` solver, whose step is not bounded by `h/C`.
///
/// Unlike the viscous force (17), which is divided by its lattice moment λ
/// (`physics::lattice::lattice_laplacian_moment`), this is left uncalibrated on purpose: on the
/// lattice at h = 2 dx the artificial viscosity's fourth moment is anisotropic (2D: 0.65 of the
/// continuum value for a shear along a lattice axis, 1.12 for a compression along it;
/// `tests/physics/poiseuille.rs`), so no single factor would calibrate it, and it is a damping with a
/// tuned α rather than a physical viscosity. For the step bound the continuum value is the larger
/// one in shear, so the step is the safer one.
pub fn equivalent_viscosity(alpha: f64, c: f64, h: f64, dimension: usize) -> f64 {
    alpha * c * 0.5 * h / (2.0 * (dimension as f64 + 2.0))
}

/// [`artificial_viscous_acceleration`] between the pair's particles, with `α = params.pair.alpha`
/// (the `artificial_viscosity` line of `kernels/pair_terms.table`), times
/// `params.artificial_viscosity_wall_factor` for a fluid–solid pair.
#[inline(always)]
pub fn pair_acceleration<const D: usize>(params: &StepParams<D>, pair: &Pair<'_, D>) -> Vector<D> {
    let factor = if pair.wall {
        params.artificial_viscosity_wall_factor
    } else {
        1.0
    };
    let u_ij = pair.u_i - pair.u_j;
    artificial_viscous_acceleration(
        params.pair.alpha * factor,
        params.c,
        params.h,
        pair.x_ij,
        &u_ij,
        pair.rho_i,
        pair.rho_j,
        pair.m_j,
        pair.grad_w,
    )
}

/// The step limit's viscosity [m²/s] of coefficient `alpha`: [`equivalent_viscosity`].
pub fn step_viscosity(alpha: f64, medium: &ViscousMedium) -> f64 {
    equivalent_viscosity(alpha, medium.sound_speed, medium.h, medium.dimension)
}
