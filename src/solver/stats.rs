//! The clock and what steps report: one step's [`StepReport`], a run's [`RunStats`].

use super::timestep::TimeStepLimit;

/// Simulated time and step count.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Clock {
    /// Simulated time [s].
    pub time: f64,
    /// Steps taken.
    pub step: u64,
    /// The last step's `dt` [s] (0 before the first): with the `density_diffusion` effect and
    /// symplectic Euler the density of that step's motion is advanced at the start of the next
    /// (`solver::plan`), so a resumed run needs it. Absent from older checkpoints (read as 0).
    #[serde(default)]
    pub last_dt: f64,
}

/// What one step did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepReport {
    /// The step taken [s].
    pub dt: f64,
    /// The criterion that limited it.
    pub limit: TimeStepLimit,
    /// Extremes of the state at the start of the step.
    pub extremes: crate::backend::StateExtremes,
    /// Fluid particles removed at the start of the step for having left the domain
    /// ([`escape::EscapePolicy::Remove`](super::escape::EscapePolicy::Remove)).
    pub removed: u64,
    /// Fluid particles created at the start of the step behind an inflow ([`open`](super::open)).
    pub created: u64,
    /// Fluid particles removed at the start of the step past an outflow's buffer
    /// ([`open`](super::open)).
    pub outflow: u64,
}

/// Density statistics over a run, from the state at the start of every step (fluid particles;
/// see `StateExtremes`).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunStats {
    /// Largest compression `max(ρ − ρ0, 0)/ρ0` seen.
    pub max_compression: f64,
    /// Sum over steps of the per-step mean compression.
    pub sum_mean_compression: f64,
    /// Largest free-surface deficit `max(ρ0 − ρ, 0)/ρ0` seen.
    #[serde(default)]
    pub max_surface_deficit: f64,
    /// Sum over steps of the per-step mean deficit.
    #[serde(default)]
    pub sum_mean_surface_deficit: f64,
    /// Position-correction statistics (`corrected` solver; zero otherwise).
    pub correction: CorrectionStats,
    /// Fluid particles the no-penetration guard put back out of a solid
    /// (`boundary::keep_out`): how often the guard, not the particle boundary, held the fluid.
    #[serde(default)]
    pub keep_out_pushes: u64,
    /// Fluid particles removed for having left the domain ([`escape`](super::escape)).
    #[serde(default)]
    pub removed_particles: u64,
    /// Fluid particles created behind an inflow ([`open`](super::open)).
    #[serde(default)]
    pub created_particles: u64,
    /// Fluid particles removed past an outflow's buffer ([`open`](super::open)).
    #[serde(default)]
    pub outflow_particles: u64,
}

/// What the position correction did over a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CorrectionStats {
    /// Integrator stages corrected.
    pub stages: u64,
    /// Iterations summed over stages.
    pub iterations: u64,
    /// Most iterations in one stage.
    pub max_iterations: u32,
    /// Stages that hit the iteration cap.
    pub unconverged_stages: u64,
    /// Largest compression `max(ρ − ρ0, 0)/ρ0` left after a stage's correction.
    pub max_compression_after: f64,
    /// Largest loop residual left after a stage's correction (`physics::correction::residual`).
    pub max_residual_after: f64,
    /// Iterations of the last stage.
    pub last_iterations: u32,
    /// Velocity solves run (one after every stage whose positions converged).
    #[serde(default)]
    pub velocity_solves: u64,
    /// Velocity-solve iterations summed over solves.
    #[serde(default)]
    pub velocity_iterations: u64,
    /// Velocity solves given up (velocity and pressure restored).
    #[serde(default)]
    pub velocity_solves_given_up: u64,
}

impl CorrectionStats {
    /// Mean iterations per corrected stage.
    pub fn mean_iterations(&self) -> f64 {
        if self.stages == 0 {
            0.0
        } else {
            self.iterations as f64 / self.stages as f64
        }
    }

    /// Mean applications of the correction operators per corrected stage: position sweeps plus
    /// velocity-solve iterations (each one neighbour pass for the density and one for the
    /// pressure force), the work measure of issue targets and `docs/performance.md`.
    pub fn mean_operator_applications(&self) -> f64 {
        if self.stages == 0 {
            0.0
        } else {
            (self.iterations + self.velocity_iterations) as f64 / self.stages as f64
        }
    }

    /// Mean iterations per velocity solve.
    pub fn mean_velocity_iterations(&self) -> f64 {
        if self.velocity_solves == 0 {
            0.0
        } else {
            self.velocity_iterations as f64 / self.velocity_solves as f64
        }
    }
}
