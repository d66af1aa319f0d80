//! Solid and fluid shapes beyond axis-aligned boxes (`geometry`): how they fill the lattice, the checks a
//! mesh must pass, and the force a mesh solid receives.

#[path = "../common/mod.rs"]
mod common;

mod fill;
mod fluid_volumes;
mod force;
mod meshes;
mod shapes;
