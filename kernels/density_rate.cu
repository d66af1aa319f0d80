// Stage `density_rate`: the continuity equation with Fourtakas et al. (2019)'s density diffusion
// ([F19], `physics::density_diffusion`), `drho_i/dt = sum_j m_j (u_i - u_j) . grad W_rho(x_ij)
// + D_i` for fluid particles, solids 0. A solid neighbour j moves with wall_vel[j], its no-slip
// velocity ([A12] eqs. 22-23) where the scene has one; otherwise the host passes `vel` itself,
// as for the forces. The diffusion D_i runs over fluid neighbours only. Twin of
// `CpuBackend::density_rate`, `physics::density_diffusion::continuity_term` and
// `diffusion_term`.
#include "sph.cuh"

SPH_KERNEL(density_rate)(u32 n, StepParams p, GridGeometry g, const u32* __restrict__ cell_start,
                         const u32* __restrict__ cell_key, const float* __restrict__ pos,
                         const float* __restrict__ vel, const float* __restrict__ wall_vel,
                         const float* __restrict__ mass, const float* __restrict__ density,
                         const u32* __restrict__ kind, const u32* __restrict__ id, float* __restrict__ rate) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    if (kind[i] != SPH_FLUID) {
        rate[i] = 0.0f;
        return;
    }
    const Smoothing s = smoothing(p.h);
    // `DiffusionCoefficients::new`: 2 delta h_s c0 with h_s = h/2, and rho0 g / c0^2.
    const float strength = 2.0f * p.density_diffusion * 0.5f * p.h * sqrtf(p.c2);
    const float hydrostatic_scale = p.rho0 / p.c2;
    const vec_t xi = vload(pos, i);
    const vec_t ui = vload(vel, i);
    const float rho_i = density[i];
    float sum = 0.0f;  // d rho_i / dt [kg/(m^3 s)]
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        if (j == i) continue;
        vec_t d = pair_delta(g, xi, pos, j);
        float r2 = vdot(d, d);
        if (!(r2 < s.h2)) continue;
        d = pair_offset(d, &r2, id[i], id[j], s.h);
        const float r = sqrtf(r2);
        const bool fluid = kind[j] == SPH_FLUID;
        const vec_t uj = fluid ? vload(vel, j) : vload(wall_vel, j);
        const vec_t grad = grad_w_density(s, p, d, r);
        sum += mass[j] * vdot(vsub(ui, uj), grad);  // continuity_term
        if (fluid) {                                 // diffusion_term, x_ji = -d
            float hydrostatic = 0.0f;
            for (int k = 0; k < D; ++k) hydrostatic += p.gravity[k] * hydrostatic_scale * d.c[k];
            const float excess = (density[j] - rho_i) - (-hydrostatic);
            sum += strength * excess * (-vdot(d, grad)) / (r * r) * (mass[j] / density[j]);
        }
    });
    rate[i] = sum;
}
