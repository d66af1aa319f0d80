//! # sph — incompressible free-surface SPH
//!
//! Smoothed-particle hydrodynamics for free-surface water flows after Gugushvili & Evstigneev
//! (the seed paper; docs/method.md gives the equations as implemented, with its numbering). This crate is the
//! CPU reference solver (rayon): smoothing kernels (20)–(22), a hash-grid neighbour search with
//! radix sort (section 3), the weakly compressible step (15)–(19), solid boundaries with forces
//! on named solids, TOML scenes, VTK/CSV/JSON output and the `sph` command-line tool.
//!
//! Flow of the public API: a [`scene::Scene`] is loaded and validated, turned into a
//! [`solver::Simulation`] (through [`run::AnySimulation`] which picks the dimension once), and
//! stepped; fields are read back from `Simulation::fields`.

#![warn(missing_docs)]
// Units are written in square brackets (`[m]`, `[kg/m³]`) and references as `[A12]`, not as links.
#![allow(rustdoc::broken_intra_doc_links)]

pub use nalgebra;

pub mod backend;
pub mod bench;
pub mod bench_scaling;
mod block_lists;
pub mod boundary;
pub mod bounded_read;
pub mod charts;
pub mod cli;
pub mod distributed;
pub mod error;
pub mod fields;
pub mod geometry;
pub mod grid;
pub mod math;
pub mod memory;
pub mod model;
pub mod neighbour_list;
pub mod output;
pub mod periodic;
pub mod physics;
pub mod probe;
pub mod render;
pub mod run;
pub mod scene;
pub mod smoothing;
pub mod solver;
pub mod surface;
pub mod sweep;
pub mod validation;

pub use error::Error;
