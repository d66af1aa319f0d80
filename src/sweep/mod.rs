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
use crate::scene::{Scene, SceneError, load_scene};
use std::path::{Path, PathBuf};

pub mod solvers;

/// Size of the sweep figures [px].
const FIGURE_SIZE: (u32, u32) = (1000, 650);

/// Longest sanitised variant name in a directory name [characters].
const MAX_DIR_NAME: usize = 80;

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

/// Splits an override's value list on the commas outside brackets, braces and quotes; each
/// value is trimmed. `"1e-2,1e-3"` gives two values, `"[0,-9.81]"` one and
/// `r#"["gravity"],["gravity","viscosity"]"#` two.
pub fn split_values(text: &str) -> Vec<String> {
    let mut values = Vec::new();
    let mut depth = 0usize;
    let mut quote: Option<char> = None;
    let mut escaped = false;
    let mut current = String::new();
    for c in text.chars() {
        match quote {
            Some(q) => {
                if escaped {
                    escaped = false;
                } else if c == '\\' && q == '"' {
                    escaped = true;
                } else if c == q {
                    quote = None;
                }
            }
            None => match c {
                '"' | '\'' => quote = Some(c),
                '[' | '{' => depth += 1,
                ']' | '}' => depth = depth.saturating_sub(1),
                ',' if depth == 0 => {
                    values.push(current.trim().to_string());
                    current.clear();
                    continue;
                }
                _ => {}
            },
        }
        current.push(c);
    }
    values.push(current.trim().to_string());
    values
}

/// One run of a sweep.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Variant {
    /// The swept values, `KEY=VALUE` joined by spaces (`solver.delta=1e-3 solver.kind=corrected`);
    /// `base` when nothing is swept.
    pub name: String,
    /// The value of each swept key ([`Sweep::keys`]), as written.
    pub values: Vec<String>,
    /// Every override of this variant (`KEY=VALUE`, in command-line order), for [`load_scene`].
    pub sets: Vec<String>,
}

/// The variants of a sweep.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Sweep {
    /// The swept keys (given with several values), in command-line order.
    pub keys: Vec<String>,
    /// The Cartesian product of the swept values, first key varying slowest.
    pub variants: Vec<Variant>,
}

impl Sweep {
    /// The variants of `sets` (each `KEY=V1,V2,...`, see [`split_values`]).
    ///
    /// # Errors
    /// A set without `=`, an empty key or value, or a swept key given twice.
    pub fn from_sets(sets: &[String]) -> Result<Self, SweepError> {
        let mut parsed: Vec<(String, Vec<String>)> = Vec::new();
        for set in sets {
            let Some((key, list)) = set.split_once('=') else {
                return Err(SweepError::MissingEquals { set: set.clone() });
            };
            let key = key.trim();
            if key.is_empty() {
                return Err(SweepError::EmptyValue {
                    set: set.clone(),
                    reason: "empty KEY before '='".into(),
                });
            }
            let values = split_values(list);
            if values.iter().any(String::is_empty) {
                return Err(SweepError::EmptyValue {
                    set: set.clone(),
                    reason: "empty value (expected KEY=V1,V2,...)".into(),
                });
            }
            parsed.push((key.to_string(), values));
        }
        let keys: Vec<String> = parsed
            .iter()
            .filter(|(_, v)| v.len() > 1)
            .map(|(k, _)| k.clone())
            .collect();
        for key in &keys {
            if parsed.iter().filter(|(k, _)| k == key).count() > 1 {
                return Err(SweepError::DuplicateKey { key: key.clone() });
            }
        }
        // Odometer over the swept sets, the last one varying fastest.
        let swept: Vec<usize> = (0..parsed.len()).filter(|&i| parsed[i].1.len() > 1).collect();
        let count: usize = swept.iter().map(|&i| parsed[i].1.len()).product();
        let mut variants = Vec::with_capacity(count);
        let mut choice = vec![0usize; parsed.len()];
        for _ in 0..count {
            let sets = parsed
                .iter()
                .zip(&choice)
                .map(|((k, v), &c)| format!("{k}={}", v[c]))
                .collect();
            let values: Vec<String> = swept.iter().map(|&i| parsed[i].1[choice[i]].clone()).collect();
            let name = if keys.is_empty() {
                "base".to_string()
            } else {
                keys.iter()
                    .zip(&values)
                    .map(|(k, v)| format!("{k}={v}"))
                    .collect::<Vec<_>>()
                    .join(" ")
            };
            variants.push(Variant { name, values, sets });
            for &i in swept.iter().rev() {
                choice[i] += 1;
                if choice[i] < parsed[i].1.len() {
                    break;
                }
                choice[i] = 0;
            }
        }
        Ok(Self { keys, variants })
    }

    /// Loads and validates the scene of every variant, before anything runs.
    ///
    /// # Errors
    /// [`SweepError::InvalidVariant`] for the first variant that does not load, naming the
    /// overrides its problems point at.
    pub fn load(&self, path: &Path) -> Result<Vec<Scene>, SweepError> {
        let count = self.variants.len();
        self.variants
            .iter()
            .enumerate()
            .map(|(i, v)| {
                load_scene(path, &v.sets).map_err(|source| {
                    let mut settings: Vec<String> = Vec::new();
                    for p in source.problems() {
                        if let crate::scene::Location::Override(key) = &p.location {
                            for set in &v.sets {
                                let matches = set.split_once('=').is_some_and(|(k, _)| k.trim() == key);
                                if matches && !settings.contains(set) {
                                    settings.push(set.clone());
                                }
                            }
                        }
                    }
                    SweepError::InvalidVariant {
                        index: i + 1,
                        count,
                        variant: v.name.clone(),
                        settings,
                        source,
                    }
                })
            })
            .collect()
    }

    /// The header of `sweep.csv` for scenes whose probes with reference data are `probes`:
    /// `variant`, one column per swept key, `wall_s`, `wall_s_per_simulated_s`,
    /// `particle_steps_per_s`, `steps`,
    /// `correction_iterations_mean` (per corrected stage), `correction_iterations_max`,
    /// `velocity_iterations_mean` (per velocity solve), `operator_applications_per_stage` (both
    /// per corrected stage), `unconverged_stages`, `max_compression`, `max_surface_deficit` (the summary's, see
    /// [`Summary::max_compression`]), `<probe>_relative_error_max` and
    /// `<probe>_relative_error_mean` per probe, `status`.
    pub fn columns(&self, probes: &[String]) -> Vec<String> {
        let mut columns = vec!["variant".to_string()];
        columns.extend(self.keys.iter().cloned());
        columns.extend(
            [
                "wall_s",
                "wall_s_per_simulated_s",
                "particle_steps_per_s",
                "steps",
                "correction_iterations_mean",
                "correction_iterations_max",
                "velocity_iterations_mean",
                "operator_applications_per_stage",
                "unconverged_stages",
                "max_compression",
                "max_surface_deficit",
            ]
            .map(String::from),
        );
        for p in probes {
            columns.push(format!("{p}_relative_error_max"));
            columns.push(format!("{p}_relative_error_mean"));
        }
        columns.push("status".into());
        columns
    }
}

/// The directory of variant `index` (0-based) of `count` in `out`:
/// `<index+1>-<name>`, the index zero-padded to the width of `count`, the name reduced to
/// `[A-Za-z0-9._-]` (other runs of characters become one `_`).
pub fn variant_dir(out: &Path, index: usize, count: usize, variant: &Variant) -> PathBuf {
    let width = count.to_string().len();
    let mut name = String::new();
    for c in variant.name.chars() {
        if c.is_ascii_alphanumeric() || matches!(c, '.' | '-') {
            name.push(c);
        } else if !name.ends_with('_') {
            name.push('_');
        }
    }
    let name: String = name.trim_matches('_').chars().take(MAX_DIR_NAME).collect();
    out.join(format!("{:0width$}-{name}", index + 1))
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
