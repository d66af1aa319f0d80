//! The CUDA backend's neighbour grid: dense over the scene's domain (section 3 of the paper, the
//! CUDA SDK "particles" scheme), unlike the CPU's sparse grid (`grid.rs`), because a dense
//! `cell_start` array is what lets one thread find its neighbours without a search. Cells have
//! the size of the kernel support `h`; the grid is padded by one cell on each side, and cell
//! coordinates are clamped into it (`kernels/sph.cuh`, `cell_of`), so a particle that leaves the
//! domain between two guards still finds every neighbour.

use crate::math::{Real, Vector};
use crate::periodic::{Periodic, PeriodicAxes};

/// Mirror of `GridGeometry` in `kernels/sph.cuh` (`#[repr(C)]`, passed to kernels by value).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridGeometry<const D: usize> {
    /// Lower corner of cell `(0, 0[, 0])` [m].
    pub origin: [Real; D],
    /// `1 / h` [1/m].
    pub inv_cell: Real,
    /// Cells per axis (x fastest in the key).
    pub dims: [u32; D],
    /// Bit `k`: axis `k` wraps (`crate::periodic`).
    pub periodic: u32,
    /// Lower face of the period along a periodic axis [m] (0 along the others).
    pub period_min: [Real; D],
    /// Period `L` along a periodic axis [m] (0 along the others).
    pub period: [Real; D],
    /// `n/L`: inverse cell size along a periodic axis of `n` cells [1/m] (0 along the others).
    pub period_inv_cell: [Real; D],
}

/// Largest number of cells the dense grid may have: 4 bytes of `cell_start` each, so 1 GiB.
pub const MAX_CELLS: u64 = 1 << 28;

/// Errors of the dense grid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DenseGridError {
    /// The domain holds more cells of size `h` than the dense grid allows.
    #[error(
        "the domain spans {cells} cells of size h = {h} m, more than the CUDA backend's dense grid allows ({MAX_CELLS}); shrink [domain]"
    )]
    TooManyCells {
        /// Cells the domain would need.
        cells: u64,
        /// Cell size [m].
        h: Real,
    },
    /// `h` is not positive or the domain is not finite.
    #[error("cannot build a grid of cell size {h} m over the domain {min:?} .. {max:?}")]
    Invalid {
        /// Cell size [m].
        h: Real,
        /// Domain lower corner [m].
        min: Vec<Real>,
        /// Domain upper corner [m].
        max: Vec<Real>,
    },
}

impl<const D: usize> GridGeometry<D> {
    /// The grid over `[min, max]` with cells of size `h` [m], padded by one cell on each side.
    pub fn new(min: &Vector<D>, max: &Vector<D>, h: Real) -> Result<Self, DenseGridError> {
        Self::new_periodic(min, max, h, PeriodicAxes::NONE)
    }

    /// [`GridGeometry::new`] with `axes` periodic, the period `[min_k, max_k)`: along such an
    /// axis the `n = ⌊L/h⌋ ≥ 3` cells of size `L/n ≥ h` sit at coordinates `1..=n` (the padding
    /// cells stay empty) and the kernels wrap cell coordinates (`cell_of`,
    /// `SPH_FOR_EACH_CANDIDATE_PERIODIC` in `kernels/sph.cuh`).
    pub fn new_periodic(
        min: &Vector<D>,
        max: &Vector<D>,
        h: Real,
        axes: PeriodicAxes,
    ) -> Result<Self, DenseGridError> {
        let invalid = || DenseGridError::Invalid {
            h,
            min: min.iter().copied().collect(),
            max: max.iter().copied().collect(),
        };
        if h.is_nan() || h <= 0.0 || !h.is_finite() {
            return Err(invalid());
        }
        let mut origin = [0.0; D];
        let mut dims = [0u32; D];
        let (mut period_min, mut period, mut period_inv_cell) = ([0.0; D], [0.0; D], [0.0; D]);
        let mut cells: u64 = 1;
        for k in 0..D {
            let extent = f64::from(max[k]) - f64::from(min[k]);
            if !extent.is_finite() || extent < 0.0 {
                return Err(invalid());
            }
            origin[k] = min[k] - h;
            let n = (extent / f64::from(h)).floor() + 3.0;
            if n > MAX_CELLS as f64 {
                return Err(DenseGridError::TooManyCells { cells: u64::MAX, h });
            }
            dims[k] = n as u32;
            if axes.contains(k) {
                let length = max[k] - min[k];
                let periodic = Periodic::new(axes, *min, *max);
                let n = periodic.cells(k, h);
                if n < 3 {
                    return Err(invalid());
                }
                dims[k] = n as u32 + 2;
                period_min[k] = min[k];
                period[k] = length;
                period_inv_cell[k] = (n as f64 / f64::from(length)) as Real;
            }
            cells = cells.saturating_mul(u64::from(dims[k]));
        }
        if cells > MAX_CELLS {
            return Err(DenseGridError::TooManyCells { cells, h });
        }
        Ok(Self {
            origin,
            inv_cell: 1.0 / h,
            dims,
            periodic: axes.bits(),
            period_min,
            period,
            period_inv_cell,
        })
    }

    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        self.dims.iter().map(|&d| d as usize).product()
    }
}
