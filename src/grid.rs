//! Neighbour search on a uniform grid, as in section 3 of the paper (the CUDA SDK "particles"
//! scheme): hash each particle to its cell, radix-sort by cell key (radsort), reorder the particle
//! arrays by the sort, find each cell's start/end, visit the neighbouring cells.
//!
//! The cell size equals the kernel support `h` (PAPER.md note 1), so all neighbours of a particle
//! lie in its own cell and the `3^D − 1` cells around it.
//!
//! Memory is proportional to the number of particles, never to the empty space between them:
//! keys are linear indices over the particles' own bounding box (padded by one cell), and only
//! non-empty cells are stored, in key order. Because x is the fastest-varying axis of the key,
//! the three cells `(x−1, x, x+1)` of one row are contiguous in the sorted particle order, so each
//! non-empty cell stores `3^(D−1)` particle ranges (3 rows in 2D, 9 in 3D) that cover its whole
//! neighbourhood.

use crate::math::{Real, Vector};
use crate::smoothing::pair_offset;
use rayon::prelude::*;
use std::ops::Range;

/// Errors of the neighbour grid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GridError {
    /// A position is NaN or infinite.
    #[error("particle {particle} has a non-finite position")]
    NonFinitePosition {
        /// Index of the particle in the current order.
        particle: usize,
    },
    /// The particles' bounding box has more cells than a 64-bit key can number.
    #[error(
        "the particles span {cells:.3e} grid cells of size {cell_size} m, more than a 64-bit key can address"
    )]
    TooManyCells {
        /// Number of cells of the padded bounding box.
        cells: f64,
        /// Cell size [m].
        cell_size: Real,
    },
    /// More than `u32::MAX` particles.
    #[error("{0} particles exceed the grid's 32-bit particle indices")]
    TooManyParticles(usize),
}

/// A uniform grid over the particles' bounding box, built from positions in sorted order.
#[derive(Debug, Clone)]
pub struct Grid<const D: usize> {
    cell_size: Real,
    /// Cell coordinate of key 0 (the lower corner of the padded bounding box).
    origin: [i64; D],
    /// Key stride of each axis (x fastest).
    stride: [u64; D],
    /// Cell key of every particle, in sorted order.
    keys: Vec<u64>,
    /// Keys of the non-empty cells, ascending.
    cell_keys: Vec<u64>,
    /// First particle of each non-empty cell; one extra entry holds the particle count.
    cell_start: Vec<u32>,
    /// For each non-empty cell, `3^(D−1)` contiguous particle ranges covering its neighbourhood.
    rows: Vec<(u32, u32)>,
    /// Index of each particle's cell in `cell_keys`.
    cell_of: Vec<u32>,
    /// Scratch pairs (key, original index) for the radix sort, kept to avoid reallocation.
    pairs: Vec<(u64, u32)>,
    /// Permutation of the last sort: new index → old index.
    perm: Vec<u32>,
}

/// Number of neighbour rows per cell: `3^(D−1)`.
const fn rows_per_cell(d: usize) -> usize {
    let mut n = 1;
    let mut k = 1;
    while k < d {
        n *= 3;
        k += 1;
    }
    n
}

impl<const D: usize> Default for Grid<D> {
    fn default() -> Self {
        Self {
            cell_size: 1.0,
            origin: [0; D],
            stride: [0; D],
            keys: Vec::new(),
            cell_keys: Vec::new(),
            cell_start: Vec::new(),
            rows: Vec::new(),
            cell_of: Vec::new(),
            pairs: Vec::new(),
            perm: Vec::new(),
        }
    }
}

impl<const D: usize> Grid<D> {
    /// Cell size [m] (the kernel support `h`).
    pub fn cell_size(&self) -> Real {
        self.cell_size
    }

    /// Number of non-empty cells.
    pub fn cell_count(&self) -> usize {
        self.cell_keys.len()
    }

    /// Bytes held by the grid's arrays (for memory reports).
    pub fn heap_bytes(&self) -> usize {
        self.keys.capacity() * 8
            + self.cell_keys.capacity() * 8
            + self.cell_start.capacity() * 4
            + self.rows.capacity() * 8
            + self.cell_of.capacity() * 4
            + self.pairs.capacity() * 16
            + self.perm.capacity() * 4
    }

    /// Stage `sort_by_cell`, first half: hashes `position` to cells of size `cell_size` [m] and
    /// radix-sorts by key. Returns the permutation `perm` (new index → old index) that the caller
    /// must apply to every particle field (see `Fields::permute`) before calling [`Grid::link`].
    pub fn sort(&mut self, position: &[Vector<D>], cell_size: Real) -> Result<&[u32], GridError> {
        let n = position.len();
        if u32::try_from(n).is_err() {
            return Err(GridError::TooManyParticles(n));
        }
        self.cell_size = cell_size;
        let inv = 1.0 / f64::from(cell_size);
        // Bounding box in cell coordinates.
        let mut lo = [i64::MAX; D];
        let mut hi = [i64::MIN; D];
        for (i, x) in position.iter().enumerate() {
            for k in 0..D {
                let c = f64::from(x[k]) * inv;
                if !c.is_finite() {
                    return Err(GridError::NonFinitePosition { particle: i });
                }
                // Cell coordinates beyond ±2^60 cannot be keyed (and would overflow i64 below).
                if c.abs() > 1.0e18 {
                    return Err(GridError::TooManyCells {
                        cells: f64::INFINITY,
                        cell_size,
                    });
                }
                let c = c.floor() as i64;
                lo[k] = lo[k].min(c);
                hi[k] = hi[k].max(c);
            }
        }
        // Pad by one cell on each side so neighbour offsets never leave the key range.
        let mut cells = 1.0f64;
        let mut stride = [0u64; D];
        let mut s: u128 = 1;
        for k in 0..D {
            if n == 0 {
                lo[k] = 0;
                hi[k] = 0;
            }
            lo[k] -= 1;
            let extent = (hi[k] + 1 - lo[k] + 1) as u128;
            cells *= extent as f64;
            stride[k] = s as u64;
            s = s.saturating_mul(extent);
        }
        if s > u128::from(u64::MAX) {
            return Err(GridError::TooManyCells { cells, cell_size });
        }
        self.origin = lo;
        self.stride = stride;
        self.pairs.clear();
        let mut pairs = std::mem::take(&mut self.pairs);
        pairs.par_extend(
            position
                .par_iter()
                .enumerate()
                .map(|(i, x)| (self.key_of(x), i as u32)),
        );
        self.pairs = pairs;
        radsort::sort_by_key(&mut self.pairs, |p| p.0);
        self.keys.clear();
        self.keys.par_extend(self.pairs.par_iter().map(|p| p.0));
        self.perm.clear();
        self.perm.par_extend(self.pairs.par_iter().map(|p| p.1));
        Ok(&self.perm)
    }

    /// Stage `sort_by_cell`, second half: builds the cell ranges and each cell's neighbour rows
    /// from the sorted keys. Call after the fields have been permuted.
    pub fn link(&mut self) {
        let n = self.keys.len();
        self.cell_keys.clear();
        self.cell_start.clear();
        self.cell_of.clear();
        self.cell_of.reserve(n);
        for (i, &k) in self.keys.iter().enumerate() {
            if self.cell_keys.last() != Some(&k) {
                self.cell_keys.push(k);
                self.cell_start.push(i as u32);
            }
            self.cell_of.push((self.cell_keys.len() - 1) as u32);
        }
        self.cell_start.push(n as u32);
        let r = rows_per_cell(D);
        let mut rows = std::mem::take(&mut self.rows);
        rows.clear();
        rows.resize(self.cell_keys.len() * r, (0, 0));
        rows.par_chunks_mut(r).enumerate().for_each(|(c, out)| {
            let key = self.cell_keys[c];
            for (row, slot) in out.iter_mut().enumerate() {
                // Offsets −1, 0, +1 on axes 1..D, enumerated by `row` in base 3.
                let mut base = key as i128;
                let mut t = row;
                for k in 1..D {
                    let off = (t % 3) as i128 - 1;
                    t /= 3;
                    base += off * self.stride[k] as i128;
                }
                *slot = self.particles_in_keys((base - 1) as u64, (base + 1) as u64);
            }
        });
        self.rows = rows;
    }

    /// Particle range of all cells with keys in `[lo, hi]` (contiguous in sorted order).
    fn particles_in_keys(&self, lo: u64, hi: u64) -> (u32, u32) {
        let a = self.cell_keys.partition_point(|&k| k < lo);
        let b = self.cell_keys.partition_point(|&k| k <= hi);
        (self.cell_start[a], self.cell_start[b])
    }

    #[inline]
    fn key_of(&self, x: &Vector<D>) -> u64 {
        let inv = 1.0 / f64::from(self.cell_size);
        let mut key = 0u64;
        for k in 0..D {
            let c = (f64::from(x[k]) * inv).floor() as i64 - self.origin[k];
            key += c as u64 * self.stride[k];
        }
        key
    }

    /// The particle ranges (in sorted order) that hold every neighbour of particle `i`.
    #[inline]
    pub fn neighbour_ranges(&self, i: usize) -> impl Iterator<Item = Range<usize>> + '_ {
        let r = rows_per_cell(D);
        let c = self.cell_of[i] as usize;
        self.rows[c * r..(c + 1) * r]
            .iter()
            .map(|&(a, b)| a as usize..b as usize)
    }

    /// Calls `f(j, x_i − x_j, |x_i − x_j|²)` for every particle `j` (including `i` itself) with
    /// `|x_i − x_j| < h`, where `h` is the cell size. `position` must be in sorted order. A pair
    /// `j ≠ i` closer than `COINCIDENT_FRACTION·h` gets the offset of
    /// [`crate::smoothing::pair_offset`] (a fixed antisymmetric direction, note 4).
    #[inline]
    pub fn for_each_neighbour<F>(&self, position: &[Vector<D>], i: usize, mut f: F)
    where
        F: FnMut(usize, Vector<D>, Real),
    {
        let xi = position[i];
        let h2 = self.cell_size * self.cell_size;
        for range in self.neighbour_ranges(i) {
            for (j, xj) in position[range.clone()].iter().enumerate() {
                let d = xi - xj;
                let r2 = d.norm_squared();
                if r2 < h2 {
                    let j = range.start + j;
                    let (d, r2) = pair_offset(d, r2, i, j, self.cell_size);
                    f(j, d, r2);
                }
            }
        }
    }
}

/// Brute-force reference: indices `j` with `|x_i − x_j| < h`, ascending. O(n) per query.
pub fn neighbours_naive<const D: usize>(position: &[Vector<D>], i: usize, h: Real) -> Vec<usize> {
    let xi = position[i];
    (0..position.len())
        .filter(|&j| (xi - position[j]).norm_squared() < h * h)
        .collect()
}
