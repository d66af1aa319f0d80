//! Periodic boundaries: a channel or a wide flume simulated as one period along chosen axes.
//!
//! Route: minimum image in the neighbour search, no image particles. Along a periodic axis `k`
//! the domain `[min_k, max_k)` of length `L_k` is one period:
//! - the neighbour grids wrap along `k` (the CPU's sparse grid, `grid.rs`, and the CUDA
//!   backend's dense grid, `kernels/sph.cuh`), with `n_k = ⌊L_k/h⌋ ≥ 3` cells of size
//!   `L_k/n_k ≥ h` (the cell is stretched to divide the period, so any `L_k ≥ 3h` works);
//! - every pair loop takes its offset `x_i − x_j` through [`Periodic::minimum_image`] (CPU:
//!   `Grid::for_each_neighbour`, whose offsets the velocity solve's lists store; CUDA:
//!   `pair_delta` in `kernels/sph.cuh`),
//!   so no stage computes a raw difference itself;
//! - the stage `wrap_positions` ([`Periodic::wrap`]) moves a fluid particle that left
//!   `[min_k, max_k)` back by `±L_k` once a step, after the last integrator stage (positions in
//!   between may lie slightly outside: the grids and the minimum image take any position within
//!   half a period of the domain). Mass and velocity are untouched: the particle is the same
//!   particle, seen one period away.
//!
//! Which axes are periodic is a value ([`PeriodicAxes`], in `StepParams::periodic`), read by
//! both backends; a scene without periodic axes runs exactly the code it ran before.

use crate::math::{Real, Vector};

/// Relative slack of the cell count `⌊L/h⌋`: a period meant as a whole number of `h` (0.21 m at
/// h = 0.07 m) is 2.9999999 h after f32 rounding of `L` and `h`, and must still give 3 cells. A
/// cell then falls short of `h` by at most this fraction, where every kernel is zero to 1e-17 of
/// its peak (poly6 `(h² − r²)³`), so no pair that counts is missed.
pub const CELL_SLACK: f64 = 1e-6;

/// The set of periodic axes, bit `k` for axis `k` (`u32` as in `kernels/sph.cuh`).
#[repr(transparent)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PeriodicAxes(u32);

impl PeriodicAxes {
    /// No periodic axis.
    pub const NONE: Self = Self(0);

    /// This set with axis `k` added.
    pub const fn with(self, k: usize) -> Self {
        Self(self.0 | (1 << k))
    }

    /// Whether axis `k` is periodic.
    #[inline(always)]
    pub const fn contains(self, k: usize) -> bool {
        self.0 & (1 << k) != 0
    }

    /// Whether no axis is periodic.
    #[inline(always)]
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The bit mask (bit `k`: axis `k`).
    pub const fn bits(self) -> u32 {
        self.0
    }

    /// The axes' names (`"x"`, `"y"`, `"z"`), ascending.
    pub fn names(self) -> Vec<&'static str> {
        ["x", "y", "z"]
            .into_iter()
            .enumerate()
            .filter(|&(k, _)| self.contains(k))
            .map(|(_, n)| n)
            .collect()
    }
}

/// The periodic axes with the period along each: the domain `[min, min + length)` [m].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Periodic<const D: usize> {
    /// Which axes are periodic.
    pub axes: PeriodicAxes,
    /// Lower face of the period along each axis [m] (the domain's lower corner).
    pub min: Vector<D>,
    /// Upper face [m] (the domain's upper corner).
    pub max: Vector<D>,
    /// Period `L = max − min` [m] (f32, as the CUDA twin computes it).
    pub length: Vector<D>,
}

impl<const D: usize> Default for Periodic<D> {
    fn default() -> Self {
        Self::none()
    }
}

impl<const D: usize> Periodic<D> {
    /// No periodic axis: [`Periodic::minimum_image`] and [`Periodic::wrap`] change nothing.
    pub fn none() -> Self {
        Self::new(PeriodicAxes::NONE, Vector::zeros(), Vector::zeros())
    }

    /// The `axes` of the domain `[min, max]` [m].
    pub fn new(axes: PeriodicAxes, min: Vector<D>, max: Vector<D>) -> Self {
        Self {
            axes,
            min,
            max,
            length: max - min,
        }
    }

    /// The minimum image of the offset `d = x_i − x_j` [m]: along each periodic axis, `d_k ∓ L_k`
    /// where `|d_k| > L_k/2`. Exact for positions within half a period of the domain; the pair
    /// within `h` is then the only image closer than `L_k − h ≥ 2h`. Twin: `periodic_minimum_image`
    /// in `kernels/sph.cuh` (the same f32 operations).
    #[inline(always)]
    pub fn minimum_image(&self, mut d: Vector<D>) -> Vector<D> {
        if self.axes.is_empty() {
            return d;
        }
        for k in 0..D {
            if self.axes.contains(k) {
                let l = self.length[k];
                if d[k] > 0.5 * l {
                    d[k] -= l;
                } else if d[k] < -0.5 * l {
                    d[k] += l;
                }
            }
        }
        d
    }

    /// Stage `wrap_positions` for one position [m]: along each periodic axis a coordinate
    /// outside `[min_k, max_k)` moves by one period `±L_k` (one: a particle moves far less than a
    /// period per step; one still outside is the domain guard's, `solver::escape`). A result
    /// that f32 rounding puts on the excluded face `max_k` goes to `min_k`, the same point.
    /// Twin: `periodic_wrap` in `kernels/sph.cuh`.
    #[inline(always)]
    pub fn wrap(&self, mut x: Vector<D>) -> Vector<D> {
        for k in 0..D {
            if self.axes.contains(k) {
                let (lo, hi, l) = (self.min[k], self.max[k], self.length[k]);
                if x[k] >= hi {
                    x[k] -= l;
                    if x[k] < lo {
                        x[k] = lo;
                    }
                } else if x[k] < lo {
                    x[k] += l;
                    if x[k] >= hi {
                        x[k] = lo;
                    }
                }
            }
        }
        x
    }

    /// Cells of size at least `h` [m] along periodic axis `k`: `⌊L_k/h⌋` (the grids need 3),
    /// with `L_k/h` raised by [`CELL_SLACK`] first.
    pub fn cells(&self, k: usize, h: Real) -> u64 {
        (f64::from(self.length[k]) / f64::from(h) * (1.0 + CELL_SLACK))
            .floor()
            .max(0.0) as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimum_image_and_wrap_move_by_one_period_along_periodic_axes_only() {
        let p = Periodic::<2>::new(
            PeriodicAxes::NONE.with(0),
            Vector::<2>::new(0.0, 0.0),
            Vector::<2>::new(1.0, 1.0),
        );
        let d = p.minimum_image(Vector::<2>::new(0.9, 0.9));
        assert!((d[0] + 0.1).abs() < 1e-6 && d[1] == 0.9, "{d:?}");
        assert_eq!(
            p.minimum_image(Vector::<2>::new(-0.3, 0.0)),
            Vector::<2>::new(-0.3, 0.0)
        );
        let x = p.wrap(Vector::<2>::new(1.05, 1.05));
        assert!((x[0] - 0.05).abs() < 1e-6 && x[1] == 1.05, "{x:?}");
        assert_eq!(p.wrap(Vector::<2>::new(-0.0, 0.5))[0], 0.0);
        // A coordinate a hair below the lower face lands on it, not on the excluded upper face.
        assert_eq!(p.wrap(Vector::<2>::new(-1e-9, 0.5))[0], 0.0);
        assert_eq!(PeriodicAxes::NONE.with(0).with(2).names(), ["x", "z"]);
        // A period of exactly 3 h in decimal input gives 3 cells despite f32 rounding.
        let three = Periodic::<2>::new(p.axes, Vector::<2>::zeros(), Vector::<2>::new(0.21, 1.0));
        assert!(f64::from(three.length[0]) / f64::from(0.07f32) < 3.0);
        assert_eq!(three.cells(0, 0.07), 3);
    }
}
