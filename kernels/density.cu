// Stage `density`: eq. (18), density by summation, rho_i = sum_j m_j W(|x_i - x_j|, h) with the
// kernel `w_density` (poly6, or the corrected solver's scaled spiky kernel),
// for fluid particles (the sum includes j = i). Twin of `CpuBackend::density` and
// `physics::density::density_term`; solid entries are left as they are.
#include "sph.cuh"

/// Eq. (18): density by summation [kg/m^3].
SPH_KERNEL(density)(u32 n, StepParams p, GridGeometry g, const u32* __restrict__ cell_start,
                    const u32* __restrict__ cell_key, const float* __restrict__ pos,
                    const float* __restrict__ mass, const u32* __restrict__ kind,
                    float* __restrict__ density) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const Smoothing s = smoothing(p.h);
    const vec_t xi = vload(pos, i);
    float sum = 0.0f;
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        vec_t d = vsub(xi, vload(pos, j));
        float r2 = vdot(d, d);
        if (r2 < s.h2) {
            d = pair_offset(d, &r2, i, j, s.h);
            sum += mass[j] * w_density(s, p, r2);
        }
    });
    density[i] = sum;
}

/// The velocity solve's density [kg/m^3], fluid only: the continuity equation integrated over
/// tau [s] from the current velocities, `rho*_i = base_i + tau sum_{j != i} m_j (u_i - u_j) .
/// grad W_rho(x_i - x_j)`, with `grad_w_density` the gradient of the kernel of (18) (the sum
/// (18) the correction measures, to first order in tau). Solids take part with their own
/// velocity. Twin of `CpuBackend::predicted_density`; solid entries are left as they are.
SPH_KERNEL(predicted_density)(u32 n, StepParams p, GridGeometry g,
                              const u32* __restrict__ cell_start, const u32* __restrict__ cell_key,
                              const float* __restrict__ pos, const float* __restrict__ vel,
                              const float* __restrict__ mass, const u32* __restrict__ kind,
                              const float* __restrict__ density_start, float tau,
                              float* __restrict__ density) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const Smoothing s = smoothing(p.h);
    const vec_t xi = vload(pos, i);
    const vec_t ui = vload(vel, i);
    float rate = 0.0f;  // d rho_i / dt [kg/(m^3 s)]
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        vec_t d = vsub(xi, vload(pos, j));
        float r2 = vdot(d, d);
        if (r2 < s.h2 && j != i) {
            d = pair_offset(d, &r2, i, j, s.h);
            const vec_t grad = grad_w_density(s, p, d, sqrtf(r2));
            rate += mass[j] * vdot(vsub(ui, vload(vel, j)), grad);
        }
    });
    density[i] = velocity_solve_base(density_start[i], p.rho0) + tau * rate;
}
