//! The solver: owns time and the order of stages; it never loops over particles itself.
//!
//! A [`Simulation`] holds the particle fields, the backend, the plan and the clock. The step
//! driver (`step.rs`) walks the plan and calls one backend method per stage.

pub mod anderson;
pub mod checkpoint;
pub mod escape;
pub mod floating;
pub mod interrupt;
pub mod open;
pub mod plan;
pub mod ranks;
pub mod stage;
pub mod step;
pub mod timestep;

mod backend;
mod config;
mod error;
mod initial_state;
mod simulation;
mod stats;

pub use config::{Correction, Integrator, SimConfig, SurfaceTension};
pub use error::{SetupError, StepError};
pub use simulation::Simulation;
pub use stats::{Clock, CorrectionStats, RunStats, StepReport};
