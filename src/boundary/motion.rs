//! Prescribed rigid motion of a solid (scene `[[solid]] motion = { kind = ..., ... }`), one of
//! the kinds of [`Motion`]: a sway, the forcing of a sloshing tank, a piston wave maker
//! ([`Piston`]), the same translation with its stroke from first-order wave-maker theory, a
//! displacement time series (`boundary::series`), or a flap wave maker (`boundary::flap`), which
//! turns the solid about a hinge by an angle of the same profile (`boundary::rigid`).
//!
//! The translations move the solid as a whole by `d(t) = A f(t)` [m], with the amplitude vector
//! `A` [m] and the scalar profile
//!
//! ```text
//! f(t) = r(t) sin(ω t),   ω = 2π / T,
//! r(t) = s(t / t_r) for t < t_r, 1 after,   s(x) = 10 x³ − 15 x⁴ + 6 x⁵   (t_r > 0)
//! r(t) = 1                                                                  (t_r = 0)
//! ```
//!
//! `s` is the quintic "smootherstep": `s(0) = 0`, `s(1) = 1` and its first and second derivatives
//! vanish at both ends, so the ramped displacement, velocity and acceleration are continuous at
//! `t = 0` and `t = t_r`: the tank starts from rest without an impulse, and the wall acceleration
//! that enters the wall pressure ([A12] eq. 27, `boundary::wall_pressure`) has no jump. The
//! velocity and acceleration are the exact derivatives (product rule):
//!
//! ```text
//! f'  = r' sin(ωt) + r ω cos(ωt)
//! f'' = r'' sin(ωt) + 2 r' ω cos(ωt) − r ω² sin(ωt)
//! r'  = s'(x)/t_r,  r'' = s''(x)/t_r²,  s'(x) = 30 x² (1 − x)²,  s''(x) = 60 x (1 − x)(1 − 2x)
//! ```
//!
//! Without a ramp this is `d = A sin(ωt)`, `d' = A ω cos(ωt)`, `d'' = −A ω² sin(ωt)`. Times are
//! simulated time [s] from the start of the run. Evaluated in f64 and rounded to f32 once, so
//! both backends place the particles from the same numbers.

use super::flap::Flap;
pub use super::rigid::{Rotation, SolidKinematics, Turn};
use super::sea_maker::SeaMaker;
use super::series::DisplacementSeries;
use crate::math::{Real, Vector};

/// A rigid sway `d(t) = A r(t) sin(2π t / T)` (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Sway {
    /// Amplitude `A` [m], one entry per axis (the scene's dimension).
    pub amplitude: Vec<f64>,
    /// Period `T` [s], > 0.
    pub period: f64,
    /// Ramp time `t_r` [s], >= 0 (0: no ramp).
    pub ramp: f64,
}

/// A solid's prescribed motion, the kind the scene chooses (`motion.kind`). Each kind is a
/// rigid motion, a translation `d(t)` or (the flap) a turn about a hinge; the stages
/// (`move_solids`, `wall_pressure`) only see its kinematics (`boundary::rigid`).
#[derive(Clone, Debug, PartialEq)]
pub enum Motion {
    /// `kind = "sway"` (the default): the amplitude is given.
    Sway(Sway),
    /// `kind = "piston"`: the amplitude is the stroke that makes a wave of the given height.
    Piston(Piston),
    /// `kind = "series"`: the displacement along a direction from a time series.
    Series(DisplacementSeries),
    /// `kind = "flap"`: a turn about a hinge, its angle given or from a target wave.
    Flap(Flap),
    /// `kind = "piston"` or `"flap"` with `sea`: a wave maker driven by an irregular or a
    /// focused sea (`boundary::sea_maker`).
    Sea(SeaMaker),
}

impl From<Sway> for Motion {
    fn from(sway: Sway) -> Self {
        Motion::Sway(sway)
    }
}

impl Motion {
    /// The scene's name of the kind.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Motion::Sway(_) => "sway",
            Motion::Piston(_) => "piston",
            Motion::Series(_) => "series",
            Motion::Flap(_) => "flap",
            Motion::Sea(s) => s.kind_name(),
        }
    }

    /// The sinusoidal translation the solid performs (`None` for a time series and a flap).
    pub fn sway(&self) -> Option<Sway> {
        match self {
            Motion::Sway(s) => Some(s.clone()),
            Motion::Piston(p) => Some(p.sway()),
            Motion::Series(_) | Motion::Flap(_) | Motion::Sea(_) => None,
        }
    }

    /// The rigid motion at time `t` [s] ([`Sway::kinematics`], the series' spline along its
    /// direction, or the flap's turn, `Flap::kinematics`).
    pub fn kinematics<const D: usize>(&self, t: f64) -> SolidKinematics<D> {
        match self {
            Motion::Sway(s) => s.kinematics(t),
            Motion::Piston(p) => p.sway().kinematics(t),
            Motion::Series(s) => along(&s.direction, s.profile(t)),
            Motion::Flap(f) => f.kinematics(t),
            Motion::Sea(s) => s.kinematics(t),
        }
    }

    /// An upper bound of the solid's speed [m/s] ([`Sway::max_speed`],
    /// `DisplacementSeries::bounds`).
    pub fn max_speed(&self) -> f64 {
        match self {
            Motion::Series(s) => s.bounds().1,
            Motion::Flap(f) => f.max_speed(),
            Motion::Sea(s) => s.max_speed(),
            _ => self.sway().map_or(0.0, |s| s.max_speed()),
        }
    }

    /// Per axis, an upper bound of `|d_k(t)|` [m] over all times (of how far a point of a flap
    /// moves, `Flap::reach`): how far the solid sweeps.
    pub fn reach(&self) -> Vec<f64> {
        match self {
            Motion::Series(s) => s.direction.iter().map(|n| n.abs() * s.bounds().0).collect(),
            Motion::Flap(f) => f.reach(f.hinge.len()),
            Motion::Sea(s) => s.reach(),
            _ => self
                .sway()
                .map(|s| s.amplitude.iter().map(|a| a.abs()).collect())
                .unwrap_or_default(),
        }
    }
}

/// Kinematics of the scalar profile `f` along the vector `v` (`v f`, `v f'`, `v f''`), rounded
/// to f32.
pub(crate) fn along<const D: usize>(v: &[f64], f: Profile) -> SolidKinematics<D> {
    let scaled = |c: f64| Vector::<D>::from_fn(|k, _| (v.get(k).copied().unwrap_or(0.0) * c) as Real);
    SolidKinematics {
        displacement: scaled(f.value),
        velocity: scaled(f.rate),
        acceleration: scaled(f.curvature),
        rotation: Rotation::None,
    }
}

/// A piston wave maker: a rigid translation along `direction` whose stroke makes, by linear
/// wave-maker theory, a progressive wave of height `H` and period `T` on water `d` deep
/// (`physics::waves`, [DD91] Dean & Dalrymple 1991, §6.2):
///
/// ```text
/// ω² = g k tanh(k d)                              (dispersion, [DD91] eq. 4.20)
/// S = H / (2 (cosh 2kd − 1) / (sinh 2kd + 2kd))   (Biésel's transfer function, [DD91] eq. 6.20)
/// d(t) = (S/2) n r(t) sin(ω t)                    (the sway of amplitude S/2 along the unit n)
/// ```
///
/// with the ramp `r` of the module doc. The wave is first-order: its height is `H` far (a few
/// depths) from the piston, where the evanescent modes of the paddle have died out.
#[derive(Clone, Debug, PartialEq)]
pub struct Piston {
    /// Target wave height `H` [m] (crest to trough), > 0.
    pub wave_height: f64,
    /// Wave period `T` [s], > 0.
    pub period: f64,
    /// Still-water depth `d` [m] at the piston, > 0.
    pub depth: f64,
    /// `|g|` [m/s²], > 0: the scene's gravity.
    pub gravity: f64,
    /// Unit direction `n` of the stroke, one entry per axis.
    pub direction: Vec<f64>,
    /// Ramp time `t_r` [s], >= 0 (0: no ramp).
    pub ramp: f64,
}

impl Piston {
    /// The wavenumber `k` [1/m] of the wave ([DD91] eq. 4.20).
    pub fn wavenumber(&self) -> f64 {
        crate::physics::waves::wavenumber(std::f64::consts::TAU / self.period, self.depth, self.gravity)
    }

    /// The wavelength `L = 2π/k` [m].
    pub fn wavelength(&self) -> f64 {
        std::f64::consts::TAU / self.wavenumber()
    }

    /// The stroke `S` [m], the piston's full excursion: `H` over Biésel's `H/S` ([DD91] eq. 6.20).
    pub fn stroke(&self) -> f64 {
        let kd = self.wavenumber() * self.depth;
        self.wave_height / crate::physics::waves::piston_height_per_stroke(kd)
    }

    /// The translation: amplitude `S/2` along `direction`, the wave's period and the ramp.
    pub fn sway(&self) -> Sway {
        let half = 0.5 * self.stroke();
        Sway {
            amplitude: self.direction.iter().map(|n| half * n).collect(),
            period: self.period,
            ramp: self.ramp,
        }
    }
}

/// The scalar profile `f` of a [`Sway`] and its first two time derivatives at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    /// `f(t)` (dimensionless).
    pub value: f64,
    /// `f'(t)` [1/s].
    pub rate: f64,
    /// `f''(t)` [1/s²].
    pub curvature: f64,
}

/// The reference positions `x0` of the solid particles, indexed by particle id.
///
/// The solid particles are the ids `first_id..first_id + position.len()` (the simulation appends
/// them after the fluid). Indexed by id, not by the cell-sorted order of `Fields`, so a sort
/// never permutes it; it is built from the scene, so a checkpoint does not store it and a
/// restart rebuilds the same values bit for bit.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SolidReference<const D: usize> {
    /// Id of the first solid particle.
    pub first_id: u32,
    /// `x0` [m] of solid particle `first_id + k` at index `k`.
    pub position: Vec<Vector<D>>,
}

/// `s(x) = 10x³ − 15x⁴ + 6x⁵` and its first two derivatives, for `x` in [0, 1].
fn smootherstep(x: f64) -> (f64, f64, f64) {
    let y = 1.0 - x;
    (
        x * x * x * (10.0 - 15.0 * x + 6.0 * x * x),
        30.0 * x * x * y * y,
        60.0 * x * y * (1.0 - 2.0 * x),
    )
}

/// The ramp `r(t)` of the module doc and its first two derivatives [1/s, 1/s²]: `s(t/t_r)`
/// before `t_r`, 1 after (and always 1 when `t_r = 0`).
pub(crate) fn ramp(t: f64, t_r: f64) -> (f64, f64, f64) {
    if t_r > 0.0 && t < t_r {
        let (s, s1, s2) = smootherstep(t.max(0.0) / t_r);
        (s, s1 / t_r, s2 / (t_r * t_r))
    } else {
        (1.0, 0.0, 0.0)
    }
}

impl Sway {
    /// Angular frequency `ω = 2π/T` [rad/s].
    pub fn omega(&self) -> f64 {
        std::f64::consts::TAU / self.period
    }

    /// The profile `f`, `f'`, `f''` at time `t` [s] (module doc).
    pub fn profile(&self, t: f64) -> Profile {
        let w = self.omega();
        let (sin, cos) = (w * t).sin_cos();
        let (r, r1, r2) = ramp(t, self.ramp);
        Profile {
            value: r * sin,
            rate: r1 * sin + r * w * cos,
            curvature: r2 * sin + 2.0 * r1 * w * cos - r * w * w * sin,
        }
    }

    /// Displacement, velocity and acceleration at time `t` [s], rounded to f32.
    pub fn kinematics<const D: usize>(&self, t: f64) -> SolidKinematics<D> {
        along(&self.amplitude, self.profile(t))
    }

    /// An upper bound of the speed `|d'(t)|` [m/s] over all times: `|A| (ω + max s'/t_r)`, with
    /// `max s' = 15/8` at `x = 1/2`. The time step treats it as a flow speed, so a wall never
    /// moves more than the CFL fraction of `h` in one step.
    pub fn max_speed(&self) -> f64 {
        let a = self.amplitude.iter().map(|c| c * c).sum::<f64>().sqrt();
        let ramp = if self.ramp > 0.0 { 1.875 / self.ramp } else { 0.0 };
        a * (self.omega() + ramp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central differences of `f` and `f'` agree with `f'` and `f''` to O(ε²): with ε = 1e-5 s
    /// and |f'''| ≲ (ω + 30/t_r)³, the error is below 1e-6 relative to the scale `ω²` here.
    #[test]
    fn derivatives_match_finite_differences_with_and_without_ramp() {
        for ramp in [0.0, 0.7] {
            let sway = Sway {
                amplitude: vec![0.05, 0.0],
                period: 1.3,
                ramp,
            };
            let w = sway.omega();
            let eps = 1e-5;
            for i in 0..400 {
                let t = 0.005 + i as f64 * 0.01;
                let (lo, mid, hi) = (sway.profile(t - eps), sway.profile(t), sway.profile(t + eps));
                let rate = (hi.value - lo.value) / (2.0 * eps);
                let curvature = (hi.rate - lo.rate) / (2.0 * eps);
                assert!(
                    (rate - mid.rate).abs() < 1e-6 * w,
                    "f' at t = {t}, ramp {ramp}: {rate} vs {}",
                    mid.rate
                );
                assert!(
                    (curvature - mid.curvature).abs() < 1e-6 * w * w,
                    "f'' at t = {t}, ramp {ramp}: {curvature} vs {}",
                    mid.curvature
                );
            }
        }
    }

    /// The ramp starts from rest (f, f', f'' all zero at t = 0), joins the pure sine with
    /// continuous f, f', f'' at t = t_r, and the speed bound holds everywhere.
    #[test]
    fn ramp_starts_from_rest_and_joins_the_sine_smoothly() {
        let sway = Sway {
            amplitude: vec![0.03, 0.04],
            period: 0.9,
            ramp: 0.5,
        };
        let start = sway.profile(0.0);
        assert_eq!((start.value, start.rate, start.curvature), (0.0, 0.0, 0.0));
        let (before, after) = (sway.profile(0.5 - 1e-12), sway.profile(0.5));
        let pure = Sway {
            ramp: 0.0,
            ..sway.clone()
        }
        .profile(0.5);
        assert_eq!(after, pure, "past the ramp the profile is the pure sine");
        assert!((before.value - after.value).abs() < 1e-9);
        assert!((before.rate - after.rate).abs() < 1e-8);
        assert!((before.curvature - after.curvature).abs() < 1e-6);
        let bound = sway.max_speed();
        let speed = |t: f64| {
            let v = sway.kinematics::<2>(t).velocity;
            f64::from(v.norm())
        };
        let fastest = (0..2000).map(|i| speed(i as f64 * 1e-3)).fold(0.0, f64::max);
        assert!(
            fastest <= bound * (1.0 + 1e-6),
            "speed {fastest} above the bound {bound}"
        );
        assert!(
            fastest > 0.5 * bound,
            "the bound {bound} is not loose by more than 2x ({fastest})"
        );
    }

    /// The piston's stroke makes H from Biésel's function: S H/S = H, the amplitude S/2 along
    /// the unit direction, and k solves the dispersion relation (each to f64 rounding).
    #[test]
    fn piston_sways_by_half_the_stroke_biesel_gives() {
        let piston = Piston {
            wave_height: 0.03,
            period: 1.1,
            depth: 0.3,
            gravity: 9.81,
            direction: vec![1.0, 0.0],
            ramp: 2.0,
        };
        let (k, d) = (piston.wavenumber(), piston.depth);
        let w = std::f64::consts::TAU / piston.period;
        assert!((9.81 * k * (k * d).tanh() / (w * w) - 1.0).abs() < 1e-12);
        let ratio = crate::physics::waves::piston_height_per_stroke(k * d);
        assert!((piston.stroke() * ratio / piston.wave_height - 1.0).abs() < 1e-12);
        let motion = Motion::Piston(piston.clone());
        let sway = motion.sway().expect("a sine");
        assert_eq!(sway.amplitude, vec![0.5 * piston.stroke(), 0.0]);
        assert_eq!((sway.period, sway.ramp), (1.1, 2.0));
        assert_eq!(motion.kinematics::<2>(3.7), sway.kinematics::<2>(3.7));
        assert_eq!(motion.max_speed(), sway.max_speed());
    }

    /// Without a ramp, d = A sin(ωt) exactly at quarter periods.
    #[test]
    fn no_ramp_is_the_plain_sine() {
        let sway = Sway {
            amplitude: vec![0.1, 0.0, -0.2],
            period: 2.0,
            ramp: 0.0,
        };
        let k = sway.kinematics::<3>(0.5);
        assert_eq!(k.displacement, Vector::<3>::new(0.1, 0.0, -0.2));
        let w = std::f64::consts::PI;
        let k0 = sway.kinematics::<3>(0.0);
        assert_eq!(
            k0.velocity,
            Vector::<3>::new((0.1 * w) as f32, 0.0, (-0.2 * w) as f32)
        );
        assert!((f64::from(k.acceleration[0]) + 0.1 * w * w).abs() < 1e-6);
    }
}
