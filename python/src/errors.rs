//! The Python exceptions: one base class and one per kind of failure, each carrying the
//! one-line message `sph` prints after `error: ` (`sph::cli::one_line`).

use pyo3::PyErr;
use pyo3::exceptions::PyException;

pyo3::create_exception!(
    _sph,
    SphError,
    PyException,
    "An error of the sph solver; str() is the line `sph` prints after `error: `."
);
pyo3::create_exception!(
    _sph,
    SceneError,
    SphError,
    "A scene that does not load or validate (the message names each bad key and its line)."
);
pyo3::create_exception!(
    _sph,
    SolverError,
    SphError,
    "A run that cannot start or that fails: a backend, a step, an output file, a run folder."
);

/// The Python exception for `e`: a [`SceneError`] when a scene error is among its causes,
/// otherwise a [`SolverError`].
pub fn to_py(e: anyhow::Error) -> PyErr {
    let line = sph::cli::one_line(&e);
    let scene = e.chain().any(|cause| {
        cause.downcast_ref::<sph::scene::SceneError>().is_some()
            || matches!(cause.downcast_ref::<sph::Error>(), Some(sph::Error::Scene(_)))
    });
    if scene {
        SceneError::new_err(line)
    } else {
        SolverError::new_err(line)
    }
}

/// [`to_py`] for a library error.
pub fn from_lib(e: impl Into<anyhow::Error>) -> PyErr {
    to_py(e.into())
}
