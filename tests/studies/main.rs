//! The commands that run a scene many times and tabulate the runs: `sph bench` (`bench`) and
//! `sph sweep` (`sweep`).

#[path = "../common/mod.rs"]
mod common;

mod bench;
mod sweep;
