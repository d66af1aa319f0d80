// Stage `equation_of_state`: eq. (19), p = max(C^2 (rho - rho0), 0) for fluid particles.
// Mirrors `CpuBackend::equation_of_state` and `physics::eos::pressure`; the `_multiphase` entry
// (`Phases::Multi`, [HA06]) takes each particle's own rest density `rest` [kg/m^3].
#include "sph.cuh"

SPH_KERNEL(equation_of_state)(u32 n, StepParams p, const float* __restrict__ density,
                              const u32* __restrict__ kind, float* __restrict__ pressure) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    pressure[i] = fmaxf(p.c2 * (density[i] - p.rho0), 0.0f);
}

SPH_KERNEL(equation_of_state_multiphase)(u32 n, StepParams p, const float* __restrict__ density,
                                         const float* __restrict__ rest,
                                         const u32* __restrict__ kind, float* __restrict__ pressure) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    pressure[i] = fmaxf(p.c2 * (density[i] - rest[i]), 0.0f);
}
