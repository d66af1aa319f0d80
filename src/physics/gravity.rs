//! Eq. (6): the body force of gravity, `f^gr = ρ g`, i.e. an acceleration `g` (eq. 15).

use crate::math::Vector;

/// Gravity [m/s²] at time `t` [s]: `g`, ramped in smoothly over `ramp` [s] when `ramp > 0`.
///
/// The ramp `g (1 − cos(π t/ramp))/2` (Adami, Hu & Adams 2012, section 6) loads a fluid at rest
/// quasi-statically, so a hydrostatic tank settles without a pressure wave ringing through it.
pub fn gravity_at<const D: usize>(g: &Vector<D>, t: f64, ramp: f64) -> Vector<D> {
    if ramp <= 0.0 || t >= ramp {
        return *g;
    }
    let s = 0.5 * (1.0 - (std::f64::consts::PI * t / ramp).cos());
    g * s as crate::math::Real
}
