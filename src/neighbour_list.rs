//! A neighbour list for sweeps at fixed positions: the velocity solve (`solver::step`) runs
//! tens of sweeps (measured 22 per solve on the 2D sloshing tank, 71 on Yeh & Petroff) while
//! no particle moves, so the pairs within `h` are found once from the grid and then visited
//! without the grid's candidate test. In 3D the grid's `3^D` cells of side `h` hold about 216
//! candidates per particle at `h = 2 dx`, of which about 33 (the sphere's share, 15 %) lie
//! within `h`; the candidate test takes about half of a grid sweep's time (`perf`).
//!
//! The list keeps the grid's visiting order and recomputes the pair offset (minimum image
//! included) exactly as
//! [`Grid::for_each_neighbour`] does, so a sweep over it gives bitwise the same sums: the
//! list changes the CPU backend's speed, not its results (the CUDA backend keeps the grid).
//! Memory: 4 bytes per listed pair plus 8 per particle, about 140 B per fluid particle in 3D
//! at `h = 2 dx`, held by the backend (its capacity is kept between solves).

use crate::grid::Grid;
use crate::math::{Real, Vector};
use crate::periodic::{Periodic, PeriodicAxes};
use crate::smoothing::pair_offset;
use rayon::prelude::*;

/// The pairs within `h` of selected particles, at the positions it was built from.
#[derive(Debug, Default, Clone)]
pub struct NeighbourList {
    cell_size: Real,
    /// The grid's periodic axes and the period along each [m] (3 entries, `D` used).
    periodic: (PeriodicAxes, [Real; 3]),
    /// First entry of particle `i` in `index`; `len + 1` entries.
    start: Vec<usize>,
    /// Neighbour indices (sorted order), each particle's in the grid's visiting order.
    index: Vec<u32>,
    /// The grid's particle ids (the coincident pairs' tie-break, `smoothing::pair_offset`).
    id: Vec<u32>,
}

impl NeighbourList {
    /// Lists, for every particle `i` with `selected(i)`, the particles `j` (itself included)
    /// with `|x_i − x_j| < h` from `grid` (built from `position`); other particles get none.
    pub fn build<const D: usize>(
        &mut self,
        grid: &Grid<D>,
        position: &[Vector<D>],
        selected: impl Fn(usize) -> bool + Sync,
    ) {
        let n = position.len();
        self.cell_size = grid.cell_size();
        self.id.clear();
        self.id.extend_from_slice(grid.ids());
        let p = grid.periodic();
        self.periodic = (
            p.axes,
            std::array::from_fn(|k| if k < D { p.length[k] } else { 0.0 }),
        );
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
        self.index.clear();
        self.index.resize(total, 0);
        // Each particle fills its own slice of `index`.
        let mut slices: Vec<&mut [u32]> = Vec::with_capacity(n);
        let mut rest = self.index.as_mut_slice();
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
            grid.for_each_neighbour(position, i, |j, _, _| {
                out[k] = j as u32;
                k += 1;
            });
        });
    }

    /// Number of particles the list was built for.
    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// Whether the list was built for no particle.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Forgets the pairs (keeps the capacity).
    pub fn clear(&mut self) {
        self.start.clear();
        self.index.clear();
    }

    /// Bytes held by the list's arrays.
    pub fn heap_bytes(&self) -> usize {
        self.start.capacity() * std::mem::size_of::<usize>()
            + self.index.capacity() * 4
            + self.id.capacity() * 4
    }

    /// Calls `f(j, x_i − x_j, |x_i − x_j|²)` for every listed neighbour of `i`, in the order
    /// and with the pair offsets of [`Grid::for_each_neighbour`] at the same positions.
    #[inline]
    pub fn for_each_neighbour<const D: usize, F>(&self, position: &[Vector<D>], i: usize, mut f: F)
    where
        F: FnMut(usize, Vector<D>, Real),
    {
        let xi = position[i];
        let (axes, length) = self.periodic;
        let periodic = Periodic::<D> {
            axes,
            length: Vector::<D>::from_fn(|k, _| length[k]),
            ..Periodic::none()
        };
        for &j in &self.index[self.start[i]..self.start[i + 1]] {
            let j = j as usize;
            let d = periodic.minimum_image(xi - position[j]);
            let (d, r2) = pair_offset(d, d.norm_squared(), self.id[i], self.id[j], self.cell_size);
            f(j, d, r2);
        }
    }
}

/// Where a loop finds a particle's neighbours: the grid, or a list built at the same positions.
#[derive(Clone, Copy)]
pub enum Neighbours<'a, const D: usize> {
    /// The cell grid (any positions the grid was linked for).
    Grid(&'a Grid<D>),
    /// A [`NeighbourList`] (fixed positions).
    List(&'a NeighbourList),
}

impl<const D: usize> Neighbours<'_, D> {
    /// [`Grid::for_each_neighbour`] or [`NeighbourList::for_each_neighbour`].
    #[inline(always)]
    pub fn for_each_neighbour<F>(&self, position: &[Vector<D>], i: usize, f: F)
    where
        F: FnMut(usize, Vector<D>, Real),
    {
        match self {
            Neighbours::Grid(g) => g.for_each_neighbour(position, i, f),
            Neighbours::List(l) => l.for_each_neighbour(position, i, f),
        }
    }
}
