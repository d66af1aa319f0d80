// Stage `wrap_positions`: periodic boundaries (`crate::periodic`). Twin of
// `CpuBackend::wrap_positions` and `Periodic::wrap` (`periodic_wrap` in sph.cuh), with the same
// f32 operations, so both backends wrap bitwise alike.
#include "sph.cuh"

/// Fluid only: each coordinate outside the domain along a periodic axis moves by one period.
SPH_KERNEL(wrap_positions)(u32 n, StepParams p, const u32* __restrict__ kind, float* __restrict__ pos) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    vstore(pos, i, periodic_wrap(p, vload(pos, i)));
}
