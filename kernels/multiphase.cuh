// Device twins of `physics::multiphase` (the `multiphase` effect; [HA06] Hu & Adams,
// J. Comput. Phys. 213 (2006) 844): the volume-form pressure pair force. Same f32 operations in
// the same order as the Rust functions, so one pair term is bitwise equal on both sides.
#pragma once

#include "sph.cuh"

/// [HA06] `p V^2 = p (m/rho)^2` [Pa m^(2D)]. Twin of `multiphase::pressure_term`.
__device__ __forceinline__ float multiphase_pressure_term(float p, float m, float rho) {
    const float v = m / rho;
    return p * v * v;
}

/// [HA06] `-(q_i + q_j) grad_w / m_i` [m/s^2]. Twin of `multiphase::pressure_acceleration`.
__device__ __forceinline__ vec_t multiphase_pressure_acceleration(float q_i, float q_j, float m_i,
                                                                  vec_t grad_w) {
    return vscale(grad_w, -(q_i + q_j) / m_i);
}
