//! Eq. (19): the linear equation of state `p = C² (ρ − ρ0)`.

use crate::math::Real;

/// Eq. (19): pressure [Pa] from density `rho` [kg/m³], rest density `rho0` [kg/m³] and squared
/// sound speed `c2` [m²/s²].
///
/// Deviation (PAPER.md note 6): clamped at zero. A particle at the free surface misses
/// neighbours, so its summed density is below `ρ0` whatever the positions; a negative pressure
/// there would pull the surface into clumps (tensile instability). Only compression is resisted.
#[inline(always)]
pub fn pressure(rho: Real, rho0: Real, c2: Real) -> Real {
    (c2 * (rho - rho0)).max(0.0)
}

/// Inverse of eq. (19) for a non-negative pressure: `ρ = ρ0 + p / C²` [kg/m³].
#[inline(always)]
pub fn density_from_pressure(p: Real, rho0: Real, c2: Real) -> Real {
    rho0 + p / c2
}
