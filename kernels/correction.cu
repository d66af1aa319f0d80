// Eqs. (23)-(24): the position correction (section 2), one sweep as the CPU runs it, and the
// end of the velocity solve that follows it (`solver::step`; its iteration is in anderson.cu,
// which reuses the kernels here). Twins of `CpuBackend::correction_error`,
// `correction_pressure`, `correct_positions`, `end_velocity_solve` and of
// `physics::correction`. A sweep on the device:
//   correction_pressure_fluid -> correction_pressure_wall -> correction_pressure_apply
//   (= `correction_pressure`), then correction_displacement -> host scale -> apply_displacement
//   (= `correct_positions`). Maxima are float bits in ints (see `extremes.cuh`); the host zeroes
//   them before the launch.
// The `_multiphase` entries (`Phases::Multi`, [HA06] Hu & Adams, J. Comput. Phys. 213 (2006)
// 844) measure each particle against its own rest density `rest` [kg/m^3] and move it by the
// volume-form pressure force (`physics::multiphase`).
#include "sph.cuh"
#include "extremes.cuh"
#include "multiphase.cuh"
#include "pair_forces.cuh"

/// The density error `(rho - rho0)/rho0` in f64, as `correction::compression` and `residual`.
__device__ __forceinline__ double correction_density_error(float rho, float rho0) {
    return ((double)rho - (double)rho0) / (double)rho0;
}

/// Eq. (24) with note 6: out[0] = bits of the largest fluid compression `max(rho - rho0, 0)/rho0`
/// (`correction::compression`), out[1] = of the largest `correction::residual` (|e| where p > 0,
/// else max(e, 0); NaN, which `max_bits` puts above every number, when e or p is NaN). Computed in f64 as the CPU, rounded to f32 for the atomic. `rho0_i` is `rho0`,
/// or `rest[i]` with `MULTIPHASE`.
template <bool MULTIPHASE>
__device__ __forceinline__ void correction_error_body(u32 n, float rho0,
                                                      const float* __restrict__ rest,
                                                      const float* __restrict__ density,
                                                      const float* __restrict__ pressure,
                                                      const u32* __restrict__ kind,
                                                      const u32* __restrict__ owned,
                                                      int* __restrict__ out) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    // A ghost of a split run is counted by its owner (`backend::partition`).
    if (i >= n || kind[i] != SPH_FLUID || !owned[i]) return;
    const double e = correction_density_error(density[i], MULTIPHASE ? rest[i] : rho0);
    const double compression = e > 0.0 ? e : 0.0;  // f64::max(e, 0): NaN gives 0
    // `correction::residual`: NaN when e or the pressure is (x != x), never read as converged.
    const float p_i = pressure[i];
    const double residual = (e != e || p_i != p_i) ? e + (double)p_i : (p_i > 0.0f ? fabs(e) : compression);
    // Read before the atomic: the maxima settle within a few blocks, after which almost every
    // thread skips its atomic (a stale read only costs an atomic that changes nothing).
    const int bc = max_bits((float)compression), br = max_bits((float)residual);
    if (bc > out[0]) atomicMax(&out[0], bc);
    if (br > out[1]) atomicMax(&out[1], br);
}

SPH_KERNEL(correction_error)(u32 n, float rho0, const float* __restrict__ density,
                             const float* __restrict__ pressure, const u32* __restrict__ kind,
                             const u32* __restrict__ owned, int* __restrict__ out) {
    correction_error_body<false>(n, rho0, nullptr, density, pressure, kind, owned, out);
}

SPH_KERNEL(correction_error_multiphase)(u32 n, const float* __restrict__ rest,
                                        const float* __restrict__ density,
                                        const float* __restrict__ pressure,
                                        const u32* __restrict__ kind, const u32* __restrict__ owned,
                                        int* __restrict__ out) {
    correction_error_body<true>(n, 0.0f, rest, density, pressure, kind, owned, out);
}

/// Eq. (19) inside the correction, fluid only: `delta_p = pressure_increment(rho, rho0, p + m, k) + m`
/// with the heavy-ball momentum `m = beta delta_p_prev` (`has_prev` != 0; `correction::MOMENTUM`),
/// `pressure_increment(rho, rho0, p, k) = max(p + k (rho - rho0), 0) - p`. Solids get 0. `rho0_i`
/// is `rho0`, or `rest[i]` with `MULTIPHASE`.
template <bool MULTIPHASE>
__device__ __forceinline__ void correction_pressure_fluid_body(
    u32 n, float rho0, const float* __restrict__ rest, float k, float beta, int has_prev,
    const float* __restrict__ density, const float* __restrict__ pressure,
    const u32* __restrict__ kind, const float* __restrict__ delta_p_prev,
    float* __restrict__ delta_p) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    if (kind[i] != SPH_FLUID) {
        delta_p[i] = 0.0f;
        return;
    }
    const float m = has_prev ? beta * delta_p_prev[i] : 0.0f;
    const float p_m = pressure[i] + m;
    const float rho0_i = MULTIPHASE ? rest[i] : rho0;
    delta_p[i] = (fmaxf(p_m + k * (density[i] - rho0_i), 0.0f) - p_m) + m;
}

SPH_KERNEL(correction_pressure_fluid)(u32 n, float rho0, float k, float beta, int has_prev,
                                      const float* __restrict__ density,
                                      const float* __restrict__ pressure,
                                      const u32* __restrict__ kind,
                                      const float* __restrict__ delta_p_prev,
                                      float* __restrict__ delta_p) {
    correction_pressure_fluid_body<false>(n, rho0, nullptr, k, beta, has_prev, density, pressure,
                                          kind, delta_p_prev, delta_p);
}

SPH_KERNEL(correction_pressure_fluid_multiphase)(u32 n, const float* __restrict__ rest, float k,
                                                 float beta, int has_prev,
                                                 const float* __restrict__ density,
                                                 const float* __restrict__ pressure,
                                                 const u32* __restrict__ kind,
                                                 const float* __restrict__ delta_p_prev,
                                                 float* __restrict__ delta_p) {
    correction_pressure_fluid_body<true>(n, 0.0f, rest, k, beta, has_prev, density, pressure,
                                         kind, delta_p_prev, delta_p);
}

/// [A12] eq. (27) without gravity for solid particles, of either sign: `r = sum_f delta_p_f W_wf /
/// sum_f W_wf` over fluid neighbours f (0 without any), as `WallPressureSums::increment`; then
/// `delta_p_w = max(p_w + r, 0) - p_w`, which keeps the wall's accumulated pressure `p_w`
/// non-negative (`CpuBackend::correction_pressure`). In place: solids read only fluid increments,
/// which this kernel does not write; `pressure` is updated later by `correction_pressure_apply`.
SPH_KERNEL(correction_pressure_wall)(u32 n, StepParams p, GridGeometry g,
                                     const u32* __restrict__ cell_start,
                                     const u32* __restrict__ cell_key, const float* __restrict__ pos,
                                     const float* __restrict__ density,
                                     const float* __restrict__ pressure,
                                     const u32* __restrict__ kind, const u32* __restrict__ id,
                                     float* delta_p) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] == SPH_FLUID) return;
    const Smoothing s = smoothing(p.h);
    const vec_t x_w = vload(pos, i);
    float weight = 0.0f;
    float pressure_sum = 0.0f;
    vec_t density_offset = vzero();
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        vec_t d = pair_delta(g, x_w, pos, j);
        float r2 = vdot(d, d);
        if (!(r2 < s.h2) || kind[j] != SPH_FLUID) continue;
        d = pair_offset(d, &r2, id[i], id[j], s.h);
        const float w = w_poly6(s, r2);
        weight += w;
        pressure_sum += delta_p[j] * w;
        density_offset = vadd(density_offset, vscale(d, density[j] * w));
    });
    float increment = 0.0f;
    if (!(weight <= 0.0f)) {  // as `WallPressureSums::increment`: a NaN weight falls through
        // g . sum rho_f (x_w - x_f) W with g = 0, kept so that non-finite values propagate alike.
        const float gravity_term = vdot(vzero(), density_offset);
        increment = (pressure_sum + gravity_term) / weight;
    }
    const float p_w = pressure[i];
    delta_p[i] = fmaxf(p_w + increment, 0.0f) - p_w;
}

/// End of `correction_pressure`: `p += delta_p` and `delta_p_prev = delta_p`, every particle.
SPH_KERNEL(correction_pressure_apply)(u32 n, const float* __restrict__ delta_p,
                                      float* __restrict__ pressure,
                                      float* __restrict__ delta_p_prev) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const float dp = delta_p[i];
    pressure[i] += dp;
    delta_p_prev[i] = dp;
}

/// Eq. (23): `dx_i = tau^2 a_i^press(delta_p)` for fluid (zero for solids), the pressure force (16)
/// of the increments over every neighbour j != i, or with `MULTIPHASE` its [HA06] volume form
/// `-(dp_i V_i^2 + dp_j V_j^2) grad W / m_i`; atomicMax of |dx| bits into `*largest`.
template <bool MULTIPHASE>
__device__ __forceinline__ void correction_displacement_body(
    u32 n, const StepParams& p, const GridGeometry& g, const u32* __restrict__ cell_start,
    const u32* __restrict__ cell_key, const float* __restrict__ pos, const float* __restrict__ mass,
    const float* __restrict__ density, const float* __restrict__ delta_p,
    const u32* __restrict__ kind, const u32* __restrict__ id, const u32* __restrict__ owned,
    float tau2,
    float* __restrict__ displacement, int* __restrict__ largest) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    if (kind[i] != SPH_FLUID) {
        vstore(displacement, i, vzero());
        return;
    }
    const Smoothing s = smoothing(p.h);
    const vec_t x_i = vload(pos, i);
    const float dp_i = delta_p[i];
    const float rho_i = density[i];
    const float m_i = mass[i];
    const float q_i = MULTIPHASE ? multiphase_pressure_term(dp_i, m_i, rho_i) : 0.0f;
    vec_t a = vzero();
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        if (j == i) continue;
        vec_t d = pair_delta(g, x_i, pos, j);
        float r2 = vdot(d, d);
        if (!(r2 < s.h2)) continue;
        d = pair_offset(d, &r2, id[i], id[j], s.h);
        const vec_t grad = vscale(grad_w_spiky(s, d, sqrtf(r2)), p.pressure_gradient_scale);
        if (MULTIPHASE) {
            const float q_j = multiphase_pressure_term(delta_p[j], mass[j], density[j]);
            a = vadd(a, multiphase_pressure_acceleration(q_i, q_j, m_i, grad));
        } else {
            a = vadd(a, pressure_acceleration(dp_i, rho_i, delta_p[j], density[j], mass[j], grad));
        }
    });
    const vec_t dx = vscale(a, tau2);  // eq. (23)
    vstore(displacement, i, dx);
    if (!owned[i]) return;  // a ghost: its owner's displacement counts
    const int b = max_bits(sqrtf(vdot(dx, dx)));
    if (b > *largest) atomicMax(largest, b);  // read first: see correction_error
}

#define SPH_CORRECTION_DISPLACEMENT_ENTRY(name, MULTIPHASE)                                        \
    SPH_KERNEL(name)(u32 n, StepParams p, GridGeometry g, const u32* __restrict__ cell_start,      \
                     const u32* __restrict__ cell_key, const float* __restrict__ pos,              \
                     const float* __restrict__ mass, const float* __restrict__ density,            \
                     const float* __restrict__ delta_p, const u32* __restrict__ kind,              \
                     const u32* __restrict__ id,                                                   \
                     const u32* __restrict__ owned, float tau2,                                    \
                     float* __restrict__ displacement, int* __restrict__ largest) {                \
        correction_displacement_body<MULTIPHASE>(n, p, g, cell_start, cell_key, pos, mass,         \
                                                 density, delta_p, kind, id, owned, tau2,              \
                                                 displacement, largest);                           \
    }

SPH_CORRECTION_DISPLACEMENT_ENTRY(correction_displacement, false)
SPH_CORRECTION_DISPLACEMENT_ENTRY(correction_displacement_multiphase, true)

/// Eq. (23) applied, fluid only: `dx = displacement * scale`, `x += dx`, `u += dx / tau`
/// (PAPER.md note 7; `tau` is the CPU's `kick_tau`, infinite for the start-up settle, which adds
/// no velocity); `scale` (<= 1) is one factor for all particles, chosen on the host from
/// `largest` as `CpuBackend::correct_positions` does (`extremes::sweep`).
SPH_KERNEL(apply_displacement)(u32 n, float scale, float tau, const u32* __restrict__ kind,
                               const float* __restrict__ displacement, float* __restrict__ pos,
                               float* __restrict__ vel) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const vec_t dx = vscale(vload(displacement, i), scale);
    vec_t u = vload(vel, i);
    for (int k = 0; k < D; ++k) u.c[k] += dx.c[k] / tau;
    vstore(pos, i, vadd(vload(pos, i), dx));
    vstore(vel, i, u);
}

/// End of an accepted velocity solve, every particle: `p = min(p, p_start)` [Pa], so the solve
/// keeps only the pressure it released (`p_start` as `begin_velocity_solve` saved it; fminf
/// ignores a NaN operand as `f32::min` does). Twin of `CpuBackend::end_velocity_solve` (`keep`).
SPH_KERNEL(keep_pressure_decreases)(u32 n, const float* __restrict__ pressure_start,
                                    float* __restrict__ pressure) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    pressure[i] = fminf(pressure[i], pressure_start[i]);
}
