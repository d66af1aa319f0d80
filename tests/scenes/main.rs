//! Scene files: the loader (parsing, validation with key paths and line numbers, overrides,
//! particle generation), the solver and probe keys, bad input that must never panic, the
//! lattice distance of generated particles, and the shipped scenes themselves.

#[path = "../common/mod.rs"]
mod common;

mod flap;
mod lattice;
mod open_boundary;
mod periodic;
mod ranks;
mod scene;
mod scene_fuzz;
mod scene_solver;
mod sea_state;
mod shipped;
mod wave_maker;
