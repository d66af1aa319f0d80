//! The kernels of `kernels/` compiled as C++ for the CPU (`kernels/shim`, built by `build.rs`
//! with `--features cuda`): each function launches one kernel over `n` items exactly as the CUDA
//! backend does, running the threads one after another. For tests that check every kernel
//! against the rayon stage it mirrors on machines without a GPU (`tests/cuda_shim.rs`).
//!
//! All pointers must be valid for the lengths the kernel reads and writes (`n` items, times `D`
//! for vectors); the functions are `unsafe` for that reason alone.

mod anderson;
mod dynamics;
mod multiphase;
mod neighbours;

pub use anderson::*;
pub use dynamics::*;
pub use multiphase::*;
pub use neighbours::*;
