//! Eqs. (23)–(24): the position correction that removes the weak compressibility (section 2).
//!
//! Per particle and per iteration, `δp_i` is the pressure increment of this sweep and `P_i` the
//! pressure accumulated so far. The pressure force (16) of the increments becomes a displacement
//! (23) `Δx_i = τ² a_i^press(δp)`, with `τ` the time since the start of the step (see
//! `solver::step`). The pure math lives here; the loops in the backends.

use crate::math::Real;

/// Heavy-ball momentum `β` of the correction sweeps: each sweep's pressure increment is
/// `pressure_increment(ρ, P + β δp_prev, k) + β δp_prev`.
///
/// Why: a sweep is a Jacobi iteration, which removes a uniform compression of a tall column only
/// by diffusing it from the surface, at a rate that falls with the square of the column's
/// height in particles. On the 2D dam break (50 layers, `ω = 0.5`) plain sweeps hit a 200
/// iteration cap in most stages at `δ = 1e-4`. With the spiky density and the velocity solve
/// (`solver::step`), `β = 0.9`: at 0.95 the two-layer tank's carried pressure settles 3.8 % of
/// the bottom pressure high (limit 3 %), at 0.9 1.5 % low, and the block thrown at a wall at
/// 0.25 h/|u| stays inside (`tests/numerics/correction.rs`). The momentum is reset after every re-sort and
/// at the start of every stage.
pub const MOMENTUM: Real = 0.9;

/// Pressure increment [Pa] of one correction sweep for a fluid particle with summed density
/// `rho` [kg/m³], accumulated pressure `p` [Pa] and stiffness `k = ω K/τ²` [m²/s²]
/// (`physics::lattice::correction_stiffness`).
///
/// Free surface (PAPER.md note 6): the pressure stays non-negative, so the correction resists
/// compression only. A particle above `ρ0` gets a positive increment; one below `ρ0` gives back
/// pressure it accumulated earlier, but never goes below zero. At a free surface, where the sum
/// (18) misses neighbours and stays below `ρ0`, this releases all pressure (`p = 0` there, the
/// free-surface condition) instead of pulling the surface together.
#[inline(always)]
pub fn pressure_increment(rho: Real, rho0: Real, p: Real, k: Real) -> Real {
    (p + k * (rho - rho0)).max(0.0) - p
}

/// The loop's error for one fluid particle: its compression, and where it carries pressure
/// (`p > 0` [Pa]) also its expansion, `|ρ − ρ0|/ρ0`.
///
/// Why the expansion: the accumulated pressure drives the next force stage. A particle that
/// carries pressure but sits below `ρ0` has too much of it; stopping on compression alone would
/// leave that excess to push its neighbours apart step after step (measured: a resting block
/// with dt = 5e-3 s reached 7.6 m/s in 0.2 s). Where `p = 0` (free surface) only compression
/// counts, as note 6 requires. NaN when the density error or the pressure is NaN: a state that
/// is not a number must stop the loop with an error, never read as converged.
#[inline(always)]
pub fn residual(rho: Real, rho0: Real, p: Real) -> f64 {
    let e = (f64::from(rho) - f64::from(rho0)) / f64::from(rho0);
    if e.is_nan() || p.is_nan() {
        f64::NAN
    } else if p > 0.0 {
        e.abs()
    } else {
        e.max(0.0)
    }
}

/// The compression measure of (24) with note 6: `max(ρ − ρ0, 0)/ρ0` (dimensionless).
#[inline(always)]
pub fn compression(rho: Real, rho0: Real) -> f64 {
    ((f64::from(rho) - f64::from(rho0)) / f64::from(rho0)).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn increment_keeps_pressure_non_negative_and_stiffness_linear() {
        assert_eq!(pressure_increment(1001.0, 1000.0, 0.0, 10.0), 10.0);
        assert_eq!(pressure_increment(1001.0, 1000.0, 5.0, 10.0), 10.0);
        assert_eq!(pressure_increment(999.0, 1000.0, 5.0, 10.0), -5.0);
        assert_eq!(pressure_increment(990.0, 1000.0, 500.0, 10.0), -100.0);
        assert_eq!(compression(999.0, 1000.0), 0.0);
        assert_eq!(compression(1000.125, 1000.0), 1.25e-4);
    }
}
