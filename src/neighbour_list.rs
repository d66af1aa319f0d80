//! The velocity solve's pairs with their kernel gradients: the solve (`solver::step`) runs tens
//! of sweeps (measured 22 per solve on the 2D sloshing tank, 71 on Yeh & Petroff) while no
//! particle moves, and each sweep visits every fluid pair twice (the predicted density and the
//! pressure acceleration), both with the spiky gradient (21) of the pair. So the pairs within
//! `h` of each fluid particle are found once from the grid, each with its spiky gradient, and the
//! sweeps read the gradient instead of testing candidates, gathering positions, taking the
//! minimum image, the coincident-pair tie-break, a square root and a division per pair. In 3D
//! the grid's `3^D` cells of side `h` hold about 216 candidates per particle at `h = 2 dx`, of
//! which about 33 (the sphere's share, 15 %) lie within `h`.
//!
//! The list keeps the grid's visiting order and computes each gradient from the offset and
//! squared distance the grid passes, by the same operations the grid loops use
//! ([`SpikyGradients`]), so a sweep over it gives bitwise the same sums: the list changes the
//! CPU backend's speed, not its results (the CUDA backend keeps the grid). A particle's own pair
//! is left out (its gradient is zero and every loop skips it). Memory: `4 (D + 1)` bytes per
//! listed pair plus 8 per particle, about 530 B per fluid particle in 3D at `h = 2 dx`, held by
//! the backend (its capacity is kept between solves); `scene::validate::memory` counts it.

use crate::grid::Grid;
use crate::math::Vector;
use crate::smoothing::Smoothing;
use rayon::prelude::*;

/// One listed pair: the neighbour's index (sorted order) and the spiky gradient
/// `∇W_spiky(x_i − x_j)` [1/m^(D+1)] (`Smoothing::grad_w_spiky`, unscaled).
#[derive(Clone, Copy, Debug)]
struct Pair<const D: usize> {
    index: u32,
    gradient: Vector<D>,
}

/// The pairs within `h` of selected particles, with their spiky gradients, at the positions it
/// was built from.
#[derive(Debug, Default, Clone)]
pub struct NeighbourList<const D: usize> {
    /// First entry of particle `i` in `pairs`; `len + 1` entries.
    start: Vec<usize>,
    /// Each particle's pairs in the grid's visiting order, its own left out.
    pairs: Vec<Pair<D>>,
}

impl<const D: usize> NeighbourList<D> {
    /// Bytes one listed pair takes.
    pub const PAIR_BYTES: usize = std::mem::size_of::<Pair<D>>();

    /// Lists, for every particle `i` with `selected(i)`, the particles `j ≠ i` with
    /// `|x_i − x_j| < h` from `grid` (built from `position`, support `kernel.h`) and their spiky
    /// gradients; other particles get none.
    pub fn build(
        &mut self,
        grid: &Grid<D>,
        kernel: &Smoothing<D>,
        position: &[Vector<D>],
        selected: impl Fn(usize) -> bool + Sync,
    ) {
        let n = position.len();
        let pairs = SpikyGradients::Grid(grid);
        self.start.clear();
        self.start.par_extend((0..n).into_par_iter().map(|i| {
            let mut count = 0usize;
            if selected(i) {
                pairs.for_each(position, kernel, i, |_, _| count += 1);
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
            gradient: Vector::<D>::zeros(),
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
            pairs.for_each(position, kernel, i, |j, gradient| {
                out[k] = Pair {
                    index: j as u32,
                    gradient,
                };
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
        self.pairs.clear();
    }

    /// Bytes held by the list's arrays.
    pub fn heap_bytes(&self) -> usize {
        self.start.capacity() * std::mem::size_of::<usize>() + self.pairs.capacity() * Self::PAIR_BYTES
    }

    /// Calls `f(j, ∇W_spiky(x_i − x_j))` for every listed neighbour `j ≠ i` of `i`, in the grid's
    /// order, with the gradient [`SpikyGradients::Grid`] gives at the positions it was built
    /// from.
    #[inline]
    pub fn for_each_gradient<F>(&self, i: usize, mut f: F)
    where
        F: FnMut(usize, Vector<D>),
    {
        for p in &self.pairs[self.start[i]..self.start[i + 1]] {
            f(p.index as usize, p.gradient);
        }
    }
}

/// Where a loop finds a particle's neighbours `j ≠ i` and their spiky gradients (21): the grid
/// (any positions it was linked for), or a [`NeighbourList`] built at the same positions for the
/// particles it lists.
#[derive(Clone, Copy)]
pub enum SpikyGradients<'a, const D: usize> {
    /// The cell grid: the gradient computed from the grid's offset and squared distance.
    Grid(&'a Grid<D>),
    /// The list's stored gradients.
    List(&'a NeighbourList<D>),
}

impl<const D: usize> SpikyGradients<'_, D> {
    /// Calls `f(j, ∇W_spiky(x_i − x_j))` for every neighbour `j ≠ i` of `i` within `h`, in the
    /// grid's order; bitwise the same gradients from the grid and from a list built from it.
    #[inline(always)]
    pub fn for_each<F>(&self, position: &[Vector<D>], kernel: &Smoothing<D>, i: usize, mut f: F)
    where
        F: FnMut(usize, Vector<D>),
    {
        match self {
            SpikyGradients::Grid(g) => g.for_each_neighbour(position, i, |j, d, r2| {
                if j != i {
                    f(j, kernel.grad_w_spiky(&d, r2.sqrt()));
                }
            }),
            SpikyGradients::List(l) => l.for_each_gradient(i, f),
        }
    }
}
