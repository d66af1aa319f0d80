// The pair accelerations of eqs. (16), (17) and [M92] eq. (4.1), and the force of a fluid
// particle on a solid one: device twins of `physics::pressure`, `physics::viscosity`,
// `physics::artificial_viscosity` and `boundary::solid_force`, shared by `forces.cu`,
// `solid_forces.cu` and `correction.cu`. Every formula keeps its twin's order of f32 operations,
// so one pair term is bitwise equal on both sides; only the order of the neighbour sums differs.
// The optional pair terms (`kernels/pair_terms.table`) each have a twin here taking a `Pair`;
// their sum `add_pair_terms<TERMS>` is generated (`pair_terms_sum.cuh`).
#pragma once

#include "sph.cuh"

/// Eq. (16) divided by rho_i: acceleration [m/s^2] of i due to j,
/// `-m_j (p_i/rho_i^2 + p_j/rho_j^2) grad_w`. Twin of `pressure::pressure_acceleration`.
__device__ __forceinline__ vec_t pressure_acceleration(float p_i, float rho_i, float p_j, float rho_j,
                                                       float m_j, vec_t grad_w) {
    return vscale(grad_w, -m_j * (p_i / (rho_i * rho_i) + p_j / (rho_j * rho_j)));
}

/// Eq. (17) divided by rho_i: `(mu/rho_i) (u_j - u_i) m_j/rho_j lap_w` [m/s^2].
/// Twin of `viscosity::viscous_acceleration`.
__device__ __forceinline__ vec_t viscous_acceleration(float mu, vec_t u_i, vec_t u_j, float rho_i,
                                                      float rho_j, float m_j, float laplacian_w) {
    return vscale(vsub(u_j, u_i), mu * m_j * laplacian_w / (rho_i * rho_j));
}

/// [M92] eq. (4.1): `-m_j Pi_ij grad_w` for approaching particles (u_ij . x_ij < 0), else 0.
/// Twin of `artificial_viscosity::artificial_viscous_acceleration`; `r2 = |x_ij|^2`.
__device__ __forceinline__ vec_t artificial_viscous_acceleration(float alpha, float c, float h,
                                                                 vec_t x_ij, float r2, vec_t u_ij,
                                                                 float rho_i, float rho_j, float m_j,
                                                                 vec_t grad_w) {
    float ux = vdot(u_ij, x_ij);
    if (ux >= 0.0f) return vzero();
    float hs = 0.5f * h;
    float mu = hs * ux / (r2 + 0.01f * hs * hs);
    float pi = -alpha * c * mu / (0.5f * (rho_i + rho_j));
    return vscale(grad_w, -m_j * pi);
}

/// Twin of `physics::pair::Pair`: particle i and neighbour j as every optional pair term sees
/// them. `x_ij` [m] (after `pair_offset`), `r2 = |x_ij|^2`, `r = |x_ij|`; `u_i`, `u_j` the
/// velocities [m/s]; `viscous_u_i`, `viscous_u_j` the velocities of (17) (a solid's no-slip
/// velocity, [A12] eqs. 22-23); `grad_w` the scaled spiky gradient; `s` the kernels.
struct Pair {
    vec_t x_ij;
    float r2, r;
    vec_t u_i, u_j, viscous_u_i, viscous_u_j;
    float rho_i, rho_j, m_j;
    vec_t grad_w;
    Smoothing s;
    bool wall;  // one of the two is a solid particle
};

/// [M92] between the pair's particles, alpha times the wall factor across a wall. Twin of `artificial_viscosity::pair_acceleration`.
__device__ __forceinline__ vec_t artificial_viscosity_pair(const StepParams& p, const Pair& c) {
    const float factor = c.wall ? p.artificial_viscosity_wall_factor : 1.0f;
    const vec_t u_ij = vsub(c.u_i, c.u_j);
    return artificial_viscous_acceleration(p.pair.alpha * factor, p.c, p.h, c.x_ij, c.r2, u_ij, c.rho_i, c.rho_j,
                                           c.m_j, c.grad_w);
}

/// Eq. (17) with the lattice's Laplacian moment undone (`physics::lattice`). Twin of
/// `viscosity::pair_acceleration`.
__device__ __forceinline__ vec_t viscosity_pair(const StepParams& p, const Pair& c) {
    const float mu = p.pair.mu * p.viscosity_scale;
    return viscous_acceleration(mu, c.viscous_u_i, c.viscous_u_j, c.rho_i, c.rho_j, c.m_j,
                                laplacian_w_viscosity(c.s, c.r));
}

#include "pair_terms_sum.cuh"

/// Force [N] (per unit depth in 2D) on solid particle s from fluid particle f: m_s times the
/// pressure acceleration (16) and the pair terms of `TERMS` from the solid's side (`c.u_i` the
/// solid's velocity u_s, zero for a fixed solid and d'(t) for a moving one; `c.viscous_u_i` its
/// no-slip velocity or u_s). Twin of `solid_force::force_on_solid`.
template <u32 TERMS>
__device__ __forceinline__ vec_t force_on_solid(const StepParams& p, float m_s, float p_s, float p_f,
                                                const Pair& c) {
    vec_t a = pressure_acceleration(p_s, c.rho_i, p_f, c.rho_j, c.m_j, c.grad_w);
    return vscale(add_pair_terms<TERMS>(a, p, c), m_s);
}
