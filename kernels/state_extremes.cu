// Stage `state_extremes`: the extremes of the fluid state for the time-step choice and the
// state guards. Twin of `CpuBackend::state_extremes` and its `first_non_finite`; the pieces are
// gathered in `Extremes` (`extremes.cuh`) and finished on the host
// (`backend::cuda::extremes::DeviceExtremes`).
//
// The largest density error is kept as the largest and smallest fluid density: |rho - rho0|/rho0
// computed in f64 is monotone on each side of rho0, so the host gets the CPU's f64 value exactly.
//
// `state_extremes_multiphase` (the `multiphase` effect) measures each particle against its own
// rest density `rest[i]`: the sums use `(rho - rest)/rest` in f64 as the CPU, the largest error
// the density scaled to the scene's `rho0`, `rho rho0 / rest` (rounded once to f32, so the
// largest error may differ from the CPU's in the last bits).
#include "sph.cuh"
#include "extremes.cuh"

__device__ __forceinline__ void state_extremes_body(u32 n, const StepParams& p,
                                                    const float* __restrict__ pos,
                                                    const float* __restrict__ vel,
                                                    const float* __restrict__ acc,
                                                    const float* __restrict__ density,
                                                    const float* __restrict__ pressure,
                                                    const u32* __restrict__ kind,
                                                    const float* __restrict__ rest,
                                                    const u32* __restrict__ owned,
                                                    Extremes* __restrict__ out) {
    // Grid-stride loop with per-thread accumulators: one set of atomics per thread, not per
    // particle (the backend launches about n/64 threads; the shim one per particle).
    const u32 stride = gridDim.x * blockDim.x;
    u32 count = 0, non_finite = SPH_NO_PARTICLE, escaped = SPH_NO_PARTICLE, nan = 0;
    int speed = 0, accel = 0, rho_max = ordered_bits(__int_as_float((int)0xff800000u)),
        rho_min = ordered_bits(__int_as_float(0x7f800000));
    double abs_sum = 0.0, comp_sum = 0.0;
    for (u32 i = blockIdx.x * blockDim.x + threadIdx.x; i < n; i += stride) {
        const vec_t x = vload(pos, i);
        const vec_t u = vload(vel, i);
        const vec_t a = vload(acc, i);
        const float rho_raw = density[i];
        // Without phases `rest` is null and rho is the density itself.
        const float rho =
            rest ? (float)((double)rho_raw * (double)p.rho0 / (double)rest[i]) : rho_raw;
        if (!(finite_vec(x) && finite_vec(u) && finite_vec(a) && finite_float(rho_raw) &&
              finite_float(pressure[i])))
            non_finite = non_finite < i ? non_finite : i;
        // A ghost of a split run is counted by its owner (`backend::partition`).
        if (kind[i] != SPH_FLUID || !owned[i]) continue;
        count += 1;
        const int bs = max_bits(sqrtf(vdot(u, u))), ba = max_bits(sqrtf(vdot(a, a)));
        speed = speed > bs ? speed : bs;
        accel = accel > ba ? accel : ba;
        if (rho != rho) {
            nan = 1;
        } else {
            const int b = ordered_bits(rho);
            rho_max = rho_max > b ? rho_max : b;
            rho_min = rho_min < b ? rho_min : b;
        }
        const double rho0_i = rest ? (double)rest[i] : (double)p.rho0;
        const double e = ((double)rho_raw - rho0_i) / rho0_i;
        abs_sum += fabs(e);
        comp_sum += e > 0.0 ? e : 0.0;  // max(e, 0): NaN gives 0, as in Rust
        bool outside = false;
        for (int k = 0; k < D; ++k)
            outside = outside || x.c[k] < p.domain_min[k] || x.c[k] > p.domain_max[k];
        if (outside) escaped = escaped < i ? escaped : i;
    }
    if (non_finite != SPH_NO_PARTICLE) atomicMin(&out->non_finite, non_finite);
    if (count == 0) return;
    atomicAdd(&out->fluid_count, count);
    atomicMax(&out->max_speed, speed);
    atomicMax(&out->max_acceleration, accel);
    if (nan) atomicMax(&out->density_nan, 1u);
    atomicMax(&out->max_density, rho_max);
    atomicMin(&out->min_density, rho_min);
    atomicAdd(&out->abs_error_sum, abs_sum);
    atomicAdd(&out->compression_sum, comp_sum);
    if (escaped != SPH_NO_PARTICLE) atomicMin(&out->escaped, escaped);
}

SPH_KERNEL(state_extremes)(u32 n, StepParams p, const float* __restrict__ pos,
                           const float* __restrict__ vel, const float* __restrict__ acc,
                           const float* __restrict__ density, const float* __restrict__ pressure,
                           const u32* __restrict__ kind, const u32* __restrict__ owned,
                           Extremes* __restrict__ out) {
    state_extremes_body(n, p, pos, vel, acc, density, pressure, kind, nullptr, owned, out);
}

/// The same against each particle's own rest density (the `multiphase` effect).
SPH_KERNEL(state_extremes_multiphase)(u32 n, StepParams p, const float* __restrict__ pos,
                                      const float* __restrict__ vel, const float* __restrict__ acc,
                                      const float* __restrict__ density,
                                      const float* __restrict__ pressure,
                                      const u32* __restrict__ kind, const float* __restrict__ rest,
                                      const u32* __restrict__ owned, Extremes* __restrict__ out) {
    state_extremes_body(n, p, pos, vel, acc, density, pressure, kind, rest, owned, out);
}
