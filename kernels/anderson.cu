// The velocity solve's iteration (`solver::step::solve_velocities`): Anderson acceleration of the
// projected Jacobi map [WN11] (`solver::anderson`), and the velocities for the current pressure.
// Twins of `CpuBackend::mix_velocity_pressure` and `CpuBackend::velocity_from_pressure`. On the
// device (backend::cuda::anderson):
//   mix_velocity_pressure:  correction_pressure_fluid(_multiphase) with has_prev = 0 (f = g(P) - P)
//     -> anderson_difference -> anderson_dots (Gram row) -> host: AndersonState::push
//     -> anderson_dots (rhs) -> host: AndersonState::coefficients, gamma uploaded -> anderson_mix;
//   velocity_from_pressure: velocity_solve_increments -> correction_pressure_wall (the start's
//     pressure and density) -> velocity_solve_solid_pressure -> correction_displacement(_multiphase)
//     (the start's density) -> velocity_from_displacement.
// The warm start before the first iteration (velocity_solve_warm_start) and the record after the
// last (velocity_solve_record): backend::cuda::warm_start.
// The window's differences are stored slot-major: slot l of a buffer of WINDOW n floats is
// `slots[l n .. (l + 1) n]`.
#include "sph.cuh"

/// Most differences held: `solver::anderson::WINDOW` (the backend checks `count <= WINDOW`).
#define ANDERSON_WINDOW 6u

/// The newest differences into ring slot `slot`, every particle: `dp_l = P - P_prev`,
/// `df_l = f - f_prev` [Pa] (`CpuBackend::mix_velocity_pressure`).
SPH_KERNEL(anderson_difference)(u32 n, u32 slot, const float* __restrict__ pressure,
                                const float* __restrict__ previous, const float* __restrict__ f,
                                const float* __restrict__ previous_f,
                                float* __restrict__ dp_slots, float* __restrict__ df_slots) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const size_t at = (size_t)slot * n + i;
    dp_slots[at] = pressure[i] - previous[i];
    df_slots[at] = f[i] - previous_f[i];
}

/// Dot products with the first `count` (<= ANDERSON_WINDOW) slots:
/// `out[l] += sum_i a[a_offset + i] slots[l n + i]` [Pa^2] (`a` is a slot when `a` is `slots`), products and sums in f64 as the CPU's `math::sum_in_order` (whose fixed order this does not
/// reproduce: parity is to a relative tolerance). Grid-stride loop: the backend launches about
/// n/64 threads, each summing its items in registers and adding once per slot; the host zeroes
/// `out`.
SPH_KERNEL(anderson_dots)(u32 n, u32 count, const float* a, u32 a_offset, const float* slots,
                          const u32* __restrict__ owned, double* __restrict__ out) {
    const u32 stride = gridDim.x * blockDim.x;
    const u32 first = blockIdx.x * blockDim.x + threadIdx.x;
    if (first >= n) return;
    double sum[ANDERSON_WINDOW];
    for (u32 l = 0; l < ANDERSON_WINDOW; ++l) sum[l] = 0.0;
    for (u32 i = first; i < n; i += stride) {
        if (!owned[i]) continue;  // a ghost: its owner adds it
        const double a_i = (double)a[a_offset + i];
        for (u32 l = 0; l < count && l < ANDERSON_WINDOW; ++l) {
            sum[l] += a_i * (double)slots[(size_t)l * n + i];
        }
    }
    for (u32 l = 0; l < count && l < ANDERSON_WINDOW; ++l) atomicAdd(&out[l], sum[l]);
}

/// The accelerated step, note 6: fluid `P = max(P + f - sum_{l < held} gamma_l (dp_l + df_l), 0)`
/// with the subtractions in slot order in f32, as the CPU; solids keep theirs. Every particle
/// first leaves its iterate for the next difference: `previous = P`, `previous_f = f`.
SPH_KERNEL(anderson_mix)(u32 n, u32 held, const float* __restrict__ gamma,
                         const u32* __restrict__ kind, const float* __restrict__ f,
                         const float* __restrict__ dp_slots, const float* __restrict__ df_slots,
                         float* __restrict__ previous, float* __restrict__ previous_f,
                         float* __restrict__ pressure) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const float p = pressure[i];
    previous[i] = p;
    previous_f[i] = f[i];
    if (kind[i] != SPH_FLUID) return;
    float mixed = p + f[i];
    for (u32 l = 0; l < held; ++l) {
        const size_t at = (size_t)l * n + i;
        mixed -= gamma[l] * (dp_slots[at] + df_slots[at]);
    }
    pressure[i] = fmaxf(mixed, 0.0f);  // f32::max: a NaN gives 0
}

/// The solve's total increments so far, fluid: `delta_p = P - P_start` [Pa]; solids get 0 (the
/// walls' come from `correction_pressure_wall` next).
SPH_KERNEL(velocity_solve_increments)(u32 n, const u32* __restrict__ kind,
                                      const float* __restrict__ pressure,
                                      const float* __restrict__ pressure_start,
                                      float* __restrict__ delta_p) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    delta_p[i] = kind[i] == SPH_FLUID ? pressure[i] - pressure_start[i] : 0.0f;
}

/// Solids after `correction_pressure_wall` (run with the start's pressure): `P = P_start +
/// delta_p`, which is `max(P_start + r, 0)` rounded as the CPU rounds it; fluid untouched.
SPH_KERNEL(velocity_solve_solid_pressure)(u32 n, const u32* __restrict__ kind,
                                          const float* __restrict__ pressure_start,
                                          const float* __restrict__ delta_p,
                                          float* __restrict__ pressure) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] == SPH_FLUID) return;
    pressure[i] = pressure_start[i] + delta_p[i];
}

/// Fluid velocities from the displacement of eq. (23) at `tau`: `u = u_start + dx / tau` [m/s]
/// (`u_start + tau a^press(P - P_start)`), component by component in f32 as the CPU divides;
/// solids untouched.
SPH_KERNEL(velocity_from_displacement)(u32 n, float tau, const u32* __restrict__ kind,
                                       const float* __restrict__ velocity_start,
                                       const float* __restrict__ displacement,
                                       float* __restrict__ vel) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const vec_t dx = vload(displacement, i);
    vec_t u = vload(velocity_start, i);
    for (int k = 0; k < D; ++k) u.c[k] += dx.c[k] / tau;
    vstore(vel, i, u);
}

/// The warm start (`CpuBackend::warm_start_velocity_solve`): a fluid particle whose record in
/// `slot` was written by the slot's last solve (`recorded_by == solves`) starts from
/// `max(P_start + dP, 0)`. Records are id-major: `id * slots + slot`.
SPH_KERNEL(velocity_solve_warm_start)(u32 n, u32 slots, u32 slot, u32 solves,
                                      const u32* __restrict__ kind, const u32* __restrict__ id,
                                      const u32* __restrict__ recorded_by,
                                      const float* __restrict__ increment,
                                      float* __restrict__ pressure) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const u32 k = id[i] * slots + slot;
    if (recorded_by[k] == solves) pressure[i] = fmaxf(pressure[i] + increment[k], 0.0f);
}

/// The solve's increments `P - P_start` of every fluid particle into its record in `slot`,
/// numbered `next` (`CpuBackend::record_velocity_solve`).
SPH_KERNEL(velocity_solve_record)(u32 n, u32 slots, u32 slot, u32 next,
                                  const u32* __restrict__ kind, const u32* __restrict__ id,
                                  const float* __restrict__ pressure,
                                  const float* __restrict__ pressure_start,
                                  u32* __restrict__ recorded_by, float* __restrict__ increment) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const u32 k = id[i] * slots + slot;
    recorded_by[k] = next;
    increment[k] = pressure[i] - pressure_start[i];
}
