//! A piston's or flap's `motion` with `sea` (`schema::SeaFile`) into a [`SeaMaker`]: the
//! wave maker's keys, then the sea's (`physics::sea_state`).

use super::*;
use crate::boundary::sea_maker::{Paddle, SeaMaker};
use crate::physics::sea_state::{Band, Sea};
use crate::physics::waves::wavenumber;
use crate::scene::schema::{MotionKind, SeaFile, SeaKind};
use std::f64::consts::TAU;

/// Fewest components: with the default band (2.5 `f_p` wide) 32 lines are `0.08 f_p` apart,
/// about the width `σ f_p` (σ = 0.07, 0.09) of the JONSWAP peak; fewer do not resolve it.
pub const MIN_COMPONENTS: i64 = 32;
/// Most components: the sea is summed on the host every stage, and its bounds sampled over a
/// repeat (`SeaMaker::new`) at a cost that grows as `N²`.
pub const MAX_COMPONENTS: i64 = 1024;
/// Default number of components: lines `0.02 f_p` apart, a repeat of 51 peak periods.
pub const DEFAULT_COMPONENTS: i64 = 128;
/// Default peak enhancement, the mean JONSWAP sea (Hasselmann et al. 1973).
pub const DEFAULT_GAMMA: f64 = 3.3;
/// Largest peak enhancement: measured JONSWAP seas lie in `1 ≤ γ ≤ 7` (Goda 2000, §2.3,
/// the range of his fit).
pub const MAX_GAMMA: f64 = 7.0;
/// Default band `[0.5, 3] f_p`: below `0.5 f_p` the spectrum is below `e⁻²⁰` of its scale;
/// above `3 f_p` lies 1.0 % of `m_0` at γ = 3.3 (`physics::sea_state`).
pub const DEFAULT_BAND: (f64, f64) = (0.5, 3.0);

/// `motion` of kind piston or flap with `sea`: `depth` (> 0), `ramp` (>= 0, default 0), the
/// paddle's keys (piston: `direction`; flap: `hinge`, `hinge_height` below `depth`), gravity,
/// and the sea; the regular wave's `wave_height` and `period`, and any other kind's key, are
/// errors. A focus must leave the paddle after the ramp: `t_f ≥ t_r + x_f / c_g(f_p)`.
pub(super) fn check_sea_motion(
    c: &mut Checker,
    path: &KeyPath,
    m: &MotionFile,
    kind: MotionKind,
    dim: Option<usize>,
    g: Option<f64>,
) -> Option<Motion> {
    let (name, paddle_keys): (&str, &[&str]) = match kind {
        MotionKind::Flap => ("flap", &["hinge", "hinge_height"]),
        _ => ("piston", &["direction"]),
    };
    let given = [
        ("amplitude", m.amplitude.is_some()),
        ("period", m.period.is_some()),
        ("wave_height", m.wave_height.is_some()),
        ("file", m.file.is_some()),
        ("angle", m.angle.is_some()),
        ("direction", m.direction.is_some()),
        ("hinge", m.hinge.is_some()),
        ("hinge_height", m.hinge_height.is_some()),
    ];
    let mut ok = true;
    for (key, present) in given {
        if present && !paddle_keys.contains(&key) {
            c.err(
                path.k(key),
                format!(
                    "not a key of motion.kind = \"{name}\" with `sea` (the sea sets the waves; remove it)"
                ),
            );
            ok = false;
        }
    }
    let depth = match m.depth {
        Some(d) => c.positive(path.k("depth"), d),
        None => {
            c.err(path.k("depth"), "required with `sea`".into());
            None
        }
    };
    let ramp = match m.ramp {
        Some(r) => c.non_negative(path.k("ramp"), r),
        None => Some(0.0),
    };
    let gravity = g.filter(|g| *g > 0.0);
    if gravity.is_none() {
        c.err(
            path.k("kind"),
            "a wave maker with `sea` needs gravity (effect \"gravity\" with a non-zero fluid.gravity): its strokes come from the dispersion relation of gravity waves".into(),
        );
    }
    let paddle = match kind {
        MotionKind::Flap => {
            let hinge = match &m.hinge {
                Some(h) => c.vector(path.k("hinge"), h, dim),
                None => {
                    c.err(path.k("hinge"), "required for motion.kind = \"flap\"".into());
                    None
                }
            };
            let hinge_height = m.hinge_height.unwrap_or(0.0);
            let below = match depth {
                Some(d) if !(hinge_height.is_finite() && hinge_height < d) => {
                    c.err(
                        path.k("hinge_height"),
                        format!("must be finite and below the still-water level (< depth = {d}), got {hinge_height}"),
                    );
                    None
                }
                _ => Some(hinge_height),
            };
            Some(Paddle::Flap {
                hinge: hinge?,
                hinge_height: below?,
                arm: 0.0,
            })
        }
        _ => super::motion::check_direction(c, path, m, dim).map(|direction| Paddle::Piston { direction }),
    };
    let sea_path = path.k("sea");
    let sea = check_sea(c, &sea_path, m.sea.as_ref()?);
    let (paddle, sea, depth, gravity, ramp) = (paddle?, sea?, depth?, gravity?, ramp?);
    if let Sea::Focused {
        focus_position,
        focus_time,
        band,
        ..
    } = &sea
    {
        let w = TAU / band.peak_period;
        let k = wavenumber(w, depth, gravity);
        let kd2 = 2.0 * k * depth;
        let group = 0.5 * (w / k) * (1.0 + kd2 / kd2.sinh());
        let earliest = ramp + focus_position / group;
        if *focus_time < earliest {
            c.err(
                sea_path.k("focus_time"),
                format!(
                    "{focus_time} s is before the group can reach the focus: the ramp ({ramp} s) plus x_f / c_g = {} s at the peak's group speed {} m/s (give focus_time >= {} s)",
                    num(focus_position / group),
                    num(group),
                    num(earliest)
                ),
            );
            return None;
        }
    }
    let maker = SeaMaker::new(paddle, sea, depth, gravity, ramp);
    if dim.is_some_and(|d| !maker.is_valid_in(d)) {
        c.err(
            sea_path,
            "its components give no finite stroke (a band of frequencies too high for f64 arithmetic): check peak_period, f_min and f_max".into(),
        );
        return None;
    }
    ok.then_some(Motion::Sea(maker))
}

/// `motion.sea`: the keys of its kind (module doc of `schema::SeaFile`); a key of the other
/// kind is an error.
fn check_sea(c: &mut Checker, path: &KeyPath, s: &SeaFile) -> Option<Sea> {
    let (name, foreign) = match s.kind {
        SeaKind::Jonswap => (
            "jonswap",
            vec![
                ("amplitude", s.amplitude.is_some()),
                ("focus_position", s.focus_position.is_some()),
                ("focus_time", s.focus_time.is_some()),
            ],
        ),
        SeaKind::Focused => (
            "focused",
            vec![
                ("significant_height", s.significant_height.is_some()),
                ("seed", s.seed.is_some()),
            ],
        ),
    };
    let mut ok = true;
    for (key, present) in foreign {
        if present {
            c.err(
                path.k(key),
                format!("not a key of sea.kind = \"{name}\" (remove it, or choose the kind it belongs to)"),
            );
            ok = false;
        }
    }
    let required = |c: &mut Checker, key: &str, v: Option<f64>| match v {
        Some(v) => c.positive(path.k(key), v),
        None => {
            c.err(path.k(key), format!("required for sea.kind = \"{name}\""));
            None
        }
    };
    let peak_period = required(c, "peak_period", s.peak_period);
    let band = check_band(c, path, s, peak_period);
    let sea = match s.kind {
        SeaKind::Jonswap => {
            let hs = required(c, "significant_height", s.significant_height);
            let seed = match s.seed {
                Some(seed) if seed >= 0 => Some(seed as u64),
                Some(seed) => {
                    c.err(path.k("seed"), format!("must be an integer >= 0, got {seed}"));
                    None
                }
                None => {
                    c.err(
                        path.k("seed"),
                        "required for sea.kind = \"jonswap\" (it picks the random phases)".into(),
                    );
                    None
                }
            };
            Sea::Irregular {
                significant_height: hs?,
                band: band?,
                seed: seed?,
            }
        }
        SeaKind::Focused => {
            let amplitude = required(c, "amplitude", s.amplitude);
            let x_f = required(c, "focus_position", s.focus_position);
            let t_f = match s.focus_time {
                Some(t) => c.finite(path.k("focus_time"), t),
                None => {
                    c.err(path.k("focus_time"), "required for sea.kind = \"focused\"".into());
                    None
                }
            };
            Sea::Focused {
                amplitude: amplitude?,
                focus_position: x_f?,
                focus_time: t_f?,
                band: band?,
            }
        }
    };
    ok.then_some(sea)
}

/// The band: `gamma` in [1, 7], `components` in [32, 1024], `0 < f_min < 1/T_p < f_max`.
fn check_band(c: &mut Checker, path: &KeyPath, s: &SeaFile, peak_period: Option<f64>) -> Option<Band> {
    let gamma = s.gamma.unwrap_or(DEFAULT_GAMMA);
    let gamma_ok = (1.0..=MAX_GAMMA).contains(&gamma);
    if !gamma_ok {
        c.err(
            path.k("gamma"),
            format!(
                "must be in [1, {MAX_GAMMA}] (1: Pierson-Moskowitz; measured seas lie in this range), got {}",
                num(gamma)
            ),
        );
    }
    let n = s.components.unwrap_or(DEFAULT_COMPONENTS);
    let n_ok = (MIN_COMPONENTS..=MAX_COMPONENTS).contains(&n);
    if !n_ok {
        c.err(
            path.k("components"),
            format!("must be in [{MIN_COMPONENTS}, {MAX_COMPONENTS}] (fewer lines do not resolve the spectrum's peak), got {n}"),
        );
    }
    let tp = peak_period?;
    let fp = 1.0 / tp;
    let f_min = match s.f_min {
        Some(f) => c.positive(path.k("f_min"), f),
        None => Some(DEFAULT_BAND.0 * fp),
    };
    let f_max = match s.f_max {
        Some(f) => c.positive(path.k("f_max"), f),
        None => Some(DEFAULT_BAND.1 * fp),
    };
    let (f_min, f_max) = (f_min?, f_max?);
    if !(f_min < fp && fp < f_max) {
        let key = if f_min >= fp { "f_min" } else { "f_max" };
        c.err(
            path.k(key),
            format!(
                "the band [{}, {}] Hz must hold the peak frequency 1/peak_period = {} Hz inside it",
                num(f_min),
                num(f_max),
                num(fp)
            ),
        );
        return None;
    }
    (gamma_ok && n_ok).then_some(Band {
        peak_period: tp,
        gamma,
        components: n as usize,
        f_min,
        f_max,
    })
}
