// Stage `solid_forces` (Fig. 4): the force of the fluid on each named solid, and its moment about
// the origin. Twin of `CpuBackend::solid_forces`: each solid particle s sums `force_on_solid` f_s
// over its fluid neighbours in f32, then adds f_s and x_s × f_s, in f64 (per thread, see below),
// to its solid's six slots `out[6 (kind[s] - 1) + k]`: force x, y, z, then moment x, y, z [N m]
// (`backend::SolidLoad`; 2D: z force 0, the moment x f_y − y f_x in the z slot, as
// `boundary::solid_force::particle_load`). The host zeroes `out` (6 doubles per solid; every
// solid particle's kind must be at most the number of solids) and, for the correction's impulse
// (`SolidForceSource::Correction`), launches the entry without pair terms and passes the pressure
// increments `delta_p` as `pressure`, as the CPU does. In (17) solid particle s carries wall_vel[s], its
// no-slip velocity ([A12] eqs. 22-23), as the forces stage does (`vel` itself where the scene has
// none). One entry per pair-term set and `Phases` (`solid_forces_t<bits>[_mp]`, generated into
// `entries_solid_forces.cuh`); `_mp` (the `multiphase` effect) takes the pressure pair term in
// [HA06]'s volume form, `-(p_s V_s^2 + p_f V_f^2) grad W`.
#include "sph.cuh"
#include "pair_forces.cuh"
#include "multiphase.cuh"

// Adds one thread's sums for solid `kind` (force in f32, moment in f64) to its six slots.
__device__ __forceinline__ void solid_forces_add(double* out, u32 kind, vec_t force, const double* moment) {
    double* slot = out + 6 * (size_t)(kind - 1);
    for (int k = 0; k < D; ++k) atomicAdd(slot + k, (double)force.c[k]);
    for (int k = 0; k < 3; ++k) atomicAdd(slot + 3 + k, moment[k]);
}

template <u32 TERMS, bool MULTIPHASE>
__device__ __forceinline__ void solid_forces_body(u32 n, const StepParams& p, const GridGeometry& g,
                                                  const u32* __restrict__ cell_start,
                                                  const u32* __restrict__ cell_key,
                                                  const float* __restrict__ pos,
                                                  const float* __restrict__ vel,
                                                  const float* __restrict__ mass,
                                                  const float* __restrict__ density,
                                                  const float* __restrict__ pressure,
                                                  const u32* __restrict__ kind, const u32* __restrict__ id,
                                                  const float* __restrict__ wall_vel,
                                                  const u32* __restrict__ owned,
                                                  double* __restrict__ out) {
    // Grid-stride loop: the backend launches about n/8 threads, each summing its solid particles
    // per solid in registers and adding to the slots only when the solid changes and at the end
    // (the slots are a handful of addresses every thread would otherwise hit). The shim launches
    // one thread per particle.
    const u32 stride = gridDim.x * blockDim.x;
    Pair c;
    c.s = smoothing(p.h);
    c.wall = true;
    u32 current = SPH_FLUID;
    vec_t total = vzero();
    double moment[3] = {0.0, 0.0, 0.0};
    bool touched = false;
    for (u32 i = blockIdx.x * blockDim.x + threadIdx.x; i < n; i += stride) {
        // A ghost of a split run: its owner adds its load (`backend::partition`).
        if (kind[i] == SPH_FLUID || !owned[i]) continue;
        const vec_t x_s = vload(pos, i);
        c.u_i = vload(vel, i);
        c.viscous_u_i = vload(wall_vel, i);
        const float m_s = mass[i];
        const float p_s = pressure[i];
        c.rho_i = density[i];
        vec_t force = vzero();
        u32 fluid_neighbours = 0;
        SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
            if (kind[j] != SPH_FLUID) continue;
            vec_t d = pair_delta(g, x_s, pos, j);
            float r2 = vdot(d, d);
            if (!(r2 < c.s.h2)) continue;
            c.x_ij = pair_offset(d, &r2, id[i], id[j], c.s.h);
            c.r2 = r2;
            c.r = sqrtf(r2);
            c.grad_w = vscale(grad_w_spiky(c.s, c.x_ij, c.r), p.pressure_gradient_scale);
            c.m_j = mass[j];
            c.rho_j = density[j];
            c.u_j = vload(vel, j);
            c.viscous_u_j = c.u_j;
            if (MULTIPHASE) {  // [HA06]: the pair terms as above, the volume-form pressure term
                const vec_t f = force_on_solid<TERMS>(p, m_s, 0.0f, 0.0f, c);
                const float q_s = multiphase_pressure_term(p_s, m_s, c.rho_i);
                const float q_f = multiphase_pressure_term(pressure[j], c.m_j, c.rho_j);
                force = vadd(force, vadd(f, multiphase_pressure_acceleration(q_s, q_f, 1.0f, c.grad_w)));
            } else {
                force = vadd(force, force_on_solid<TERMS>(p, m_s, p_s, pressure[j], c));
            }
            ++fluid_neighbours;
        });
        // A solid particle away from the fluid adds nothing.
        if (fluid_neighbours == 0) continue;
        if (kind[i] != current) {
            if (touched) solid_forces_add(out, current, total, moment);
            current = kind[i];
            total = vzero();
            for (int k = 0; k < 3; ++k) moment[k] = 0.0;
        }
        total = vadd(total, force);
        // x_s × f_s in f64 from the f32 position and force (z = 0 in 2D).
        double x[3] = {0.0, 0.0, 0.0}, f[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < D; ++k) {
            x[k] = (double)x_s.c[k];
            f[k] = (double)force.c[k];
        }
        moment[0] += x[1] * f[2] - x[2] * f[1];
        moment[1] += x[2] * f[0] - x[0] * f[2];
        moment[2] += x[0] * f[1] - x[1] * f[0];
        touched = true;
    }
    if (touched) solid_forces_add(out, current, total, moment);
}

#include "entries_solid_forces.cuh"
