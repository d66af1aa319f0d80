// Stage `wall_velocity`: no-slip walls for the viscous force (17), [A12] (Adami, Hu & Adams
// 2012) eqs. (22)-(23). Every solid particle w gets, in `wall_vel`, the velocity it carries in
// (17): `2 u_w - u~_w`, with u~_w = sum_f u_f W_wf / sum_f W_wf the Shepard average (poly6 weights,
// eq. 20) of its fluid neighbours' velocities and u_w its own velocity (zero for a fixed wall,
// d'(t) for a moving one); its own velocity without fluid neighbours. Fluid entries are left as
// they are. Twin of `CpuBackend::wall_velocity` and `boundary::wall_velocity::WallVelocitySums`.
#include "sph.cuh"

/// [A12] eqs. (22)-(23): wall_vel[w] = 2 u_w - sum_f u_f W_wf / sum_f W_wf [m/s].
SPH_KERNEL(wall_velocity)(u32 n, StepParams p, GridGeometry g, const u32* __restrict__ cell_start,
                          const u32* __restrict__ cell_key, const float* __restrict__ pos,
                          const float* __restrict__ vel, const u32* __restrict__ kind, const u32* __restrict__ id,
                          float* __restrict__ wall_vel) {
    u32 w = blockIdx.x * blockDim.x + threadIdx.x;
    if (w >= n || kind[w] == SPH_FLUID) return;
    const Smoothing s = smoothing(p.h);
    const vec_t xw = vload(pos, w);
    // WallVelocitySums: weight, velocity.
    float weight = 0.0f;
    vec_t sum = vzero();
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[w], j, {
        if (kind[j] != SPH_FLUID) continue;
        vec_t d = pair_delta(g, xw, pos, j);
        float r2 = vdot(d, d);
        if (r2 < s.h2) {
            d = pair_offset(d, &r2, id[w], id[j], s.h);
            const float wj = w_poly6(s, r2);
            const vec_t u = vload(vel, j);
            weight += wj;
            for (int k = 0; k < D; ++k) sum.c[k] += u.c[k] * wj;
        }
    });
    const vec_t uw = vload(vel, w);
    vec_t out = uw;
    if (!(weight <= 0.0f)) {  // as `WallVelocitySums::viscous_velocity`: a NaN weight falls through
        for (int k = 0; k < D; ++k) out.c[k] = uw.c[k] * 2.0f - sum.c[k] / weight;
    }
    vstore(wall_vel, w, out);
}
