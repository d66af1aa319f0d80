//! Pressure, level and velocity probes against a reference record (`[probe.reference]` with
//! `columns = [time, value]`).
//!
//! **Normalisation.** With `length = H` the simulated curve is compared as `T = t sqrt(g/H)`
//! and `p/(ρ0 g H)` (pressure), `η/H` (level) or `u/sqrt(g H)` (velocity), the dam-break
//! scaling of Buchner (2002) and Colagrossi & Landrini (2003), and the same `length` as a
//! front's `T = t sqrt(g/a)`; without `length` in seconds and SI units. The reference file is
//! read in the units of its columns.
//!
//! **Measures** (all in the compared units, over the reference's `time_range`):
//! - every kind: the RMS error `sqrt(mean (sim(T_k) − ref_k)²)` over the reference points `k`
//!   in the range, the simulated curve linearly interpolated at each `T_k` ([`rms_error`]);
//! - a level: the first arrival, the first time the level reaches its initial value (the
//!   first point in the range) plus [`ARRIVAL_FRACTION`] of the reference's rise (its largest
//!   value in the range minus its initial one), for the simulation and the reference alike
//!   ([`arrival_time`]);
//! - a pressure: the peak (the largest value in the range) and its time, and the rise time
//!   from [`RISE_FROM`] to [`RISE_TO`] of that peak (each curve its own peak; the first
//!   crossings before the peak; [`rise_time`]). A range around one impact gives that impact's
//!   peak and rise; and the pressure impulse, the integral of the pressure over the range
//!   where both curves have points ([`impulse_in`]). An impact's peak depends on what sets its
//!   duration (compressibility, air, the time step of an incompressible solver, the sensor's
//!   bandwidth), and repeated experiments scatter widely in it (Lobovský et al., J. Fluids
//!   Struct. 48 (2014) 407); the impulse is set by the momentum the wall takes (Cooker &
//!   Peregrine, J. Fluid Mech. 297 (1995) 193) and is the measure of an impact that converges (docs/method.md, "The far-wall sensor run to run").
//!
//! The reference's measures come from its first series (the first the scene names, else the
//! first in the file), sorted by time; the RMS error uses the points of every series compared.

use super::compare::{ProbeComparison, ProbeError, group_series, onset_in, peak_in};
use crate::scene::{Probe, ProbeKind, ProbeReference, Scene};
use crate::validation::read_curves;
use std::path::Path;

/// The fraction of the reference's rise that marks a level's first arrival.
pub const ARRIVAL_FRACTION: f64 = 0.1;

/// The fraction of the peak where a pressure's rise starts.
pub const RISE_FROM: f64 = 0.1;

/// The fraction of the peak where a pressure's rise ends.
pub const RISE_TO: f64 = 0.9;

/// What a pressure, level or velocity probe measures against its reference.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SignalMeasures {
    /// RMS error and the number of reference points it was taken over; `None` when no
    /// reference point lies within both the range and the simulated times.
    pub rms: Option<(f64, usize)>,
    /// Level: first arrival `(simulated, reference)`; `None` for other kinds, or when either
    /// never arrives within the range.
    pub arrival: Option<(Option<f64>, f64)>,
    /// Pressure: the peak and rise; `None` for other kinds, or when either curve has no point
    /// in the range.
    pub peak: Option<SignalPeak>,
}

/// A pressure's peak and rise, simulated and reference, in the compared units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SignalPeak {
    /// The simulation's `(T, peak)`.
    pub simulated: (f64, f64),
    /// The reference's `(T, peak)`.
    pub reference: (f64, f64),
    /// Rise times from [`RISE_FROM`] to [`RISE_TO`] of the peak `(simulated, reference)`; each
    /// `None` when that curve starts above `RISE_FROM` of its peak.
    pub rise: (Option<f64>, Option<f64>),
    /// The pressure impulses `(simulated, reference)` over the range where both curves have
    /// points ([`impulse_in`]); `None` when that span is empty.
    pub impulse: Option<(f64, f64)>,
}

/// The RMS difference of `simulated` (sorted by time) from the `reference` points whose time
/// lies in `range`, with the number of points compared.
pub fn rms_error(
    simulated: &[(f64, f64)],
    reference: &[(f64, f64)],
    range: (f64, f64),
) -> Option<(f64, usize)> {
    let (sum, count) = reference
        .iter()
        .filter(|&&(t, v)| t >= range.0 && t <= range.1 && v.is_finite())
        .filter_map(|&(t, v)| crate::validation::interpolate(simulated, t).map(|s| (s - v).powi(2)))
        .fold((0.0, 0usize), |(sum, count), e| (sum + e, count + 1));
    (count > 0).then(|| ((sum / count as f64).sqrt(), count))
}

/// The first time in `range` at which `points` (sorted by time) reach their first value in the
/// range plus `rise`, linearly interpolated; `None` when they never do.
pub fn arrival_time(points: &[(f64, f64)], range: (f64, f64), rise: f64) -> Option<f64> {
    let initial = points
        .iter()
        .find(|(t, v)| *t >= range.0 && *t <= range.1 && v.is_finite())?
        .1;
    onset_in(points, range, initial + rise)
}

/// The time from the first crossing of [`RISE_FROM`] of `peak` to the first crossing of
/// [`RISE_TO`] of it, both from `start` to the peak's time, for `points` sorted by time;
/// `None` when the curve is already above `RISE_FROM` of the peak at `start`.
pub fn rise_time(points: &[(f64, f64)], start: f64, peak: (f64, f64)) -> Option<f64> {
    let range = (start, peak.0);
    let first = points.iter().find(|(t, v)| *t >= start && v.is_finite())?;
    if first.1 >= RISE_FROM * peak.1 {
        return None;
    }
    let from = onset_in(points, range, RISE_FROM * peak.1)?;
    let to = onset_in(points, range, RISE_TO * peak.1)?;
    Some(to - from)
}

/// The integral of `points` (sorted by time, linearly interpolated) from `a` to `b`; `None`
/// unless the points span `[a, b]`, `a < b`, with finite values.
pub fn impulse_in(points: &[(f64, f64)], a: f64, b: f64) -> Option<f64> {
    if a >= b {
        return None;
    }
    let (start, end) = (
        crate::validation::interpolate(points, a)?,
        crate::validation::interpolate(points, b)?,
    );
    // The corners inside (a, b), between the interpolated ends.
    let mut curve = vec![(a, start)];
    curve.extend(points.iter().copied().filter(|&(t, _)| t > a && t < b));
    curve.push((b, end));
    let sum: f64 = curve
        .windows(2)
        .map(|w| (w[1].0 - w[0].0) * (w[0].1 + w[1].1) / 2.0)
        .sum();
    sum.is_finite().then_some(sum)
}

/// The span of `range` where both curves (sorted by time) have points.
fn common_span(one: &[(f64, f64)], other: &[(f64, f64)], range: (f64, f64)) -> Option<(f64, f64)> {
    let a = range.0.max(one.first()?.0).max(other.first()?.0);
    let b = range.1.min(one.last()?.0).min(other.last()?.0);
    (a < b).then_some((a, b))
}

/// The measures of `simulated` against the reference, both sorted by time: `first` is the
/// reference's first series, `all` every compared point.
pub fn signal_measures(
    kind: ProbeKind,
    simulated: &[(f64, f64)],
    first: &[(f64, f64)],
    all: &[(f64, f64)],
    range: (f64, f64),
) -> SignalMeasures {
    let rms = rms_error(simulated, all, range);
    let arrival = (kind == ProbeKind::Level)
        .then(|| {
            let initial = first.iter().find(|(t, _)| *t >= range.0 && *t <= range.1)?.1;
            let top = peak_in(first, range)?.1;
            let rise = ARRIVAL_FRACTION * (top - initial);
            (rise > 0.0).then_some(())?;
            let reference = arrival_time(first, range, rise)?;
            Some((arrival_time(simulated, range, rise), reference))
        })
        .flatten();
    let peak = (kind == ProbeKind::Pressure)
        .then(|| {
            let (sim, reference) = (peak_in(simulated, range)?, peak_in(first, range)?);
            Some(SignalPeak {
                simulated: sim,
                reference,
                rise: (
                    rise_time(simulated, range.0, sim),
                    rise_time(first, range.0, reference),
                ),
                impulse: common_span(simulated, first, range)
                    .and_then(|(a, b)| Some((impulse_in(simulated, a, b)?, impulse_in(first, a, b)?))),
            })
        })
        .flatten();
    SignalMeasures { rms, arrival, peak }
}

/// The factors `(time, value)` that turn seconds and SI values into the compared units:
/// `(sqrt(g/H), 1/(ρ0 g H))` for a pressure, `1/H` for a level, `1/sqrt(g H)` for a velocity
/// with `length = H`; `(1, 1)` without.
fn scales(scene: &Scene, probe: &Probe, reference: &ProbeReference) -> Result<(f64, f64), ProbeError> {
    let Some(length) = reference.length else {
        return Ok((1.0, 1.0));
    };
    let g = scene
        .gravity
        .as_ref()
        .map(|g| g.iter().map(|c| c * c).sum::<f64>().sqrt())
        .filter(|g| *g > 0.0)
        .ok_or_else(|| ProbeError::NoGravity {
            probe: probe.name.clone(),
        })?;
    let value = match probe.kind {
        ProbeKind::Pressure => 1.0 / (scene.rho0 * g * length),
        ProbeKind::Velocity => 1.0 / (g * length).sqrt(),
        _ => 1.0 / length,
    };
    Ok(((g / length).sqrt(), value))
}

/// A pressure, level or velocity probe's samples `(t [s], value)` against its reference
/// record at `path`.
pub(super) fn compare_signal(
    scene: &Scene,
    probe: &Probe,
    reference: &ProbeReference,
    path: &Path,
    samples: &[(f64, f64)],
) -> Result<ProbeComparison, ProbeError> {
    let (time_scale, value_scale) = scales(scene, probe, reference)?;
    let Some((time, value)) = &reference.columns else {
        return Err(ProbeError::NoColumns {
            probe: probe.name.clone(),
        });
    };
    let points = read_curves(path, time, value).map_err(|source| ProbeError::Reference {
        probe: probe.name.clone(),
        source,
    })?;
    let mut series = group_series(reference, points.into_iter().map(|p| (p.series, (p.t, p.value))));
    if let Some(first) = reference.series.first() {
        // The scene's first series leads.
        if let Some(k) = series.iter().position(|(name, _)| name == first) {
            series.swap(0, k);
        }
    }
    for (_, pts) in &mut series {
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let Some((_, first)) = series.first() else {
        return Err(ProbeError::NoSeries {
            probe: probe.name.clone(),
            file: path.display().to_string(),
            series: reference.series.clone(),
        });
    };
    let simulated: Vec<(f64, f64)> = samples
        .iter()
        .map(|&(t, v)| (t * time_scale, v * value_scale))
        .collect();
    let mut all: Vec<(f64, f64)> = series.iter().flat_map(|(_, p)| p.iter().copied()).collect();
    all.sort_by(|a, b| a.0.total_cmp(&b.0));
    let signal = signal_measures(probe.kind, &simulated, first, &all, reference.time_range);
    Ok(ProbeComparison {
        name: probe.name.clone(),
        kind: probe.kind,
        simulated,
        reference: series,
        error: None,
        peak: None,
        signal: Some(signal),
        normalised: reference.length.is_some(),
    })
}

/// A comparison's entry in `summary.json`'s `probe_errors` (docs/output.md): `units`
/// (`"normalised"` or `"SI"`), `rms_error` and `points`; a level's `arrival_time` and
/// `reference_arrival_time`; a pressure's `peak`, `peak_time`, `reference_peak`,
/// `reference_peak_time`, `peak_error` (relative), `peak_time_error`, `rise_time`,
/// `reference_rise_time`, `impulse`, `reference_impulse` and `impulse_error` (relative). Times
/// and values are in the compared units.
pub fn summary_json(c: &ProbeComparison) -> serde_json::Value {
    let mut out = serde_json::Map::new();
    out.insert(
        "units".into(),
        if c.normalised { "normalised" } else { "SI" }.into(),
    );
    let Some(m) = &c.signal else {
        return out.into();
    };
    out.insert("rms_error".into(), m.rms.map(|r| r.0).into());
    out.insert("points".into(), m.rms.map_or(0, |r| r.1).into());
    if let Some((sim, reference)) = m.arrival {
        out.insert("arrival_time".into(), sim.into());
        out.insert("reference_arrival_time".into(), reference.into());
    }
    if let Some(p) = &m.peak {
        let json = serde_json::json!({
            "peak": p.simulated.1,
            "peak_time": p.simulated.0,
            "reference_peak": p.reference.1,
            "reference_peak_time": p.reference.0,
            "peak_error": (p.simulated.1 - p.reference.1) / p.reference.1,
            "peak_time_error": p.simulated.0 - p.reference.0,
            "rise_time": p.rise.0,
            "reference_rise_time": p.rise.1,
        });
        if let serde_json::Value::Object(map) = json {
            out.extend(map);
        }
        if let Some((sim, reference)) = p.impulse {
            out.insert("impulse".into(), sim.into());
            out.insert("reference_impulse".into(), reference.into());
            out.insert("impulse_error".into(), ((sim - reference) / reference).into());
        }
    }
    out.into()
}

/// The lines `sph run` and `sph compare` print for a comparison's `summary.json` entry
/// ([`summary_json`]); empty for other entries.
pub fn summary_lines(name: &str, e: &serde_json::Value) -> Vec<String> {
    let Some(units) = e.get("units").and_then(|v| v.as_str()) else {
        return Vec::new();
    };
    let num = |k: &str| e.get(k).and_then(|v| v.as_f64()).unwrap_or(f64::NAN);
    let unit = if units == "normalised" {
        "normalised"
    } else {
        "s, SI"
    };
    let mut lines = vec![format!(
        "probe {name}: RMS error against reference {:.4} over {} points ({unit})",
        num("rms_error"),
        e.get("points").and_then(|v| v.as_u64()).unwrap_or(0)
    )];
    if e.get("reference_arrival_time").is_some() {
        lines.push(format!(
            "probe {name}: first arrival at {:.3}, reference {:.3}",
            num("arrival_time"),
            num("reference_arrival_time")
        ));
    }
    if e.get("peak").is_some() {
        lines.push(format!(
            "probe {name}: peak {:.4} at {:.3}; reference {:.4} at {:.3} ({:+.1} %); rise {:.3}, reference {:.3}",
            num("peak"),
            num("peak_time"),
            num("reference_peak"),
            num("reference_peak_time"),
            100.0 * num("peak_error"),
            num("rise_time"),
            num("reference_rise_time")
        ));
    }
    if e.get("impulse").is_some() {
        lines.push(format!(
            "probe {name}: impulse {:.4}, reference {:.4} ({:+.1} %)",
            num("impulse"),
            num("reference_impulse"),
            100.0 * num("impulse_error")
        ));
    }
    lines
}
