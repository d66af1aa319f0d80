//! The scene file's keys of moving boundaries and wave flumes (`[[solid]] motion`,
//! `[damping_zone]`), as deserialized, before validation (`scene::validate::motion`).

use serde::Deserialize;

/// `[[solid]] motion = { kind = ..., ... }`: a prescribed rigid translation of the solid, of the
/// kind `kind` (default `"sway"`; `boundary::motion::Motion`). `t` is the simulated time \[s\].
///
/// - `kind = "sway"`: `motion = { amplitude = [A_x, A_y(, A_z)], period = T, ramp = t_r }`; the
///   solid translates by `d(t) = A r(t) sin(2π t / T)` \[m\].
/// - `kind = "piston"`: `motion = { kind = "piston", wave_height = H, period = T, depth = d,
///   direction = [n_x, n_y(, n_z)], ramp = t_r }`, a piston wave maker: the same translation
///   along the unit `direction` with the amplitude `S/2`, `S` the stroke that makes waves of
///   height `H` and period `T` on water `d` deep by first-order wave-maker theory
///   (`boundary::motion::Piston`, Dean & Dalrymple 1991 eqs. 4.20 and 6.20). Needs gravity.
/// - `kind = "series"`: `motion = { kind = "series", file = "stroke.csv", direction = [..] }`:
///   the displacement along the unit `direction` from a CSV file of `t_s, displacement_m`
///   samples (a header line first), joined by a natural cubic spline
///   (`boundary::series`); held at the first and last sample outside them. No period or ramp.
///
/// - `kind = "flap"`: `motion = { kind = "flap", hinge = [x, z] (3D [x, y, z]), wave_height = H,
///   period = T, depth = d, hinge_height = l, ramp = t_r }`, a flap wave maker: the solid turns
///   about the horizontal axis through `hinge` (2D: out of the plane; 3D: along `y`) by
///   `θ(t) = Θ r(t) sin(2π t / T)`, `θ > 0` moving its top towards `+x`; `Θ` makes waves of
///   height `H` on water `d` deep by first-order flap theory, the hinge `l` above the bed
///   (default 0; negative: below the bed) (`boundary::flap`, Dean & Dalrymple 1991 §6.2). Or
///   `angle = Θ` \[rad\] instead of `wave_height`, `depth` and `hinge_height`. Needs gravity
///   with `wave_height`.
/// - `kind = "piston"` or `"flap"` with `sea = { kind = "jonswap" | "focused", ... }` in place
///   of `wave_height` and `period` (and `angle`): the paddle makes an irregular sea or a
///   focused group (`SeaFile`, `boundary::sea_maker`); `depth`, `ramp` and the paddle's keys
///   stay.
///
/// Without `ramp` (or `ramp = 0`) `r = 1`; with it the amplitude grows from 0 over the first
/// `t_r` seconds as `r = s(t/t_r)`, `s(x) = 10x³ − 15x⁴ + 6x⁵`, whose first two derivatives
/// vanish at both ends, so the start is not impulsive (`boundary::motion` gives the exact
/// derivatives used for the wall velocity and acceleration). Rules: `amplitude` (sway) has
/// `dimension` finite entries, not all zero; `wave_height`, `depth` (piston) > 0; `direction`
/// (piston) has `dimension` finite entries, not all zero (it is normalised); `period` > 0;
/// `ramp` >= 0; a key of the other kind is an error; the solid swept over its amplitude per
/// axis stays inside the domain.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionFile {
    /// The kind of motion; default `sway`.
    pub kind: Option<MotionKind>,
    /// Sway: amplitude `A` \[m\], `dimension` entries.
    pub amplitude: Option<Vec<f64>>,
    /// Sway and piston: period `T` \[s\], > 0 (the piston's: the wave's).
    pub period: Option<f64>,
    /// Ramp time `t_r` \[s\], >= 0; default 0 (no ramp).
    pub ramp: Option<f64>,
    /// Piston: target wave height `H` \[m\], crest to trough, > 0.
    pub wave_height: Option<f64>,
    /// Piston: still-water depth `d` \[m\] in front of the piston, > 0.
    pub depth: Option<f64>,
    /// Piston and series: direction of the stroke, `dimension` entries, not all zero.
    pub direction: Option<Vec<f64>>,
    /// Series: the CSV file of the displacement samples, relative to the scene file's directory
    /// (or absolute).
    pub file: Option<String>,
    /// Flap: the hinge point \[m\], `dimension` entries.
    pub hinge: Option<Vec<f64>>,
    /// Flap: the hinge's height above the bed \[m\], below the still-water level (`< depth`);
    /// negative: below the bed. Default 0 (hinged at the bed).
    pub hinge_height: Option<f64>,
    /// Flap: the angle amplitude `Θ` \[rad\], not 0, instead of `wave_height` and `depth`.
    pub angle: Option<f64>,
    /// Piston and flap: the sea state to make, instead of `wave_height` and `period`
    /// (`SeaFile`).
    pub sea: Option<SeaFile>,
}

/// `motion.kind`: what prescribes a solid's translation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MotionKind {
    /// The amplitude is given.
    Sway,
    /// A piston wave maker: the amplitude from a target wave.
    Piston,
    /// A displacement time series read from a file.
    Series,
    /// A flap wave maker: a turn about a hinge.
    Flap,
}

/// `[damping_zone]`: `start = [x0..]`, `end = [x1..]` \[m\], `strength = β` \[1/s\]. Every step the
/// velocity of a fluid particle at `x` is multiplied by `max(0, 1 − Δt β r²)`, `r` the depth
/// past the plane through `start` towards the parallel plane through `end` as a fraction of
/// their distance, clamped to [0, 1] (`physics::damping_zone`, Altomare et al. 2017). Rules:
/// `start`, `end` have `dimension` finite entries and differ; `strength` > 0, default 10.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DampingZoneFile {
    /// A point of the plane where the damping starts (zero strength) \[m\].
    pub start: Vec<f64>,
    /// A point of the plane where it reaches full strength \[m\]; the zone's direction is
    /// from `start` to `end`.
    pub end: Vec<f64>,
    /// `β` \[1/s\], > 0; default 10 (DualSPHysics' `redumax`).
    pub strength: Option<f64>,
}

/// `motion.sea = { kind = ..., ... }` of a piston or flap wave maker: an irregular sea or a
/// focused group from a band of Goda's JONSWAP spectrum (`physics::sea_state`,
/// `boundary::sea_maker`), in place of the regular wave's `wave_height` and `period`.
///
/// - `kind = "jonswap"`: `significant_height = H_s` \[m\], `peak_period = T_p` \[s\], `seed`
///   (an integer >= 0), random phases;
/// - `kind = "focused"`: `amplitude = A` \[m\] (the linear crest at the focus),
///   `focus_position = x_f` \[m\] (from the paddle's mean face along the stroke),
///   `focus_time = t_f` \[s\], `peak_period = T_p`;
///
/// both with `gamma` (default 3.3, >= 1), `components` (default 128, 32 to 1024), `f_min`,
/// `f_max` \[Hz\] (default 0.5/T_p and 3/T_p).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeaFile {
    /// The kind of sea.
    pub kind: SeaKind,
    /// jonswap: significant wave height `H_s` \[m\], > 0.
    pub significant_height: Option<f64>,
    /// Peak period `T_p` \[s\], > 0.
    pub peak_period: Option<f64>,
    /// Peak enhancement `γ`, >= 1; default 3.3.
    pub gamma: Option<f64>,
    /// Number of components; default 128.
    pub components: Option<i64>,
    /// jonswap: the seed of the random phases, >= 0.
    pub seed: Option<i64>,
    /// Lower end of the band \[Hz\]; default `0.5 / T_p`.
    pub f_min: Option<f64>,
    /// Upper end of the band \[Hz\]; default `3 / T_p`.
    pub f_max: Option<f64>,
    /// focused: the linear crest `A` \[m\] at the focus, > 0.
    pub amplitude: Option<f64>,
    /// focused: the focus' distance `x_f` \[m\] from the paddle, > 0.
    pub focus_position: Option<f64>,
    /// focused: the focus' time `t_f` \[s\].
    pub focus_time: Option<f64>,
}

/// `motion.sea.kind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SeaKind {
    /// An irregular sea of random phases.
    Jonswap,
    /// A focused group (NewWave).
    Focused,
}
