//! `sph run SCENE`: run and write results, with a progress bar on a terminal.

use super::BackendArg;
use crate::backend::BackendKind;
use crate::run::{CHECKPOINT_FILE, Restart, RunOptions, RunState, run_scene};
use crate::solver::checkpoint::read_header;
use anyhow::Context;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// The run's progress bar (simulated time out of 1000), drawn only when stderr is a terminal.
pub(crate) fn progress_bar() -> ProgressBar {
    let target = if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    };
    let bar = ProgressBar::with_draw_target(Some(1000), target);
    bar.set_style(
        ProgressStyle::with_template("{bar:30} t = {msg} ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}

/// The scene file's name without extension (default output folder and scene name).
fn stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into())
}

/// How `sph run` checkpoints: every N steps, and/or resuming the run in a directory.
#[derive(Clone, Debug, Default)]
pub struct CheckpointArgs {
    /// `--checkpoint-every N`.
    pub every: Option<u64>,
    /// `--resume RUN_DIR`.
    pub resume: Option<PathBuf>,
    /// `--force`: replace another run's files in the output folder.
    pub force: bool,
    /// `--accept-edited-scene`: resume although the scene file changed.
    pub accept_edited_scene: bool,
}

/// Runs the scene at `path`, or resumes the run in `checkpoint.resume`; as one rank of a split
/// run over the transport `ranks` (only rank 0 reports).
#[allow(clippy::too_many_arguments)]
pub fn run(
    path: Option<&Path>,
    out: Option<PathBuf>,
    threads: Option<usize>,
    backend: BackendArg,
    sets: &[String],
    checkpoint: CheckpointArgs,
    reference_dir: Option<&Path>,
    ranks: Option<crate::backend::partition::SharedCommunicator>,
) -> anyhow::Result<()> {
    let root = ranks
        .as_ref()
        .is_none_or(|comm| crate::backend::partition::lock(comm).rank() == 0);
    anyhow::ensure!(
        checkpoint.every != Some(0),
        "--checkpoint-every must be at least 1 step"
    );
    let (path, sets, out, resume): (PathBuf, Vec<String>, PathBuf, bool) = match &checkpoint.resume {
        Some(dir) => {
            anyhow::ensure!(
                path.is_none() && out.is_none(),
                "--resume RUN_DIR takes the scene and the output folder from the run; give no SCENE or --out"
            );
            let file = dir.join(CHECKPOINT_FILE);
            let (_, header) =
                read_header(&file).with_context(|| format!("resuming from {}", dir.display()))?;
            let state: RunState = serde_json::from_value(header.metadata)
                .with_context(|| format!("{}: not a checkpoint of sph run", file.display()))?;
            let (scene, mut stored) = state
                .scene
                .with_context(|| format!("{}: names no scene file", file.display()))?;
            // Later overrides (e.g. a new --end-time) win over the stored ones.
            stored.extend(sets.iter().cloned());
            (scene, stored, dir.clone(), true)
        }
        None => {
            let path = path.context("give a SCENE file, or --resume RUN_DIR")?;
            let out = out.unwrap_or_else(|| PathBuf::from("out").join(stem(path)));
            (path.to_path_buf(), sets.to_vec(), out, false)
        }
    };
    let path = path.as_path();
    let scene = super::load_located(path, &sets, reference_dir, root)
        .with_context(|| format!("loading scene {}", path.display()))?;
    // Split across ranks, the domain is cut as the scene's `[ranks]` says (with the command
    // line's overrides among `sets`).
    let ranks = ranks.map(|comm| crate::run::Ranks {
        comm,
        method: scene.ranks.method,
        rebalance: scene.ranks.rebalance,
        device: super::ranks::local_rank(),
    });
    let stem = stem(path);
    // Stored absolute, so that --resume works from any folder.
    let absolute = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    let restart = Restart {
        every: checkpoint.every,
        resume,
        accept_edited_scene: checkpoint.accept_edited_scene,
        scene: Some((absolute, sets.clone())),
    };
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        anyhow::ensure!(n > 0, "--threads must be at least 1");
        builder = builder.num_threads(n);
    } else if ranks.is_some() {
        // The ranks on one machine share its cores.
        let cores = std::thread::available_parallelism().map_or(1, usize::from);
        builder = builder.num_threads((cores / super::ranks::local_ranks()).max(1));
    }
    let pool = builder.build().context("starting the worker threads")?;
    check_address_space(&scene, pool.current_num_threads())?;
    let options = RunOptions {
        out_dir: Some(out.clone()),
        force: checkpoint.force,
        stop: super::signals::stop_flag(),
        backend: match backend {
            BackendArg::Cpu => BackendKind::Cpu,
            BackendArg::Cuda => BackendKind::Cuda,
        },
        threads: pool.current_num_threads(),
        scene_name: scene.name.clone().unwrap_or(stem),
        restart,
        ranks,
    };
    if root && options.stop.is_some() {
        let summary = out.join("summary.json");
        super::signals::on_second_signal(move |signal| super::signals::mark_interrupted(&summary, signal));
    }
    let bar = if root {
        progress_bar()
    } else {
        ProgressBar::hidden()
    };
    let mut last = std::time::Instant::now();
    let mut warned = 0u64;
    let mut warned_removed = false;
    let summary = pool.install(|| {
        run_scene(&scene, &options, &mut |p| {
            if p.unconverged_stages > warned {
                if warned == 0 {
                    bar.suspend(|| {
                        eprintln!(
                            "warning: t = {:.4} s: the position correction hit solver.max_iterations before \
                             reaching solver.delta; continuing (counted as unconverged_stages in summary.json; \
                             solver.strict = true stops instead)",
                            p.time
                        )
                    });
                }
                warned = p.unconverged_stages;
            }
            if p.removed_particles > 0 && !warned_removed {
                warned_removed = true;
                bar.suspend(|| {
                    eprintln!(
                        "warning: t = {:.4} s: fluid particles left the domain and are removed (counted in steps.csv and summary.json; solver.on_escape = \"stop\" ends the run instead)",
                        p.time
                    )
                });
            }
            if last.elapsed().as_millis() >= 100 || p.time >= p.end_time {
                last = std::time::Instant::now();
                bar.set_position((1000.0 * p.time / p.end_time) as u64);
                bar.set_message(format!(
                    "{:.4}/{} s, {} steps, {:.3e} particle-steps/s",
                    p.time, p.end_time, p.steps, p.particle_steps_per_second
                ));
            }
        })
    });
    bar.finish_and_clear();
    let summary = match summary {
        Ok(summary) => summary,
        Err(e) => {
            let context = crate::run::failure_context(path, &out, &e);
            return Err(anyhow::Error::new(e).context(context));
        }
    };
    if !root {
        return Ok(());
    }
    println!(
        "{}: {} particles ({} fluid), {} steps to t = {:.4} s in {:.1} s wall, {:.3e} particle-steps/s; results in {}",
        summary.scene,
        summary.particles,
        summary.fluid_particles,
        summary.steps,
        summary.simulated_time,
        summary.wall_seconds,
        summary.particle_steps_per_second,
        out.display()
    );
    println!(
        "density: max compression {:.2e} (mean {:.2e}); max free-surface deficit {:.2e} (mean {:.2e})",
        summary.max_compression,
        summary.mean_compression,
        summary.max_surface_deficit,
        summary.mean_surface_deficit
    );
    if let Some(mean) = summary.extra.get("correction_iterations_mean") {
        println!(
            "position correction: {:.1} iterations per stage on average, {} at most, {} stages unconverged, \
             max compression after correction {:.2e}",
            mean.as_f64().unwrap_or(f64::NAN),
            summary
                .extra
                .get("correction_iterations_max")
                .unwrap_or(&0.into()),
            summary.extra.get("unconverged_stages").unwrap_or(&0.into()),
            summary
                .extra
                .get("max_compression_after_correction")
                .and_then(|v| v.as_f64())
                .unwrap_or(f64::NAN)
        );
    }
    if let (Some(solves), Some(mean)) = (
        summary.extra.get("velocity_solves").and_then(|v| v.as_u64()),
        summary
            .extra
            .get("velocity_iterations_mean")
            .and_then(|v| v.as_f64()),
    ) {
        println!(
            "velocity solve: {mean:.1} iterations per solve on average, {} of {solves} given up",
            summary.extra.get("velocity_solves_given_up").unwrap_or(&0.into())
        );
        if let Some(work) = summary
            .extra
            .get("operator_applications_per_stage")
            .and_then(|v| v.as_f64())
        {
            println!(
                "correction work: {work:.1} operator applications per stage (position sweeps + velocity iterations)"
            );
        }
    }
    if let Some(pushes) = summary
        .extra
        .get("keep_out_pushes")
        .and_then(|v| v.as_u64())
        .filter(|&p| p > 0)
    {
        println!(
            "no-penetration guard: {pushes} times a fluid particle was put back out of a solid \
             (keep_out_pushes in summary.json)"
        );
    }
    if let Some(serde_json::Value::Object(errors)) = summary.extra.get("probe_errors") {
        for (name, e) in errors {
            let num = |k: &str| e.get(k).and_then(|v| v.as_f64()).unwrap_or(f64::NAN);
            if e.get("status").and_then(|v| v.as_str()) == Some("skipped") {
                println!(
                    "probe {name}: not compared with {} (reference data not available)",
                    e.get("reference_file")
                        .and_then(|v| v.as_str())
                        .unwrap_or("its reference")
                );
                continue;
            }
            let signal = crate::probe::signal::summary_lines(name, e);
            if !signal.is_empty() {
                for line in signal {
                    println!("{line}");
                }
                continue;
            }
            match (e.get("error_max"), e.get("peak_N")) {
                (Some(_), _) => println!(
                    "probe {name}: error against reference max {:.1} %, mean {:.1} %",
                    100.0 * num("error_max"),
                    100.0 * num("error_mean")
                ),
                (None, Some(_)) => {
                    println!(
                        "probe {name}: peak {:.2} N at t = {:.3} s; reference {:.2} N at {:.3} s ({:+.1} %, {:+.3} s)",
                        num("peak_N"),
                        num("peak_time_s"),
                        num("reference_peak_N"),
                        num("reference_peak_time_s"),
                        100.0 * num("peak_error"),
                        num("peak_time_error_s")
                    );
                    if num("onset_time_s").is_finite() {
                        println!(
                            "probe {name}: impact onset at t = {:.3} s, reference {:.3} s; onset to peak {:+.3} s against the reference",
                            num("onset_time_s"),
                            num("reference_onset_time_s"),
                            num("rise_time_error_s")
                        );
                    }
                }
                _ => println!("probe {name}: no reference point inside the simulated time"),
            }
        }
    }
    for warning in &summary.warnings {
        eprintln!("warning: {warning}");
    }
    Ok(())
}

/// Refuses a run whose address space would pass `ulimit -v` with its worker threads' heaps
/// (`memory::address_space_need`); `sph check`'s estimate counts resident memory only, as it
/// does not know `--threads`.
fn check_address_space(scene: &crate::scene::Scene, threads: usize) -> anyhow::Result<()> {
    let Some(limit) = crate::memory::address_space_limit() else {
        return Ok(());
    };
    let counts = crate::scene::count_particles(scene)?;
    let resident = crate::scene::run_bytes(
        counts.total,
        counts.fluid,
        crate::scene::scene_particle_bytes(scene),
    )
    .unwrap_or(u64::MAX);
    let need = crate::memory::address_space_need(resident, threads);
    anyhow::ensure!(
        need <= limit,
        "particles.spacing: the run needs about {need} bytes of address space ({resident} resident, \
         {} per worker thread for its heap and stack, {threads} threads), more than the {limit} \
         bytes ulimit -v allows; raise ulimit -v, or use fewer --threads",
        crate::memory::ADDRESS_SPACE_PER_THREAD
    );
    Ok(())
}
