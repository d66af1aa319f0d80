//! Eq. (17): the viscous force with the Laplacian of the viscosity kernel (22).

use crate::math::{Real, Vector};

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
