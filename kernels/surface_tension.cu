// Stages `surface_normals` and `surface_tension`: [AAT13] Akinci, Akinci & Teschner 2013
// cohesion and curvature forces between fluid particles. Twins of `CpuBackend::surface_normals`,
// `CpuBackend::surface_tension` and `physics::surface_tension` (same f32 operations in the same
// order per pair; only the order of the neighbour sums differs). Launched only in scenes with the
// `surface_tension` effect.
#include "sph.cuh"

/// Gradient of eq. (20) at offset x, `-6 K (h^2 - r^2)^2 x` [1/m^(D+1)]. Twin of
/// `Smoothing::grad_w`.
__device__ __forceinline__ vec_t grad_w_poly6(const Smoothing& s, vec_t x) {
    const float r2 = vdot(x, x);
    if (r2 >= s.h2) return vzero();
    const float q = s.h2 - r2;
    return vscale(x, -6.0f * s.poly6 * q * q);
}

/// [AAT13] eq. (2): the cohesion spline C(r) [1/m^D], normalised by 32/(pi h^9) in 3D and
/// 25280/(627 pi h^8) in 2D. Twin of `surface_tension::cohesion_kernel`.
__device__ __forceinline__ float cohesion_kernel(float r, float h) {
    if (r > h || r <= 0.0f) return 0.0f;
    const double norm = D == 2 ? 25280.0 / (627.0 * SPH_PI) : 32.0 / SPH_PI;
    const float k = (float)(norm / pow((double)h, D + 6));
    const float s = (h - r) * (h - r) * (h - r) * r * r * r;
    if (2.0f * r > h) return k * s;
    const float h3 = h * h * h;
    return k * (2.0f * s - h3 * h3 / 64.0f);
}

/// [AAT13] eq. (3): n_i = h sum_j (m_j/rho_j) grad W(x_ij) over fluid neighbours (dimensionless,
/// into the fluid at a free surface); zero for solids.
SPH_KERNEL(surface_normals)(u32 n, StepParams p, GridGeometry g, const u32* __restrict__ cell_start,
                            const u32* __restrict__ cell_key, const float* __restrict__ pos,
                            const float* __restrict__ mass, const float* __restrict__ density,
                            const u32* __restrict__ kind, float* __restrict__ normal) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    vec_t sum = vzero();
    if (kind[i] == SPH_FLUID) {
        const Smoothing s = smoothing(p.h);
        const vec_t xi = vload(pos, i);
        SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
            if (kind[j] != SPH_FLUID) continue;
            vec_t d = vsub(xi, vload(pos, j));
            float r2 = vdot(d, d);
            if (!(r2 < s.h2)) continue;
            d = pair_offset(d, &r2, i, j, s.h);
            sum = vadd(sum, vscale(grad_w_poly6(s, d), mass[j] / density[j]));
        });
    }
    vstore(normal, i, vscale(sum, p.h));
}

/// [AAT13] eqs. (1)-(5): adds sum_j -gamma K_ij (m_j C(r) x_ij/r + n_i - n_j) over fluid
/// neighbours to the acceleration of fluid particle i [m/s^2], K_ij = 2 rho0/(rho_i + rho_j).
SPH_KERNEL(surface_tension)(u32 n, StepParams p, GridGeometry g, const u32* __restrict__ cell_start,
                            const u32* __restrict__ cell_key, const float* __restrict__ pos,
                            const float* __restrict__ mass, const float* __restrict__ density,
                            const u32* __restrict__ kind, const float* __restrict__ normal,
                            float* __restrict__ acc) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const float h = p.h;
    const vec_t xi = vload(pos, i);
    const vec_t n_i = vload(normal, i);
    const float rho_i = density[i];
    vec_t sum = vzero();
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        if (j == i || kind[j] != SPH_FLUID) continue;
        vec_t d = vsub(xi, vload(pos, j));
        float r2 = vdot(d, d);
        if (!(r2 < h * h)) continue;
        d = pair_offset(d, &r2, i, j, h);
        const float r = sqrtf(r2);
        const float k_ij = 2.0f * p.rho0 / (rho_i + density[j]);
        const vec_t cohesion = vscale(d, mass[j] * cohesion_kernel(r, h) / r);
        const vec_t pair = vadd(cohesion, vsub(n_i, vload(normal, j)));
        sum = vadd(sum, vscale(pair, -p.surface_tension_gamma * k_ij));
    });
    vstore(acc, i, vadd(vload(acc, i), sum));
}
