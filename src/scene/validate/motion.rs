//! A solid's `motion` table (`schema::MotionFile`) into a [`Motion`] of the kind it names, and
//! the `[damping_zone]` table, the wave flume's other end.

use super::*;
use crate::boundary::flap::{Flap, FlapAmplitude};
use crate::boundary::motion::{Motion, Piston};
use crate::boundary::series::DisplacementSeries;
use crate::scene::DampingZoneSpec;
use crate::scene::schema::{DampingZoneFile, MotionKind};

/// A solid's `motion` table: the keys of its kind (sway: finite amplitudes, not all zero;
/// piston: positive wave height and depth, a direction not zero, and gravity `g` [m/s²], the
/// scene's `|fluid.gravity|`; both a positive period and a non-negative ramp; series: a
/// direction not zero and a readable file of samples, relative to `dir`); a key of another kind
/// is an error. The swept box is checked with the geometry.
pub(super) fn check_motion(
    c: &mut Checker,
    path: &KeyPath,
    m: &MotionFile,
    dim: Option<usize>,
    g: Option<f64>,
    dir: &Path,
) -> Option<Motion> {
    let kind = m.kind.unwrap_or(MotionKind::Sway);
    if m.sea.is_some() && matches!(kind, MotionKind::Piston | MotionKind::Flap) {
        return super::sea::check_sea_motion(c, path, m, kind, dim, g);
    }
    let kind_name = match kind {
        MotionKind::Sway => "sway",
        MotionKind::Piston => "piston",
        MotionKind::Series => "series",
        MotionKind::Flap => "flap",
    };
    let flap_keys = [
        ("hinge", m.hinge.is_some()),
        ("hinge_height", m.hinge_height.is_some()),
        ("angle", m.angle.is_some()),
    ];
    let own: Vec<(&str, bool)> = match kind {
        MotionKind::Sway => vec![
            ("wave_height", m.wave_height.is_some()),
            ("depth", m.depth.is_some()),
            ("direction", m.direction.is_some()),
            ("file", m.file.is_some()),
            ("sea", m.sea.is_some()),
        ],
        MotionKind::Piston => vec![("amplitude", m.amplitude.is_some()), ("file", m.file.is_some())],
        MotionKind::Series => vec![
            ("amplitude", m.amplitude.is_some()),
            ("wave_height", m.wave_height.is_some()),
            ("depth", m.depth.is_some()),
            ("period", m.period.is_some()),
            ("ramp", m.ramp.is_some()),
            ("sea", m.sea.is_some()),
        ],
        MotionKind::Flap => vec![
            ("amplitude", m.amplitude.is_some()),
            ("direction", m.direction.is_some()),
            ("file", m.file.is_some()),
        ],
    };
    // The flap's own keys belong to no other kind.
    let foreign: Vec<(&str, bool)> = match kind {
        MotionKind::Flap => own,
        _ => own.into_iter().chain(flap_keys).collect(),
    };
    let mut ok = true;
    for (key, given) in foreign {
        if given {
            c.err(
                path.k(key),
                format!(
                    "not a key of motion.kind = \"{kind_name}\" (remove it, or choose the kind it belongs to)"
                ),
            );
            ok = false;
        }
    }
    // A series has neither period nor ramp (refused above as foreign keys).
    let timed = kind != MotionKind::Series;
    let period = match (m.period, timed) {
        (Some(t), true) => c.positive(path.k("period"), t),
        (None, true) => {
            c.err(
                path.k("period"),
                format!("required for motion.kind = \"{kind_name}\""),
            );
            None
        }
        (_, false) => None,
    };
    let ramp = match m.ramp {
        Some(r) if timed => c.non_negative(path.k("ramp"), r),
        _ => Some(0.0),
    };
    let required = |c: &mut Checker, key: &str, v: Option<f64>| match v {
        Some(v) => c.positive(path.k(key), v),
        None => {
            c.err(path.k(key), format!("required for motion.kind = \"{kind_name}\""));
            None
        }
    };
    let motion = match kind {
        MotionKind::Sway => {
            let Some(a) = &m.amplitude else {
                c.err(path.k("amplitude"), "required for motion.kind = \"sway\"".into());
                return None;
            };
            let amplitude = c.vector(path.k("amplitude"), a, dim);
            if amplitude.as_ref().is_some_and(|a| a.iter().all(|&x| x == 0.0)) {
                c.err(
                    path.k("amplitude"),
                    "all entries are 0, so the solid would not move (remove `motion` for a fixed solid)"
                        .into(),
                );
                return None;
            }
            Motion::Sway(Sway {
                amplitude: amplitude?,
                period: period?,
                ramp: ramp?,
            })
        }
        MotionKind::Series => {
            let direction = check_direction(c, path, m, dim)?;
            Motion::Series(read_series(c, path, m, dir, direction)?)
        }
        MotionKind::Flap => Motion::Flap(check_flap(c, path, m, dim, g, period, ramp)?),
        MotionKind::Piston => {
            let wave_height = required(c, "wave_height", m.wave_height);
            let depth = required(c, "depth", m.depth);
            let direction = check_direction(c, path, m, dim);
            let gravity = match g {
                Some(g) if g > 0.0 => Some(g),
                _ => {
                    c.err(
                        path.k("kind"),
                        "a piston wave maker needs gravity (effect \"gravity\" with a non-zero fluid.gravity): its stroke comes from the dispersion relation of gravity waves".into(),
                    );
                    None
                }
            };
            Motion::Piston(Piston {
                wave_height: wave_height?,
                period: period?,
                depth: depth?,
                gravity: gravity?,
                direction: direction?,
                ramp: ramp?,
            })
        }
    };
    ok.then_some(motion)
}

/// A flap's keys (`boundary::flap`): `hinge` of `dimension` finite entries; either `angle`
/// (finite, not 0) or `wave_height` and `depth` (> 0) with `hinge_height` (default 0, below
/// `depth`) and gravity, not both. The arm is set from the solid's box (`check_solid`).
fn check_flap(
    c: &mut Checker,
    path: &KeyPath,
    m: &MotionFile,
    dim: Option<usize>,
    g: Option<f64>,
    period: Option<f64>,
    ramp: Option<f64>,
) -> Option<Flap> {
    let hinge = match &m.hinge {
        Some(h) => c.vector(path.k("hinge"), h, dim),
        None => {
            c.err(path.k("hinge"), "required for motion.kind = \"flap\"".into());
            None
        }
    };
    let amplitude = match (m.angle, m.wave_height) {
        (Some(_), Some(_)) => {
            c.err(
                path.k("angle"),
                "give either `angle` or `wave_height` (with `depth`), not both".into(),
            );
            None
        }
        (Some(a), None) => {
            if m.depth.is_some() || m.hinge_height.is_some() {
                let key = if m.depth.is_some() {
                    "depth"
                } else {
                    "hinge_height"
                };
                c.err(path.k(key), "belongs with `wave_height`, not `angle`".into());
                None
            } else if !a.is_finite() || a == 0.0 {
                c.err(
                    path.k("angle"),
                    format!("must be finite and not 0 [rad], got {a}"),
                );
                None
            } else {
                Some(FlapAmplitude::Angle(a))
            }
        }
        (None, wave_height) => {
            let wave_height = match wave_height {
                Some(h) => c.positive(path.k("wave_height"), h),
                None => {
                    c.err(
                        path.k("wave_height"),
                        "required for motion.kind = \"flap\" (or give `angle`)".into(),
                    );
                    None
                }
            };
            let depth = match m.depth {
                Some(d) => c.positive(path.k("depth"), d),
                None => {
                    c.err(path.k("depth"), "required with `wave_height`".into());
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
            let gravity = match g {
                Some(g) if g > 0.0 => Some(g),
                _ => {
                    c.err(
                        path.k("kind"),
                        "a flap with `wave_height` needs gravity (effect \"gravity\" with a non-zero fluid.gravity): its angle comes from the dispersion relation of gravity waves".into(),
                    );
                    None
                }
            };
            Some(FlapAmplitude::Wave {
                wave_height: wave_height?,
                depth: depth?,
                hinge_height: below?,
                gravity: gravity?,
            })
        }
    };
    Some(Flap {
        hinge: hinge?,
        amplitude: amplitude?,
        period: period?,
        ramp: ramp?,
        arm: 0.0,
    })
}

/// `motion.direction` (piston, series): `dimension` finite entries, not all zero; normalised.
pub(super) fn check_direction(
    c: &mut Checker,
    path: &KeyPath,
    m: &MotionFile,
    dim: Option<usize>,
) -> Option<Vec<f64>> {
    let Some(n) = &m.direction else {
        c.err(path.k("direction"), "required for this motion.kind".into());
        return None;
    };
    let n = c.vector(path.k("direction"), n, dim)?;
    let norm = n.iter().map(|x| x * x).sum::<f64>().sqrt();
    if norm == 0.0 {
        c.err(
            path.k("direction"),
            "all entries are 0: give the direction the solid moves along".into(),
        );
        return None;
    }
    Some(n.iter().map(|x| x / norm).collect())
}

/// `motion.file` (series): the samples of the CSV file at `dir`/`file`; a missing or bad file is
/// an error naming it.
fn read_series(
    c: &mut Checker,
    path: &KeyPath,
    m: &MotionFile,
    dir: &Path,
    direction: Vec<f64>,
) -> Option<DisplacementSeries> {
    let Some(file) = &m.file else {
        c.err(path.k("file"), "required for motion.kind = \"series\"".into());
        return None;
    };
    let full = dir.join(file);
    // Only a regular file, at most `MAX_CSV_BYTES` (`crate::bounded_read`).
    let bytes = match crate::bounded_read::read_regular_file(&full, crate::output::csv_read::MAX_CSV_BYTES) {
        Ok(b) => b,
        Err(e) => {
            c.err(path.k("file"), e.to_string());
            return None;
        }
    };
    let Ok(text) = String::from_utf8(bytes) else {
        c.err(path.k("file"), format!("{} is not UTF-8 text", full.display()));
        return None;
    };
    let series =
        DisplacementSeries::parse(&text).and_then(|(t, s)| DisplacementSeries::new(file, t, s, direction));
    match series {
        Ok(s) => Some(s),
        Err(e) => {
            c.err(path.k("file"), format!("{}: {e}", full.display()));
            None
        }
    }
}

/// `[damping_zone]`: `start` and `end` of `dimension` finite entries, distinct (either may lie
/// outside the domain: the zone may reach past the tank's end); `strength` > 0.
pub(super) fn check_damping_zone(
    c: &mut Checker,
    z: &DampingZoneFile,
    dim: Option<usize>,
) -> Option<DampingZoneSpec> {
    let path = KeyPath::key("damping_zone");
    let start = c.vector(path.k("start"), &z.start, dim);
    let end = c.vector(path.k("end"), &z.end, dim);
    let strength = match z.strength {
        Some(b) => c.positive(path.k("strength"), b),
        None => Some(DampingZoneSpec::DEFAULT_STRENGTH),
    };
    let (start, end) = (start?, end?);
    if start == end {
        c.err(
            path.k("end"),
            "equals `start`: the zone needs a length (its direction is from start to end)".into(),
        );
        return None;
    }
    Some(DampingZoneSpec {
        start,
        end,
        strength: strength?,
    })
}
