//! `sph bench [--backend cpu,cuda] [--sizes 1e4,1e5,...] [--scene S]`: the paper's Fig. 5 as a
//! table (printed, and written to `bench.csv`); with `--plot` also as `bench.png` (log-log).

use super::BackendArg;
use crate::backend::BackendKind;
use crate::bench::{BenchOptions, BenchRow, bench, stages_csv, timing_figure, to_csv};
use crate::output::plot::write_png;
use anyhow::Context;
use std::path::{Path, PathBuf};

/// Parses a particle count such as `1e5` or `250000`.
pub fn parse_size(text: &str) -> anyhow::Result<u64> {
    let v: f64 = text
        .trim()
        .parse()
        .with_context(|| format!("--sizes: {text:?} is not a number"))?;
    anyhow::ensure!(
        (100.0..=1e10).contains(&v),
        "--sizes: {text} is outside 100 .. 1e10 particles"
    );
    Ok(v.round() as u64)
}

fn print_row(r: &BenchRow) {
    println!(
        "{:>11} {:>5} {:>24} {:>12.3e} {:>12.3e} {:>7.2} {:>12.3e} {:>12.3e} {:>8.0} {:>8.0} {:>8}",
        r.particles,
        r.backend,
        r.device,
        r.seconds_per_step,
        r.seconds_per_sweep,
        r.sweeps_per_step,
        r.particle_steps_per_second,
        r.interactions_per_second,
        r.bytes_per_particle,
        r.peak_resident_per_particle,
        r.speedup.map_or("-".to_string(), |x| format!("{x:.1}x")),
    );
}

/// Runs the benchmark.
#[allow(clippy::too_many_arguments)]
pub fn run_bench(
    scene: &Path,
    out: Option<PathBuf>,
    threads: Option<usize>,
    backends: &[BackendArg],
    sizes: &[String],
    steps: usize,
    sweeps: usize,
    sets: &[String],
    plot: bool,
) -> anyhow::Result<()> {
    let sizes = sizes
        .iter()
        .map(|s| parse_size(s))
        .collect::<anyhow::Result<Vec<_>>>()?;
    anyhow::ensure!(
        steps >= 1 && sweeps >= 1,
        "--steps and --sweeps must be at least 1"
    );
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        anyhow::ensure!(n > 0, "--threads must be at least 1");
        builder = builder.num_threads(n);
    }
    let pool = builder.build().context("starting the worker threads")?;
    let options = BenchOptions {
        sizes,
        backends: backends
            .iter()
            .map(|b| match b {
                BackendArg::Cpu => BackendKind::Cpu,
                BackendArg::Cuda => BackendKind::Cuda,
            })
            .collect(),
        steps,
        sweeps,
        threads: pool.current_num_threads(),
    };
    if options.backends.contains(&BackendKind::Cuda) {
        crate::backend::cuda::probe()?;
    }
    println!(
        "{:>11} {:>5} {:>24} {:>12} {:>12} {:>7} {:>12} {:>12} {:>8} {:>8} {:>8}",
        "particles",
        "back",
        "device",
        "s/step",
        "s/sweep",
        "sw/step",
        "p-steps/s",
        "inter/s",
        "B/part",
        "RSS/part",
        "speedup"
    );
    let rows = pool.install(|| bench(scene, sets, &options, &mut print_row))?;
    let out = out.unwrap_or_else(|| PathBuf::from("out").join("bench"));
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let csv = out.join("bench.csv");
    std::fs::write(&csv, to_csv(&rows)).with_context(|| format!("writing {}", csv.display()))?;
    let stages = out.join("bench_stages.csv");
    std::fs::write(&stages, stages_csv(&rows)).with_context(|| format!("writing {}", stages.display()))?;
    println!("per stage [ms per step]:");
    for r in &rows {
        let parts: Vec<String> = r
            .stages
            .iter()
            .map(|(name, t)| format!("{name} {:.3}", 1e3 * t))
            .collect();
        println!("{:>11} {:>5}: {}", r.particles, r.backend, parts.join(", "));
        let stage = |name: &str| r.stages.iter().find(|(n, _)| n == name).map(|(_, t)| *t);
        let (position, velocity) = r.stage_sweeps;
        if let (Some(t), true) = (stage("correct_positions"), position > 0.0) {
            let mut line = format!(
                "{position:.1} position sweeps per step, {:.3} ms each",
                1e3 * t / position
            );
            if let (Some(v), true) = (stage("velocity_solve"), velocity > 0.0) {
                line += &format!(
                    "; {velocity:.1} velocity sweeps, {:.3} ms each",
                    1e3 * v / velocity
                );
            }
            println!("{:>11} {:>5}: {line}", "", "");
        }
    }
    println!("wrote {} and {}", csv.display(), stages.display());
    if plot {
        let png = out.join("bench.png");
        write_png(&timing_figure(&rows), &png, (900, 600))
            .with_context(|| format!("writing {}", png.display()))?;
        println!("wrote {}", png.display());
    }
    Ok(())
}

/// `sph bench --ranks 1,2,4`: the scaling table (`bench_scaling`), printed and written to
/// `bench_scaling.csv`.
pub fn run_scaling(
    scene: &Path,
    out: Option<PathBuf>,
    threads: Option<usize>,
    ranks: &[usize],
    sizes: &[String],
    steps: usize,
    sets: &[String],
) -> anyhow::Result<()> {
    use crate::bench_scaling::{ScalingRow, scaling, scaling_csv};
    let sizes = sizes
        .iter()
        .map(|s| parse_size(s))
        .collect::<anyhow::Result<Vec<_>>>()?;
    anyhow::ensure!(steps >= 1, "--steps must be at least 1");
    anyhow::ensure!(
        ranks.iter().all(|&r| (1..=1024).contains(&r)),
        "--ranks: each rank count must be 1 to 1024"
    );
    let threads = match threads {
        Some(n) => {
            anyhow::ensure!(n > 0, "--threads must be at least 1");
            n
        }
        None => std::thread::available_parallelism().map_or(1, usize::from),
    };
    println!(
        "{:>11} {:>5} {:>8} {:>12} {:>10} {:>14} {:>10} {:>10}",
        "particles", "ranks", "thr/rank", "s/step", "efficiency", "halo B/step", "refresh/st", "ghosts/rk"
    );
    let mut print = |r: &ScalingRow| {
        println!(
            "{:>11} {:>5} {:>8} {:>12.3e} {:>10.2} {:>14.3e} {:>10.1} {:>10.0}",
            r.particles,
            r.ranks,
            r.threads_per_rank,
            r.seconds_per_step,
            r.efficiency,
            r.bytes_per_step,
            r.refreshes_per_step,
            r.ghosts_per_rank
        );
    };
    let rows = scaling(scene, sets, &sizes, ranks, steps, threads, &mut print)?;
    let out = out.unwrap_or_else(|| PathBuf::from("out").join("bench"));
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let csv = out.join("bench_scaling.csv");
    std::fs::write(&csv, scaling_csv(&rows)).with_context(|| format!("writing {}", csv.display()))?;
    println!("wrote {}", csv.display());
    Ok(())
}
