//! Eq. (16): the symmetric pressure force, with the spiky kernel gradient (21).

use crate::math::{Real, Vector};

/// Eq. (16) divided by `ρ_i` (eq. 15): acceleration [m/s²] of particle `i` due to neighbour `j`,
/// `−m_j (p_i/ρ_i² + p_j/ρ_j²) ∇W^press(x_i − x_j, h)`.
///
/// Inputs: pressures [Pa], densities [kg/m³], `m_j` [kg], `grad_w` = spiky gradient [1/m^(D+1)].
/// Multiplied by `m_i` the pair force is antisymmetric in `i, j`, so momentum is conserved.
#[inline(always)]
pub fn pressure_acceleration<const D: usize>(
    p_i: Real,
    rho_i: Real,
    p_j: Real,
    rho_j: Real,
    m_j: Real,
    grad_w: &Vector<D>,
) -> Vector<D> {
    pressure_acceleration_from_terms(pressure_term(p_i, rho_i), pressure_term(p_j, rho_j), m_j, grad_w)
}

/// One particle's factor `p/ρ²` of eq. (16) [m⁵/(kg s²)]: pressure [Pa], density [kg/m³].
/// The CPU backend computes it once per particle instead of once per pair.
#[inline(always)]
pub fn pressure_term(p: Real, rho: Real) -> Real {
    p / (rho * rho)
}

/// [`pressure_acceleration`] from the two particles' [`pressure_term`]s `q_i`, `q_j`:
/// `−m_j (q_i + q_j) ∇W` [m/s²], bit for bit the same value.
#[inline(always)]
pub fn pressure_acceleration_from_terms<const D: usize>(
    q_i: Real,
    q_j: Real,
    m_j: Real,
    grad_w: &Vector<D>,
) -> Vector<D> {
    grad_w * (-m_j * (q_i + q_j))
}
