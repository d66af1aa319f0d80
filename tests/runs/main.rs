//! A run's life: checkpoints and restarts bit-identical to a run never stopped (in the library
//! and through `sph run --resume`, after SIGKILL at chosen and at random points), the run
//! folder that belongs to one run, and the state guards that stop a run keeping its last good
//! files.

#[path = "../common/mod.rs"]
mod common;

mod checkpoint;
mod kill_resume;
mod long_step;
mod restart;
mod run_folder;
