//! Probes: quantities sampled over a run (`[[probe]]` in a scene), written to `probes.csv`,
//! and compared with reference data when the probe names some (`[probe.reference]`).
//!
//! `front`: the surge front, the largest fluid coordinate along the probe's axis minus its
//! origin [m] (Martin & Moyce's z, measured from the back wall). Against a reference it is
//! normalised as `Z = z/a`, `T = t sqrt(g/a)` with `a` = `reference.length` and `g = |gravity|`
//! (square column, n = 1; docs/validation.md).
//!
//! `force`: the force of the fluid on one solid along the axis [N] (2D: [N/m]), averaged over
//! each sampling interval (the per-step force of particle methods is noisy). Against a
//! reference (time [s], force [N], e.g. Yeh & Petroff's column) the comparison is the first
//! peak: the largest force within the reference's `time_range`, and when it occurs.
//!
//! `pressure`, `velocity`: the fluid's pressure [Pa], or its velocity along the axis [m/s], at
//! the probe's point, interpolated from the fluid particles with Shepard's normalisation;
//! `level`: a wave gauge, the height [m] of the free surface above the probe's point along the
//! axis; `flow_rate`: the volume flux through a segment (2D, [m²/s]) or rectangle (3D, [m³/s])
//! normal to the axis ([`interpolate`] says how each is read). Each is the value at the
//! sampling time.

pub mod interpolate;

use crate::fields::{FLUID, Fields};
use crate::math::Real;
use crate::output::plot::{Figure, PlotError, Series, SeriesStyle, write_png};
use crate::output::{CsvTable, CsvValue, OutputError, force_unit};
use crate::scene::{Probe, ProbeKind, ProbeReference, ReferenceLocation, Scene};
use crate::smoothing::Smoothing;
use crate::validation::{CurveError, read_column_force, read_surge_front, relative_error};
use std::path::{Path, PathBuf};

/// What a probe's reading depends on besides the particles: the scene's kernel support and
/// domain.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeSpace {
    /// Kernel support radius `h` [m] of the interpolations.
    pub h: f64,
    /// Upper corner of the domain [m]: where a level gauge's line ends.
    pub domain_max: Vec<f64>,
}

impl ProbeSpace {
    /// The scene's.
    pub fn of(scene: &Scene) -> ProbeSpace {
        ProbeSpace {
            h: scene.smoothing_length,
            domain_max: scene.domain.max.clone(),
        }
    }
}

/// Value of one probe on the current state: the front position [m], the force on its solid
/// during the last step [N] (`solid_forces` as `Simulation::solid_forces`), or the pressure
/// [Pa], surface height [m] or velocity [m/s] at its point ([`interpolate`]).
pub fn measure<const D: usize>(
    probe: &Probe,
    space: &ProbeSpace,
    fields: &Fields<D>,
    solid_forces: &[[f64; 3]],
) -> f64 {
    let at_point = |read: &dyn Fn(&Smoothing<D>, &[f64]) -> f64| -> f64 {
        match (Smoothing::<D>::new(space.h as Real), probe.point.as_deref()) {
            (Ok(kernel), Some(point)) if point.len() == D => read(&kernel, point),
            _ => f64::NAN,
        }
    };
    match probe.kind {
        ProbeKind::Pressure => at_point(&|k, x| interpolate::pressure(fields, k, x)),
        ProbeKind::Velocity => at_point(&|k, x| interpolate::velocity(fields, k, x, probe.axis.min(D - 1))),
        ProbeKind::FlowRate => at_point(&|k, x| {
            let size = probe.size.as_deref().unwrap_or(&[]);
            interpolate::flow_rate(fields, k, x, probe.axis.min(D - 1), size)
        }),
        ProbeKind::Level => at_point(&|k, x| {
            let axis = probe.axis.min(D - 1);
            let top = space.domain_max.get(axis).copied().unwrap_or(x[axis]);
            interpolate::level(fields, k, x, axis, top)
        }),
        ProbeKind::Front => {
            let axis = probe.axis.min(D - 1);
            let front = (0..fields.len())
                .filter(|&i| fields.kind[i] == FLUID)
                .map(|i| f64::from(fields.position[i][axis]))
                .fold(f64::NEG_INFINITY, f64::max);
            front - probe.origin
        }
        ProbeKind::Force => probe
            .solid
            .and_then(|k| solid_forces.get(k))
            .map_or(0.0, |f| f[probe.axis.min(2)]),
    }
}

/// The column of `probe` in `probes.csv` of a `dimension`-D run: `<name>_m` for a front,
/// `<name>_N` for a force (`<name>_N_per_m` in 2D: per metre of depth), `<name>_Pa` for a
/// pressure, `<name>_m` for a level, `<name>_m_per_s` for a velocity, `<name>_m2_per_s` (2D)
/// or `<name>_m3_per_s` for a flow rate, as
/// [`crate::output::csv`]'s convention has it.
pub fn column_name(probe: &Probe, dimension: usize) -> String {
    match probe.kind {
        ProbeKind::Front | ProbeKind::Level => format!("{}_m", probe.name),
        ProbeKind::Force => format!("{}_{}", probe.name, force_unit(dimension)),
        ProbeKind::Pressure => format!("{}_Pa", probe.name),
        ProbeKind::Velocity => format!("{}_m_per_s", probe.name),
        ProbeKind::FlowRate if dimension == 2 => format!("{}_m2_per_s", probe.name),
        ProbeKind::FlowRate => format!("{}_m3_per_s", probe.name),
    }
}

/// Samples of every probe of a scene, and the `probes.csv` they are written to.
pub struct ProbeLog {
    probes: Vec<Probe>,
    space: ProbeSpace,
    /// `(t [s], value)` per probe.
    samples: Vec<Vec<(f64, f64)>>,
    table: Option<CsvTable>,
    interval: f64,
    next: f64,
    /// Per probe: `Σ value · dt` and `Σ dt` since the last sample (force probes' averages).
    running: Vec<(f64, f64)>,
}

/// What a [`ProbeLog`] has recorded, kept with a checkpoint.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ProbeState {
    /// `(t [s], value)` per probe.
    pub samples: Vec<Vec<(f64, f64)>>,
    /// Time of the next sample [s].
    pub next: f64,
    /// Per probe: `Σ value · dt` and `Σ dt` since the last sample.
    pub running: Vec<(f64, f64)>,
    /// Length of `probes.csv` [bytes], when written.
    pub table_len: Option<u64>,
}

impl ProbeLog {
    /// A log for `scene`'s probes, sampled every `interval` [s]; writes `probes.csv` in `dir`
    /// when given (columns `t_s` and one [`column_name`] per probe).
    pub fn create(scene: &Scene, dir: Option<&Path>, interval: f64) -> Result<Self, OutputError> {
        Self::open(scene, dir, interval, None)
    }

    /// The log as it was at a checkpoint: its samples, and `probes.csv` cut back to its length
    /// then.
    pub fn resume(
        scene: &Scene,
        dir: Option<&Path>,
        interval: f64,
        state: ProbeState,
    ) -> Result<Self, OutputError> {
        let mut log = Self::open(scene, dir, interval, state.table_len)?;
        if state.samples.len() != log.probes.len() || state.running.len() != log.probes.len() {
            return Err(OutputError::malformed(
                &dir.map_or_else(PathBuf::new, |d| d.join("checkpoint.bin")),
                "its probes are not this scene's",
            ));
        }
        log.samples = state.samples;
        log.running = state.running;
        log.next = state.next;
        Ok(log)
    }

    /// What the log has recorded (flushing `probes.csv` to learn its length).
    pub fn state(&mut self) -> Result<ProbeState, OutputError> {
        let table_len = match self.table.as_mut() {
            Some(t) => Some(t.len_on_disk()?),
            None => None,
        };
        Ok(ProbeState {
            samples: self.samples.clone(),
            next: self.next,
            running: self.running.clone(),
            table_len,
        })
    }

    fn open(
        scene: &Scene,
        dir: Option<&Path>,
        interval: f64,
        resume_len: Option<u64>,
    ) -> Result<Self, OutputError> {
        let probes = scene.probes.clone();
        let table = match dir {
            Some(dir) if !probes.is_empty() => {
                let mut columns = vec!["t_s".to_string()];
                columns.extend(probes.iter().map(|p| column_name(p, scene.dimension)));
                let columns: Vec<&str> = columns.iter().map(String::as_str).collect();
                let path = dir.join("probes.csv");
                Some(match resume_len {
                    Some(len) => CsvTable::resume(&path, &columns, len)?,
                    None => CsvTable::create(&path, &columns)?,
                })
            }
            _ => None,
        };
        Ok(Self {
            space: ProbeSpace::of(scene),
            samples: vec![Vec::new(); probes.len()],
            running: vec![(0.0, 0.0); probes.len()],
            probes,
            table,
            interval,
            next: 0.0,
        })
    }

    /// Whether [`ProbeLog::record`] at time `t` [s] reads particle fields (a probe other than
    /// a force is due), so a device-resident backend must copy them to the host first.
    pub fn wants_fields(&self, t: f64, now: bool) -> bool {
        (t >= self.next || now) && self.probes.iter().any(|p| p.kind != ProbeKind::Force)
    }

    /// Called after every step of length `dt` [s] ending at `t` [s]: records the probes if a
    /// sample is due (or `now`); force probes report their mean over the interval.
    pub fn record<const D: usize>(
        &mut self,
        t: f64,
        dt: f64,
        fields: &Fields<D>,
        solid_forces: &[[f64; 3]],
        now: bool,
    ) -> Result<(), OutputError> {
        if self.probes.is_empty() {
            return Ok(());
        }
        for (p, run) in self.probes.iter().zip(self.running.iter_mut()) {
            if p.kind == ProbeKind::Force && dt > 0.0 {
                run.0 += measure(p, &self.space, fields, solid_forces) * dt;
                run.1 += dt;
            }
        }
        if t < self.next && !now {
            return Ok(());
        }
        while self.next <= t {
            self.next += self.interval;
        }
        let values: Vec<f64> = self
            .probes
            .iter()
            .zip(self.running.iter_mut())
            .map(|(p, run)| {
                let v = match p.kind {
                    ProbeKind::Force if run.1 > 0.0 => run.0 / run.1,
                    _ => measure(p, &self.space, fields, solid_forces),
                };
                *run = (0.0, 0.0);
                v
            })
            .collect();
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
    if probe.kind == ProbeKind::Force {
        return compare_force(probe, reference, path, samples).map(Some);
    }
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
    let points = read_surge_front(path).map_err(|source| ProbeError::Reference {
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
    }))
}

/// The largest value within `range` (inclusive), as `(t, value)`.
fn peak_in(points: &[(f64, f64)], range: (f64, f64)) -> Option<(f64, f64)> {
    points
        .iter()
        .copied()
        .filter(|(t, v)| *t >= range.0 && *t <= range.1 && v.is_finite())
        .max_by(|a, b| a.1.total_cmp(&b.1))
}

/// The first time within `range` at which `points` (in time order) reach `level`, linearly
/// interpolated between the samples either side.
fn onset_in(points: &[(f64, f64)], range: (f64, f64), level: f64) -> Option<f64> {
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
    let force = runs.first().is_some_and(|(_, c)| c.kind == ProbeKind::Force);
    Figure {
        title: title.into(),
        x_label: if force { "t [s]" } else { "T = t sqrt(g/a)" }.into(),
        y_label: if force {
            "force on the solid [N]"
        } else {
            "Z = z/a (surge front)"
        }
        .into(),
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
