// The kernels of `kernels/` compiled for the CPU (see cuda_shim.h), once per dimension
// (-DSPH_DIM=2, 3). Each `sph_shim_<kernel>_<D>` launches one kernel over n items with the
// launch shape of the CUDA backend; parameters come by pointer so the Rust side needs no
// by-value FFI structs. Used by tests/cuda_shim.rs.
#include "cuda_shim.h"

#define SPH_KERNEL(name) static void name
#include "../sph.cuh"

#define SPH_CAT_(a, b, c) a##b##_##c
#define SPH_CAT(a, b, c) SPH_CAT_(a, b, c)
#define SPH_EXPORT(name) extern "C" void SPH_CAT(sph_shim_, name, SPH_DIM)

// Kernels and their launchers, by group (each group's file lists its kernels).
#include "exports_neighbours.inc"
#include "exports_dynamics.inc"
#include "exports_multiphase.inc"
#include "exports_anderson.inc"
