//! `sph._sph`: the native half of the `sph` Python package (PyO3).
//!
//! It follows the library's own path: a scene is loaded and validated ([`scene`]), turned into
//! a simulation and stepped ([`simulation`]), or run to its end time into a run folder and swept
//! over parameters ([`run`]) through the same library functions `sph run` and `sph sweep` call,
//! so a run from Python writes the files the command line writes, byte for byte. The pure-Python
//! package `python/sph/` re-exports these classes and adds the progress bar and the tables.
//!
//! Errors arrive as [`errors::SceneError`] or [`errors::SolverError`] carrying the one line
//! `sph` prints after `error: `.

use pyo3::prelude::*;

mod errors;
mod run;
mod scene;
mod simulation;

/// The native module.
#[pymodule]
fn _sph(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SphError", py.get_type::<errors::SphError>())?;
    m.add("SceneError", py.get_type::<errors::SceneError>())?;
    m.add("SolverError", py.get_type::<errors::SolverError>())?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<simulation::PySimulation>()?;
    m.add_function(wrap_pyfunction!(run::run_file, m)?)?;
    m.add_function(wrap_pyfunction!(run::sweep_file, m)?)?;
    m.add("CUDA_FEATURE", cfg!(feature = "cuda"))?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
