//! The damping zone of a wave flume ([AEA17]): in a band of the tank the fluid's velocity is
//! relaxed towards zero every step, more strongly the deeper into the band, so the waves that
//! enter it die out instead of reflecting off the end wall.
//!
//! For a zone from the plane through `x0` [m] to the parallel plane through `x1` [m] (normal
//! `n = (x1 − x0)/L`, `L = |x1 − x0|`), each step of length `Δt` [s] multiplies the velocity of a
//! fluid particle at `x` by
//!
//! ```text
//! f(x, Δt) = max(0, 1 − Δt β r(x)²),   r(x) = clamp((x − x0)·n / L, 0, 1)
//! ```
//!
//! with the strength `β` [1/s]: nothing before `x0`, a quadratic ramp up to `x1`, and the full
//! `1 − Δt β` beyond (the end of the tank). This is [AEA17]'s damping, `v = v0 f(x, Δt)` with
//! `f = 1 − Δt β ((x − x0)/(x1 − x0))²` (the damping zone of DualSPHysics, whose default `β`,
//! `redumax`, is 10 s⁻¹), here projected on the zone's direction so it holds for any orientation and in
//! 3D. The quadratic ramp starts the damping gently, so the zone's own start reflects little.
//!
//! [AEA17] Altomare, Domínguez, Crespo, González-Cao, Suzuki, Gómez-Gesteira & Troch,
//! "Long-crested wave generation and absorption for SPH-based DualSPHysics model", Coastal
//! Engineering 127 (2017) 37–54.

use crate::math::{Real, Vector};

/// A damping zone as the stage `damping_zone` uses it (f32, `D` components).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DampingZone<const D: usize> {
    /// `x0` [m], a point of the plane where the zone starts.
    pub start: Vector<D>,
    /// `n / L` [1/m]: the zone's direction over its length, so `(x − x0)·(n/L)` is the depth
    /// into the zone as a fraction of its length.
    pub gradient: Vector<D>,
    /// `β` [1/s]: the relaxation rate at full strength.
    pub strength: Real,
}

impl<const D: usize> DampingZone<D> {
    /// The zone from `start` to `end` [m] (`D` entries each, distinct points) of strength
    /// `strength` [1/s]. Evaluated in f64 and rounded to f32 once.
    pub fn new(start: &[f64], end: &[f64], strength: f64) -> Self {
        let along: Vec<f64> = (0..D).map(|k| end[k] - start[k]).collect();
        let length2: f64 = along.iter().map(|a| a * a).sum();
        DampingZone {
            start: Vector::from_fn(|k, _| start[k] as Real),
            gradient: Vector::from_fn(|k, _| (along[k] / length2) as Real),
            strength: strength as Real,
        }
    }

    /// `r(x)²`, the zone's ramp at `x` [m]: 0 before the start, 1 beyond the end. The
    /// projection is summed axis by axis in this order (the kernel's twin does the same).
    pub fn ramp(&self, x: &Vector<D>) -> Real {
        let mut s: Real = 0.0;
        for k in 0..D {
            s += (x[k] - self.start[k]) * self.gradient[k];
        }
        let r = s.clamp(0.0, 1.0);
        r * r
    }

    /// `f(x, Δt) = max(0, 1 − Δt β r(x)²)`, the factor on the velocity of a fluid particle at
    /// `x` [m] over a step `dt` [s] (module doc).
    pub fn velocity_factor(&self, x: &Vector<D>, dt: Real) -> Real {
        (1.0 - dt * self.strength * self.ramp(x)).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 1 before the zone, `1 − Δt β/4` halfway (r = 1/2), `1 − Δt β` at and past the end, in
    /// any direction; and never negative, however long the step.
    #[test]
    fn the_factor_ramps_from_one_to_full_strength_along_the_zone() {
        let zone = DampingZone::<2>::new(&[4.0, 0.0], &[6.0, 0.0], 10.0);
        let at = |x: f32| zone.velocity_factor(&Vector::<2>::new(x, 0.3), 0.01);
        assert_eq!(at(3.0), 1.0);
        assert_eq!(at(4.0), 1.0);
        assert!((at(5.0) - (1.0 - 0.01 * 10.0 / 4.0)).abs() < 1e-6);
        assert!((at(6.0) - 0.9).abs() < 1e-6);
        assert!((at(7.5) - 0.9).abs() < 1e-6);
        assert_eq!(zone.velocity_factor(&Vector::<2>::new(7.0, 0.0), 1.0), 0.0);
        // A zone along −y in 3D: the same ramp by the distance along its direction.
        let down = DampingZone::<3>::new(&[0.0, 2.0, 0.0], &[0.0, 1.0, 0.0], 4.0);
        let r = down.ramp(&Vector::<3>::new(9.0, 1.25, -3.0));
        assert!((r - 0.5625).abs() < 1e-6, "{r}");
    }
}
