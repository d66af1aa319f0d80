// Stage `state_extremes`: the extremes of the fluid state for the time-step choice and the
// state guards. Twin of `CpuBackend::state_extremes` and its `first_non_finite`; the pieces are
// gathered in `Extremes` (`extremes.cuh`) and finished on the host
// (`backend::cuda::extremes::DeviceExtremes`).
//
// The largest density error is kept as the largest and smallest fluid density: |rho - rho0|/rho0
// computed in f64 is monotone on each side of rho0, so the host gets the CPU's f64 value exactly.
#include "sph.cuh"
#include "extremes.cuh"

SPH_KERNEL(state_extremes)(u32 n, StepParams p, const float* __restrict__ pos,
                           const float* __restrict__ vel, const float* __restrict__ acc,
                           const float* __restrict__ density, const float* __restrict__ pressure,
                           const u32* __restrict__ kind, Extremes* __restrict__ out) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const vec_t x = vload(pos, i);
    const vec_t u = vload(vel, i);
    const vec_t a = vload(acc, i);
    const float rho = density[i];
    // Any particle, any of the fields `first_non_finite` checks.
    if (!(finite_vec(x) && finite_vec(u) && finite_vec(a) && finite_float(rho) && finite_float(pressure[i])))
        atomicMin(&out->non_finite, i);
    if (kind[i] != SPH_FLUID) return;
    atomicAdd(&out->fluid_count, 1u);
    atomicMax(&out->max_speed, max_bits(sqrtf(vdot(u, u))));
    atomicMax(&out->max_acceleration, max_bits(sqrtf(vdot(a, a))));
    if (rho != rho) {
        atomicMax(&out->density_nan, 1u);
    } else {
        atomicMax(&out->max_density, ordered_bits(rho));
        atomicMin(&out->min_density, ordered_bits(rho));
    }
    const double e = ((double)rho - (double)p.rho0) / (double)p.rho0;
    atomicAdd(&out->abs_error_sum, fabs(e));
    atomicAdd(&out->compression_sum, e > 0.0 ? e : 0.0);  // max(e, 0): NaN gives 0, as in Rust
    bool outside = false;
    for (int k = 0; k < D; ++k) outside = outside || x.c[k] < p.domain_min[k] || x.c[k] > p.domain_max[k];
    if (outside) atomicMin(&out->escaped, i);
}
