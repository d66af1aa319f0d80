//! `sph bench --ranks 1,2,4`: the scaling table of a run split across ranks (issue "Beyond
//! one machine"): for each particle count and rank count, the time per step, the parallel
//! efficiency against one rank, and the bytes the ranks send each other per step.
//!
//! The ranks are threads of this process joined by `LocalWorld` (the collective code MPI
//! runs, without MPI), each with its share of the worker threads, as ranks on one machine
//! would have. The bytes are what MPI would carry; the times include no network.

use crate::bench::scaled_scene;
use crate::distributed::{HaloTraffic, LocalWorld, Method, Rebalance};
use crate::error::Error;
use crate::run::simulation_from_scene;
use crate::scene::Scene;
use crate::solver::Simulation;
use crate::solver::ranks::SplitError;
use std::path::Path;
use std::sync::{Arc, Mutex};

/// One row of the scaling table.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalingRow {
    /// Particles of the whole run.
    pub particles: u64,
    /// Ranks.
    pub ranks: usize,
    /// Worker threads per rank.
    pub threads_per_rank: usize,
    /// Wall time per step [s] (the ranks step together).
    pub seconds_per_step: f64,
    /// `T(1) / (ranks · T(ranks))` at this size (1 for one rank).
    pub efficiency: f64,
    /// Bytes sent between ranks per step, all ranks together: migration, ghosts at rebuilds and
    /// ghost refreshes.
    pub bytes_per_step: f64,
    /// Ghost refreshes per step (each sends every field of every ghost).
    pub refreshes_per_step: f64,
    /// Ghosts per rank at the last rebuild, on average.
    pub ghosts_per_rank: f64,
}

/// Columns of `bench_scaling.csv`.
pub const SCALING_COLUMNS: [&str; 8] = [
    "particles",
    "ranks",
    "threads_per_rank",
    "step_time_s",
    "parallel_efficiency",
    "halo_bytes_per_step",
    "refreshes_per_step",
    "ghosts_per_rank",
];

/// The table as CSV ([`SCALING_COLUMNS`]).
pub fn scaling_csv(rows: &[ScalingRow]) -> String {
    let mut out = SCALING_COLUMNS.join(",") + "\n";
    for r in rows {
        out += &format!(
            "{},{},{},{:e},{:.4},{:e},{:.2},{:.1}\n",
            r.particles,
            r.ranks,
            r.threads_per_rank,
            r.seconds_per_step,
            r.efficiency,
            r.bytes_per_step,
            r.refreshes_per_step,
            r.ghosts_per_rank
        );
    }
    out
}

/// Measures `scene` scaled to each of `sizes` on each of `ranks`, `steps` timed steps after one
/// untimed step, with `threads` worker threads shared among the ranks.
///
/// # Errors
/// [`Error`] when a scene does not build or a step fails.
pub fn scaling(
    path: &Path,
    sets: &[String],
    sizes: &[u64],
    ranks: &[usize],
    steps: usize,
    threads: usize,
    report: &mut dyn FnMut(&ScalingRow),
) -> Result<Vec<ScalingRow>, Error> {
    let mut rows: Vec<ScalingRow> = Vec::new();
    for &size in sizes {
        let scene = scaled_scene(path, sets, size)?;
        for &n in ranks {
            let mut row = match scene.dimension {
                2 => measure::<2>(&scene, n, steps, threads)?,
                _ => measure::<3>(&scene, n, steps, threads)?,
            };
            let one = rows
                .iter()
                .find(|r| r.particles == row.particles && r.ranks == 1)
                .map(|r| r.seconds_per_step);
            row.efficiency = one.map_or(if n == 1 { 1.0 } else { f64::NAN }, |t1| {
                t1 / (n as f64 * row.seconds_per_step)
            });
            report(&row);
            rows.push(row);
        }
    }
    Ok(rows)
}

/// One rank's figures: seconds per step, traffic over the timed steps, ghosts.
struct RankFigures {
    seconds: f64,
    sent: HaloTraffic,
    particles: u64,
}

fn measure<const D: usize>(
    scene: &Scene,
    ranks: usize,
    steps: usize,
    threads: usize,
) -> Result<ScalingRow, Error> {
    let per_rank = (threads / ranks).max(1);
    let results = LocalWorld::run(ranks, |rank| -> Result<RankFigures, Error> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(per_rank)
            .build()
            .map_err(|e| SplitError::RankFailed(e.to_string()))?;
        pool.install(|| {
            let mut sim: Simulation<D> = simulation_from_scene(scene)?;
            let particles = sim.fields.len() as u64;
            let comm: crate::backend::partition::SharedCommunicator = Arc::new(Mutex::new(Box::new(rank)));
            sim.split_across_ranks(comm, Method::Bisection, Rebalance::Never)?;
            let end = f64::INFINITY;
            sim.step(end)?; // untimed: the settle and the first halo
            let before = sim.halo_traffic().unwrap_or_default();
            let start = std::time::Instant::now();
            for _ in 0..steps {
                sim.step(end)?;
            }
            let seconds = start.elapsed().as_secs_f64() / steps as f64;
            let after = sim.halo_traffic().unwrap_or_default();
            let sent = HaloTraffic {
                refreshes: after.refreshes - before.refreshes,
                migration_bytes: after.migration_bytes - before.migration_bytes,
                ghost_bytes: after.ghost_bytes - before.ghost_bytes,
                refresh_bytes: after.refresh_bytes - before.refresh_bytes,
                ..after
            };
            Ok(RankFigures {
                seconds,
                sent,
                particles,
            })
        })
    });
    let mut figures = Vec::with_capacity(ranks);
    for r in results {
        match r {
            Ok(f) => figures.push(f?),
            Err(panic) => {
                return Err(SplitError::RankFailed(panic).into());
            }
        }
    }
    let steps = steps as f64;
    let bytes: u64 = figures
        .iter()
        .map(|f| f.sent.migration_bytes + f.sent.ghost_bytes + f.sent.refresh_bytes)
        .sum();
    Ok(ScalingRow {
        particles: figures[0].particles,
        ranks,
        threads_per_rank: per_rank,
        seconds_per_step: figures.iter().map(|f| f.seconds).fold(0.0, f64::max),
        efficiency: f64::NAN,
        bytes_per_step: bytes as f64 / steps,
        refreshes_per_step: figures[0].sent.refreshes as f64 / steps,
        ghosts_per_rank: figures.iter().map(|f| f.sent.ghosts as f64).sum::<f64>() / ranks as f64,
    })
}
