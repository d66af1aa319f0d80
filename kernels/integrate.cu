// Time integration: stages `integrate` (semi-implicit Euler), `store_step_start` and `rk_stage`
// (SSP-RK3, Shu-Osher form). Twins of `CpuBackend::integrate`, `store_step_start`, `rk_stage`,
// with the same f32 operations per component. NVRTC contracts a*b + c into one fma unless the
// kernels are compiled with `--fmad=false`, which bitwise equality with the CPU needs.
#include "sph.cuh"

/// Semi-implicit Euler, fluid only: `u += a dt`, then `x += u dt`; `dt` [s].
SPH_KERNEL(integrate)(u32 n, float dt, const u32* __restrict__ kind, const float* __restrict__ acc,
                      float* __restrict__ vel, float* __restrict__ pos) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    vec_t u = vadd(vload(vel, i), vscale(vload(acc, i), dt));
    vec_t x = vadd(vload(pos, i), vscale(u, dt));
    vstore(vel, i, u);
    vstore(pos, i, x);
}

/// SSP-RK3: remembers `x^n`, `u^n` of every particle.
SPH_KERNEL(store_step_start)(u32 n, const float* __restrict__ pos, const float* __restrict__ vel,
                             float* __restrict__ pos_start, float* __restrict__ vel_start) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    vstore(pos_start, i, vload(pos, i));
    vstore(vel_start, i, vload(vel, i));
}

/// One Shu-Osher stage, fluid only: `x <- a x^n + b (x + dt u)`, `u <- a u^n + b (u + dt acc)`.
SPH_KERNEL(rk_stage)(u32 n, float dt, float a, float b, const u32* __restrict__ kind,
                     const float* __restrict__ acc, const float* __restrict__ pos_start,
                     const float* __restrict__ vel_start, float* __restrict__ pos,
                     float* __restrict__ vel) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const vec_t x = vload(pos, i);
    const vec_t u = vload(vel, i);
    const vec_t x_euler = vadd(x, vscale(u, dt));
    const vec_t u_euler = vadd(u, vscale(vload(acc, i), dt));
    vstore(pos, i, vadd(vscale(vload(pos_start, i), a), vscale(x_euler, b)));
    vstore(vel, i, vadd(vscale(vload(vel_start, i), a), vscale(u_euler, b)));
}

/// Symplectic Euler for the density (the `density_diffusion` effect), fluid only:
/// `rho += dt drho/dt`; `dt` [s].
SPH_KERNEL(integrate_density)(u32 n, float dt, const u32* __restrict__ kind,
                              const float* __restrict__ rate, float* __restrict__ density) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    density[i] = density[i] + rate[i] * dt;
}

/// SSP-RK3 with the `density_diffusion` effect: remembers `rho^n` of every particle.
SPH_KERNEL(store_density_start)(u32 n, const float* __restrict__ density,
                                float* __restrict__ density_start) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    density_start[i] = density[i];
}

/// One Shu-Osher stage of the density, fluid only: `rho <- a rho^n + b (rho + dt drho/dt)`.
SPH_KERNEL(rk_density_stage)(u32 n, float dt, float a, float b, const u32* __restrict__ kind,
                             const float* __restrict__ rate, const float* __restrict__ density_start,
                             float* __restrict__ density) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const float euler = density[i] + rate[i] * dt;
    density[i] = density_start[i] * a + euler * b;
}
