//! `run_file` and `sweep_file`: `sph run` and `sph sweep` from Python, through the same library
//! calls (`run::run_scene`, `sweep::run_sweep`) with the options the command line builds, so
//! they write the same files.
//!
//! Interruption: while a run goes on, SIGINT also sets the run's stop flag (a signal-hook action
//! chained after Python's own handler), so Ctrl-C ends the run after its current step with a
//! checkpoint and the status `interrupted`, exactly as `sph run` ends it; Python then raises
//! `KeyboardInterrupt`. An exception raised by the progress callback ends the run the same way
//! (as SIGINT) and is raised again once the folder is consistent.

use crate::errors::{from_lib, to_py};
use crate::simulation::{backend_kind, pool};
use anyhow::Context;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sph::run::{Progress, Restart, RunOptions, run_scene};
use sph::sweep::{Sweep, SweepEvent, run_sweep};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// SIGINT's number, the signal a Python-side stop stands for.
const SIGINT: usize = 2;

/// The stop flag of one run, set by SIGINT while it is registered.
struct StopOnSigint {
    flag: Arc<AtomicUsize>,
    #[cfg(unix)]
    id: Option<signal_hook::SigId>,
}

impl StopOnSigint {
    fn new() -> Self {
        let flag = Arc::new(AtomicUsize::new(0));
        #[cfg(unix)]
        let id = signal_hook::flag::register_usize(signal_hook::consts::SIGINT, flag.clone(), SIGINT).ok();
        Self {
            flag,
            #[cfg(unix)]
            id,
        }
    }
}

impl Drop for StopOnSigint {
    fn drop(&mut self) {
        #[cfg(unix)]
        if let Some(id) = self.id.take() {
            signal_hook::low_level::unregister(id);
        }
    }
}

/// Calls the Python `callback` with `make`'s dict; an exception is kept in `error` and stops
/// the run through `flag`.
fn notify(
    callback: Option<&Py<PyAny>>,
    error: &Mutex<Option<PyErr>>,
    flag: &AtomicUsize,
    make: impl FnOnce(Python<'_>) -> PyResult<Bound<'_, PyDict>>,
) {
    let Some(callback) = callback else { return };
    Python::attach(|py| {
        let result = make(py).and_then(|d| callback.call1(py, (d,)));
        if let Err(e) = result {
            let mut slot = error.lock().unwrap_or_else(|p| p.into_inner());
            if slot.is_none() {
                *slot = Some(e);
            }
            flag.store(SIGINT, Ordering::SeqCst);
        }
    });
}

/// A run's progress as a dict.
fn progress_dict<'py>(py: Python<'py>, p: &Progress) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("time", p.time)?;
    d.set_item("end_time", p.end_time)?;
    d.set_item("steps", p.steps)?;
    d.set_item("particle_steps_per_second", p.particle_steps_per_second)?;
    d.set_item("unconverged_stages", p.unconverged_stages)?;
    d.set_item("removed_particles", p.removed_particles)?;
    Ok(d)
}

/// The exception for a run that ended with `error`: the callback's own exception, or the
/// pending `KeyboardInterrupt` of a Ctrl-C, or the run's error with `context`.
fn ended(py: Python<'_>, error: sph::Error, kept: Option<PyErr>, context: String) -> PyErr {
    if let Some(e) = kept {
        return e;
    }
    if matches!(error, sph::Error::Interrupted { .. })
        && let Err(e) = py.check_signals()
    {
        return e;
    }
    to_py(anyhow::Error::new(error).context(context))
}

/// The scene file's name without extension.
fn stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into())
}

/// `sph run PATH --out OUT --set ...`: runs the scene to its end time into `out` and returns
/// the summary (`summary.json`) as JSON text. `progress(dict)` is called after every step.
#[pyfunction]
#[pyo3(signature = (path, out, sets=Vec::new(), threads=None, backend="cpu", force=false, checkpoint_every=None, reference_dir=None, progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn run_file(
    py: Python<'_>,
    path: PathBuf,
    out: PathBuf,
    sets: Vec<String>,
    threads: Option<usize>,
    backend: &str,
    force: bool,
    checkpoint_every: Option<u64>,
    reference_dir: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
) -> PyResult<String> {
    if checkpoint_every == Some(0) {
        return Err(pyo3::exceptions::PyValueError::new_err(
            "checkpoint_every must be at least 1 step",
        ));
    }
    let kind = backend_kind(backend)?;
    let scene = sph::cli::load_located(&path, &sets, reference_dir.as_deref(), true)
        .with_context(|| format!("loading scene {}", path.display()))
        .map_err(to_py)?;
    // Stored absolute, so that `sph run --resume` works from any folder (as `sph run` stores it).
    let absolute = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
    let pool = pool(threads)?;
    let stop = StopOnSigint::new();
    let options = RunOptions {
        out_dir: Some(out.clone()),
        force,
        stop: Some(stop.flag.clone()),
        ranks: None,
        backend: kind,
        threads: pool.current_num_threads(),
        scene_name: scene.name.clone().unwrap_or_else(|| stem(&path)),
        restart: Restart {
            every: checkpoint_every,
            resume: false,
            accept_edited_scene: false,
            scene: Some((absolute, sets.clone())),
        },
    };
    let error = Mutex::new(None);
    let callback = progress.as_ref();
    let flag = &stop.flag;
    let result = py.detach(|| {
        pool.install(|| {
            run_scene(&scene, &options, &mut |p| {
                notify(callback, &error, flag, |py| progress_dict(py, p))
            })
        })
    });
    drop(stop);
    let kept = error.into_inner().unwrap_or_else(|p| p.into_inner());
    match result {
        Ok(summary) => match kept {
            Some(e) => Err(e),
            None => serde_json::to_string(&summary).map_err(|e| to_py(e.into())),
        },
        Err(e) => {
            let context = sph::run::failure_context(&path, &out, &e);
            Err(ended(py, e, kept, context))
        }
    }
}

/// `sph sweep PATH --out OUT --set KEY=V1,V2 ... [--solvers ...]`: runs every variant into
/// `out` and returns, per variant, `{index, name, dir, status}` as JSON text. `progress(dict)`
/// is called when a variant starts (`event="started"`), after every step (`"step"`) and when
/// it finishes (`"finished"`).
#[pyfunction]
#[pyo3(signature = (path, out, sets=Vec::new(), solvers=Vec::new(), threads=None, backend="cpu", force=false, reference_dir=None, progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn sweep_file(
    py: Python<'_>,
    path: PathBuf,
    out: PathBuf,
    sets: Vec<String>,
    solvers: Vec<String>,
    threads: Option<usize>,
    backend: &str,
    force: bool,
    reference_dir: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
) -> PyResult<String> {
    let kind = backend_kind(backend)?;
    let sweep = if solvers.is_empty() {
        Sweep::from_sets(&sets)
    } else {
        Sweep::solvers(&solvers, &sets)
    }
    .map_err(from_lib)?;
    let mut scenes = sweep
        .load(&path)
        .with_context(|| format!("loading scene {}", path.display()))
        .map_err(to_py)?;
    let dir = sph::scene::reference_dir(reference_dir.as_deref());
    for (k, scene) in scenes.iter_mut().enumerate() {
        for skipped in sph::scene::locate_references(scene, dir.as_deref()) {
            if k == 0 {
                eprintln!("warning: {skipped}");
            }
        }
    }
    let pool = pool(threads)?;
    let stop = StopOnSigint::new();
    let options = RunOptions {
        out_dir: None,
        force,
        stop: Some(stop.flag.clone()),
        ranks: None,
        backend: kind,
        threads: pool.current_num_threads(),
        scene_name: scenes
            .first()
            .and_then(|s| s.name.clone())
            .unwrap_or_else(|| stem(&path)),
        restart: Default::default(),
    };
    let error = Mutex::new(None);
    let callback = progress.as_ref();
    let flag = &stop.flag;
    let result = py.detach(|| {
        pool.install(|| {
            run_sweep(&sweep, &scenes, &out, &options, &mut |event| match event {
                SweepEvent::Started {
                    index,
                    count,
                    variant,
                    dir,
                } => notify(callback, &error, flag, |py| {
                    let d = PyDict::new(py);
                    d.set_item("event", "started")?;
                    d.set_item("index", index)?;
                    d.set_item("count", count)?;
                    d.set_item("variant", &variant.name)?;
                    d.set_item("dir", dir)?;
                    Ok(d)
                }),
                SweepEvent::Progress(p) => notify(callback, &error, flag, |py| {
                    let d = progress_dict(py, p)?;
                    d.set_item("event", "step")?;
                    Ok(d)
                }),
                SweepEvent::Finished { index, count, result } => notify(callback, &error, flag, |py| {
                    let d = PyDict::new(py);
                    d.set_item("event", "finished")?;
                    d.set_item("index", index)?;
                    d.set_item("count", count)?;
                    d.set_item("variant", &result.variant.name)?;
                    d.set_item("status", &result.status)?;
                    Ok(d)
                }),
            })
        })
    });
    drop(stop);
    let kept = error.into_inner().unwrap_or_else(|p| p.into_inner());
    match result {
        Ok(report) => {
            if let Some(e) = kept {
                return Err(e);
            }
            let variants: Vec<serde_json::Value> = report
                .results
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    serde_json::json!({
                        "index": i + 1,
                        "name": r.variant.name,
                        "values": r.variant.values,
                        "sets": r.variant.sets,
                        "dir": r.dir,
                        "status": r.status,
                    })
                })
                .collect();
            let json = serde_json::json!({
                "keys": sweep.keys,
                "variants": variants,
                "skipped_figures": report.skipped_figures,
            });
            Ok(json.to_string())
        }
        Err(e) => {
            let interrupted = matches!(e, sph::sweep::SweepError::Interrupted { .. });
            let context = format!("sweeping scene {} into {}", path.display(), out.display());
            if let Some(k) = kept {
                return Err(k);
            }
            if interrupted && let Err(k) = py.check_signals() {
                return Err(k);
            }
            Err(to_py(anyhow::Error::new(e).context(context)))
        }
    }
}
