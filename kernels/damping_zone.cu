// Stage `damping_zone`: the damping zone of a wave flume ([AEA17] Altomare et al., Coastal
// Eng. 127 (2017); `physics::damping_zone`). Twin of `CpuBackend::damping_zone` and
// `DampingZone::velocity_factor`, with the same f32 operations in the same order (compiled with
// `--fmad=false`), so both backends damp bitwise alike.
#include "sph.cuh"

/// Fluid only: `u *= max(0, 1 - dt beta r^2)`, `r = clamp((x - x0).(n/L), 0, 1)`; `dt` [s],
/// `beta` [1/s], `x0 = (ox, oy, oz)` [m], `n/L = (ax, ay, az)` [1/m] (z unused in 2D).
SPH_KERNEL(damping_zone)(u32 n, float dt, float beta, float ox, float oy, float oz, float ax,
                         float ay, float az, const u32* __restrict__ kind,
                         const float* __restrict__ pos, float* __restrict__ vel) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const vec_t x = vload(pos, i);
    const float o[3] = {ox, oy, oz};
    const float a[3] = {ax, ay, az};
    float s = 0.0f;
    for (int k = 0; k < D; ++k) s += (x.c[k] - o[k]) * a[k];
    const float r = fminf(fmaxf(s, 0.0f), 1.0f);
    const float factor = fmaxf(1.0f - dt * beta * (r * r), 0.0f);
    vstore(vel, i, vscale(vload(vel, i), factor));
}
