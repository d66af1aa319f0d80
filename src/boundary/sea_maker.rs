//! A piston or flap wave maker driven by a sea state (scene `motion = { kind = "piston" |
//! "flap", sea = { ... }, ... }`): the target sea (`physics::sea_state`) is turned, component
//! by component, into the paddle's stroke at the still-water level by the wave maker's
//! first-order transfer function at that component's frequency ([DD91] §6.2,
//! `physics::waves`):
//!
//! ```text
//! a_i cos(ω_i t − k_i x − φ_i)  ←  X_i sin(ω_i t − φ_i),   X_i = a_i / (H/S)(k_i d)
//! X(t) = r(t) Σ_i X_i sin(ω_i t − φ_i)
//! ```
//!
//! the regular wave maker's pairing (`boundary::motion::Piston`: the stroke `(S/2) sin ωt`
//! makes `(H/2) cos(ωt − kx)`), `r` the ramp of `boundary::motion` (the product rule gives
//! `X'` and `X''`). A piston translates by `X(t)` along its direction; a flap turns about its
//! hinge by `θ = atan(X / (d − l))`, so it crosses the still-water level at `X`, with
//!
//! ```text
//! θ' = X' / ((d − l)(1 + u²)),   θ'' = X'' / ((d − l)(1 + u²)) − 2 u X'² / ((d − l)² (1 + u²)²),
//! u = X / (d − l)
//! ```
//!
//! (`boundary::flap` for the hinge's geometry). Displacement, velocity and acceleration are
//! therefore exact derivatives of one another, as the wall pressure needs ([A12] eq. 27).

use super::flap::Flap;
use super::motion::{Profile, along, ramp};
use super::rigid::{Rotation, SolidKinematics, Turn};
use crate::math::Vector;
use crate::physics::sea_state::{Sea, WaveComponents};
use crate::physics::waves::{flap_height_per_stroke, piston_height_per_stroke};
use std::f64::consts::TAU;

/// Most sine terms the sampled bounds may sum (`SeaMaker::signal_bounds`): about a second of
/// host time; the default band takes `19 N²`, 3e5 for 128 lines.
pub const MAX_BOUND_TERMS: f64 = 5e7;

/// The paddle that makes the sea.
#[derive(Clone, Debug, PartialEq)]
pub enum Paddle {
    /// A piston: translation along the unit `direction` (one entry per axis).
    Piston {
        /// Unit direction `n` of the stroke.
        direction: Vec<f64>,
    },
    /// A flap turning about a horizontal hinge (the axis of `boundary::flap`).
    Flap {
        /// The hinge point `c` [m], one entry per axis.
        hinge: Vec<f64>,
        /// The hinge's height `l` [m] above the bed, `< d`.
        hinge_height: f64,
        /// The largest distance [m] from the hinge to a point of the solid (`Flap::arm_to_box`).
        arm: f64,
    },
}

/// A wave maker driven by a sea state (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct SeaMaker {
    /// The paddle.
    pub paddle: Paddle,
    /// The target sea.
    pub sea: Sea,
    /// Still-water depth `d` [m] at the paddle, > 0.
    pub depth: f64,
    /// `|g|` [m/s²], > 0.
    pub gravity: f64,
    /// Ramp time `t_r` [s], >= 0.
    pub ramp: f64,
    /// The sea's components on this water (`Sea::components`).
    pub waves: WaveComponents,
    /// The stroke amplitudes `X_i` [m] at the still-water level.
    pub stroke: Vec<f64>,
    /// Upper bounds of `|Σ X_i sin(ω_i t − φ_i)|` [m] and of its rate [m/s] over all times.
    bounds: (f64, f64),
}

impl SeaMaker {
    /// The wave maker of `sea` by `paddle` on water `depth` [m] deep, gravity `gravity`
    /// [m/s²], ramp `ramp` [s]. Inputs are validated by the scene (`is_valid_in`).
    pub fn new(paddle: Paddle, sea: Sea, depth: f64, gravity: f64, ramp: f64) -> Self {
        let waves = sea.components(depth, gravity);
        let stroke = waves
            .amplitude
            .iter()
            .zip(&waves.wavenumber)
            .map(|(a, k)| {
                let kd = k * depth;
                let ratio = match &paddle {
                    Paddle::Piston { .. } => piston_height_per_stroke(kd),
                    Paddle::Flap { hinge_height, .. } => flap_height_per_stroke(kd, hinge_height / depth),
                };
                a / ratio
            })
            .collect();
        let mut maker = SeaMaker {
            paddle,
            sea,
            depth,
            gravity,
            ramp,
            waves,
            stroke,
            bounds: (0.0, 0.0),
        };
        maker.bounds = maker.signal_bounds();
        maker
    }

    /// The scene's name of the kind: `"piston"` or `"flap"`.
    pub fn kind_name(&self) -> &'static str {
        match self.paddle {
            Paddle::Piston { .. } => "piston",
            Paddle::Flap { .. } => "flap",
        }
    }

    /// The unramped stroke `Σ X_i sin(ω_i t − φ_i)` and its two time derivatives.
    fn signal(&self, t: f64) -> Profile {
        let mut p = Profile {
            value: 0.0,
            rate: 0.0,
            curvature: 0.0,
        };
        for (i, x) in self.stroke.iter().enumerate() {
            let w = TAU * self.waves.frequency[i];
            let (sin, cos) = (w * t - self.waves.phase[i]).sin_cos();
            p.value += x * sin;
            p.rate += x * w * cos;
            p.curvature -= x * w * w * sin;
        }
        p
    }

    /// The stroke `X(t)` [m] at the still-water level with the ramp, and its rate [m/s] and
    /// curvature [m/s²] (module doc).
    pub fn stroke_profile(&self, t: f64) -> Profile {
        let s = self.signal(t);
        let (r, r1, r2) = ramp(t, self.ramp);
        Profile {
            value: r * s.value,
            rate: r1 * s.value + r * s.rate,
            curvature: r2 * s.value + 2.0 * r1 * s.rate + r * s.curvature,
        }
    }

    /// The flap's lever `d − l` [m] (1 for a piston, unused).
    fn lever(&self) -> f64 {
        match &self.paddle {
            Paddle::Piston { .. } => 1.0,
            Paddle::Flap { hinge_height, .. } => self.depth - hinge_height,
        }
    }

    /// The flap's angle `θ` [rad] and its two time derivatives (module doc).
    pub fn flap_angle(&self, t: f64) -> Profile {
        let x = self.stroke_profile(t);
        let l = self.lever();
        let u = x.value / l;
        let q = 1.0 + u * u;
        Profile {
            value: u.atan(),
            rate: x.rate / (l * q),
            curvature: x.curvature / (l * q) - 2.0 * u * x.rate * x.rate / (l * l * q * q),
        }
    }

    /// The rigid motion at time `t` [s]: the piston's translation, or the flap's turn.
    pub fn kinematics<const D: usize>(&self, t: f64) -> SolidKinematics<D> {
        match &self.paddle {
            Paddle::Piston { direction } => along(direction, self.stroke_profile(t)),
            Paddle::Flap { hinge, .. } => {
                let a = self.flap_angle(t);
                SolidKinematics {
                    displacement: Vector::zeros(),
                    velocity: Vector::zeros(),
                    acceleration: Vector::zeros(),
                    rotation: Rotation::About(Turn::about_axis(
                        hinge,
                        Flap::axis::<D>(),
                        a.value,
                        a.rate,
                        a.curvature,
                    )),
                }
            }
        }
    }

    /// Bounds of `|Σ X_i sin(ω_i t − φ_i)|` and of its rate over all times: the largest of
    /// samples `δ = 1/(16 f_N)` apart over one repeat `1/Δf` (the sum is periodic), raised
    /// by `δ²/8 Σ X_i ω_i²` (resp. `ω_i³`): at an extremum the derivative vanishes, so the
    /// nearest sample, at most `δ/2` away, is within `max|f''| δ²/8` of it. Where that would
    /// take more than [`MAX_BOUND_TERMS`] terms, the sums `Σ|X_i|` and `Σ|X_i| ω_i`.
    fn signal_bounds(&self) -> (f64, f64) {
        let f_top = self.waves.frequency.iter().copied().fold(0.0, f64::max);
        let repeat = self.sea.band().repeat_period();
        if !(f_top > 0.0 && repeat.is_finite()) {
            return (0.0, 0.0);
        }
        let moment = |p: i32| -> f64 {
            self.stroke
                .iter()
                .zip(&self.waves.frequency)
                .map(|(x, f)| x.abs() * (TAU * f).powi(p))
                .sum()
        };
        let samples = (16.0 * f_top * repeat).ceil();
        if samples * self.stroke.len() as f64 > MAX_BOUND_TERMS {
            // A narrow band far from zero: the strict, looser bounds `Σ|X_i|`, `Σ|X_i| ω_i`.
            return (moment(0), moment(1));
        }
        let n = samples as usize;
        let delta = repeat / n as f64;
        let (mut reach, mut speed) = (0.0f64, 0.0f64);
        for j in 0..n {
            let s = self.signal(j as f64 * delta);
            reach = reach.max(s.value.abs());
            speed = speed.max(s.rate.abs());
        }
        let margin = delta * delta / 8.0;
        (reach + margin * moment(2), speed + margin * moment(3))
    }

    /// An upper bound of the stroke's speed `|X'|` [m/s] with the ramp:
    /// `max|X| · max s'/t_r + max|X'|`, `max s' = 15/8` (`Sway::max_speed`).
    fn stroke_speed(&self) -> f64 {
        let ramp = if self.ramp > 0.0 { 1.875 / self.ramp } else { 0.0 };
        self.bounds.0 * ramp + self.bounds.1
    }

    /// An upper bound of the speed [m/s] of any point of the solid: the stroke's for a piston;
    /// `arm · max|θ'| ≤ arm · max|X'| / (d − l)` for a flap.
    pub fn max_speed(&self) -> f64 {
        match &self.paddle {
            Paddle::Piston { .. } => self.stroke_speed(),
            Paddle::Flap { arm, .. } => arm * self.stroke_speed() / self.lever(),
        }
    }

    /// Per axis, an upper bound of how far a point of the solid moves [m]: `|n_k| max|X|` for a
    /// piston; the chord `2 arm sin(Θ/2)`, `Θ = atan(max|X| / (d − l))`, in the flap's plane.
    pub fn reach(&self) -> Vec<f64> {
        match &self.paddle {
            Paddle::Piston { direction } => direction.iter().map(|n| n.abs() * self.bounds.0).collect(),
            Paddle::Flap { hinge, arm, .. } => {
                let dim = hinge.len();
                let angle = (self.bounds.0 / self.lever()).atan();
                let chord = 2.0 * arm * (0.5 * angle).sin();
                (0..dim)
                    .map(|k| if dim == 3 && k == 1 { 0.0 } else { chord })
                    .collect()
            }
        }
    }

    /// Sets a flap's arm, the largest distance [m] from its hinge to the solid's box
    /// `min`..`max` (`Flap::arm_to_box`); nothing for a piston.
    pub fn set_arm_to_box(&mut self, min: &[f64], max: &[f64]) {
        if let Paddle::Flap { hinge, arm, .. } = &mut self.paddle {
            let far = |k: usize| {
                let c = hinge.get(k).copied().unwrap_or(0.0);
                (min[k] - c).abs().max((max[k] - c).abs())
            };
            *arm = (0..min.len().min(max.len()))
                .map(|k| far(k).powi(2))
                .sum::<f64>()
                .sqrt();
        }
    }

    /// The unit direction the waves leave the paddle in: the piston's stroke, `+x` for a flap
    /// (its top turns towards `+x` for `θ > 0`).
    pub fn wave_direction(&self) -> Vec<f64> {
        match &self.paddle {
            Paddle::Piston { direction } => direction.clone(),
            Paddle::Flap { hinge, .. } => (0..hinge.len()).map(|k| if k == 0 { 1.0 } else { 0.0 }).collect(),
        }
    }

    /// Whether the numbers make a finite motion in `dim` dimensions.
    pub fn is_valid_in(&self, dim: usize) -> bool {
        let paddle_ok = match &self.paddle {
            Paddle::Piston { direction } => direction.len() == dim && direction.iter().all(|n| n.is_finite()),
            Paddle::Flap {
                hinge,
                hinge_height,
                arm,
            } => {
                hinge.len() == dim
                    && hinge.iter().all(|c| c.is_finite())
                    && hinge_height.is_finite()
                    && *hinge_height < self.depth
                    && arm.is_finite()
            }
        };
        paddle_ok
            && [self.depth, self.gravity]
                .iter()
                .all(|v| v.is_finite() && *v > 0.0)
            && self.ramp.is_finite()
            && self.ramp >= 0.0
            && self.stroke.iter().all(|x| x.is_finite())
            && self.bounds.0.is_finite()
            && self.bounds.1.is_finite()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::sea_state::Band;

    fn band() -> Band {
        Band {
            peak_period: 1.1,
            gamma: 3.3,
            components: 128,
            f_min: 0.5 / 1.1,
            f_max: 3.0 / 1.1,
        }
    }

    fn irregular() -> Sea {
        Sea::Irregular {
            significant_height: 0.04,
            band: band(),
            seed: 1,
        }
    }

    fn focused() -> Sea {
        Sea::Focused {
            amplitude: 0.04,
            focus_position: 2.0,
            focus_time: 10.0,
            band: band(),
        }
    }

    fn piston(sea: Sea) -> SeaMaker {
        let paddle = Paddle::Piston {
            direction: vec![1.0, 0.0],
        };
        SeaMaker::new(paddle, sea, 0.3, 9.81, 2.2)
    }

    fn flap(sea: Sea) -> SeaMaker {
        let paddle = Paddle::Flap {
            hinge: vec![0.0, 0.0],
            hinge_height: 0.0,
            arm: 0.1f64.hypot(0.5),
        };
        SeaMaker::new(paddle, sea, 0.3, 9.81, 2.2)
    }

    /// Each stroke amplitude times the paddle's transfer function at its frequency is the
    /// component's wave amplitude (f64 rounding), for the piston and the bed-hinged flap.
    #[test]
    fn strokes_make_the_components_by_the_transfer_functions() {
        for maker in [piston(irregular()), flap(irregular())] {
            for i in 0..maker.stroke.len() {
                let kd = maker.waves.wavenumber[i] * 0.3;
                let ratio = match maker.paddle {
                    Paddle::Piston { .. } => piston_height_per_stroke(kd),
                    Paddle::Flap { .. } => flap_height_per_stroke(kd, 0.0),
                };
                let a = maker.waves.amplitude[i];
                assert!((maker.stroke[i] * ratio - a).abs() <= 1e-14 * a);
            }
        }
    }

    /// Velocity and acceleration are the derivatives of the displacement: central differences
    /// (ε = 1e-4 s) of `X` and `X'` match `X'` and `X''` within 1e-5 of the scale `max|X'|`,
    /// `max|X''|` (the O(ε²) truncation, `ε² |X'''|/6`, is below 1e-6 of it with frequencies up
    /// to 3 f_p = 2.7 Hz), in the ramp and after it; the same for a flap's angle, and the
    /// kinematics are these numbers rounded to f32.
    #[test]
    fn rates_are_the_derivatives_of_the_displacement() {
        let eps = 1e-4;
        for sea in [irregular(), focused()] {
            let (p, f) = (piston(sea.clone()), flap(sea));
            let scale_rate = p.bounds.1;
            let scale_curvature: f64 = p
                .stroke
                .iter()
                .zip(&p.waves.frequency)
                .map(|(x, f)| x * (TAU * f).powi(2))
                .sum();
            for i in 0..300 {
                let t = 0.013 + 0.04 * i as f64;
                let (lo, mid, hi) = (
                    p.stroke_profile(t - eps),
                    p.stroke_profile(t),
                    p.stroke_profile(t + eps),
                );
                let rate = (hi.value - lo.value) / (2.0 * eps);
                let curvature = (hi.rate - lo.rate) / (2.0 * eps);
                assert!(
                    (rate - mid.rate).abs() < 1e-5 * scale_rate,
                    "X' at {t}: {rate} vs {}",
                    mid.rate
                );
                assert!(
                    (curvature - mid.curvature).abs() < 1e-5 * scale_curvature,
                    "X'' at {t}: {curvature} vs {}",
                    mid.curvature
                );
                let k = p.kinematics::<2>(t);
                assert_eq!(k.displacement[0], mid.value as f32);
                assert_eq!(
                    (k.velocity[0], k.acceleration[0]),
                    (mid.rate as f32, mid.curvature as f32)
                );
                let (lo, mid, hi) = (f.flap_angle(t - eps), f.flap_angle(t), f.flap_angle(t + eps));
                let rate = (hi.value - lo.value) / (2.0 * eps);
                let curvature = (hi.rate - lo.rate) / (2.0 * eps);
                assert!((rate - mid.rate).abs() < 1e-5 * scale_rate / 0.3, "θ' at {t}");
                assert!(
                    (curvature - mid.curvature).abs() < 1e-5 * scale_curvature / 0.3,
                    "θ'' at {t}"
                );
                // 2D: the hinge axis is −z, so ω_z = −θ'.
                let Rotation::About(turn) = f.kinematics::<2>(t).rotation else {
                    panic!("a flap turns")
                };
                assert_eq!(turn.angular_velocity[2], -(mid.rate as f32));
            }
            // The flap crosses the still-water level at the stroke: (d − l) tan θ = X.
            let (x, a) = (f.stroke_profile(7.3).value, f.flap_angle(7.3).value);
            assert!((0.3 * a.tan() - x).abs() < 1e-15);
        }
    }

    /// The ramp starts the paddle from rest (X, X', X'' all 0 at t = 0); the speed and reach
    /// bounds hold at every sample of a repeat (every 2 ms) and are within 5 % of the largest
    /// sampled values past the ramp (the bound is the sampled maximum plus a margin).
    #[test]
    fn bounds_hold_and_are_close() {
        for maker in [piston(irregular()), piston(focused()), flap(irregular())] {
            let start = maker.stroke_profile(0.0);
            assert_eq!((start.value, start.rate, start.curvature), (0.0, 0.0, 0.0));
            let (speed, reach) = (maker.max_speed(), maker.reach());
            let repeat = maker.sea.band().repeat_period();
            let (mut fastest, mut farthest) = (0.0f64, 0.0f64);
            let far = Vector::<2>::new(-0.1, 0.5);
            for j in 0..(repeat / 0.002) as usize {
                let t = j as f64 * 0.002;
                let k = maker.kinematics::<2>(t);
                let x = k.position(&far);
                let u = f64::from(k.velocity_at(&x).norm());
                let moved = f64::from((x[0] - far[0]).abs());
                assert!(u <= speed * (1.0 + 1e-5), "speed {u} above {speed} at {t}");
                assert!(
                    moved <= reach[0] + 1e-6,
                    "reach {moved} above {} at {t}",
                    reach[0]
                );
                if t > maker.ramp {
                    fastest = fastest.max(u);
                    farthest = farthest.max(moved);
                }
            }
            if let Paddle::Piston { .. } = maker.paddle {
                assert!(farthest > 0.95 * reach[0], "reach {} loose: {farthest}", reach[0]);
                assert!(fastest > 0.95 * maker.bounds.1, "speed loose: {fastest}");
            }
        }
    }
}
