//! Probes for the CUDA libraries before cudarc touches them: with dynamic loading, cudarc panics
//! (it does not return an error) when it cannot load `libcuda` or `libnvrtc`.

use crate::backend::BackendError;

fn unavailable(reason: impl Into<String>) -> BackendError {
    BackendError::Unavailable {
        backend: "cuda",
        reason: reason.into(),
    }
}

/// The CUDA driver library (`libcuda.so`, installed with the NVIDIA driver).
///
/// # Errors
/// [`BackendError::Unavailable`] when it cannot be loaded.
pub fn check_driver() -> Result<(), BackendError> {
    // SAFETY: only tries to dlopen the library by its usual names; no symbol is called.
    if unsafe { cudarc::driver::sys::is_culib_present() } {
        Ok(())
    } else {
        Err(unavailable(
            "no CUDA driver library (libcuda.so) could be loaded: is an NVIDIA driver installed?",
        ))
    }
}

/// The NVRTC library (`libnvrtc.so`, from the CUDA toolkit or the `nvidia-cuda-nvrtc-cu12`
/// wheel, on `LD_LIBRARY_PATH`).
///
/// # Errors
/// [`BackendError::Unavailable`] when it cannot be loaded.
pub fn check_nvrtc() -> Result<(), BackendError> {
    // SAFETY: as above.
    if unsafe { cudarc::nvrtc::sys::is_culib_present() } {
        Ok(())
    } else {
        Err(unavailable(
            "no NVRTC library (libnvrtc.so) could be loaded: install the CUDA toolkit or \
             `pip install nvidia-cuda-nvrtc-cu12` and put its nvidia/cuda_nvrtc/lib on LD_LIBRARY_PATH",
        ))
    }
}

/// A GPU the driver can open (call after [`check_driver`]).
///
/// # Errors
/// [`BackendError::Unavailable`] when the driver fails to initialise or finds no device.
pub fn check_device() -> Result<(), BackendError> {
    cudarc::driver::result::init()
        .map_err(|e| unavailable(format!("the CUDA driver failed to initialise ({e:?})")))?;
    let count = cudarc::driver::result::device::get_count()
        .map_err(|e| unavailable(format!("the CUDA driver cannot count devices ({e:?})")))?;
    if count < 1 {
        return Err(unavailable("the CUDA driver found no GPU"));
    }
    Ok(())
}
