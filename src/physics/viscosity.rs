//! Eq. (17): the viscous force with the Laplacian of the viscosity kernel (22).

use super::pair::{Pair, ViscousMedium};
use crate::math::{Real, Vector};
use crate::model::params::StepParams;

/// Eq. (17) divided by `ρ_i` (eq. 15): acceleration [m/s²] of particle `i` due to neighbour `j`,
/// `(μ/ρ_i) (u_j − u_i) m_j/ρ_j ∇²W^visc(|x_i − x_j|, h)`.
///
/// Inputs: dynamic viscosity `mu` [Pa s], velocities [m/s], densities [kg/m³], `m_j` [kg],
/// `laplacian_w` [1/m^(D+2)]. Multiplied by `m_i`, the pair force is antisymmetric.
#[inline(always)]
pub fn viscous_acceleration<const D: usize>(
    mu: Real,
    u_i: &Vector<D>,
    u_j: &Vector<D>,
    rho_i: Real,
    rho_j: Real,
    m_j: Real,
    laplacian_w: Real,
) -> Vector<D> {
    (u_j - u_i) * (mu * m_j * laplacian_w / (rho_i * rho_j))
}

/// Eq. (17) between the pair's particles with the lattice's Laplacian moment undone
/// (`physics::lattice`): [`viscous_acceleration`] with `μ = params.pair.mu ·
/// params.viscosity_scale` and the pair's viscous velocities (the `viscosity` line of
/// `kernels/pair_terms.table`).
#[inline(always)]
pub fn pair_acceleration<const D: usize>(params: &StepParams<D>, pair: &Pair<'_, D>) -> Vector<D> {
    let mu = params.pair.mu * params.viscosity_scale;
    viscous_acceleration(
        mu,
        pair.viscous_u_i,
        pair.viscous_u_j,
        pair.rho_i,
        pair.rho_j,
        pair.m_j,
        pair.kernel.laplacian_w_viscosity(pair.r),
    )
}

/// The step limit's viscosity [m²/s] of dynamic viscosity `mu` [Pa s]: the operator (17) acts
/// with `μ/λ`, so its stiffness is that of `ν/λ`; the lightest phase has the largest `μ/ρ0`.
pub fn step_viscosity(mu: f64, medium: &ViscousMedium) -> f64 {
    mu / medium.lightest_rho0 * medium.viscosity_scale
}
