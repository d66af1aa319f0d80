// The no-penetration guard (`boundary::keep_out`): twin of `KeepOutBox::push_out` as
// `CpuBackend::keep_out` applies it, box after box in order, to every fluid particle.
#include "sph.cuh"

/// Floats per box in `boxes`: min[D], max[D], velocity[D], solid index.
#define SPH_KEEP_OUT_STRIDE (3 * D + 1)

/// Fluid inside a box is put `margin` [m] outside the face it came in through and loses the
/// velocity component, relative to the box, that points into it. The face: with has_from, where
/// the segment from the step's start position `from` (SSP-RK3) enters the box (the axis entered
/// last, ties to the lower axis); otherwise, or when `from` is inside the box, the nearest face
/// (ties: lower axis, lower side). With has_from, fluid outside a box whose segment from `from`
/// passes through the box's interior is put back the same way. Per push, for the box's solid `s`,
/// `out[7 s]` counts one, `out[7 s + 1 + k]` adds the fluid's momentum change `m du_k`
/// [kg m/s] and `out[7 s + 4 + k]` its angular momentum about the origin `x × m du`
/// [kg m²/s] at the pushed position (`keep_out::push_moment`; the host zeroes `out`, 7 doubles
/// per solid); a ghost of a split run (`owned[i]` 0) is pushed but not counted. Twin of
/// `KeepOutBox::push_out`.
SPH_KERNEL(keep_out)(u32 n, u32 boxes, const float* __restrict__ box, float margin,
                     const u32* __restrict__ kind, const float* __restrict__ mass,
                     const float* __restrict__ from, u32 has_from, const u32* __restrict__ owned,
                     float* __restrict__ pos,
                     float* __restrict__ vel, double* __restrict__ out) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    vec_t x = vload(pos, i);
    vec_t u = vload(vel, i);
    const vec_t start = has_from ? vload(from, i) : vzero();
    bool moved = false;
    for (u32 b = 0; b < boxes; ++b) {
        const float* lo = box + b * SPH_KEEP_OUT_STRIDE;
        const float* hi = lo + D;
        const float* wall = hi + D;
        bool inside = true;
        for (int k = 0; k < D; ++k) inside = inside && x.c[k] > lo[k] && x.c[k] < hi[k];
        int axis = 0;
        bool upper = false;
        bool entered = false;
        if (!inside) {
            // Outside: back only if the segment from the step's start passes through the box's
            // interior (it went through the solid). Twin of `KeepOutBox::crossed_face`.
            if (!has_from) continue;
            float enter = 0.0f, leave = 1.0f;
            bool missed = false;
            for (int k = 0; k < D; ++k) {
                const float d = x.c[k] - start.c[k];
                if (d == 0.0f) {
                    if (start.c[k] <= lo[k] || start.c[k] >= hi[k]) missed = true;
                    continue;
                }
                const float at_min = (lo[k] - start.c[k]) / d;
                const float at_max = (hi[k] - start.c[k]) / d;
                const float near = d > 0.0f ? at_min : at_max;
                const float far = d > 0.0f ? at_max : at_min;
                if (near > enter) { enter = near; axis = k; upper = d < 0.0f; entered = true; }
                leave = fminf(leave, far);
            }
            if (missed || !entered || !(enter < leave)) continue;
        } else if (has_from) {
            float best = 0.0f;
            for (int k = 0; k < D; ++k) {
                float t;
                bool up;
                if (start.c[k] <= lo[k]) {
                    up = false;
                    t = (lo[k] - start.c[k]) / (x.c[k] - start.c[k]);
                } else if (start.c[k] >= hi[k]) {
                    up = true;
                    t = (start.c[k] - hi[k]) / (start.c[k] - x.c[k]);
                } else {
                    continue;
                }
                if (!entered || t > best) { axis = k; upper = up; best = t; entered = true; }
            }
        }
        if (inside && !entered) {
            float depth = 3.402823466e38f;  // FLT_MAX: every depth of a finite x is below it
            for (int k = 0; k < D; ++k) {
                const float below = x.c[k] - lo[k];
                const float above = hi[k] - x.c[k];
                if (below < depth) { axis = k; upper = false; depth = below; }
                if (above < depth) { axis = k; upper = true; depth = above; }
            }
        }
        const float relative = u.c[axis] - wall[axis];
        const float before = u.c[axis];
        if (upper) {
            x.c[axis] = hi[axis] + margin;
            if (relative < 0.0f) u.c[axis] = wall[axis];
        } else {
            x.c[axis] = lo[axis] - margin;
            if (relative > 0.0f) u.c[axis] = wall[axis];
        }
        moved = true;
        if (!owned[i]) continue;  // a ghost is pushed as its owner is, which counts the push
        double* slot = out + 7 * (size_t)wall[D];
        const double dp = (double)mass[i] * ((double)u.c[axis] - (double)before);
        double r[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < D; ++k) r[k] = (double)x.c[k];
        double p[3] = {0.0, 0.0, 0.0};
        p[axis] = dp;
        atomicAdd(slot, 1.0);
        atomicAdd(slot + 1 + axis, dp);
        atomicAdd(slot + 4, r[1] * p[2] - r[2] * p[1]);
        atomicAdd(slot + 5, r[2] * p[0] - r[0] * p[2]);
        atomicAdd(slot + 6, r[0] * p[1] - r[1] * p[0]);
    }
    if (moved) {
        vstore(pos, i, x);
        vstore(vel, i, u);
    }
}
