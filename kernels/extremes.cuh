// Global maxima, minima and sums over particles, through atomics only (the rules of `sph.cuh`).
// Mirrored in Rust by `backend::cuda::extremes` (`DeviceExtremes`), which sets the initial
// values and turns the result into the CPU's `StateExtremes`.
//
// Maxima of non-negative floats are kept as their bits in an int: for x, y >= 0, x < y exactly
// when bits(x) < bits(y), and a NaN (made positive by fabsf) has bits above +inf, so it wins, as
// the CPU's `math::max_in_order` lets NaN win. Floats of any sign use `ordered_bits`.
#pragma once

#include "sph.cuh"

/// Index meaning "no particle" in the atomicMin slots.
#define SPH_NO_PARTICLE 0xFFFFFFFFu

/// Bits of the non-negative `x` (or NaN, made positive), for an atomicMax on int.
__device__ __forceinline__ int max_bits(float x) { return __float_as_int(fabsf(x)); }

/// An int that orders as the float `x` does, for floats of either sign (NaN excluded):
/// the sign-magnitude bits of a negative float are flipped to two's complement order. Its own
/// inverse (`extremes::from_ordered_bits` in Rust).
__device__ __forceinline__ int ordered_bits(float x) {
    int b = __float_as_int(x);
    return b >= 0 ? b : b ^ 0x7FFFFFFF;
}

/// True when `x` is neither infinite nor NaN (exponent bits not all ones).
__device__ __forceinline__ bool finite_float(float x) {
    return (__float_as_int(x) & 0x7F800000) != 0x7F800000;
}

__device__ __forceinline__ bool finite_vec(vec_t v) {
    bool ok = true;
    for (int k = 0; k < D; ++k) ok = ok && finite_float(v.c[k]);
    return ok;
}

/// Result of `state_extremes` (`StateExtremes` of the CPU), mirrored by `DeviceExtremes`
/// (`#[repr(C)]`, 48 bytes). The host uploads `DeviceExtremes::initial()` before the launch.
struct Extremes {
    int max_speed;           // max_bits of the largest fluid |u| [m/s]; initial 0
    int max_acceleration;    // max_bits of the largest fluid |a| [m/s^2]; initial 0
    int max_density;         // ordered_bits of the largest non-NaN fluid density; initial -inf
    int min_density;         // ordered_bits of the smallest non-NaN fluid density; initial +inf
    u32 density_nan;         // 1 when some fluid density is NaN; initial 0
    u32 fluid_count;         // number of fluid particles; initial 0
    u32 non_finite;          // smallest index with a non-finite field; initial SPH_NO_PARTICLE
    u32 escaped;             // smallest fluid index outside the domain; initial SPH_NO_PARTICLE
    double abs_error_sum;    // sum over fluid of |rho - rho0|/rho0 (f64, as the CPU); initial 0
    double compression_sum;  // sum over fluid of max(rho - rho0, 0)/rho0; initial 0
};
