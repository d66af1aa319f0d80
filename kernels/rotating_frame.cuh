// The rotating frame's fictitious accelerations ([B67] Batchelor 1967, 3.2), shared by
// `forces.cu` and `wall_pressure.cu`. Twins of `physics::rotating_frame`, with the same
// operations in the same order; in 2D on (x, y, 0) with the third component dropped.
#pragma once
#include "sph.cuh"

/// Twin of `physics::rotating_frame` `cross`: a x b.
__device__ __forceinline__ void rotating_frame_cross(const float* a, const float* b, float* out) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/// x - x_c embedded in 3D ((x, y, 0) in 2D).
__device__ __forceinline__ void rotating_frame_offset(const StepParams& p, vec_t x, float* r) {
    r[0] = 0.0f;
    r[1] = 0.0f;
    r[2] = 0.0f;
    for (int k = 0; k < D; ++k) r[k] = x.c[k] - p.rotation_centre[k];
}

/// [B67] 3.2: Coriolis plus centrifugal acceleration, a = -Omega x (2 u + Omega x (x - x_c)).
/// Twin of `physics::rotating_frame::rotating_frame_acceleration`.
__device__ __forceinline__ vec_t rotating_frame_acceleration(const StepParams& p, vec_t x, vec_t u) {
    float r[3], v[3] = {0.0f, 0.0f, 0.0f}, wr[3], a[3];
    rotating_frame_offset(p, x, r);
    for (int k = 0; k < D; ++k) v[k] = u.c[k];
    rotating_frame_cross(p.angular_velocity, r, wr);
    const float s[3] = {2.0f * v[0] + wr[0], 2.0f * v[1] + wr[1], 2.0f * v[2] + wr[2]};
    rotating_frame_cross(p.angular_velocity, s, a);
    vec_t out;
    for (int k = 0; k < D; ++k) out.c[k] = -a[k];
    return out;
}

/// [B67] 3.2: the centrifugal part alone, -Omega x (Omega x (x - x_c)).
/// Twin of `physics::rotating_frame::centrifugal_acceleration`.
__device__ __forceinline__ vec_t rotating_frame_centrifugal(const StepParams& p, vec_t x) {
    float r[3], wr[3], a[3];
    rotating_frame_offset(p, x, r);
    rotating_frame_cross(p.angular_velocity, r, wr);
    rotating_frame_cross(p.angular_velocity, wr, a);
    vec_t out;
    for (int k = 0; k < D; ++k) out.c[k] = -a[k];
    return out;
}
