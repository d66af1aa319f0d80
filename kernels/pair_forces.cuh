// The pair accelerations of eqs. (16), (17) and [M92] eq. (4.1), and the force of a fluid
// particle on a solid one: device twins of `physics::pressure`, `physics::viscosity`,
// `physics::artificial_viscosity` and `boundary::solid_force`, shared by `forces.cu`,
// `solid_forces.cu` and `correction.cu`. Every formula keeps its twin's order of f32 operations,
// so one pair term is bitwise equal on both sides; only the order of the neighbour sums differs.
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

/// Force [N] (per unit depth in 2D) on solid particle s from fluid particle f: m_s times the pair
/// accelerations from the solid's side, with the solid's velocity u_s (zero for a fixed solid,
/// d'(t) for a moving one) in the artificial viscosity and `uv_s` in (17) (its no-slip velocity,
/// [A12] eqs. 22-23, or u_s), (17) scaled by `p.viscosity_scale`. `offset = x_s - x_f`, `r2` its
/// squared length, `grad_w` the scaled spiky gradient. Twin of `solid_force::force_on_solid`.
__device__ __forceinline__ vec_t force_on_solid(const StepParams& p, float m_s, float p_s, float rho_s,
                                                float m_f, float p_f, float rho_f, vec_t offset,
                                                float r2, vec_t u_s, vec_t u_f, vec_t uv_s,
                                                vec_t grad_w, float laplacian_w) {
    vec_t a = pressure_acceleration(p_s, rho_s, p_f, rho_f, m_f, grad_w);
    if (p.mu > 0.0f) {
        const float mu = p.mu * p.viscosity_scale;
        a = vadd(a, viscous_acceleration(mu, uv_s, u_f, rho_s, rho_f, m_f, laplacian_w));
    }
    if (p.alpha > 0.0f) {
        vec_t u_sf = vsub(u_s, u_f);
        a = vadd(a, artificial_viscous_acceleration(p.alpha, p.c, p.h, offset, r2, u_sf, rho_s, rho_f,
                                                    m_f, grad_w));
    }
    return vscale(a, m_s);
}
