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
use crate::math::{Real, Vector};
use crate::smoothing::Smoothing;
use rayon::prelude::*;

/// Lists of `T` per item: `start[k]..start[k + 1]` of `entries` is item `k`'s. Filled in two
/// parallel passes (count, then fill), each item in its own slice.
#[derive(Debug, Clone)]
struct Lists<T> {
    start: Vec<usize>,
    entries: Vec<T>,
}

impl<T> Default for Lists<T> {
    fn default() -> Self {
        Self {
            start: Vec::new(),
            entries: Vec::new(),
        }
    }
}

impl<T: Copy + Send + Sync> Lists<T> {
    /// `items` lists: `count(k)` entries for item `k`, written by `fill(k, slice)` (which
    /// writes exactly that many), `blank` until then.
    fn build(
        &mut self,
        items: usize,
        blank: T,
        count: impl Fn(usize) -> usize + Sync + Send,
        fill: impl Fn(usize, &mut [T]) + Sync,
    ) {
        self.start.clear();
        self.start.par_extend((0..items).into_par_iter().map(count));
        // Exclusive prefix sum, with the total appended.
        let mut total = 0usize;
        for s in &mut self.start {
            let c = *s;
            *s = total;
            total += c;
        }
        self.start.push(total);
        self.entries.clear();
        self.entries.resize(total, blank);
        let mut slices: Vec<&mut [T]> = Vec::with_capacity(items);
        let mut rest = self.entries.as_mut_slice();
        for w in self.start.windows(2) {
            let (head, tail) = rest.split_at_mut(w[1] - w[0]);
            slices.push(head);
            rest = tail;
        }
        slices.into_par_iter().enumerate().for_each(|(k, out)| {
            if !out.is_empty() {
                fill(k, out);
            }
        });
    }

    fn items(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    fn of(&self, k: usize) -> &[T] {
        &self.entries[self.start[k]..self.start[k + 1]]
    }

    fn clear(&mut self) {
        self.start.clear();
        self.entries.clear();
    }

    fn heap_bytes(&self) -> usize {
        self.start.capacity() * std::mem::size_of::<usize>()
            + self.entries.capacity() * std::mem::size_of::<T>()
    }
}

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
    /// Each particle's pairs in the grid's visiting order, its own left out.
    pairs: Lists<Pair<D>>,
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
        selected: impl Fn(usize) -> bool + Sync + Send,
    ) {
        let pairs = SpikyGradients::Grid(grid);
        let blank = Pair {
            index: 0,
            gradient: Vector::<D>::zeros(),
        };
        self.pairs.build(
            position.len(),
            blank,
            |i| {
                let mut count = 0usize;
                if selected(i) {
                    pairs.for_each(position, kernel, i, |_, _| count += 1);
                }
                count
            },
            |i, out| {
                let mut k = 0;
                pairs.for_each(position, kernel, i, |j, gradient| {
                    out[k] = Pair {
                        index: j as u32,
                        gradient,
                    };
                    k += 1;
                });
            },
        );
    }

    /// Number of particles the list was built for.
    pub fn len(&self) -> usize {
        self.pairs.items()
    }

    /// Whether the list was built for no particle.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Forgets the pairs (keeps the capacity).
    pub fn clear(&mut self) {
        self.pairs.clear();
    }

    /// Bytes held by the list's arrays.
    pub fn heap_bytes(&self) -> usize {
        self.pairs.heap_bytes()
    }

    /// Calls `f(j, ∇W_spiky(x_i − x_j))` for every listed neighbour `j ≠ i` of `i`, in the grid's
    /// order, with the gradient [`SpikyGradients::Grid`] gives at the positions it was built
    /// from.
    #[inline]
    pub fn for_each_gradient<F>(&self, i: usize, mut f: F)
    where
        F: FnMut(usize, Vector<D>),
    {
        for p in self.pairs.of(i) {
            f(p.index as usize, p.gradient);
        }
    }
}

/// The fluid neighbours of the wet solids at the velocity solve's fixed positions, each with
/// the grid's offset `x_w − x_j` [m] and the poly6 weight `W(r²)` (20) [1/m^D]: what the walls'
/// [A12] extrapolation (`boundary::wall_pressure`) sums every sweep. Bitwise what the grid's
/// loop gives (the grid's order, its fluid pairs only). `4 (D + 2)` bytes per pair.
#[derive(Debug, Default, Clone)]
pub struct WetSolidPairs<const D: usize> {
    pairs: Lists<FluidPair<D>>,
}

/// One fluid neighbour of a wet solid: its index, the offset [m] and the poly6 weight [1/m^D].
#[derive(Clone, Copy, Debug)]
struct FluidPair<const D: usize> {
    index: u32,
    offset: Vector<D>,
    weight: Real,
}

impl<const D: usize> WetSolidPairs<D> {
    /// Lists the fluid neighbours (`is_fluid(j)`) of each solid in `wet` (sorted indices) from
    /// `grid` (built from `position`), with their offsets and poly6 weights.
    pub fn build(
        &mut self,
        grid: &Grid<D>,
        kernel: &Smoothing<D>,
        position: &[Vector<D>],
        wet: &[u32],
        is_fluid: impl Fn(usize) -> bool + Sync + Send,
    ) {
        let blank = FluidPair {
            index: 0,
            offset: Vector::<D>::zeros(),
            weight: 0.0,
        };
        self.pairs.build(
            wet.len(),
            blank,
            |k| {
                let mut count = 0usize;
                grid.for_each_neighbour(position, wet[k] as usize, |j, _, _| {
                    count += usize::from(is_fluid(j));
                });
                count
            },
            |k, out| {
                let mut n = 0;
                grid.for_each_neighbour(position, wet[k] as usize, |j, offset, r2| {
                    if is_fluid(j) {
                        out[n] = FluidPair {
                            index: j as u32,
                            offset,
                            weight: kernel.w(r2),
                        };
                        n += 1;
                    }
                });
            },
        );
    }

    /// Whether the list holds no solid (outside a velocity solve).
    pub fn is_empty(&self) -> bool {
        self.pairs.items() == 0
    }

    /// Forgets the pairs (keeps the capacity).
    pub fn clear(&mut self) {
        self.pairs.clear();
    }

    /// Bytes held by the list's arrays.
    pub fn heap_bytes(&self) -> usize {
        self.pairs.heap_bytes()
    }

    /// Calls `f(j, x_w − x_j, W)` for every fluid neighbour `j` of the `k`-th wet solid, in the
    /// grid's order.
    #[inline]
    pub fn for_each_fluid<F>(&self, k: usize, mut f: F)
    where
        F: FnMut(usize, &Vector<D>, Real),
    {
        for p in self.pairs.of(k) {
            f(p.index as usize, &p.offset, p.weight);
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
