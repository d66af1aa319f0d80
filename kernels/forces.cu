// Stage `forces`: eqs. (15)-(17) and (6), the acceleration of fluid particles; solids get zero.
// Twin of `CpuBackend::forces` (`fluid_acceleration`). One body, eight entry points: the terms a
// scene does not ask for are compiled out, as the CPU monomorphises them (`ForceTerms`):
// `forces_p` (pressure), `forces_pv` (+ viscosity 17), `forces_pa` (+ artificial viscosity
// [M92]), `forces_pva` (both), and each with the rotating frame's Coriolis and centrifugal
// forces ([B67] 3.2): `forces_pr`, `forces_pvr`, `forces_par`, `forces_pvar`. In (17) a solid
// neighbour j carries wall_vel[j], its no-slip velocity ([A12] eqs. 22-23, `wall_velocity.cu`);
// where the scene has none the host passes `vel` itself, so j carries its own velocity. With the
// `multiphase` effect the pressure pair term is [HA06]'s volume form (`multiphase.cuh`): the same
// eight with the suffix `_mp` (`forces_p_mp`, ...).
#include "sph.cuh"
#include "pair_forces.cuh"
#include "rotating_frame.cuh"
#include "multiphase.cuh"

/// Eqs. (15)-(17) and (6) for particle i: gravity plus the pair terms of every neighbour j != i,
/// added per neighbour in the CPU's order (pressure, artificial viscosity, viscosity).
template <bool VISCOUS, bool ARTIFICIAL, bool ROTATING, bool MULTIPHASE>
__device__ __forceinline__ void forces_body(u32 n, const StepParams& p, const GridGeometry& g,
                                            const u32* __restrict__ cell_start,
                                            const u32* __restrict__ cell_key,
                                            const float* __restrict__ pos,
                                            const float* __restrict__ vel,
                                            const float* __restrict__ mass,
                                            const float* __restrict__ density,
                                            const float* __restrict__ pressure,
                                            const u32* __restrict__ kind,
                                            const float* __restrict__ wall_vel,
                                            float* __restrict__ acc) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    if (kind[i] != SPH_FLUID) {
        vstore(acc, i, vzero());
        return;
    }
    const Smoothing s = smoothing(p.h);
    const vec_t x_i = vload(pos, i);
    const vec_t u_i = vload(vel, i);
    const float p_i = pressure[i];
    const float rho_i = density[i];
    // Eq. (17) with the lattice's Laplacian moment undone (`physics::lattice`).
    const float mu = p.mu * p.viscosity_scale;
    const float m_i = mass[i];
    const float q_i = MULTIPHASE ? multiphase_pressure_term(p_i, m_i, rho_i) : 0.0f;
    vec_t a;
    for (int k = 0; k < D; ++k) a.c[k] = p.gravity[k];  // eq. (6)
    if (ROTATING) a = vadd(a, rotating_frame_acceleration(p, x_i, u_i));  // [B67] 3.2
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        if (j == i) continue;
        vec_t d = vsub(x_i, vload(pos, j));
        float r2 = vdot(d, d);
        if (!(r2 < s.h2)) continue;
        d = pair_offset(d, &r2, i, j, s.h);
        const float r = sqrtf(r2);
        const float m_j = mass[j];
        const float rho_j = density[j];
        const vec_t grad = vscale(grad_w_spiky(s, d, r), p.pressure_gradient_scale);
        if (MULTIPHASE) {  // [HA06]
            const float q_j = multiphase_pressure_term(pressure[j], m_j, rho_j);
            a = vadd(a, multiphase_pressure_acceleration(q_i, q_j, m_i, grad));
        } else {
            a = vadd(a, pressure_acceleration(p_i, rho_i, pressure[j], rho_j, m_j, grad));
        }
        if (ARTIFICIAL) {
            const vec_t u_ij = vsub(u_i, vload(vel, j));
            a = vadd(a, artificial_viscous_acceleration(p.alpha, p.c, p.h, d, r2, u_ij, rho_i, rho_j,
                                                        m_j, grad));
        }
        if (VISCOUS) {
            const float lap = laplacian_w_viscosity(s, r);
            const vec_t u_j = kind[j] == SPH_FLUID ? vload(vel, j) : vload(wall_vel, j);
            a = vadd(a, viscous_acceleration(mu, u_i, u_j, rho_i, rho_j, m_j, lap));
        }
    });
    vstore(acc, i, a);
}

#define SPH_FORCES_ENTRY(name, VISCOUS, ARTIFICIAL, ROTATING, MULTIPHASE)                                        \
    SPH_KERNEL(name)(u32 n, StepParams p, GridGeometry g, const u32* __restrict__ cell_start,     \
                     const u32* __restrict__ cell_key, const float* __restrict__ pos,             \
                     const float* __restrict__ vel, const float* __restrict__ mass,               \
                     const float* __restrict__ density, const float* __restrict__ pressure,       \
                     const u32* __restrict__ kind, const float* __restrict__ wall_vel,            \
                     float* __restrict__ acc) {                                                   \
        forces_body<VISCOUS, ARTIFICIAL, ROTATING, MULTIPHASE>(n, p, g, cell_start, cell_key, pos, vel, mass, density, \
                                         pressure, kind, wall_vel, acc);                          \
    }

/// Pressure (16) and gravity only.
SPH_FORCES_ENTRY(forces_p, false, false, false, false)
/// Pressure and viscosity (17).
SPH_FORCES_ENTRY(forces_pv, true, false, false, false)
/// Pressure and artificial viscosity ([M92]).
SPH_FORCES_ENTRY(forces_pa, false, true, false, false)
/// Pressure, viscosity and artificial viscosity.
SPH_FORCES_ENTRY(forces_pva, true, true, false, false)
/// Pressure and the rotating frame ([B67] 3.2).
SPH_FORCES_ENTRY(forces_pr, false, false, true, false)
/// Pressure, viscosity and the rotating frame.
SPH_FORCES_ENTRY(forces_pvr, true, false, true, false)
/// Pressure, artificial viscosity and the rotating frame.
SPH_FORCES_ENTRY(forces_par, false, true, true, false)
/// Pressure, viscosity, artificial viscosity and the rotating frame.
SPH_FORCES_ENTRY(forces_pvar, true, true, true, false)

// The same with the [HA06] volume-form pressure force (the `multiphase` effect).
/// Pressure (16) and gravity only. [HA06]
SPH_FORCES_ENTRY(forces_p_mp, false, false, false, true)
/// Pressure and viscosity (17). [HA06]
SPH_FORCES_ENTRY(forces_pv_mp, true, false, false, true)
/// Pressure and artificial viscosity ([M92]). [HA06]
SPH_FORCES_ENTRY(forces_pa_mp, false, true, false, true)
/// Pressure, viscosity and artificial viscosity. [HA06]
SPH_FORCES_ENTRY(forces_pva_mp, true, true, false, true)
/// Pressure and the rotating frame ([B67] 3.2). [HA06]
SPH_FORCES_ENTRY(forces_pr_mp, false, false, true, true)
/// Pressure, viscosity and the rotating frame. [HA06]
SPH_FORCES_ENTRY(forces_pvr_mp, true, false, true, true)
/// Pressure, artificial viscosity and the rotating frame. [HA06]
SPH_FORCES_ENTRY(forces_par_mp, false, true, true, true)
/// Pressure, viscosity, artificial viscosity and the rotating frame. [HA06]
SPH_FORCES_ENTRY(forces_pvar_mp, true, true, true, true)
