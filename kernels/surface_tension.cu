// Stages `surface_normals` and `surface_tension`, both surface-tension models: the capillary
// stress of the surface layers with artificial stress (`physics::surface_stress`, when
// p.surface_tension_model == SPH_SURFACE_STRESS) or [AAT13] Akinci, Akinci & Teschner 2013 cohesion and curvature
// forces between fluid particles. Twins of `CpuBackend::surface_normals`,
// `CpuBackend::surface_tension` and the physics modules (same f32 operations in the same order
// per pair; only the order of the neighbour sums differs). Launched only in scenes with the
// `surface_tension` effect.
#include "sph.cuh"

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

/// The rest density of particle j: its own with the `multiphase` effect (`p.phases`), else rho0.
__device__ __forceinline__ float rest_of(const StepParams& p, const float* rest_density, u32 j) {
    return p.phases == SPH_PHASES_MULTI ? rest_density[j] : p.rho0;
}

/// [AAT13] eq. (3): n_i = h sum_j (m_j/rho_j) grad W(x_ij) over fluid neighbours (dimensionless,
/// into the fluid at a free surface); zero for solids. The surface stress weighs each neighbour by
/// its rest volume m_j/rho0_j instead (h grad c).
SPH_KERNEL(surface_normals)(u32 n, StepParams p, GridGeometry g, const u32* __restrict__ cell_start,
                            const u32* __restrict__ cell_key, const float* __restrict__ pos,
                            const float* __restrict__ mass, const float* __restrict__ density,
                            const float* __restrict__ rest_density,
                            const u32* __restrict__ kind, const u32* __restrict__ id, float* __restrict__ normal) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    vec_t sum = vzero();
    const bool rest_volume = p.surface_tension_model == SPH_SURFACE_STRESS;
    if (kind[i] == SPH_FLUID) {
        const Smoothing s = smoothing(p.h);
        const vec_t xi = vload(pos, i);
        SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
            if (kind[j] != SPH_FLUID) continue;
            vec_t d = pair_delta(g, xi, pos, j);
            float r2 = vdot(d, d);
            if (!(r2 < s.h2)) continue;
            d = pair_offset(d, &r2, id[i], id[j], s.h);
            const float rho_j = rest_volume ? rest_of(p, rest_density, j) : density[j];
            sum = vadd(sum, vscale(grad_w_poly6(s, d), mass[j] / rho_j));
        });
    }
    vstore(normal, i, vscale(sum, p.h));
}

/// Surface weight of a normal of length len = |h grad c|: 0 below 0.2, 1 above 0.5, linear
/// between. Twin of `surface_stress::surface_weight`.
__device__ __forceinline__ float surface_weight(float len) {
    return fminf(fmaxf((len - 0.2f) / (0.5f - 0.2f), 0.0f), 1.0f);
}

/// T x of a particle with normal n: (sigma/h) w(|n|) (|n| x - n (n.x)/|n|). Twin of
/// `surface_stress::stress_along`.
__device__ __forceinline__ vec_t stress_along(float sigma, float h, vec_t n, vec_t x) {
    const float len = sqrtf(vdot(n, n));
    const float w = surface_weight(len);
    if (w == 0.0f) return vzero();
    return vscale(vsub(vscale(x, len), vscale(n, vdot(n, x) / len)), sigma * w / h);
}

/// 1 - eps (W(r)/W(dx))^4 with eps = 0.2: Monaghan's artificial stress. Twin of
/// `surface_stress::tensile_factor`.
__device__ __forceinline__ float tensile_factor(float w_r, float w_dx) {
    const float q = w_r / w_dx;
    const float q2 = q * q;
    return 1.0f - 0.2f * (q2 * q2);
}

/// The surface stress (`physics::surface_stress`): adds sum_j m_j/(rho0_i rho0_j) (T_i + T_j) .
/// grad W t over fluid neighbours to the acceleration of fluid particle i [m/s^2], spiky gradient
/// times 1/kappa, t the tensile factor.
__device__ __forceinline__ void surface_stress(u32 i, const StepParams& p, const GridGeometry& g,
                                               const u32* cell_start, const u32* cell_key,
                                               const float* pos, const float* mass,
                                               const float* rest_density,
                                               const u32* kind, const u32* id, const float* normal,
                                               float* acc) {
    const Smoothing s = smoothing(p.h);
    const float w_dx = w_poly6(s, p.spacing * p.spacing);
    const vec_t xi = vload(pos, i);
    const vec_t n_i = vload(normal, i);
    const float rho0_i = rest_of(p, rest_density, i);
    const bool bulk_i = surface_weight(sqrtf(vdot(n_i, n_i))) == 0.0f;
    vec_t sum = vzero();
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        if (j == i || kind[j] != SPH_FLUID) continue;
        const vec_t n_j = vload(normal, j);
        // Neither carries a stress: no force, and no kernel to evaluate.
        if (bulk_i && surface_weight(sqrtf(vdot(n_j, n_j))) == 0.0f) continue;
        vec_t d = pair_delta(g, xi, pos, j);
        float r2 = vdot(d, d);
        if (!(r2 < s.h2)) continue;
        d = pair_offset(d, &r2, id[i], id[j], s.h);
        const vec_t grad = vscale(grad_w_spiky(s, d, sqrtf(r2)), p.pressure_gradient_scale);
        const float tensile = tensile_factor(w_poly6(s, r2), w_dx);
        const vec_t t = vadd(stress_along(p.surface_tension_sigma, p.h, n_i, grad),
                             stress_along(p.surface_tension_sigma, p.h, n_j, grad));
        const float rho0_j = rest_of(p, rest_density, j);
        sum = vadd(sum, vscale(t, mass[j] * tensile / (rho0_i * rho0_j)));
    });
    vstore(acc, i, vadd(vload(acc, i), sum));
}

/// [AAT13] eqs. (1)-(5): adds sum_j -gamma K_ij (m_j C(r) x_ij/r + n_i - n_j) over fluid
/// neighbours to the acceleration of fluid particle i [m/s^2], K_ij = 2 rho0/(rho_i + rho_j).
/// With p.surface_tension_model == SPH_SURFACE_STRESS the surface stress (above) instead.
SPH_KERNEL(surface_tension)(u32 n, StepParams p, GridGeometry g, const u32* __restrict__ cell_start,
                            const u32* __restrict__ cell_key, const float* __restrict__ pos,
                            const float* __restrict__ mass, const float* __restrict__ density,
                            const float* __restrict__ rest_density,
                            const u32* __restrict__ kind, const u32* __restrict__ id, const float* __restrict__ normal,
                            float* __restrict__ acc) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    if (p.surface_tension_model == SPH_SURFACE_STRESS) {
        surface_stress(i, p, g, cell_start, cell_key, pos, mass, rest_density, kind, id, normal,
                       acc);
        return;
    }
    const float h = p.h;
    const vec_t xi = vload(pos, i);
    const vec_t n_i = vload(normal, i);
    const float rho_i = density[i];
    vec_t sum = vzero();
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        if (j == i || kind[j] != SPH_FLUID) continue;
        vec_t d = pair_delta(g, xi, pos, j);
        float r2 = vdot(d, d);
        if (!(r2 < h * h)) continue;
        d = pair_offset(d, &r2, id[i], id[j], h);
        const float r = sqrtf(r2);
        const float k_ij = 2.0f * p.rho0 / (rho_i + density[j]);
        const vec_t cohesion = vscale(d, mass[j] * cohesion_kernel(r, h) / r);
        const vec_t pair = vadd(cohesion, vsub(n_i, vload(normal, j)));
        sum = vadd(sum, vscale(pair, -p.surface_tension_gamma * k_ij));
    });
    vstore(acc, i, vadd(vload(acc, i), sum));
}
