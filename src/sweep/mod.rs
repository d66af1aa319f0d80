//! Parameter sweeps (`sph sweep`): one run per combination of scene overrides, and a table and
//! figures that compare them.
//!
//! A sweep is given as `--set KEY=V1,V2,...` overrides. Values are split on the commas that are
//! not inside brackets, braces or quotes ([`split_values`]), so `fluid.gravity=[0,-9.81]` is one
//! value. A key with several values is *swept*; several swept keys give their Cartesian product,
//! the first key varying slowest ([`Sweep::from_sets`]); a key with one value applies to every
//! variant. Every variant is loaded and validated before anything runs ([`Sweep::load`]).
//!
//! [`run_sweep`] runs each variant in `DIR/<index>-<variant>/` (the normal run outputs), and
//! writes in `DIR`:
//! - `sweep.csv`: one row per variant, rewritten after each one (columns in [`Sweep::columns`]);
//! - `sweep.png`: error against wall time, log-log — the first reference probe's mean relative
//!   error when one was measured, else the largest compression `max(ρ − ρ0, 0)/ρ0`;
//! - `fronts.png`: the first reference probe's curve of every variant with the reference data,
//!   normalised as in [`crate::probe`] (`T = t sqrt(g/a)`, `Z = z/a`); the paper's Fig. 1 when
//!   the sweep is over `solver.kind=wcsph,corrected`;
//! - `pareto.png`: the same error against wall time per simulated second, one line per solver
//!   kind ([`solvers`]: `--solvers` sweeps `wcsph` over sound speeds and `corrected` over δ).
//!
//! A variant whose run fails (a step error, say) is recorded with its status and the sweep goes on.

use crate::output::plot::{Figure, PlotError, Series, SeriesStyle, write_png};
use crate::output::{CsvFile, CsvTable, CsvValue, OutputError, Summary, read_summary};
use crate::probe::{ProbeComparison, ProbeError, column_name, compare_samples, front_figure};
use crate::run::{Progress, RunOptions, run_scene};
use crate::scene::{Scene, SceneError};
use std::path::{Path, PathBuf};

pub mod solvers;
mod variants;

pub use variants::{Sweep, Variant, split_values, variant_dir};

/// Size of the sweep figures [px].
const FIGURE_SIZE: (u32, u32) = (1000, 650);

/// Errors of a sweep.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// A `--set` has no `=`.
    #[error("--set {set:?}: expected KEY=V1,V2,... (no '=' found)")]
    MissingEquals {
        /// The override as given.
        set: String,
    },
    /// A `--set` has an empty key or an empty value in its list.
    #[error("--set {set:?}: {reason}")]
    EmptyValue {
        /// The override as given.
        set: String,
        /// What is empty.
        reason: String,
    },
    /// A swept key is given more than once (also by `--end-time`, which sets `solver.end_time`).
    #[error("--set {key}: a swept key may be given only once")]
    DuplicateKey {
        /// The key.
        key: String,
    },
    /// A `--solvers` entry is malformed.
    #[error("--solvers {given:?}: {reason}")]
    BadSolvers {
        /// The entry as given.
        given: String,
        /// What is wrong.
        reason: String,
    },
    /// `--solvers` sweeps the solvers; a `--set` may then give only one value.
    #[error("--set {key}: with --solvers a --set takes one value (the solvers are the sweep)")]
    SweptWithSolvers {
        /// The swept key.
        key: String,
    },
    /// A variant's scene does not load; nothing has run.
    #[error("variant {index}/{count} ({variant}) is invalid{}", culprits(settings))]
    InvalidVariant {
        /// 1-based index of the variant.
        index: usize,
        /// Number of variants.
        count: usize,
        /// The variant's name (its swept values).
        variant: String,
        /// The overrides the scene's problems point at, as `KEY=VALUE`.
        settings: Vec<String>,
        /// The scene's error.
        source: SceneError,
    },
    /// Writing `sweep.csv` or creating a directory failed.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A figure could not be drawn or written.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// A probe could not be compared with its reference data.
    #[error(transparent)]
    Probe(#[from] ProbeError),
    /// The sweep's folder is in use or holds files of another sweep or run.
    #[error(transparent)]
    Folder(#[from] crate::run::RunFolderError),
    /// A signal ended the sweep during a variant (that variant was checkpointed).
    #[error("interrupted by signal {signal}; the variants so far are in sweep.csv")]
    Interrupted {
        /// The signal's number.
        signal: usize,
    },
}

fn culprits(settings: &[String]) -> String {
    if settings.is_empty() {
        String::new()
    } else {
        format!(" (bad value: {})", settings.join(", "))
    }
}

/// The outcome of one variant.
#[derive(Clone, Debug)]
pub struct VariantResult {
    /// The variant.
    pub variant: Variant,
    /// Its output directory.
    pub dir: PathBuf,
    /// `completed`, or `failed: <reason>`.
    pub status: String,
    /// The run's summary (for a failed run, the `summary.json` it wrote, if any).
    pub summary: Option<Summary>,
    /// The probes with reference data, compared with it (from the variant's `probes.csv`).
    pub comparisons: Vec<ProbeComparison>,
}

impl VariantResult {
    /// A number from the summary's `extra` map.
    fn extra(&self, key: &str) -> Option<f64> {
        self.summary.as_ref()?.extra.get(key)?.as_f64()
    }

    /// `error_max` or `error_mean` of a probe, from the summary's `probe_errors`.
    pub fn probe_error(&self, probe: &str, which: &str) -> Option<f64> {
        self.summary
            .as_ref()?
            .extra
            .get("probe_errors")?
            .get(probe)?
            .get(which)?
            .as_f64()
    }

    /// The largest compression `max(ρ − ρ0, 0)/ρ0` of the run ([`Summary::max_compression`]).
    pub fn max_compression(&self) -> Option<f64> {
        self.summary.as_ref().map(|s| s.max_compression)
    }

    /// The largest free-surface deficit `max(ρ0 − ρ, 0)/ρ0` of the run
    /// ([`Summary::max_surface_deficit`]).
    pub fn max_surface_deficit(&self) -> Option<f64> {
        self.summary.as_ref().map(|s| s.max_surface_deficit)
    }
}

/// What happens during [`run_sweep`], for a progress display.
pub enum SweepEvent<'a> {
    /// Variant `index` (1-based) of `count` starts.
    Started {
        /// 1-based index.
        index: usize,
        /// Number of variants.
        count: usize,
        /// The variant.
        variant: &'a Variant,
        /// Its output directory.
        dir: &'a Path,
    },
    /// The running variant's progress, after every step.
    Progress(&'a Progress),
    /// Variant `index` (1-based) of `count` has finished (completed or failed).
    Finished {
        /// 1-based index.
        index: usize,
        /// Number of variants.
        count: usize,
        /// Its outcome.
        result: &'a VariantResult,
    },
}

/// The results of a sweep.
#[derive(Clone, Debug)]
pub struct SweepReport {
    /// One per variant, in order.
    pub results: Vec<VariantResult>,
    /// The probes with reference data (`sweep.csv` error columns).
    pub probes: Vec<String>,
    /// The figures that could not be drawn, with the reason (no finite data, say).
    pub skipped_figures: Vec<String>,
}

/// Runs every variant (`scenes` from [`Sweep::load`]) into `out`, with `options` (its `out_dir`
/// is replaced by each variant's directory), and writes `sweep.csv`, `sweep.png`, `fronts.png`
/// and `pareto.png`.
///
/// # Errors
/// Only for the sweep's own files (`sweep.csv`, directories, a figure that fails to be written
/// for another reason than lacking data); a failing variant is recorded in its row.
pub fn run_sweep(
    sweep: &Sweep,
    scenes: &[Scene],
    out: &Path,
    options: &RunOptions,
    events: &mut dyn FnMut(SweepEvent),
) -> Result<SweepReport, SweepError> {
    // The sweep owns its folder as a run does (`run::folder`): locked, its own files listed,
    // another sweep's replaced only with `force`; each variant's folder is a run folder.
    let mut folder = crate::run::RunFolder::fresh(out, crate::run::RunIdentity::new(None), options.force)?;
    let mut probes: Vec<String> = Vec::new();
    for scene in scenes {
        for p in scene.probes.iter().filter(|p| p.reference.is_some()) {
            if !probes.contains(&p.name) {
                probes.push(p.name.clone());
            }
        }
    }
    let columns = sweep.columns(&probes);
    let columns: Vec<&str> = columns.iter().map(String::as_str).collect();
    let mut table = CsvTable::create(&folder.claim("sweep.csv")?, &columns)?;
    let count = sweep.variants.len();
    let mut results = Vec::with_capacity(count);
    for (i, (variant, scene)) in sweep.variants.iter().zip(scenes).enumerate() {
        let dir = variant_dir(out, i, count, variant);
        events(SweepEvent::Started {
            index: i + 1,
            count,
            variant,
            dir: &dir,
        });
        let result = run_variant(variant, scene, &dir, options, &mut |p| {
            events(SweepEvent::Progress(p))
        })?;
        push_row(&mut table, &result, &probes)?;
        table.flush()?;
        let signal = options
            .stop
            .as_ref()
            .map_or(0, |s| s.load(std::sync::atomic::Ordering::SeqCst));
        if signal != 0 {
            return Err(SweepError::Interrupted { signal });
        }
        events(SweepEvent::Finished {
            index: i + 1,
            count,
            result: &result,
        });
        results.push(result);
    }
    let mut skipped_figures = Vec::new();
    let name = scenes
        .first()
        .and_then(|s| s.name.clone())
        .unwrap_or_else(|| "sweep".into());
    let figures = [
        ("sweep.png", error_figure(&name, &results, probes.first())),
        ("fronts.png", fronts_figure(&name, &results, probes.first())),
        (
            "pareto.png",
            solvers::pareto_figure(&name, &results, probes.first()),
        ),
    ];
    for (file, figure) in figures {
        let result = match figure {
            Some(figure) => write_png(&figure, &folder.claim(file)?, FIGURE_SIZE),
            None => Err(PlotError::NoData { title: file.into() }),
        };
        match result {
            Ok(()) => {}
            Err(e @ PlotError::NoData { .. }) => skipped_figures.push(format!("{file}: {e}")),
            Err(e) => return Err(e.into()),
        }
    }
    Ok(SweepReport {
        results,
        probes,
        skipped_figures,
    })
}

/// Runs one variant into `dir`; a failed run is a result, not an error.
fn run_variant(
    variant: &Variant,
    scene: &Scene,
    dir: &Path,
    options: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
) -> Result<VariantResult, SweepError> {
    // The files read back below come from this run: the variant's folder is a new run's
    // (another sweep's variant replaced only when the sweep is forced, `run::folder`).
    let options = RunOptions {
        out_dir: Some(dir.to_path_buf()),
        ..options.clone()
    };
    let (status, summary) = match run_scene(scene, &options, progress) {
        Ok(summary) => (summary.status.clone(), Some(summary)),
        Err(e) => (
            format!("failed: {e}"),
            read_summary(&dir.join("summary.json")).ok(),
        ),
    };
    let comparisons = comparisons_from_csv(scene, &dir.join("probes.csv")).unwrap_or_default();
    Ok(VariantResult {
        variant: variant.clone(),
        dir: dir.to_path_buf(),
        status,
        summary,
        comparisons,
    })
}

fn push_row(table: &mut CsvTable, r: &VariantResult, probes: &[String]) -> Result<(), OutputError> {
    let number = |x: Option<f64>| x.map_or(CsvValue::Text(""), CsvValue::Float);
    let integer = |x: Option<u64>| x.map_or(CsvValue::Text(""), |n| CsvValue::Int(n as i64));
    let extra_int = |key: &str| r.summary.as_ref().and_then(|s| s.extra.get(key)?.as_u64());
    let mut row: Vec<CsvValue> = vec![CsvValue::Text(&r.variant.name)];
    row.extend(r.variant.values.iter().map(|v| CsvValue::Text(v)));
    row.push(number(r.summary.as_ref().map(|s| s.wall_seconds)));
    row.push(number(solvers::wall_per_simulated_second(r)));
    row.push(number(r.summary.as_ref().map(|s| s.particle_steps_per_second)));
    row.push(integer(r.summary.as_ref().map(|s| s.steps)));
    row.push(number(r.extra("correction_iterations_mean")));
    row.push(integer(extra_int("correction_iterations_max")));
    row.push(number(r.extra("velocity_iterations_mean")));
    row.push(number(r.extra("operator_applications_per_stage")));
    row.push(integer(extra_int("unconverged_stages")));
    row.push(number(r.max_compression()));
    row.push(number(r.max_surface_deficit()));
    for p in probes {
        row.push(number(r.probe_error(p, "error_max")));
        row.push(number(r.probe_error(p, "error_mean")));
    }
    row.push(CsvValue::Text(&r.status));
    table.push_row(&row)
}

/// `sweep.png`: one marker per variant at (wall time, error), log-log; the error is the mean
/// relative error of `probe` if any variant has one, else the largest compression.
fn error_figure(scene: &str, results: &[VariantResult], probe: Option<&String>) -> Option<Figure> {
    let probe_error = |r: &VariantResult| probe.and_then(|p| r.probe_error(p, "error_mean"));
    let use_probe = results.iter().any(|r| probe_error(r).is_some_and(f64::is_finite));
    let y_label = match probe {
        Some(p) if use_probe => format!("{p}: mean relative error against reference [-]"),
        _ => "max compression max(rho - rho0, 0)/rho0 [-]".into(),
    };
    let series: Vec<Series> = results
        .iter()
        .filter_map(|r| {
            let x = r.summary.as_ref()?.wall_seconds;
            let y = if use_probe {
                probe_error(r)?
            } else {
                r.max_compression()?
            };
            Some(Series {
                label: r.variant.name.clone(),
                points: vec![(x, y)],
                style: SeriesStyle::Markers,
            })
        })
        .collect();
    (!series.is_empty()).then(|| Figure {
        title: format!("{scene}: error against wall time"),
        x_label: "wall time [s]".into(),
        y_label,
        log_x: true,
        log_y: true,
        series,
        vertical_lines: Vec::new(),
    })
}

/// `fronts.png`: `probe`'s normalised curve of every variant, with the reference data.
fn fronts_figure(scene: &str, results: &[VariantResult], probe: Option<&String>) -> Option<Figure> {
    let probe = probe?;
    let runs: Vec<(String, &ProbeComparison)> = results
        .iter()
        .filter_map(|r| {
            let c = r.comparisons.iter().find(|c| &c.name == probe)?;
            Some((r.variant.name.clone(), c))
        })
        .collect();
    (!runs.is_empty()).then(|| front_figure(&format!("{scene}: probe {probe}, every variant"), &runs))
}

/// Reads a run's `probes.csv` (columns `t_s` and one [`crate::probe::column_name`] per probe)
/// and compares each probe of `scene` that has reference data with it, normalised as
/// [`crate::probe::compare`] does: `T = t sqrt(g/a)`, `Z = z/a` with `g = |gravity|` and
/// `a = reference.length`.
///
/// # Errors
/// The file cannot be read, lacks a probe's column or holds a cell that is not a number
/// ([`SweepError::Output`], naming the file, line and column), or the reference data cannot be
/// read or has none of the probe's series ([`SweepError::Probe`]).
pub fn comparisons_from_csv(scene: &Scene, path: &Path) -> Result<Vec<ProbeComparison>, SweepError> {
    let table = CsvFile::read(path).map_err(OutputError::from)?;
    let time = table.column("t_s").map_err(OutputError::from)?;
    let mut out = Vec::new();
    for probe in &scene.probes {
        if probe.reference.is_none() {
            continue;
        }
        let k = table
            .column(&column_name(probe, scene.dimension))
            .map_err(OutputError::from)?;
        let samples = table.points(time, k, |_| true).map_err(OutputError::from)?;
        if let Some(c) = compare_samples(scene, probe, &samples)? {
            out.push(c);
        }
    }
    Ok(out)
}
