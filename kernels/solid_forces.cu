// Stage `solid_forces` (Fig. 4): the force of the fluid on each named solid. Twin of
// `CpuBackend::solid_forces`: each solid particle s sums `force_on_solid` over its fluid
// neighbours in f32, then adds the sum in f64 (per thread, see below) to its solid's three slots
// `out[3 (kind[s] - 1) + axis]` (z = 0 in 2D). The host zeroes `out` (3 doubles per solid; every
// solid particle's kind must be at most the number of solids) and, for the correction's impulse
// (`SolidForceSource::Correction`), passes `p` with `mu = alpha = 0` and the pressure increments
// `delta_p` as `pressure`, as the CPU does. In (17) solid particle s carries wall_vel[s], its
// no-slip velocity ([A12] eqs. 22-23), as the forces stage does (`vel` itself where the scene has
// none). `solid_forces_multiphase` (the `multiphase` effect) takes the pressure pair term in
// [HA06]'s volume form, `-(p_s V_s^2 + p_f V_f^2) grad W`.
#include "sph.cuh"
#include "pair_forces.cuh"
#include "multiphase.cuh"

template <bool MULTIPHASE>
__device__ __forceinline__ void solid_forces_body(u32 n, const StepParams& p, const GridGeometry& g,
                                                  const u32* __restrict__ cell_start,
                                                  const u32* __restrict__ cell_key,
                                                  const float* __restrict__ pos,
                                                  const float* __restrict__ vel,
                                                  const float* __restrict__ mass,
                                                  const float* __restrict__ density,
                                                  const float* __restrict__ pressure,
                                                  const u32* __restrict__ kind,
                                                  const float* __restrict__ wall_vel,
                                                  double* __restrict__ out) {
    // Grid-stride loop: the backend launches about n/8 threads, each summing its solid particles
    // per solid in registers and adding to the slots only when the solid changes and at the end
    // (the slots are a handful of addresses every thread would otherwise hit). The shim launches
    // one thread per particle.
    const u32 stride = gridDim.x * blockDim.x;
    const Smoothing s = smoothing(p.h);
    u32 current = SPH_FLUID;
    vec_t total = vzero();
    bool touched = false;
    for (u32 i = blockIdx.x * blockDim.x + threadIdx.x; i < n; i += stride) {
        if (kind[i] == SPH_FLUID) continue;
        const vec_t x_s = vload(pos, i);
        const vec_t u_s = vload(vel, i);
        const vec_t uv_s = vload(wall_vel, i);
        const float m_s = mass[i];
        const float p_s = pressure[i];
        const float rho_s = density[i];
        vec_t force = vzero();
        u32 fluid_neighbours = 0;
        SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
            if (kind[j] != SPH_FLUID) continue;
            vec_t d = vsub(x_s, vload(pos, j));
            float r2 = vdot(d, d);
            if (!(r2 < s.h2)) continue;
            d = pair_offset(d, &r2, i, j, s.h);
            const float r = sqrtf(r2);
            const vec_t grad = vscale(grad_w_spiky(s, d, r), p.pressure_gradient_scale);
            if (MULTIPHASE) {  // [HA06]: viscous terms as above, the volume-form pressure term
                const vec_t f = force_on_solid(p, m_s, 0.0f, rho_s, mass[j], 0.0f, density[j], d, r2,
                                               u_s, vload(vel, j), uv_s, grad,
                                               laplacian_w_viscosity(s, r));
                const float q_s = multiphase_pressure_term(p_s, m_s, rho_s);
                const float q_f = multiphase_pressure_term(pressure[j], mass[j], density[j]);
                force = vadd(force, vadd(f, multiphase_pressure_acceleration(q_s, q_f, 1.0f, grad)));
            } else {
                force = vadd(force, force_on_solid(p, m_s, p_s, rho_s, mass[j], pressure[j], density[j],
                                                   d, r2, u_s, vload(vel, j), uv_s, grad,
                                                   laplacian_w_viscosity(s, r)));
            }
            ++fluid_neighbours;
        });
        // A solid particle away from the fluid adds nothing.
        if (fluid_neighbours == 0) continue;
        if (kind[i] != current) {
            if (touched) {
                double* slot = out + 3 * (size_t)(current - 1);
                for (int k = 0; k < D; ++k) atomicAdd(slot + k, (double)total.c[k]);
            }
            current = kind[i];
            total = vzero();
        }
        total = vadd(total, force);
        touched = true;
    }
    if (touched) {
        double* slot = out + 3 * (size_t)(current - 1);
        for (int k = 0; k < D; ++k) atomicAdd(slot + k, (double)total.c[k]);
    }
}

#define SPH_SOLID_FORCES_ENTRY(name, MULTIPHASE)                                                   \
    SPH_KERNEL(name)(u32 n, StepParams p, GridGeometry g, const u32* __restrict__ cell_start,      \
                     const u32* __restrict__ cell_key, const float* __restrict__ pos,              \
                     const float* __restrict__ vel, const float* __restrict__ mass,                \
                     const float* __restrict__ density, const float* __restrict__ pressure,        \
                     const u32* __restrict__ kind, const float* __restrict__ wall_vel,             \
                     double* __restrict__ out) {                                                   \
        solid_forces_body<MULTIPHASE>(n, p, g, cell_start, cell_key, pos, vel, mass, density,      \
                                      pressure, kind, wall_vel, out);                              \
    }

/// Fig. 4 with the pair terms of (16), (17), [M92].
SPH_SOLID_FORCES_ENTRY(solid_forces, false)
/// The same with the [HA06] volume-form pressure term (the `multiphase` effect).
SPH_SOLID_FORCES_ENTRY(solid_forces_multiphase, true)
