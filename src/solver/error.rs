//! What stops a step ([`StepError`]) or a set-up ([`SetupError`]).

use super::timestep::TimeStepLimit;
use crate::smoothing::UnsupportedDimension;

/// Errors that stop a step. Each names the step, the time, the particle and the quantity.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StepError {
    /// A field became NaN or infinite.
    #[error("step {step}, t = {time:.6} s: particle {particle} has a non-finite {quantity}")]
    NonFinite {
        /// Step number.
        step: u64,
        /// Simulated time [s].
        time: f64,
        /// Particle id (index in the initial layout).
        particle: u32,
        /// Name of the field.
        quantity: &'static str,
    },
    /// A fluid particle left the domain box.
    #[error("step {step}, t = {time:.6} s: fluid particle {particle} left the domain at {position:?} m")]
    Escaped {
        /// Step number.
        step: u64,
        /// Simulated time [s].
        time: f64,
        /// Particle id (index in the initial layout).
        particle: u32,
        /// Its position [m].
        position: Vec<f64>,
    },
    /// The position correction hit its iteration cap in a `strict` scene.
    #[error(
        "step {step}, t = {time:.6} s, stage {stage}: the position correction did not reach delta = \
         {delta:e} in {iterations} iterations (residual {residual:.3e}); raise \
         solver.max_iterations, lower the time step, or drop solver.strict"
    )]
    Unconverged {
        /// Step number.
        step: u64,
        /// Simulated time [s].
        time: f64,
        /// Integrator stage (1-based).
        stage: usize,
        /// Iterations done.
        iterations: u32,
        /// Residual left (`physics::correction::residual`: compression, and expansion where
        /// pressure remains).
        residual: f64,
        /// The tolerance.
        delta: f64,
    },
    /// The chosen time step cannot advance the run: zero, not finite, or so small that the
    /// time does not change in f64 (`t + dt == t`, or `end + dt == end` for a step not cut to
    /// land on the end time, which the run could then never reach). Without this stop such a
    /// run loops for ever. `sph check` refuses the scene values that lead here in advance
    /// (`scene::progress`); this catches what only the flow decides.
    #[error(
        "step {step}, t = {time:e} s: the time step dt = {dt:e} s ({limit} limit) does not advance \
         the time in f64 (end time {end_time:e} s), so the run cannot finish; check solver.dt, \
         solver.cfl, fluid.sound_speed and the [fluid] coefficients of the viscous pair terms"
    )]
    Stalled {
        /// Step number.
        step: u64,
        /// Simulated time [s].
        time: f64,
        /// The step chosen [s].
        dt: f64,
        /// The criterion that chose it.
        limit: TimeStepLimit,
        /// The run's end time [s].
        end_time: f64,
    },
    /// A stop signal came and the step was still running a grace time later
    /// (`solver::interrupt`): the step was abandoned, its state is not written.
    #[error(
        "step {step}, t = {time:.6} s: stopped inside the step by signal {signal} (the step was still running \
         a grace time after it; the last finished step's state is what is on disk)"
    )]
    Interrupted {
        /// The step that was running.
        step: u64,
        /// Simulated time at its start [s].
        time: f64,
        /// The signal's number.
        signal: usize,
    },
    /// The backend failed (a device launch or copy).
    #[error("step {step}: {source}")]
    Backend {
        /// Step number.
        step: u64,
        /// The backend's error.
        source: crate::backend::BackendError,
    },
    /// The neighbour grid could not be built.
    #[error("step {step}: {source}")]
    Grid {
        /// Step number.
        step: u64,
        /// The grid's error.
        source: crate::grid::GridError,
    },
}

/// Errors building a simulation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SetupError {
    /// Dimension other than 2 or 3.
    #[error(transparent)]
    Dimension(#[from] UnsupportedDimension),
    /// A numeric setting that cannot run (the scene validator normally catches these first).
    #[error("invalid setting {key}: {reason}")]
    Invalid {
        /// The setting.
        key: &'static str,
        /// Why.
        reason: String,
    },
}
