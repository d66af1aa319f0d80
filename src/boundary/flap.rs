//! A flap wave maker (scene `motion = { kind = "flap", ... }`): a paddle hinged about a
//! horizontal axis (2D: out of the plane; 3D: along `y`) through the hinge point `c`, turning by
//!
//! ```text
//! θ(t) = Θ f(t),   f(t) = r(t) sin(ω t)                (the ramped sine of `boundary::motion`)
//! ```
//!
//! with `θ > 0` turning the paddle's top towards `+x`. `Θ` [rad] is given (`angle`), or comes
//! from a target wave by first-order flap wave-maker theory ([DD91] Dean & Dalrymple 1991, §6.2,
//! `physics::waves::flap_height_per_stroke`): the stroke `S` at the still-water level, `d − l`
//! above the hinge (`l` the hinge's height above the bed), is `H` over the flap's `H/S`, and
//! `Θ = atan(S / (2 (d − l)))`, so the flap crosses the still-water level at `±S/2` from rest at
//! the extremes of its swing. `θ' = Θ f'`, `θ'' = Θ f''` are the exact derivatives, so the
//! wall velocity and acceleration (`boundary::rigid`) are consistent with the positions.

use super::motion::{Piston, Sway};
use super::rigid::{Rotation, SolidKinematics, Turn};
use crate::math::Vector;

/// How the flap's angle amplitude `Θ` is set.
#[derive(Clone, Debug, PartialEq)]
pub enum FlapAmplitude {
    /// `Θ` [rad] given (`motion.angle`).
    Angle(f64),
    /// From the target wave (`motion.wave_height`, `motion.depth`, `motion.hinge_height`).
    Wave {
        /// Target wave height `H` [m], > 0.
        wave_height: f64,
        /// Still-water depth `d` [m] at the flap, > 0.
        depth: f64,
        /// The hinge's height `l` [m] above the bed, `< d` (negative: below the bed).
        hinge_height: f64,
        /// `|g|` [m/s²], > 0: the scene's gravity.
        gravity: f64,
    },
}

/// A flap wave maker (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Flap {
    /// The hinge point `c` [m], one entry per axis.
    pub hinge: Vec<f64>,
    /// The angle amplitude, given or from a wave.
    pub amplitude: FlapAmplitude,
    /// Period `T` [s], > 0.
    pub period: f64,
    /// Ramp time `t_r` [s], >= 0 (0: no ramp).
    pub ramp: f64,
    /// The largest distance [m] from the hinge to a point of the solid (set from the solid's
    /// box, `Flap::arm_to_box`): bounds the speed and the sweep.
    pub arm: f64,
}

impl Flap {
    /// The wave's wavenumber `k` [1/m] by the dispersion relation ([DD91] eq. 4.20), when the
    /// amplitude comes from a wave.
    pub fn wavenumber(&self) -> Option<f64> {
        match &self.amplitude {
            FlapAmplitude::Angle(_) => None,
            FlapAmplitude::Wave { depth, gravity, .. } => Some(
                Piston {
                    wave_height: 1.0,
                    period: self.period,
                    depth: *depth,
                    gravity: *gravity,
                    direction: Vec::new(),
                    ramp: self.ramp,
                }
                .wavenumber(),
            ),
        }
    }

    /// The stroke `S` [m] at the still-water level, `H` over the flap's `H/S` ([DD91] §6.2),
    /// when the amplitude comes from a wave.
    pub fn stroke(&self) -> Option<f64> {
        let FlapAmplitude::Wave {
            wave_height,
            depth,
            hinge_height,
            ..
        } = &self.amplitude
        else {
            return None;
        };
        let kd = self.wavenumber()? * depth;
        let ratio = crate::physics::waves::flap_height_per_stroke(kd, hinge_height / depth);
        Some(wave_height / ratio)
    }

    /// The angle amplitude `Θ` [rad] (module doc).
    pub fn angle(&self) -> f64 {
        match &self.amplitude {
            FlapAmplitude::Angle(a) => *a,
            FlapAmplitude::Wave {
                depth, hinge_height, ..
            } => {
                let stroke = self.stroke().unwrap_or(0.0);
                (0.5 * stroke / (depth - hinge_height)).atan()
            }
        }
    }

    /// The angle's profile: the sine of amplitude `Θ`, period `T` and ramp `t_r`.
    pub fn sway(&self) -> Sway {
        Sway {
            amplitude: vec![self.angle()],
            period: self.period,
            ramp: self.ramp,
        }
    }

    /// The unit hinge axis: `−z` in 2D, `+y` in 3D, so that `θ > 0` moves the top to `+x`.
    pub(crate) fn axis<const D: usize>() -> [f64; 3] {
        if D == 2 { [0.0, 0.0, -1.0] } else { [0.0, 1.0, 0.0] }
    }

    /// The rigid motion at time `t` [s]: no translation, the turn `θ(t)` about the hinge.
    pub fn kinematics<const D: usize>(&self, t: f64) -> SolidKinematics<D> {
        let f = self.sway().profile(t);
        let a = self.angle();
        let turn = Turn::about_axis(
            &self.hinge,
            Self::axis::<D>(),
            a * f.value,
            a * f.rate,
            a * f.curvature,
        );
        SolidKinematics {
            displacement: Vector::zeros(),
            velocity: Vector::zeros(),
            acceleration: Vector::zeros(),
            rotation: Rotation::About(turn),
        }
    }

    /// Whether a flap's numbers make a finite motion in `dim` dimensions: a finite hinge of `dim`
    /// entries, a positive period, a non-negative ramp, a finite arm, and a finite angle (a wave's
    /// height, depth and gravity positive, the hinge below the still-water level).
    pub fn is_valid_in(&self, dim: usize) -> bool {
        let wave_ok = match &self.amplitude {
            FlapAmplitude::Angle(a) => a.is_finite(),
            FlapAmplitude::Wave {
                wave_height,
                depth,
                hinge_height,
                gravity,
            } => {
                [*wave_height, *depth, *gravity]
                    .iter()
                    .all(|v| v.is_finite() && *v > 0.0)
                    && hinge_height.is_finite()
                    && *hinge_height < *depth
            }
        };
        wave_ok
            && self.hinge.len() == dim
            && self.hinge.iter().all(|c| c.is_finite())
            && self.period.is_finite()
            && self.period > 0.0
            && self.ramp.is_finite()
            && self.ramp >= 0.0
            && self.arm.is_finite()
            && self.angle().is_finite()
    }

    /// The largest distance [m] from the hinge to the box `min`..`max` (its farthest corner).
    pub fn arm_to_box(&self, min: &[f64], max: &[f64]) -> f64 {
        let far = |k: usize| {
            let c = self.hinge.get(k).copied().unwrap_or(0.0);
            (min[k] - c).abs().max((max[k] - c).abs())
        };
        (0..min.len().min(max.len()))
            .map(|k| far(k).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    /// An upper bound of the speed [m/s] of any point of the solid: `arm · max |θ'|`
    /// (`Sway::max_speed` of the angle).
    pub fn max_speed(&self) -> f64 {
        self.arm * self.sway().max_speed()
    }

    /// Per axis, an upper bound of how far a point of the solid moves [m]: the chord
    /// `2 arm sin(|Θ|/2)` in the plane of the turn (`x` and the vertical), 0 along the hinge.
    pub fn reach(&self, dim: usize) -> Vec<f64> {
        let chord = 2.0 * self.arm * (0.5 * self.angle().abs().min(std::f64::consts::PI)).sin();
        (0..dim)
            .map(|k| if dim == 3 && k == 1 { 0.0 } else { chord })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flume_flap() -> Flap {
        Flap {
            hinge: vec![0.0, 0.0],
            amplitude: FlapAmplitude::Wave {
                wave_height: 0.04,
                depth: 0.3,
                hinge_height: 0.0,
                gravity: 9.81,
            },
            period: 1.1,
            ramp: 2.2,
            arm: 0.1f64.hypot(0.5),
        }
    }

    /// The stroke makes `H` by the flap's transfer function, `k` solves the dispersion relation,
    /// and the flap crosses the still-water level at `S/2` from rest at the amplitude (`Θ` from
    /// `atan`), each to f64 rounding.
    #[test]
    fn flap_angle_gives_half_the_stroke_at_the_still_water_level() {
        let flap = flume_flap();
        let k = flap.wavenumber().expect("a wave");
        let w = std::f64::consts::TAU / 1.1;
        assert!((9.81 * k * (k * 0.3f64).tanh() / (w * w) - 1.0).abs() < 1e-12);
        let s = flap.stroke().expect("a wave");
        let ratio = crate::physics::waves::flap_height_per_stroke(k * 0.3, 0.0);
        assert!((s * ratio / 0.04 - 1.0).abs() < 1e-12);
        assert!((0.3 * flap.angle().tan() - 0.5 * s).abs() < 1e-12);
        let given = Flap {
            amplitude: FlapAmplitude::Angle(0.1),
            ..flap
        };
        assert_eq!((given.angle(), given.stroke()), (0.1, None));
    }

    /// θ' and θ'' are the exact derivatives of θ: the kinematics' angular velocity and
    /// acceleration agree with central differences of the turn (ε = 1e-4 s: O(ε²) truncation
    /// below 1e-5 of the scale `Θ ω` and `Θ ω²`), at times in and after the ramp; the point at
    /// the still-water level moves with the velocity `ω × r` by a finite difference of the
    /// positions (the same tolerance, f32 positions of order 0.3 m: 1e-7 m / 2ε = 5e-4 m/s,
    /// against speeds of order 0.2 m/s, hence 1 % there).
    #[test]
    fn flap_rates_are_the_derivatives_of_its_angle() {
        let flap = flume_flap();
        let (a, w) = (flap.angle(), std::f64::consts::TAU / 1.1);
        let angle = |t: f64| a * flap.sway().profile(t).value;
        let eps = 1e-4;
        for i in 0..60 {
            let t = 0.05 + 0.1 * i as f64;
            let k = flap.kinematics::<2>(t);
            let Rotation::About(turn) = k.rotation else {
                panic!("a flap turns")
            };
            // 2D: ω = −θ' z.
            let rate = (angle(t + eps) - angle(t - eps)) / (2.0 * eps);
            let curvature = (angle(t + eps) - 2.0 * angle(t) + angle(t - eps)) / (eps * eps);
            let omega = -f64::from(turn.angular_velocity[2]);
            let alpha = -f64::from(turn.angular_acceleration[2]);
            assert!(
                (omega - rate).abs() < 1e-5 * a * w + 1e-7,
                "θ' at {t}: {omega} vs {rate}"
            );
            assert!(
                (alpha - curvature).abs() < 1e-5 * a * w * w + 1e-4,
                "θ'' at {t}: {alpha} vs {curvature}"
            );
            let x0 = Vector::<2>::new(0.0, 0.3);
            let (lo, hi) = (
                flap.kinematics::<2>(t - eps).position(&x0),
                flap.kinematics::<2>(t + eps).position(&x0),
            );
            let u = k.velocity_at(&k.position(&x0));
            let fd = (hi - lo) / (2.0 * eps as f32);
            assert!((fd - u).norm() < 0.01 * u.norm() + 1e-3, "u at {t}: {u} vs {fd}");
        }
        // θ > 0 moves the top towards +x (3D: about +y).
        let top = Vector::<3>::new(0.0, 0.2, 0.3);
        let k3 = flap.kinematics::<3>(2.2 + 0.25 * 1.1);
        assert!(k3.position(&top)[0] > 0.03, "{}", k3.position(&top));
        assert_eq!(k3.position(&top)[1], 0.2);
    }

    /// The speed and sweep bounds hold over a ramp and a few periods.
    #[test]
    fn flap_speed_and_reach_bound_its_points() {
        let flap = flume_flap();
        let far = Vector::<2>::new(-0.1, 0.5);
        let (bound, reach) = (flap.max_speed(), flap.reach(2));
        for i in 0..5000 {
            let k = flap.kinematics::<2>(i as f64 * 1e-3);
            let x = k.position(&far);
            assert!(f64::from(k.velocity_at(&x).norm()) <= bound * (1.0 + 1e-5));
            for c in 0..2 {
                assert!(f64::from((x[c] - far[c]).abs()) <= reach[c] + 1e-6);
            }
        }
    }
}
