//! Probes: quantities sampled over a run (`[[probe]]` in a scene), written to `probes.csv`,
//! and compared with reference data when the probe names some (`[probe.reference]`).
//!
//! `front`: the surge front, the largest fluid coordinate along the probe's axis minus its
//! origin [m] (Martin & Moyce's z, measured from the back wall). Against a reference it is
//! normalised as `Z = z/a`, `T = t sqrt(g/a)` with `a` = `reference.length` and `g = |gravity|`
//! (square column, n = 1; `../shared/validation/SOURCES.md`, section 1).

use crate::fields::{FLUID, Fields};
use crate::output::plot::{Figure, PlotError, Series, SeriesStyle, write_png};
use crate::output::{CsvTable, CsvValue, OutputError};
use crate::scene::{Probe, ProbeKind, Scene};
use crate::validation::{CurveError, read_surge_front, relative_error};
use std::path::Path;

/// Value of one probe on the current state: the front position [m].
pub fn measure<const D: usize>(probe: &Probe, fields: &Fields<D>) -> f64 {
    match probe.kind {
        ProbeKind::Front => {
            let axis = probe.axis.min(D - 1);
            let front = (0..fields.len())
                .filter(|&i| fields.kind[i] == FLUID)
                .map(|i| f64::from(fields.position[i][axis]))
                .fold(f64::NEG_INFINITY, f64::max);
            front - probe.origin
        }
    }
}

/// Samples of every probe of a scene, and the `probes.csv` they are written to.
pub struct ProbeLog {
    probes: Vec<Probe>,
    /// `(t [s], value)` per probe.
    samples: Vec<Vec<(f64, f64)>>,
    table: Option<CsvTable>,
    interval: f64,
    next: f64,
}

impl ProbeLog {
    /// A log for `scene`'s probes, sampled every `interval` [s]; writes `probes.csv` in `dir`
    /// when given (columns `t_s` and one `<name>_m` per probe).
    pub fn create(scene: &Scene, dir: Option<&Path>, interval: f64) -> Result<Self, OutputError> {
        let probes = scene.probes.clone();
        let table = match dir {
            Some(dir) if !probes.is_empty() => {
                let mut columns = vec!["t_s".to_string()];
                columns.extend(probes.iter().map(|p| format!("{}_m", p.name)));
                let columns: Vec<&str> = columns.iter().map(String::as_str).collect();
                Some(CsvTable::create(&dir.join("probes.csv"), &columns)?)
            }
            _ => None,
        };
        Ok(Self {
            samples: vec![Vec::new(); probes.len()],
            probes,
            table,
            interval,
            next: 0.0,
        })
    }

    /// Records the probes at time `t` [s] if a sample is due (or `force`).
    pub fn record<const D: usize>(
        &mut self,
        t: f64,
        fields: &Fields<D>,
        force: bool,
    ) -> Result<(), OutputError> {
        if self.probes.is_empty() || (t < self.next && !force) {
            return Ok(());
        }
        while self.next <= t {
            self.next += self.interval;
        }
        let values: Vec<f64> = self.probes.iter().map(|p| measure(p, fields)).collect();
        for (s, v) in self.samples.iter_mut().zip(&values) {
            s.push((t, *v));
        }
        if let Some(table) = self.table.as_mut() {
            let mut row = vec![CsvValue::from(t)];
            row.extend(values.iter().map(|&v| CsvValue::from(v)));
            table.push_row(&row)?;
            table.flush()?;
        }
        Ok(())
    }

    /// The samples of probe `k`: `(t [s], value)`.
    pub fn samples(&self, k: usize) -> &[(f64, f64)] {
        &self.samples[k]
    }

    /// The probes.
    pub fn probes(&self) -> &[Probe] {
        &self.probes
    }
}

/// A probe compared with its reference data.
#[derive(Clone, Debug)]
pub struct ProbeComparison {
    /// Probe name.
    pub name: String,
    /// The simulated curve, normalised as the reference (`(T, Z)` for a front).
    pub simulated: Vec<(f64, f64)>,
    /// Reference points per series, normalised: `(series, [(T, Z)])`.
    pub reference: Vec<(String, Vec<(f64, f64)>)>,
    /// Relative error of the simulation at the reference points within the probe's time range;
    /// `None` when no reference point lies in the simulated range.
    pub error: Option<CurveError>,
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

/// Compares one probe's samples `(t [s], value [m])` with its reference data; `None` when the
/// probe names none.
pub fn compare_samples(
    scene: &Scene,
    probe: &Probe,
    samples: &[(f64, f64)],
) -> Result<Option<ProbeComparison>, ProbeError> {
    let Some(reference) = &probe.reference else {
        return Ok(None);
    };
    let g = scene
        .gravity
        .as_ref()
        .map(|g| g.iter().map(|c| c * c).sum::<f64>().sqrt())
        .filter(|g| *g > 0.0)
        .ok_or_else(|| ProbeError::NoGravity {
            probe: probe.name.clone(),
        })?;
    let a = reference.length;
    let time_scale = (g / a).sqrt();
    let points = read_surge_front(&reference.file).map_err(|source| ProbeError::Reference {
        probe: probe.name.clone(),
        source,
    })?;
    let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for p in points {
        if !reference.series.is_empty() && !reference.series.contains(&p.series) {
            continue;
        }
        match series.iter_mut().find(|(name, _)| *name == p.series) {
            Some((_, pts)) => pts.push((p.t, p.z)),
            None => series.push((p.series.clone(), vec![(p.t, p.z)])),
        }
    }
    if series.is_empty() {
        return Err(ProbeError::NoSeries {
            probe: probe.name.clone(),
            file: reference.file.display().to_string(),
            series: reference.series.clone(),
        });
    }
    let simulated: Vec<(f64, f64)> = samples.iter().map(|&(t, z)| (t * time_scale, z / a)).collect();
    let all: Vec<(f64, f64)> = series.iter().flat_map(|(_, p)| p.iter().copied()).collect();
    let error = relative_error(&simulated, &all, reference.time_range);
    Ok(Some(ProbeComparison {
        name: probe.name.clone(),
        simulated,
        reference: series,
        error,
    }))
}

/// Draws probe comparisons on one figure: one line per `(label, comparison)`, the reference
/// points (from the first) as markers. The paper's Fig. 1 when the runs are `wcsph` and
/// `corrected`.
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
    Figure {
        title: title.into(),
        x_label: "T = t sqrt(g/a)".into(),
        y_label: "Z = z/a (surge front)".into(),
        series,
        ..Figure::default()
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
