//! `CudaBackend::new`: a GPU opened, the kernels compiled for it by NVRTC and loaded.

use super::*;

impl<const D: usize> CudaBackend<D, Gpu> {
    /// Compiles the kernels for GPU `device` (modulo the GPUs this process sees) and uploads
    /// `fields`; `params` gives the domain of the dense grid. Call `cuda::probe` first (cudarc
    /// panics when a library is missing).
    ///
    /// # Errors
    /// [`BackendError::Unavailable`] when NVRTC rejects a kernel, [`BackendError::Device`] when
    /// the context, an allocation or the upload fails.
    pub fn new(fields: &Fields<D>, params: &StepParams<D>, device: usize) -> Result<Self, BackendError> {
        let count = CudaContext::device_count().map_err(|e| device_error("counting the GPUs", e))?;
        let ordinal = device % (count.max(1) as usize);
        let ctx =
            CudaContext::new(ordinal).map_err(|e| device_error(&format!("opening GPU {ordinal}"), e))?;
        let (major, minor) = ctx
            .compute_capability()
            .map_err(|e| device_error("reading the compute capability", e))?;
        let device_name = ctx.name().unwrap_or_else(|_| "unknown GPU".into());
        let arch = arch_for(major, minor);
        let modules = compile_all(D, arch).map_err(|e| BackendError::Unavailable {
            backend: "cuda",
            reason: e.to_string(),
        })?;
        let mut functions = vec![None; KERNEL_NAMES.len()];
        for (file, ptx) in modules {
            let module = ctx
                .load_module(ptx)
                .map_err(|e| device_error(&format!("loading kernels/{file}.cu"), e))?;
            for (slot, &name) in functions.iter_mut().zip(&KERNEL_NAMES) {
                if let Ok(function) = module.load_function(name) {
                    *slot = Some(function);
                }
            }
        }
        let functions = functions
            .into_iter()
            .zip(&KERNEL_NAMES)
            .map(|(f, name)| {
                f.ok_or_else(|| BackendError::Unavailable {
                    backend: "cuda",
                    reason: format!("no kernel named {name} in kernels/"),
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Self::on_device(Gpu::new(&ctx, functions, device_name), fields, params)
    }
}
