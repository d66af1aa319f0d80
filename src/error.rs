//! The crate's error type, gathering each boundary's typed errors.

/// Any error of the library.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene file is missing, malformed or impossible.
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
    /// The simulation could not be set up.
    #[error(transparent)]
    Setup(#[from] crate::solver::SetupError),
    /// A step failed (non-finite value, escaped particle, grid overflow).
    #[error(transparent)]
    Step(#[from] crate::solver::StepError),
    /// Writing results failed.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    /// A free surface could not be reconstructed or written.
    #[error(transparent)]
    Surface(#[from] crate::output::surface_series::SurfaceOutputError),
    /// A figure could not be drawn or written.
    #[error(transparent)]
    Plot(#[from] crate::output::plot::PlotError),
    /// A run's frames could not be rendered.
    #[error(transparent)]
    Render(#[from] crate::render::RenderError),
    /// A probe could not be compared with its reference data.
    #[error(transparent)]
    Probe(#[from] crate::probe::ProbeError),
    /// A parameter sweep could not be set up or run.
    #[error(transparent)]
    Sweep(#[from] crate::sweep::SweepError),
    /// A checkpoint could not be written, read or applied.
    #[error(transparent)]
    Checkpoint(#[from] crate::solver::checkpoint::CheckpointError),
    /// The run folder is held by another run, holds another run's files, or cannot be used.
    #[error(transparent)]
    Folder(#[from] crate::run::RunFolderError),
    /// A signal (SIGINT, SIGTERM) ended the run after its current step, the run's state
    /// checkpointed; or inside a step still running a grace time after the signal
    /// (`solver::interrupt`), that step's state not written. `summary.json` says `interrupted`.
    #[error("{}", interrupted_message(*signal, *inside_step))]
    Interrupted {
        /// The signal's number.
        signal: usize,
        /// The step abandoned, where the signal ended the run inside one.
        inside_step: Option<u64>,
    },
    /// The requested backend is not available.
    #[error(transparent)]
    Backend(#[from] crate::backend::BackendError),
    /// The run cannot be split across ranks.
    #[error(transparent)]
    Split(#[from] crate::solver::ranks::SplitError),
}

/// The message of [`Error::Interrupted`].
fn interrupted_message(signal: usize, inside_step: Option<u64>) -> String {
    match inside_step {
        None => format!(
            "interrupted by signal {signal}; the run was checkpointed and can be continued with sph run --resume"
        ),
        Some(step) => format!(
            "interrupted by signal {signal} inside step {step}, which was still running a grace time after it; \
             that step's state was not written (sph run --resume continues from the last checkpoint, if one was written)"
        ),
    }
}
