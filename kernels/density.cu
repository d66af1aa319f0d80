// Stage `density`: eq. (18), density by summation, rho_i = sum_j m_j W_poly6(|x_i - x_j|, h),
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
            sum += mass[j] * w_poly6(s, r2);
        }
    });
    density[i] = sum;
}
