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

//!
//! Periodic axes (`crate::periodic`): along a periodic axis of period `L` the cell coordinate is
//! taken modulo `n = ⌊L/h⌋ ≥ 3` cells of size `L/n ≥ h`, with no padding. The rows of three
//! cells then break at the seam, so a periodic grid stores each cell's `3^D` neighbour cells as
//! single ranges (in the same order: axis 0 fastest), and every candidate's offset goes
//! through [`Periodic::minimum_image`].
//!
//! After the cells, [`Grid::link`] lists each particle's candidates within
//! `(1 + CANDIDATE_SKIN) h` once (`candidates`), and [`Grid::for_each_neighbour`] visits that
//! list: the same pairs in the same order as the cells while particles drift less than
//! `CANDIDATE_SKIN / 2 · h` since the sort, at a sixth of the candidates in 3D. Why: the CPU
//! backend visits every particle's neighbours in several passes per sort (density, wall
//! pressure, gradient moment, forces, the correction's sweeps and the velocity solve's lists),
//! and the cells' `3^D` candidates hold about 216 particles in 3D at `h = 2 dx` (36 in 2D), of
//! which about 33 (13) lie within `h`.
use crate::block_lists::BlockLists;
use crate::math::{Real, Vector};
use crate::periodic::Periodic;
use crate::smoothing::pair_offset;
use rayon::prelude::*;
use std::ops::Range;

/// Extra reach of the candidate lists beyond `h`, in units of `h`. It covers a drift of
/// `CANDIDATE_SKIN / 2 · h` of each particle of a pair since the sort; the solver re-sorts at
/// half of that (`solver::step::RESORT_DRIFT`), so rounding has a factor 2 of room.
pub const CANDIDATE_SKIN: Real = 0.02;

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
    /// A periodic axis shorter than three cells of size `h` (the wrapped neighbour cells would
    /// repeat; scene validation refuses such a domain).
    #[error("the period {length} m along axis {axis} holds fewer than 3 cells of size {cell_size} m")]
    PeriodTooShort {
        /// Axis index.
        axis: usize,
        /// Period [m].
        length: Real,
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
    /// Every particle's id (`Fields::id`) in sorted order, given to [`Grid::link`]: the
    /// coincident pairs' tie-break (`smoothing::pair_offset`).
    id: Vec<u32>,
    /// The periodic axes of the last sort.
    periodic: Periodic<D>,
    /// Cells along each axis: the padded bounding box, or the `n` cells of a periodic axis.
    extent: [i64; D],
    /// Inverse cell size per axis [1/m]: `1/h`, or `n/L` along a periodic axis.
    inv_cell: [f64; D],
    /// Ranges per cell in `rows`: `3^(D−1)` rows, or `3^D` single cells with periodic axes.
    rows_per_cell: usize,
    /// Each particle's candidates within `(1 + CANDIDATE_SKIN) h` at the positions given to
    /// [`Grid::link`], in the cells' order.
    candidates: BlockLists<u32>,
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
            id: Vec::new(),
            periodic: Periodic::none(),
            extent: [0; D],
            inv_cell: [1.0; D],
            rows_per_cell: rows_per_cell(D),
            candidates: BlockLists::default(),
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
            + self.id.capacity() * 4
            + self.candidates.heap_bytes()
    }

    /// Stage `sort_by_cell`, first half: hashes `position` to cells of size `cell_size` [m] and
    /// radix-sorts by key. Returns the permutation `perm` (new index → old index) that the caller
    /// must apply to every particle field (see `Fields::permute`) before calling [`Grid::link`].
    pub fn sort(&mut self, position: &[Vector<D>], cell_size: Real) -> Result<&[u32], GridError> {
        self.sort_periodic(position, cell_size, &Periodic::none())
    }

    /// [`Grid::sort`] with the `periodic` axes wrapped (module docs): the pair offsets of
    /// [`Grid::for_each_neighbour`] are then minimum images.
    pub fn sort_periodic(
        &mut self,
        position: &[Vector<D>],
        cell_size: Real,
        periodic: &Periodic<D>,
    ) -> Result<&[u32], GridError> {
        let n = position.len();
        if u32::try_from(n).is_err() {
            return Err(GridError::TooManyParticles(n));
        }
        self.cell_size = cell_size;
        self.periodic = *periodic;
        self.rows_per_cell = if periodic.axes.is_empty() {
            rows_per_cell(D)
        } else {
            3 * rows_per_cell(D)
        };
        let inv = 1.0 / f64::from(cell_size);
        for k in 0..D {
            self.inv_cell[k] = inv;
            if periodic.axes.contains(k) {
                let cells = periodic.cells(k, cell_size);
                if cells < 3 {
                    return Err(GridError::PeriodTooShort {
                        axis: k,
                        length: periodic.length[k],
                        cell_size,
                    });
                }
                self.extent[k] = cells as i64;
                self.inv_cell[k] = cells as f64 / f64::from(periodic.length[k]);
            }
        }
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
            let extent = if periodic.axes.contains(k) {
                // Coordinates modulo the period's cells, unpadded.
                lo[k] = 0;
                self.extent[k] as u128
            } else {
                (hi[k] + 1 - lo[k] + 1) as u128
            };
            self.extent[k] = extent as i64;
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
    /// from the sorted keys, keeps the particles' ids `id` (sorted order, one per particle;
    /// the tie-break of coincident pairs), and lists each particle's candidates from the sorted
    /// `position` (module docs). Call after the fields have been permuted.
    ///
    /// # Panics
    /// When `id` or `position` does not hold one entry per sorted particle.
    pub fn link(&mut self, id: &[u32], position: &[Vector<D>]) {
        let n = self.keys.len();
        assert_eq!(id.len(), n, "Grid::link needs one id per sorted particle");
        assert_eq!(
            position.len(),
            n,
            "Grid::link needs one position per sorted particle"
        );
        self.id.clear();
        self.id.extend_from_slice(id);
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
        let r = self.rows_per_cell;
        let mut rows = std::mem::take(&mut self.rows);
        rows.clear();
        rows.resize(self.cell_keys.len() * r, (0, 0));
        if self.periodic.axes.is_empty() {
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
        } else {
            rows.par_chunks_mut(r).enumerate().for_each(|(c, out)| {
                self.link_periodic(self.cell_keys[c], out);
            });
        }
        self.rows = rows;
        self.list_candidates(position);
    }

    /// Fills `candidates` from the cells' ranges at the sorted `position`.
    fn list_candidates(&mut self, position: &[Vector<D>]) {
        let reach = self.cell_size * (1.0 + CANDIDATE_SKIN);
        let reach2 = reach * reach;
        let mut candidates = std::mem::take(&mut self.candidates);
        candidates.build(position.len(), |i, out| {
            let xi = position[i];
            for range in self.neighbour_ranges(i) {
                for (j, xj) in position[range.clone()].iter().enumerate() {
                    if self.periodic.minimum_image(xi - xj).norm_squared() < reach2 {
                        out.push((range.start + j) as u32);
                    }
                }
            }
        });
        self.candidates = candidates;
    }

    /// The `3^D` neighbour cells of the cell `key` of a periodic grid, one range each, axis 0
    /// fastest: offsets −1, 0, +1 per axis, wrapped modulo the period's cells along periodic
    /// axes (the other axes are padded, so their offsets stay inside).
    fn link_periodic(&self, key: u64, out: &mut [(u32, u32)]) {
        let mut cell = [0i64; D];
        for k in 0..D {
            cell[k] = (key / self.stride[k]) as i64 % self.extent[k];
        }
        for (t, slot) in out.iter_mut().enumerate() {
            let mut neighbour = 0u64;
            let mut rest = t;
            for k in 0..D {
                let mut c = cell[k] + (rest % 3) as i64 - 1;
                rest /= 3;
                if self.periodic.axes.contains(k) {
                    c = c.rem_euclid(self.extent[k]);
                }
                neighbour += c as u64 * self.stride[k];
            }
            *slot = self.particles_in_keys(neighbour, neighbour);
        }
    }

    /// Particle range of all cells with keys in `[lo, hi]` (contiguous in sorted order).
    fn particles_in_keys(&self, lo: u64, hi: u64) -> (u32, u32) {
        let a = self.cell_keys.partition_point(|&k| k < lo);
        let b = self.cell_keys.partition_point(|&k| k <= hi);
        (self.cell_start[a], self.cell_start[b])
    }

    #[inline]
    fn key_of(&self, x: &Vector<D>) -> u64 {
        let mut key = 0u64;
        for k in 0..D {
            let c = if self.periodic.axes.contains(k) {
                let from_min = f64::from(x[k]) - f64::from(self.periodic.min[k]);
                ((from_min * self.inv_cell[k]).floor() as i64).rem_euclid(self.extent[k])
            } else {
                (f64::from(x[k]) * self.inv_cell[k]).floor() as i64 - self.origin[k]
            };
            key += c as u64 * self.stride[k];
        }
        key
    }

    /// The particle ranges (in sorted order) that hold every neighbour of particle `i`.
    #[inline]
    pub fn neighbour_ranges(&self, i: usize) -> impl Iterator<Item = Range<usize>> + '_ {
        let r = self.rows_per_cell;
        let c = self.cell_of[i] as usize;
        self.rows[c * r..(c + 1) * r]
            .iter()
            .map(|&(a, b)| a as usize..b as usize)
    }

    /// The periodic axes of the last sort.
    pub fn periodic(&self) -> &Periodic<D> {
        &self.periodic
    }

    /// The particles' ids in sorted order, as given to [`Grid::link`].
    pub fn ids(&self) -> &[u32] {
        &self.id
    }

    /// Calls `f(j, x_i − x_j, |x_i − x_j|²)` for every particle `j` (including `i` itself) with
    /// `|x_i − x_j| < h`, where `h` is the cell size (`x_i − x_j` the minimum image along
    /// periodic axes), in the order of the cells' ranges (`Grid::neighbour_ranges`). `position`
    /// must be in sorted order, each particle within `CANDIDATE_SKIN / 2 · h` of where
    /// [`Grid::link`] saw it: the pairs come from its candidate lists. A pair
    /// `j ≠ i` closer than `COINCIDENT_FRACTION·h` gets the offset of
    /// [`crate::smoothing::pair_offset`] (a fixed antisymmetric direction from the ids given to
    /// [`Grid::link`], note 4).
    #[inline]
    pub fn for_each_neighbour<F>(&self, position: &[Vector<D>], i: usize, mut f: F)
    where
        F: FnMut(usize, Vector<D>, Real),
    {
        let xi = position[i];
        let h2 = self.cell_size * self.cell_size;
        for &j in self.candidates.of(i) {
            let j = j as usize;
            let d = self.periodic.minimum_image(xi - position[j]);
            let r2 = d.norm_squared();
            if r2 < h2 {
                let (d, r2) = pair_offset(d, r2, self.id[i], self.id[j], self.cell_size);
                f(j, d, r2);
            }
        }
    }
}

/// Brute-force reference with periodic axes: indices `j` with `|minimum image of x_i − x_j| <
/// h`, ascending. O(n) per query.
pub fn neighbours_naive_periodic<const D: usize>(
    position: &[Vector<D>],
    i: usize,
    h: Real,
    periodic: &Periodic<D>,
) -> Vec<usize> {
    let xi = position[i];
    (0..position.len())
        .filter(|&j| periodic.minimum_image(xi - position[j]).norm_squared() < h * h)
        .collect()
}

/// Brute-force reference: indices `j` with `|x_i − x_j| < h`, ascending. O(n) per query.
pub fn neighbours_naive<const D: usize>(position: &[Vector<D>], i: usize, h: Real) -> Vec<usize> {
    let xi = position[i];
    (0..position.len())
        .filter(|&j| (xi - position[j]).norm_squared() < h * h)
        .collect()
}
