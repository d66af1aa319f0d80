//! `sph sweep SCENE --set KEY=V1,V2,...`: run one variant per value (the Cartesian product of
//! several swept keys), or `--solvers wcsph=C1,C2 --solvers corrected=D1,D2` (each solver over
//! its own key), and write `sweep.csv`, `sweep.png`, `fronts.png` and `pareto.png`.

use super::BackendArg;
use crate::backend::BackendKind;
use crate::run::RunOptions;
use crate::sweep::{Sweep, SweepEvent, VariantResult, run_sweep};
use anyhow::Context;
use indicatif::ProgressBar;
use std::path::{Path, PathBuf};

/// Where a sweep writes: `--out` and `--force`.
#[derive(Clone, Debug, Default)]
pub struct SweepOut {
    /// `--out DIR`.
    pub dir: Option<PathBuf>,
    /// `--force`: replace another sweep's files there.
    pub force: bool,
}

/// Runs the sweep of the scene at `path` over `sets` (each `KEY=V1,V2,...`).
pub fn sweep(
    path: &Path,
    out: SweepOut,
    threads: Option<usize>,
    backend: BackendArg,
    sets: &[String],
    solvers: &[String],
    reference_dir: Option<&Path>,
) -> anyhow::Result<()> {
    let sweep = if solvers.is_empty() {
        Sweep::from_sets(sets)?
    } else {
        Sweep::solvers(solvers, sets)?
    };
    let mut scenes = sweep
        .load(path)
        .with_context(|| format!("loading scene {}", path.display()))?;
    let dir = crate::scene::reference_dir(reference_dir);
    for (k, scene) in scenes.iter_mut().enumerate() {
        for skipped in crate::scene::locate_references(scene, dir.as_deref()) {
            if k == 0 {
                eprintln!("warning: {skipped}");
            }
        }
    }
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let force = out.force;
    let out = out
        .dir
        .unwrap_or_else(|| PathBuf::from("out").join(format!("{stem}-sweep")));
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        anyhow::ensure!(n > 0, "--threads must be at least 1");
        builder = builder.num_threads(n);
    }
    let pool = builder.build().context("starting the worker threads")?;
    let scene_name = scenes.first().and_then(|s| s.name.clone()).unwrap_or(stem);
    let options = RunOptions {
        out_dir: None,
        force,
        stop: super::signals::stop_flag(),
        ranks: None,
        backend: match backend {
            BackendArg::Cpu => BackendKind::Cpu,
            BackendArg::Cuda => BackendKind::Cuda,
        },
        threads: pool.current_num_threads(),
        scene_name,
        restart: Default::default(),
    };
    let mut bar: Option<ProgressBar> = None;
    let mut last = std::time::Instant::now();
    let report = pool.install(|| {
        run_sweep(&sweep, &scenes, &out, &options, &mut |event| match event {
            SweepEvent::Started {
                index,
                count,
                variant,
                dir,
            } => {
                println!("variant {index}/{count}: {} (in {})", variant.name, dir.display());
                bar = Some(super::run::progress_bar());
            }
            SweepEvent::Progress(p) => {
                if let Some(b) = &bar
                    && (last.elapsed().as_millis() >= 100 || p.time >= p.end_time)
                {
                    last = std::time::Instant::now();
                    b.set_position((1000.0 * p.time / p.end_time) as u64);
                    b.set_message(format!(
                        "{:.4}/{} s, {} steps, {:.3e} particle-steps/s",
                        p.time, p.end_time, p.steps, p.particle_steps_per_second
                    ));
                }
            }
            SweepEvent::Finished { index, count, result } => {
                if let Some(b) = bar.take() {
                    b.finish_and_clear();
                }
                println!("variant {index}/{count}: {}", finished_line(result));
            }
        })
    });
    if let Some(b) = bar.take() {
        b.finish_and_clear();
    }
    let report =
        report.with_context(|| format!("sweeping scene {} into {}", path.display(), out.display()))?;
    for note in &report.skipped_figures {
        eprintln!("warning: figure not written: {note}");
    }
    let failed = report.results.iter().filter(|r| r.status != "completed").count();
    println!(
        "{} variants ({} failed); results in {}",
        report.results.len(),
        failed,
        out.join("sweep.csv").display()
    );
    Ok(())
}

/// `completed in 12.300 s wall, 812 steps, front error mean 4.1 % (max 6.0 %), max compression
/// 1.2e-3, max surface deficit 3.1e-1`; a failure is its status followed by the same figures so
/// far in brackets.
fn finished_line(r: &VariantResult) -> String {
    let mut parts = Vec::new();
    if let Some(s) = &r.summary {
        parts.push(format!("{:.3} s wall, {} steps", s.wall_seconds, s.steps));
        if let Some(n) = s.extra.get("unconverged_stages").and_then(|v| v.as_u64())
            && n > 0
        {
            parts.push(format!("{n} correction stages unconverged"));
        }
    }
    for c in &r.comparisons {
        match (
            r.probe_error(&c.name, "error_mean"),
            r.probe_error(&c.name, "error_max"),
        ) {
            (Some(mean), Some(max)) => parts.push(format!(
                "{} error mean {:.1} % (max {:.1} %)",
                c.name,
                100.0 * mean,
                100.0 * max
            )),
            _ => parts.push(format!("{}: no reference point reached", c.name)),
        }
    }
    if let Some(e) = r.max_compression() {
        parts.push(format!("max compression {e:.2e}"));
    }
    if let Some(e) = r.max_surface_deficit() {
        parts.push(format!("max surface deficit {e:.2e}"));
    }
    let parts = parts.join(", ");
    if r.status == "completed" {
        format!("completed in {parts}")
    } else if parts.is_empty() {
        r.status.clone()
    } else {
        format!("{} ({parts})", r.status)
    }
}
