//! The domain decomposition (`sph::distributed`): regions that tile the domain with balanced
//! counts, halos that hold every neighbour a rank's particles need, migration that moves every
//! particle to its owner bit for bit, and a lost rank that stops the others with an error.
//! The ranks are threads of one process (`LocalWorld`), which run the same collective code as
//! MPI; `tests/mpi` runs the MPI transport under `mpirun`.

#[path = "../common/mod.rs"]
mod common;

mod balance;
mod decomposition;
mod exchange;
mod particles;
mod split_output;
mod split_run;
