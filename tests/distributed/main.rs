//! The domain decomposition (`sph::distributed`): regions that tile the domain with balanced
//! counts, halos that hold every neighbour a rank's particles need, migration that moves every
//! particle to its owner bit for bit, and a lost rank that stops the others with an error.
//! Whole runs split across ranks: the dam breaks and a sloshing tank on 1, 2, 3 and 4 ranks
//! against one, rebalancing, and the run folder a split `run_scene` writes.
//! The ranks are threads of one process (`LocalWorld`), which run the same collective code as
//! MPI; `.ci/run` runs `examples/mpi_exchange` and `sph run` under `mpirun`
//! (`tests/mpi/compare_split_run.py`).

#[path = "../common/mod.rs"]
mod common;

mod balance;
mod decomposition;
mod exchange;
mod particles;
mod probe_reach;
mod split_checkpoint;
mod split_cuda;
mod split_output;
mod split_run;
