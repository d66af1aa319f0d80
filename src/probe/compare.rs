//! Probes against reference data: a front's relative error, a force's first peak
//! ([`compare_samples`]); pressure, level and velocity in [`signal`](super::signal).

use super::ProbeLog;
use super::signal::{SignalMeasures, compare_signal};
use crate::output::plot::{Figure, PlotError, Series, SeriesStyle, write_png};
use crate::scene::{Probe, ProbeKind, ProbeReference, ReferenceLocation, Scene};
use crate::validation::{CurveError, read_column_force, read_surge_front, relative_error};
use std::path::Path;

/// A probe compared with its reference data.
#[derive(Clone, Debug)]
pub struct ProbeComparison {
    /// Probe name.
    pub name: String,
    /// What the probe measures.
    pub kind: ProbeKind,
    /// The simulated curve, normalised as the reference (`(T, Z)` for a front).
    pub simulated: Vec<(f64, f64)>,
    /// Reference points per series, normalised: `(series, [(T, Z)])`.
    pub reference: Vec<(String, Vec<(f64, f64)>)>,
    /// Front: relative error of the simulation at the reference points within the probe's
    /// time range; `None` when no reference point lies in the simulated range, and for forces.
    pub error: Option<CurveError>,
    /// Force: the first peak, simulated and reference; `None` for fronts or when either has no
    /// point in the time range.
    pub peak: Option<Peak>,
    /// Pressure, level and velocity: their measures ([`super::signal`]); `None` for fronts
    /// and forces.
    pub signal: Option<SignalMeasures>,
    /// Whether the curves are normalised by a `length` (a front always is; a force never).
    pub normalised: bool,
}

/// The largest force within a force probe's time range, as `(t [s], F [N])`, and the impact
/// onset before it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    /// Of the simulation.
    pub simulated: (f64, f64),
    /// Of the reference record.
    pub reference: (f64, f64),
    /// Impact onset `(simulated, reference)` [s]: the first time each curve reaches
    /// [`ONSET_FRACTION`] of the reference peak, linearly interpolated; `None` when either never
    /// does within the range. The peak time measured from the onset does not depend on where a
    /// record puts its time origin (Yeh & Petroff's is inferred, see validation/SOURCES.md).
    pub onset: Option<(f64, f64)>,
}

/// The fraction of the reference peak that marks the impact onset of a force record.
pub const ONSET_FRACTION: f64 = 0.25;

impl Peak {
    /// Simulated minus reference time from onset to peak [s]; `None` without onsets.
    pub fn rise_time_error(&self) -> Option<f64> {
        self.onset
            .map(|(sim, reference)| (self.simulated.0 - sim) - (self.reference.0 - reference))
    }
}

/// Errors comparing a probe with reference data.
#[derive(Debug, thiserror::Error)]
pub enum ProbeError {
    /// The reference file could not be read.
    #[error("probe {probe}: {source}")]
    Reference {
        /// Probe name.
        probe: String,
        /// The reader's error.
        source: crate::validation::ValidationError,
    },
    /// The scene has no gravity, so `T = t sqrt(g/a)` is undefined.
    #[error("probe {probe}: comparing with reference data needs the gravity effect")]
    NoGravity {
        /// Probe name.
        probe: String,
    },
    /// The probe's reference file was never looked up in a reference directory.
    #[error(
        "probe {probe}: reference file {file} was not looked up in a reference directory \
         (scene::locate_references)"
    )]
    Unlocated {
        /// Probe name.
        probe: String,
        /// The file as the scene names it.
        file: String,
    },
    /// A pressure, level or velocity reference without its `columns`.
    #[error("probe {probe}: its reference names no columns [time, value]")]
    NoColumns {
        /// Probe name.
        probe: String,
    },
    /// The reference file has none of the series the probe names.
    #[error("probe {probe}: {file} has no points of the series {series:?}")]
    NoSeries {
        /// Probe name.
        probe: String,
        /// The file.
        file: String,
        /// The series asked for.
        series: Vec<String>,
    },
}

/// Compares every probe that names reference data with it.
pub fn compare(scene: &Scene, log: &ProbeLog) -> Result<Vec<ProbeComparison>, ProbeError> {
    let mut out = Vec::new();
    for (k, probe) in log.probes().iter().enumerate() {
        if let Some(c) = compare_samples(scene, probe, log.samples(k))? {
            out.push(c);
        }
    }
    Ok(out)
}

/// Reads every reference file the scene's probes name and checks it holds what the probe
/// compares with (the series asked for; gravity for a front), so that `sph run` fails at its
/// start rather than after the run.
pub fn check_references(scene: &Scene) -> Result<(), ProbeError> {
    for probe in &scene.probes {
        compare_samples(scene, probe, &[])?;
    }
    Ok(())
}

/// The path of a probe's reference file: `None` when the probe names none or its file is not
/// available (the comparison is skipped, see [`crate::scene::references`]).
fn reference_path(probe: &Probe) -> Result<Option<(&ProbeReference, &Path)>, ProbeError> {
    let Some(reference) = &probe.reference else {
        return Ok(None);
    };
    match &reference.location {
        ReferenceLocation::Found(path) => Ok(Some((reference, path))),
        ReferenceLocation::Missing(_) => Ok(None),
        ReferenceLocation::Unlocated => Err(ProbeError::Unlocated {
            probe: probe.name.clone(),
            file: reference.file.display().to_string(),
        }),
    }
}

/// Compares one probe's samples `(t [s], value [m])` with its reference data; `None` when the
/// probe names none or its reference file is not available.
pub fn compare_samples(
    scene: &Scene,
    probe: &Probe,
    samples: &[(f64, f64)],
) -> Result<Option<ProbeComparison>, ProbeError> {
    let Some((reference, path)) = reference_path(probe)? else {
        return Ok(None);
    };
    match probe.kind {
        ProbeKind::Force => return compare_force(probe, reference, path, samples).map(Some),
        ProbeKind::Pressure | ProbeKind::Level | ProbeKind::Velocity => {
            return compare_signal(scene, probe, reference, path, samples).map(Some);
        }
        // Scene validation refuses references for flow rates and moments.
        ProbeKind::Front | ProbeKind::FlowRate | ProbeKind::Moment => {}
    }
    let g = scene
        .gravity
        .as_ref()
        .map(|g| g.iter().map(|c| c * c).sum::<f64>().sqrt())
        .filter(|g| *g > 0.0)
        .ok_or_else(|| ProbeError::NoGravity {
            probe: probe.name.clone(),
        })?;
    let Some(a) = reference.length else {
        return Err(ProbeError::NoGravity {
            probe: probe.name.clone(),
        });
    };
    let time_scale = (g / a).sqrt();
    let points = read_surge_front(path).map_err(|source| ProbeError::Reference {
        probe: probe.name.clone(),
        source,
    })?;
    let series = group_series(reference, points.into_iter().map(|p| (p.series, (p.t, p.z))));
    if series.is_empty() {
        return Err(ProbeError::NoSeries {
            probe: probe.name.clone(),
            file: path.display().to_string(),
            series: reference.series.clone(),
        });
    }
    let simulated: Vec<(f64, f64)> = samples.iter().map(|&(t, z)| (t * time_scale, z / a)).collect();
    let all: Vec<(f64, f64)> = series.iter().flat_map(|(_, p)| p.iter().copied()).collect();
    let error = relative_error(&simulated, &all, reference.time_range);
    Ok(Some(ProbeComparison {
        name: probe.name.clone(),
        kind: probe.kind,
        simulated,
        reference: series,
        error,
        peak: None,
        signal: None,
        normalised: true,
    }))
}

/// The `(t, value)` points of a long-format reference grouped by series, in the file's order,
/// keeping only the series the reference names (all when it names none).
pub(super) fn group_series(
    reference: &ProbeReference,
    points: impl IntoIterator<Item = (String, (f64, f64))>,
) -> Vec<(String, Vec<(f64, f64)>)> {
    let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for (name, point) in points {
        if !reference.series.is_empty() && !reference.series.contains(&name) {
            continue;
        }
        match series.iter_mut().find(|(n, _)| *n == name) {
            Some((_, pts)) => pts.push(point),
            None => series.push((name, vec![point])),
        }
    }
    series
}

/// The largest value within `range` (inclusive), as `(t, value)`.
pub(super) fn peak_in(points: &[(f64, f64)], range: (f64, f64)) -> Option<(f64, f64)> {
    points
        .iter()
        .copied()
        .filter(|(t, v)| *t >= range.0 && *t <= range.1 && v.is_finite())
        .max_by(|a, b| a.1.total_cmp(&b.1))
}

/// The first time within `range` at which `points` (in time order) reach `level`, linearly
/// interpolated between the samples either side.
pub(super) fn onset_in(points: &[(f64, f64)], range: (f64, f64), level: f64) -> Option<f64> {
    let inside: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(t, v)| *t >= range.0 && *t <= range.1 && t.is_finite() && v.is_finite())
        .collect();
    let first = inside.iter().position(|&(_, v)| v >= level)?;
    if first == 0 {
        return Some(inside[0].0);
    }
    let ((t0, v0), (t1, v1)) = (inside[first - 1], inside[first]);
    Some(t0 + (t1 - t0) * (level - v0) / (v1 - v0))
}

/// A force probe against a force record (time [s], force [N]): the first peak.
fn compare_force(
    probe: &Probe,
    reference: &ProbeReference,
    path: &Path,
    samples: &[(f64, f64)],
) -> Result<ProbeComparison, ProbeError> {
    let points = read_column_force(path).map_err(|source| ProbeError::Reference {
        probe: probe.name.clone(),
        source,
    })?;
    let curve: Vec<(f64, f64)> = points.iter().map(|p| (p.time, p.force)).collect();
    let mut in_time = curve.clone();
    in_time.sort_by(|a, b| a.0.total_cmp(&b.0));
    let label = reference
        .file
        .file_stem()
        .map_or_else(|| "reference".to_string(), |s| s.to_string_lossy().into_owned());
    let range = reference.time_range;
    let peak = peak_in(samples, range)
        .zip(peak_in(&curve, range))
        .map(|(simulated, reference)| {
            let level = ONSET_FRACTION * reference.1;
            let onset = onset_in(samples, (range.0, simulated.0), level).zip(onset_in(
                &in_time,
                (range.0, reference.0),
                level,
            ));
            Peak {
                simulated,
                reference,
                onset,
            }
        });
    Ok(ProbeComparison {
        name: probe.name.clone(),
        kind: probe.kind,
        simulated: samples.to_vec(),
        reference: vec![(label, curve)],
        error: None,
        peak,
        signal: None,
        normalised: false,
    })
}

/// Draws probe comparisons on one figure: one line per `(label, comparison)`, the reference
/// points (from the first) as markers. The paper's Fig. 1 when the runs are `wcsph` and
/// `corrected` and the probe is the dam-break front.
pub fn front_figure(title: &str, runs: &[(String, &ProbeComparison)]) -> Figure {
    let mut series: Vec<Series> = runs
        .iter()
        .map(|(label, c)| Series {
            label: label.clone(),
            points: c.simulated.clone(),
            style: SeriesStyle::Line,
        })
        .collect();
    if let Some((_, first)) = runs.first() {
        for (name, pts) in &first.reference {
            series.push(Series {
                label: format!("experiment: {name}"),
                points: pts.clone(),
                style: SeriesStyle::Markers,
            });
        }
    }
    let (x_label, y_label) = runs.first().map_or(("", ""), |(_, c)| axis_labels(c));
    Figure {
        title: title.into(),
        x_label: x_label.into(),
        y_label: y_label.into(),
        series,
        ..Figure::default()
    }
}

/// The axis labels of a comparison's figure: its time and its value, in the compared units.
fn axis_labels(c: &ProbeComparison) -> (&'static str, &'static str) {
    let time = if c.normalised { "T = t sqrt(g/H)" } else { "t [s]" };
    match (c.kind, c.normalised) {
        (ProbeKind::Front, _) => ("T = t sqrt(g/a)", "Z = z/a (surge front)"),
        (ProbeKind::Force, _) => ("t [s]", "force on the solid [N]"),
        (ProbeKind::Pressure, true) => (time, "p/(rho0 g H)"),
        (ProbeKind::Pressure, false) => (time, "pressure [Pa]"),
        (ProbeKind::Level, true) => (time, "level/H"),
        (ProbeKind::Level, false) => (time, "level [m]"),
        (ProbeKind::Velocity, true) => (time, "u/sqrt(g H)"),
        (ProbeKind::Velocity, false) => (time, "velocity [m/s]"),
        (ProbeKind::FlowRate, _) => (time, "flow rate"),
        (ProbeKind::Moment, _) => ("t [s]", "moment on the solid [N m]"),
    }
}

/// Writes `<dir>/<probe>.png` for each comparison of one run.
pub fn write_figures(dir: &Path, label: &str, comparisons: &[ProbeComparison]) -> Result<(), PlotError> {
    for c in comparisons {
        let figure = front_figure(&format!("{}: {label}", c.name), &[(label.to_string(), c)]);
        write_png(&figure, &dir.join(format!("{}.png", c.name)), (900, 600))?;
    }
    Ok(())
}
