//! `mpirun -np N sph run`: whether this process is one of several MPI ranks, and the split
//! run it then takes part in (`run::Ranks`, docs/distributed.md).

use crate::backend::partition::SharedCommunicator;
use crate::distributed::Rebalance;

/// How the CLI asks to cut the domain (`--decomposition`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DecompositionArg {
    /// Slabs along the domain's longest axis.
    Slabs,
    /// Recursive coordinate bisection.
    Bisection,
}

/// `--rebalance LIMIT` or `never`.
pub fn parse_rebalance(text: &str) -> Result<Rebalance, String> {
    if text == "never" {
        return Ok(Rebalance::Never);
    }
    match text.parse::<f64>() {
        Ok(limit) if limit.is_finite() && limit > 0.0 => Ok(Rebalance::Above(limit)),
        _ => Err(format!(
            "expected an imbalance above which to cut the domain again (max/mean - 1, e.g. 0.1) or never, got {text}"
        )),
    }
}

/// `--decomposition` and `--rebalance` as overrides of the scene's `[ranks]` keys (so that a
/// resumed run keeps them with the run's other overrides).
pub fn scene_overrides(decomposition: Option<DecompositionArg>, rebalance: Option<Rebalance>) -> Vec<String> {
    let mut sets = Vec::new();
    if let Some(d) = decomposition {
        let name = match d {
            DecompositionArg::Slabs => "slabs",
            DecompositionArg::Bisection => "bisection",
        };
        sets.push(format!("ranks.decomposition=\"{name}\""));
    }
    match rebalance {
        Some(Rebalance::Above(limit)) => sets.push(format!("ranks.rebalance={limit:e}")),
        Some(Rebalance::Never) => sets.push("ranks.rebalance=\"never\"".into()),
        None => {}
    }
    sets
}

/// The number of ranks an MPI launcher started, from the variables it sets (Open MPI, MPICH
/// and Intel MPI's Hydra, Slurm's PMI), if this process was started by one.
pub fn launched_ranks() -> Option<usize> {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"]
        .iter()
        .find_map(|v| std::env::var(v).ok()?.parse().ok())
}

/// Ranks on this machine, for the default thread count (each rank takes its share of the cores).
pub fn local_ranks() -> usize {
    ["OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"]
        .iter()
        .find_map(|v| std::env::var(v).ok()?.parse().ok())
        .unwrap_or(1)
}

/// This process's rank among the ranks on its machine (0 when the launcher does not say):
/// which GPU it takes with `--backend cuda`.
pub fn local_rank() -> usize {
    [
        "OMPI_COMM_WORLD_LOCAL_RANK",
        "MPI_LOCALRANKID",
        "SLURM_LOCALID",
        "PMI_LOCAL_RANK",
    ]
    .iter()
    .find_map(|v| std::env::var(v).ok()?.parse().ok())
    .unwrap_or(0)
}

/// The ranks' transport, if an MPI launcher started this process as one of several ranks
/// (the run cuts its domain as the scene's `[ranks]` says).
///
/// # Errors
/// When started as one of several ranks by a build without the `mpi` feature (each would run
/// the whole scene into the same folder), or when MPI cannot start.
pub fn join() -> anyhow::Result<Option<SharedCommunicator>> {
    let launched = launched_ranks().unwrap_or(1);
    #[cfg(feature = "mpi")]
    if launched > 1 {
        use std::sync::{Arc, Mutex};
        let world = crate::distributed::mpi_world::MpiWorld::initialize()?;
        return Ok(Some(Arc::new(Mutex::new(Box::new(world)))));
    }
    anyhow::ensure!(
        launched <= 1,
        "started as one of {launched} MPI ranks, but this sph was built without the mpi feature: \
         every rank would run the whole scene into the same folder. Build with \
         cargo build --release --features mpi (docs/distributed.md)"
    );
    Ok(None)
}
