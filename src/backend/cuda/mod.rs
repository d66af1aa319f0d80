//! The CUDA backend (section 3 of the paper): the stage kernels of `kernels/`, embedded at build
//! time, compiled at run time with NVRTC for the GPU found, launched through cudarc, with every
//! particle field resident in device memory. It mirrors the CPU backend stage for stage under
//! the same names (one `.cu` entry point or a short sequence per `Backend` method), and the same
//! plan drives both.
//!
//! Without `--features cuda`, or without the CUDA driver library, NVRTC or a GPU, selecting this
//! backend is a one-line error naming what is missing, never a panic and never a silent fallback
//! to the CPU. cudarc's dynamic loading panics when a library is missing, so the libraries are
//! probed (`library`) before the first cudarc call.

use super::BackendError;
#[cfg(feature = "cuda")]
use super::{Backend, params::StepParams};
#[cfg(feature = "cuda")]
use crate::fields::Fields;

#[cfg(feature = "cuda")]
pub mod compile;
#[cfg(feature = "cuda")]
mod device;
#[cfg(feature = "cuda")]
pub mod extremes;
pub mod grid;
#[cfg(feature = "cuda")]
pub mod launch;
#[cfg(feature = "cuda")]
pub mod library;
#[cfg(feature = "cuda")]
pub mod shim;
pub mod sources;

#[cfg(feature = "cuda")]
pub use device::CudaBackend;

/// Checks whether the CUDA backend can run on this machine: the binary has the feature, and the
/// driver and NVRTC libraries load and a GPU answers.
///
/// # Errors
/// [`BackendError::Unavailable`] naming the first thing missing.
pub fn probe() -> Result<(), BackendError> {
    #[cfg(not(feature = "cuda"))]
    {
        Err(BackendError::Unavailable {
            backend: "cuda",
            reason: "this binary was built without `--features cuda`".into(),
        })
    }
    #[cfg(feature = "cuda")]
    {
        library::check_driver()?;
        library::check_nvrtc()?;
        library::check_device()
    }
}

/// A CUDA backend holding a device copy of `fields`, with kernels compiled for dimension `D`,
/// on GPU `device` modulo the number of GPUs this process sees (`CUDA_VISIBLE_DEVICES`
/// narrows them).
///
/// # Errors
/// [`BackendError::Unavailable`] as [`probe`], or when NVRTC rejects a kernel;
/// [`BackendError::Device`] when an allocation or the upload fails.
#[cfg(feature = "cuda")]
pub fn create<const D: usize>(
    fields: &Fields<D>,
    params: &StepParams<D>,
    device: usize,
) -> Result<Box<dyn Backend<D> + Send>, BackendError> {
    probe()?;
    Ok(Box::new(CudaBackend::new(fields, params, device)?))
}

/// Without `--features cuda` the backend cannot be created.
///
/// # Errors
/// Always [`BackendError::Unavailable`].
#[cfg(not(feature = "cuda"))]
pub fn create<const D: usize>(
    _fields: &crate::fields::Fields<D>,
    _params: &super::params::StepParams<D>,
    _device: usize,
) -> Result<Box<dyn super::Backend<D> + Send>, BackendError> {
    probe()?;
    unreachable!("probe fails without the cuda feature")
}
