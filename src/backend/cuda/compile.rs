//! NVRTC compilation of the embedded kernels (`sources`): one PTX module per kernel file, for
//! one dimension (`-DSPH_DIM`) and one GPU architecture. Needs only `libnvrtc`, no GPU, so the
//! tests compile every kernel on machines without one (`tests/cuda_nvrtc.rs`).

use super::sources::KERNEL_SOURCES;
use cudarc::nvrtc::{CompileOptions, Ptx};

/// A kernel file NVRTC rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("NVRTC could not compile kernels/{file}.cu for {arch}, D = {dim}: {log}")]
pub struct CompileError {
    /// Kernel file stem.
    pub file: String,
    /// Target architecture.
    pub arch: String,
    /// Dimension.
    pub dim: usize,
    /// NVRTC's message and log.
    pub log: String,
}

/// The architecture name NVRTC takes for compute capability `major.minor` (`"sm_90"`).
pub fn arch_for(major: i32, minor: i32) -> &'static str {
    match (major, minor) {
        (7, 5) => "sm_75",
        (8, 0) => "sm_80",
        (8, 6) => "sm_86",
        (8, 7) => "sm_87",
        (8, 9) => "sm_89",
        (9, 0) => "sm_90",
        (10, 0) => "sm_100",
        (12, 0) => "sm_120",
        // Unlisted chips: PTX for the oldest target CUDA 12 and 13 both support (Turing), which
        // the driver compiles for any later chip.
        _ => "sm_75",
    }
}

/// Compiles every kernel file for dimension `dim` (2 or 3) and `arch` (e.g. `"sm_90"`):
/// `(file stem, PTX)`. Single precision with IEEE division and square root, as the CPU.
///
/// Call [`super::library::check_nvrtc`] first: cudarc panics when NVRTC is missing.
///
/// # Errors
/// The first file that does not compile, with NVRTC's log.
pub fn compile_all(dim: usize, arch: &'static str) -> Result<Vec<(&'static str, Ptx)>, CompileError> {
    KERNEL_SOURCES
        .iter()
        .map(|&(file, source)| {
            let options = CompileOptions {
                arch: Some(arch),
                options: vec![format!("-DSPH_DIM={dim}"), "--std=c++17".into()],
                prec_div: Some(true),
                prec_sqrt: Some(true),
                fmad: Some(false),
                ..Default::default()
            };
            cudarc::nvrtc::compile_ptx_with_opts(source, options)
                .map(|ptx| (file, ptx))
                .map_err(|e| CompileError {
                    file: file.into(),
                    arch: arch.into(),
                    dim,
                    log: format!("{e:?}"),
                })
        })
        .collect()
}
