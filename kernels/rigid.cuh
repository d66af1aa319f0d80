// A solid's rigid motion at one time (`boundary::rigid`), shared by `move_solids.cu` and
// `wall_pressure.cu`. Twins of `SolidKinematics::{position, velocity_at, acceleration_at}`, with
// the same f32 operations in the same order. One record of SPH_MOTION_FLOATS floats per solid
// (`SolidKinematics::kernel_floats`): the rotation's tag (0: none, 1: about a pivot), d, d', d''
// (D each) [m, m/s, m/s^2], the pivot c (D) [m], R - I (D*D, row-major), omega and alpha (3 each)
// [rad/s, rad/s^2]; in 2D vectors are embedded as (x, y, 0) (`rotating_frame.cuh`).
#pragma once
#include "sph.cuh"
#include "rotating_frame.cuh"

/// Twin of `boundary::rigid::motion_floats`.
#define SPH_MOTION_FLOATS (1 + 4 * D + D * D + 6)

/// Solid `s`'s record in `motion`.
__device__ __forceinline__ const float* rigid_record(const float* motion, u32 s) {
    return motion + (size_t)s * SPH_MOTION_FLOATS;
}

/// Whether the record turns (`Rotation::About`).
__device__ __forceinline__ bool rigid_turns(const float* m) { return m[0] != 0.0f; }

/// Vector `slot` (0: d, 1: d', 2: d'', 3: c) of the record.
__device__ __forceinline__ vec_t rigid_vector(const float* m, int slot) {
    vec_t v;
    for (int k = 0; k < D; ++k) v.c[k] = m[1 + slot * D + k];
    return v;
}

/// Twin of `SolidKinematics::position`: x = (x0 + d) + (R - I)(x0 - c).
__device__ __forceinline__ vec_t rigid_position(const float* m, vec_t x0) {
    vec_t x = vadd(x0, rigid_vector(m, 0));
    if (rigid_turns(m)) {
        const vec_t a = vsub(x0, rigid_vector(m, 3));
        const float* offset = m + 1 + 4 * D;
        for (int k = 0; k < D; ++k) {
            float turn = offset[k * D] * a.c[0];
            for (int j = 1; j < D; ++j) turn += offset[k * D + j] * a.c[j];
            x.c[k] += turn;
        }
    }
    return x;
}

/// The arm r = (x - c) - d, embedded in 3D.
__device__ __forceinline__ void rigid_arm(const float* m, vec_t x, float* r) {
    const vec_t v = vsub(vsub(x, rigid_vector(m, 3)), rigid_vector(m, 0));
    r[0] = 0.0f;
    r[1] = 0.0f;
    r[2] = 0.0f;
    for (int k = 0; k < D; ++k) r[k] = v.c[k];
}

/// Twin of `SolidKinematics::velocity_at`: u = d' + omega x r.
__device__ __forceinline__ vec_t rigid_velocity_at(const float* m, vec_t x) {
    vec_t u = rigid_vector(m, 1);
    if (rigid_turns(m)) {
        float r[3], wr[3];
        rigid_arm(m, x, r);
        rotating_frame_cross(m + 1 + 4 * D + D * D, r, wr);
        for (int k = 0; k < D; ++k) u.c[k] += wr[k];
    }
    return u;
}

/// Twin of `SolidKinematics::acceleration_at`: a = d'' + (alpha x r + omega x (omega x r)).
__device__ __forceinline__ vec_t rigid_acceleration_at(const float* m, vec_t x) {
    vec_t a = rigid_vector(m, 2);
    if (rigid_turns(m)) {
        const float* omega = m + 1 + 4 * D + D * D;
        float r[3], tangential[3], wr[3], centripetal[3];
        rigid_arm(m, x, r);
        rotating_frame_cross(omega + 3, r, tangential);
        rotating_frame_cross(omega, r, wr);
        rotating_frame_cross(omega, wr, centripetal);
        for (int k = 0; k < D; ++k) a.c[k] += tangential[k] + centripetal[k];
    }
    return a;
}
