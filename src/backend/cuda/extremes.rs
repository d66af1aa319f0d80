//! The device's global reductions turned into the CPU's answers: `Extremes` of
//! `kernels/extremes.cuh` (filled by `kernels/state_extremes.cu`) becomes [`StateExtremes`], and
//! the float-bit maxima of `kernels/correction.cu` become the values `CpuBackend` returns.
//!
//! Kernels keep maxima of non-negative floats as their bits in an `i32` (`atomicMax` on int), a
//! NaN made positive so that it wins, as `math::max_in_order` lets NaN win; the CPU then takes
//! `.max(0.0)`, which turns NaN into 0, and so do the functions here.

use crate::backend::{StateExtremes, Sweep};
use crate::math::Real;

/// "No particle" in the index slots (`SPH_NO_PARTICLE`).
const NO_PARTICLE: u32 = u32::MAX;

/// `ordered_bits` of `kernels/extremes.cuh`: an `i32` that orders as the float does (NaN
/// excluded). Its own inverse.
fn ordered_bits(x: f32) -> i32 {
    let b = x.to_bits() as i32;
    if b >= 0 { b } else { b ^ 0x7FFF_FFFF }
}

/// Inverse of [`ordered_bits`].
fn from_ordered_bits(b: i32) -> f32 {
    let b = if b >= 0 { b } else { b ^ 0x7FFF_FFFF };
    f32::from_bits(b as u32)
}

/// Mirror of `Extremes` in `kernels/extremes.cuh` (`#[repr(C)]`, 48 bytes): the raw result of
/// the `state_extremes` kernel. Upload [`DeviceExtremes::initial`] before each launch.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DeviceExtremes {
    /// Bits of the largest fluid speed [m/s].
    pub max_speed: i32,
    /// Bits of the largest fluid acceleration magnitude [m/s²].
    pub max_acceleration: i32,
    /// `ordered_bits` of the largest non-NaN fluid density [kg/m³].
    pub max_density: i32,
    /// `ordered_bits` of the smallest non-NaN fluid density [kg/m³].
    pub min_density: i32,
    /// 1 when some fluid density is NaN.
    pub density_nan: u32,
    /// Number of fluid particles.
    pub fluid_count: u32,
    /// Smallest index (current order) of a particle with a non-finite position, velocity,
    /// acceleration, density or pressure; `u32::MAX` if none.
    pub non_finite: u32,
    /// Smallest index (current order) of a fluid particle outside the domain; `u32::MAX` if none.
    pub escaped: u32,
    /// Σ over fluid of `|ρ − ρ0|/ρ0`.
    pub abs_error_sum: f64,
    /// Σ over fluid of `max(ρ − ρ0, 0)/ρ0`.
    pub compression_sum: f64,
}

impl DeviceExtremes {
    /// The values the slots must hold before the kernel runs: neutral elements of each reduction.
    pub fn initial() -> Self {
        Self {
            max_speed: 0,
            max_acceleration: 0,
            max_density: ordered_bits(f32::NEG_INFINITY),
            min_density: ordered_bits(f32::INFINITY),
            density_nan: 0,
            fluid_count: 0,
            non_finite: NO_PARTICLE,
            escaped: NO_PARTICLE,
            abs_error_sum: 0.0,
            compression_sum: 0.0,
        }
    }

    /// The largest `|ρ − ρ0|/ρ0` as `CpuBackend::state_extremes` computes it before `.max(0.0)`
    /// (NaN when a fluid density is NaN; 0 without fluid). Exact: the f64 error is monotone on
    /// each side of `ρ0`, so its maximum is at the largest or the smallest density.
    fn raw_max_abs_density_error(&self, rho0: f32) -> f64 {
        if self.density_nan != 0 {
            return f64::NAN;
        }
        if self.min_density > self.max_density {
            return 0.0; // no fluid density was seen
        }
        let rho0 = f64::from(rho0);
        let error = |rho: f32| ((f64::from(rho) - rho0) / rho0).abs();
        error(from_ordered_bits(self.max_density)).max(error(from_ordered_bits(self.min_density)))
    }

    /// The largest compression `max(ρ − ρ0, 0)/ρ0` (NaN densities give 0, as on the CPU).
    fn max_compression(&self, rho0: f32) -> f64 {
        if self.min_density > self.max_density {
            return 0.0;
        }
        let rho0 = f64::from(rho0);
        ((f64::from(from_ordered_bits(self.max_density)) - rho0) / rho0).max(0.0)
    }

    /// The largest free-surface deficit `max(ρ0 − ρ, 0)/ρ0`, at the smallest density (NaN
    /// densities give 0, as on the CPU).
    fn max_surface_deficit(&self, rho0: f32) -> f64 {
        if self.min_density > self.max_density {
            return 0.0;
        }
        let rho0 = f64::from(rho0);
        (-((f64::from(from_ordered_bits(self.min_density)) - rho0) / rho0)).max(0.0)
    }

    /// The extremes as `CpuBackend::state_extremes` reports them, for rest density `rho0`
    /// [kg/m³], with `non_finite: None`: the host names the field of
    /// [`DeviceExtremes::first_non_finite`] from the particle's values.
    pub fn finish(&self, rho0: f32) -> StateExtremes {
        let count = f64::from(self.fluid_count);
        let mean = |s: f64| if count > 0.0 { s / count } else { 0.0 };
        StateExtremes {
            max_speed: max_from_bits(self.max_speed),
            max_acceleration: max_from_bits(self.max_acceleration),
            max_abs_density_error: self.raw_max_abs_density_error(rho0).max(0.0),
            mean_abs_density_error: mean(self.abs_error_sum),
            max_compression: self.max_compression(rho0).max(0.0),
            mean_compression: mean(self.compression_sum),
            max_surface_deficit: self.max_surface_deficit(rho0),
            mean_surface_deficit: mean(self.abs_error_sum - self.compression_sum),
            non_finite: None,
            escaped: (self.escaped != NO_PARTICLE).then_some(self.escaped as usize),
        }
    }

    /// One rank's share of the extremes before they combine over ranks
    /// (`StateExtremes::from_parts`): the maxima as the CPU keeps them (a NaN speed,
    /// acceleration or density error stays NaN) and the fluid count and error sums.
    pub fn rank_parts(&self, rho0: f32) -> ([f64; 5], [f64; 3]) {
        let raw = |bits: i32| f64::from(f32::from_bits(bits as u32));
        (
            [
                raw(self.max_speed),
                raw(self.max_acceleration),
                self.raw_max_abs_density_error(rho0),
                self.max_compression(rho0),
                self.max_surface_deficit(rho0),
            ],
            [
                f64::from(self.fluid_count),
                self.abs_error_sum,
                self.compression_sum,
            ],
        )
    }

    /// The smallest index of a fluid particle outside the domain, if any.
    pub fn escaped_index(&self) -> Option<usize> {
        (self.escaped != NO_PARTICLE).then_some(self.escaped as usize)
    }

    /// The smallest index of a particle with a non-finite field, if any (without the condition
    /// of [`DeviceExtremes::first_non_finite`]).
    pub fn non_finite_index(&self) -> Option<usize> {
        (self.non_finite != NO_PARTICLE).then_some(self.non_finite as usize)
    }

    /// The first particle with a non-finite field, reported under the CPU's condition: only when
    /// the largest fluid speed, acceleration or density error is itself not finite (a NaN
    /// elsewhere, such as a solid's pressure alone, is left to show up there first).
    pub fn first_non_finite(&self) -> Option<usize> {
        let speed = f64::from(f32::from_bits(self.max_speed as u32));
        let acceleration = f64::from(f32::from_bits(self.max_acceleration as u32));
        // (ρ − ρ0)/ρ0 in f64 is finite exactly when ρ is, for any f32 ρ0 > 0 (no overflow).
        let density = self.raw_max_abs_density_error(1.0);
        if (speed + acceleration + density).is_finite() || self.non_finite == NO_PARTICLE {
            None
        } else {
            Some(self.non_finite as usize)
        }
    }
}

/// A maximum kept as float bits by a kernel (`max_bits` of `kernels/extremes.cuh`, zeroed
/// before the launch), as the CPU's `max_in_order(..).max(0.0)`: NaN gives 0.
pub fn max_from_bits(bits: i32) -> f64 {
    f64::from(f32::from_bits(bits as u32)).max(0.0)
}

/// A maximum kept as float bits (as [`max_from_bits`]) whose NaN stays NaN: the correction's
/// residual, NaN when a fluid particle's density or pressure is (`physics::correction::residual`),
/// as the CPU's `math::non_negative_or_nan`.
pub fn max_from_bits_or_nan(bits: i32) -> f64 {
    let x = f64::from(f32::from_bits(bits as u32));
    if x.is_nan() { x } else { x.max(0.0) }
}

/// `CpuBackend::correct_positions`' choice of one scale for all displacements from the largest
/// `|Δx|` [m] (from the bits of `correction_displacement`, [`max_from_bits`], and over the ranks
/// of a split run): `max_step / largest` when that exceeds `max_step` [m], else 1. Launch
/// `apply_displacement` with `sweep.scale as f32` (exact).
pub fn sweep(largest: f64, max_step: f32) -> Sweep {
    let scale = if largest > f64::from(max_step) {
        (f64::from(max_step) / largest) as Real
    } else {
        1.0
    };
    Sweep {
        largest: largest * f64::from(scale),
        scale: f64::from(scale),
    }
}
