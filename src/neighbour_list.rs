//! A neighbour list for sweeps at fixed positions: the velocity solve (`solver::step`) runs
//! tens of sweeps (measured 22 per solve on the 2D sloshing tank, 71 on Yeh & Petroff) while
//! no particle moves, so the pairs within `h` are found once from the grid, each with the offset
//! and squared distance the grid computes for it, and then visited without the grid's candidate
//! test, the position gathers, the minimum image or the coincident-pair tie-break. In 3D the
//! grid's `3^D` cells of side `h` hold about 216 candidates per particle at `h = 2 dx`, of which
//! about 33 (the sphere's share, 15 %) lie within `h`; the candidate test takes about half of a
//! grid sweep's time (`perf`).
//!
//! The list keeps the grid's visiting order and stores the pair offset (minimum image included)
//! exactly as [`Grid::for_each_neighbour`] computes it, so a sweep over it gives bitwise the
//! same sums: the list changes the CPU backend's speed, not its results (the CUDA backend keeps
//! the grid). The velocity solve lists the fluid only: its loops over the wet solids (a few
//! layers along the wetted walls) take the grid. Memory: `4 (D + 1)` bytes per listed pair (index
//! and offset) plus 8 per particle, about 530 B per fluid particle in 3D at `h = 2 dx`, held by the backend (its
//! capacity is kept between solves); `scene::validate::memory` counts it.

use crate::grid::Grid;
use crate::math::{Real, Vector};
use rayon::prelude::*;

/// One listed pair: the neighbour's index (sorted order) and `x_i − x_j` [m] as the grid
/// passes it. Its squared length is recomputed from the offset by the grid's own operation
/// (`norm_squared`), bitwise what the grid passes, also for a coincident pair, whose offset
/// has one non-zero component (`smoothing::pair_offset`).
#[derive(Clone, Copy, Debug)]
struct Pair<const D: usize> {
    index: u32,
    offset: Vector<D>,
}

/// The pairs within `h` of selected particles, at the positions it was built from.
#[derive(Debug, Default, Clone)]
pub struct NeighbourList<const D: usize> {
    /// First entry of particle `i` in `pairs`; `len + 1` entries.
    start: Vec<usize>,
    /// Each particle's pairs in the grid's visiting order.
    pairs: Vec<Pair<D>>,
}

impl<const D: usize> NeighbourList<D> {
    /// Bytes one listed pair takes.
    pub const PAIR_BYTES: usize = std::mem::size_of::<Pair<D>>();

    /// Lists, for every particle `i` with `selected(i)`, the particles `j` (itself included)
    /// with `|x_i − x_j| < h` from `grid` (built from `position`); other particles get none.
    pub fn build(&mut self, grid: &Grid<D>, position: &[Vector<D>], selected: impl Fn(usize) -> bool + Sync) {
        let n = position.len();
        self.start.clear();
        self.start.par_extend((0..n).into_par_iter().map(|i| {
            let mut count = 0usize;
            if selected(i) {
                grid.for_each_neighbour(position, i, |_, _, _| count += 1);
            }
            count
        }));
        // Exclusive prefix sum, with the total appended.
        let mut total = 0usize;
        for s in &mut self.start {
            let c = *s;
            *s = total;
            total += c;
        }
        self.start.push(total);
        let blank = Pair {
            index: 0,
            offset: Vector::<D>::zeros(),
        };
        self.pairs.clear();
        self.pairs.resize(total, blank);
        // Each particle fills its own slice of `pairs`.
        let mut slices: Vec<&mut [Pair<D>]> = Vec::with_capacity(n);
        let mut rest = self.pairs.as_mut_slice();
        for w in self.start.windows(2) {
            let (head, tail) = rest.split_at_mut(w[1] - w[0]);
            slices.push(head);
            rest = tail;
        }
        slices.into_par_iter().enumerate().for_each(|(i, out)| {
            if out.is_empty() {
                return;
            }
            let mut k = 0;
            grid.for_each_neighbour(position, i, |j, offset, _| {
                out[k] = Pair {
                    index: j as u32,
                    offset,
                };
                k += 1;
            });
        });
    }

    /// Number of particles the list was built for.
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// Whether particle `i` was selected when the list was built (a selected particle lists at
    /// least itself).
    #[inline(always)]
    pub fn lists(&self, i: usize) -> bool {
        self.start[i + 1] > self.start[i]
    }

    /// Whether the list was built for no particle.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Forgets the pairs (keeps the capacity).
    pub fn clear(&mut self) {
        self.start.clear();
        self.pairs.clear();
    }

    /// Bytes held by the list's arrays.
    pub fn heap_bytes(&self) -> usize {
        self.start.capacity() * std::mem::size_of::<usize>() + self.pairs.capacity() * Self::PAIR_BYTES
    }

    /// Calls `f(j, x_i − x_j, |x_i − x_j|²)` for every listed neighbour of `i`, in the order
    /// and with the pair offsets of [`Grid::for_each_neighbour`] at the positions it was built
    /// from.
    #[inline]
    pub fn for_each_neighbour<F>(&self, i: usize, mut f: F)
    where
        F: FnMut(usize, Vector<D>, Real),
    {
        for p in &self.pairs[self.start[i]..self.start[i + 1]] {
            f(p.index as usize, p.offset, p.offset.norm_squared());
        }
    }
}

/// Where a loop finds a particle's neighbours: the grid, or a list built at the same positions.
#[derive(Clone, Copy)]
pub enum Neighbours<'a, const D: usize> {
    /// The cell grid (any positions the grid was linked for).
    Grid(&'a Grid<D>),
    /// A [`NeighbourList`] (fixed positions) for the particles it lists, the grid it was built
    /// from for the others.
    List(&'a NeighbourList<D>, &'a Grid<D>),
}

impl<const D: usize> Neighbours<'_, D> {
    /// [`Grid::for_each_neighbour`], or [`NeighbourList::for_each_neighbour`] where the list
    /// holds `i` (a listed particle has at least itself as a pair).
    #[inline(always)]
    pub fn for_each_neighbour<F>(&self, position: &[Vector<D>], i: usize, f: F)
    where
        F: FnMut(usize, Vector<D>, Real),
    {
        match self {
            Neighbours::Grid(g) => g.for_each_neighbour(position, i, f),
            Neighbours::List(l, g) => {
                if l.lists(i) {
                    l.for_each_neighbour(i, f)
                } else {
                    g.for_each_neighbour(position, i, f)
                }
            }
        }
    }
}
