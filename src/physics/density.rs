//! Eq. (18): density by summation, `ρ_i = Σ_j m_j W(|x_i − x_j|, h)`, with the poly6 kernel (20).

use crate::math::Real;
use crate::smoothing::Smoothing;

/// Eq. (18): contribution of neighbour `j` (mass `m_j` [kg]) at squared distance `r2` [m²] to
/// the density of particle `i` [kg/m³]. The sum includes `j = i` (`r = 0`).
#[inline(always)]
pub fn density_term<const D: usize>(kernel: &Smoothing<D>, m_j: Real, r2: Real) -> Real {
    m_j * kernel.w(r2)
}
