//! The CUDA backend's entry point.
//!
//! The stage kernels (NVRTC-compiled from `kernels/`, launched through cudarc) are the subject of
//! a later issue; until they exist, selecting this backend is a clear error, never a silent
//! fallback to the CPU. With `--features cuda` the driver library is probed first so the error
//! also says whether a GPU could be used at all.

use super::BackendError;

pub mod grid;
pub mod sources;
#[cfg(feature = "cuda")]
pub mod shim;

/// Checks whether the CUDA backend can run on this machine.
pub fn probe() -> Result<(), BackendError> {
    Err(BackendError::Unavailable {
        backend: "cuda",
        reason: reason(),
    })
}

#[cfg(not(feature = "cuda"))]
fn reason() -> String {
    "this binary was built without `--features cuda`".into()
}

#[cfg(feature = "cuda")]
fn reason() -> String {
    // Probe the driver through cudarc's dynamic loading; a missing libcuda is not a panic.
    let driver = std::panic::catch_unwind(cudarc::driver::result::init);
    let found = match driver {
        Ok(Ok(())) => "a CUDA driver was found".to_string(),
        Ok(Err(e)) => format!("the CUDA driver failed to initialise ({e:?})"),
        Err(_) => "no CUDA driver library (libcuda) could be loaded".to_string(),
    };
    format!("{found}, but the CUDA stage kernels are not implemented yet; use --backend cpu")
}
