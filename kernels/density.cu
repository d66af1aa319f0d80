// Stage `density`: eq. (18), density by summation, rho_i = sum_j m_j W(|x_i - x_j|, h) with the
// kernel `w_density` (poly6, or the corrected solver's scaled spiky kernel),
// for fluid particles (the sum includes j = i). Twin of `CpuBackend::density` and
// `physics::density::density_term`; solid entries are left as they are. The `_multiphase`
// entries (`Phases::Multi`, [HA06] Hu & Adams, J. Comput. Phys. 213 (2006) 844) take the number
// density times the particle's own mass, `rho_i = m_i sum_j W`, and each particle's own rest
// density `rest` [kg/m^3] (`physics::multiphase`).
#include "sph.cuh"

/// Eq. (18): density by summation [kg/m^3]; [HA06] `m_i sum_j W` with `MULTIPHASE`.
template <bool MULTIPHASE>
__device__ __forceinline__ void density_body(u32 n, const StepParams& p, const GridGeometry& g,
                                             const u32* __restrict__ cell_start,
                                             const u32* __restrict__ cell_key,
                                             const float* __restrict__ pos,
                                             const float* __restrict__ mass,
                                             const u32* __restrict__ kind, const u32* __restrict__ id,
                                             float* __restrict__ density) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const Smoothing s = smoothing(p.h);
    const vec_t xi = vload(pos, i);
    float sum = 0.0f;  // sum_j m_j W, or the number density sum_j W with MULTIPHASE
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        vec_t d = pair_delta(g, xi, pos, j);
        float r2 = vdot(d, d);
        if (r2 < s.h2) {
            d = pair_offset(d, &r2, id[i], id[j], s.h);
            if (MULTIPHASE)
                sum += w_density(s, p, r2);
            else
                sum += mass[j] * w_density(s, p, r2);
        }
    });
    density[i] = MULTIPHASE ? mass[i] * sum : sum;
}

#define SPH_DENSITY_ENTRY(name, MULTIPHASE)                                                        \
    SPH_KERNEL(name)(u32 n, StepParams p, GridGeometry g, const u32* __restrict__ cell_start,      \
                     const u32* __restrict__ cell_key, const float* __restrict__ pos,              \
                     const float* __restrict__ mass, const u32* __restrict__ kind, const u32* __restrict__ id,                 \
                     float* __restrict__ density) {                                                \
        density_body<MULTIPHASE>(n, p, g, cell_start, cell_key, pos, mass, kind, id, density);         \
    }

SPH_DENSITY_ENTRY(density, false)
SPH_DENSITY_ENTRY(density_multiphase, true)

/// The velocity solve's density [kg/m^3], fluid only: the continuity equation integrated over
/// tau [s] from the current velocities, `rho*_i = base_i + tau sum_{j != i} m_j (u_i - u_j) .
/// grad W_rho(x_i - x_j)`, with `grad_w_density` the gradient of the kernel of (18) (the sum
/// (18) the correction measures, to first order in tau). Solids take part with their own
/// velocity. With `MULTIPHASE` each term takes the particle's own mass `m_i` and the base its own
/// rest density `rest[i]`. Twin of `CpuBackend::predicted_density`; solid entries are left as
/// they are.
template <bool MULTIPHASE>
__device__ __forceinline__ void predicted_density_body(
    u32 n, const StepParams& p, const GridGeometry& g, const u32* __restrict__ cell_start,
    const u32* __restrict__ cell_key, const float* __restrict__ pos, const float* __restrict__ vel,
    const float* __restrict__ mass, const float* __restrict__ rest, const u32* __restrict__ kind, const u32* __restrict__ id,
    const float* __restrict__ density_start, float tau, float* __restrict__ density) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const Smoothing s = smoothing(p.h);
    const vec_t xi = vload(pos, i);
    const vec_t ui = vload(vel, i);
    float rate = 0.0f;  // d rho_i / dt [kg/(m^3 s)]
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        vec_t d = pair_delta(g, xi, pos, j);
        float r2 = vdot(d, d);
        if (r2 < s.h2 && j != i) {
            d = pair_offset(d, &r2, id[i], id[j], s.h);
            const vec_t grad = grad_w_density(s, p, d, sqrtf(r2));
            const float m = MULTIPHASE ? mass[i] : mass[j];
            rate += m * vdot(vsub(ui, vload(vel, j)), grad);
        }
    });
    const float rho0 = MULTIPHASE ? rest[i] : p.rho0;
    density[i] = velocity_solve_base(density_start[i], rho0) + tau * rate;
}

SPH_KERNEL(predicted_density)(u32 n, StepParams p, GridGeometry g,
                              const u32* __restrict__ cell_start, const u32* __restrict__ cell_key,
                              const float* __restrict__ pos, const float* __restrict__ vel,
                              const float* __restrict__ mass, const u32* __restrict__ kind, const u32* __restrict__ id,
                              const float* __restrict__ density_start, float tau,
                              float* __restrict__ density) {
    predicted_density_body<false>(n, p, g, cell_start, cell_key, pos, vel, mass, nullptr, kind, id,
                                  density_start, tau, density);
}

SPH_KERNEL(predicted_density_multiphase)(u32 n, StepParams p, GridGeometry g,
                                         const u32* __restrict__ cell_start,
                                         const u32* __restrict__ cell_key,
                                         const float* __restrict__ pos,
                                         const float* __restrict__ vel,
                                         const float* __restrict__ mass,
                                         const float* __restrict__ rest,
                                         const u32* __restrict__ kind, const u32* __restrict__ id,
                                         const float* __restrict__ density_start, float tau,
                                         float* __restrict__ density) {
    predicted_density_body<true>(n, p, g, cell_start, cell_key, pos, vel, mass, rest, kind, id,
                                 density_start, tau, density);
}
