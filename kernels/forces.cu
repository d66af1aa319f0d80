// Stage `forces`: eqs. (15)-(17) and (6), the acceleration of fluid particles; solids get zero.
// Twin of `CpuBackend::forces` (`fluid_acceleration`). One body, one entry per `ForceTerms` and
// `Phases` (generated from kernels/launch.table into `entries_forces.cuh`: `forces_t<bits>`, with
// `_r` for the rotating frame's Coriolis and centrifugal forces, [B67] 3.2, and `_mp` for
// [HA06]'s volume-form pressure force, `multiphase.cuh`): the terms a scene does not ask for are
// compiled out, as the CPU monomorphises them. In (17) a solid neighbour j carries wall_vel[j],
// its no-slip velocity ([A12] eqs. 22-23, `wall_velocity.cu`); where the scene has none the host
// passes `vel` itself, so j carries its own velocity.
#include "sph.cuh"
#include "pair_forces.cuh"
#include "rotating_frame.cuh"
#include "multiphase.cuh"

/// Eqs. (15)-(17) and (6) for particle i: gravity plus the pressure force and the pair terms of
/// `TERMS` (`add_pair_terms`, in table order) of every neighbour j != i.
template <u32 TERMS, bool ROTATING, bool MULTIPHASE>
__device__ __forceinline__ void forces_body(u32 n, const StepParams& p, const GridGeometry& g,
                                            const u32* __restrict__ cell_start,
                                            const u32* __restrict__ cell_key,
                                            const float* __restrict__ pos,
                                            const float* __restrict__ vel,
                                            const float* __restrict__ mass,
                                            const float* __restrict__ density,
                                            const float* __restrict__ pressure,
                                            const u32* __restrict__ kind, const u32* __restrict__ id,
                                            const float* __restrict__ wall_vel,
                                            float* __restrict__ acc) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    if (kind[i] != SPH_FLUID) {
        vstore(acc, i, vzero());
        return;
    }
    Pair c;
    c.s = smoothing(p.h);
    const vec_t x_i = vload(pos, i);
    c.u_i = vload(vel, i);
    c.viscous_u_i = c.u_i;
    const float p_i = pressure[i];
    c.rho_i = density[i];
    const float m_i = mass[i];
    const float q_i = MULTIPHASE ? multiphase_pressure_term(p_i, m_i, c.rho_i) : 0.0f;
    vec_t a;
    for (int k = 0; k < D; ++k) a.c[k] = p.gravity[k];  // eq. (6)
    if (ROTATING) a = vadd(a, rotating_frame_acceleration(p, x_i, c.u_i));  // [B67] 3.2
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        if (j == i) continue;
        vec_t d = pair_delta(g, x_i, pos, j);
        float r2 = vdot(d, d);
        if (!(r2 < c.s.h2)) continue;
        c.x_ij = pair_offset(d, &r2, id[i], id[j], c.s.h);
        c.r2 = r2;
        c.r = sqrtf(r2);
        c.m_j = mass[j];
        c.rho_j = density[j];
        c.grad_w = vscale(grad_w_spiky(c.s, c.x_ij, c.r), p.pressure_gradient_scale);
        if (MULTIPHASE) {  // [HA06]
            const float q_j = multiphase_pressure_term(pressure[j], c.m_j, c.rho_j);
            a = vadd(a, multiphase_pressure_acceleration(q_i, q_j, m_i, c.grad_w));
        } else {
            a = vadd(a, pressure_acceleration(p_i, c.rho_i, pressure[j], c.rho_j, c.m_j, c.grad_w));
        }
        c.u_j = vload(vel, j);
        c.viscous_u_j = kind[j] == SPH_FLUID ? c.u_j : vload(wall_vel, j);
        c.wall = kind[j] != SPH_FLUID;
        a = add_pair_terms<TERMS>(a, p, c);
    });
    vstore(acc, i, a);
}

#include "entries_forces.cuh"
