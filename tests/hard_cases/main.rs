//! The hard cases (`scenes/hard/`, docs/hard-cases.md): the suite of every hard scene with both
//! solvers checked after every step (`suite`), violent sloshing in a swayed tank (`sloshing`),
//! and the resting column's standing wave that guards the velocity solve's tolerance
//! (`standing_wave`).

#[path = "../common/mod.rs"]
mod common;

mod sloshing;
mod standing_wave;
mod suite;
