//! The CUDA backend's neighbour grid: dense over the scene's domain (section 3 of the paper, the
//! CUDA SDK "particles" scheme), unlike the CPU's sparse grid (`grid.rs`), because a dense
//! `cell_start` array is what lets one thread find its neighbours without a search. Cells have
//! the size of the kernel support `h`; the grid is padded by one cell on each side, and cell
//! coordinates are clamped into it (`kernels/sph.cuh`, `cell_of`), so a particle that leaves the
//! domain between two guards still finds every neighbour.

use crate::math::{Real, Vector};

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
            cells = cells.saturating_mul(u64::from(dims[k]));
        }
        if cells > MAX_CELLS {
            return Err(DenseGridError::TooManyCells { cells, h });
        }
        Ok(Self {
            origin,
            inv_cell: 1.0 / h,
            dims,
        })
    }

    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        self.dims.iter().map(|&d| d as usize).product()
    }
}
