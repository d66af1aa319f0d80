//! The velocity solve's pairs with their kernel gradients: the solve (`solver::step`) runs tens
//! of sweeps (measured 22 per solve on the 2D sloshing tank, 71 on Yeh & Petroff) while no
//! particle moves, and each sweep visits every fluid pair twice (the predicted density and the
//! pressure acceleration), both with the spiky gradient (21) of the pair. So the pairs within
//! `h` of each fluid particle are found once from the grid, each with its spiky gradient, and the
//! sweeps read the gradient instead of testing candidates, gathering positions, taking the
//! minimum image, the coincident-pair tie-break, a square root and a division per pair (in 3D
//! the grid lists about 36 candidates per particle at `h = 2 dx`, of which about 33 lie within
//! `h`). Filled in one walk per block of particles (`crate::block_lists`).
//!
//! The list keeps the grid's visiting order and computes each gradient from the offset and
//! squared distance the grid passes, by the same operations the grid loops use
//! ([`SpikyGradients`]), so a sweep over it gives bitwise the same sums: the list changes the
//! CPU backend's speed, not its results (the CUDA backend keeps the grid). A particle's own pair
//! is left out (its gradient is zero and every loop skips it). Memory: `4 (D + 1)` bytes per
//! listed pair plus 4 per particle, about 530 B per fluid particle in 3D at `h = 2 dx`, held by
//! the backend (its capacity is kept between solves); `scene::validate::memory` counts it.

use crate::block_lists::BlockLists;
use crate::grid::Grid;
use crate::math::{Real, Vector};
use crate::smoothing::Smoothing;

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
    pairs: BlockLists<Pair<D>>,
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
        let pairs = SpikyGradients::Grid(grid);
        self.pairs.build(position.len(), |i, out| {
            if selected(i) {
                pairs.for_each(position, kernel, i, |j, gradient| {
                    out.push(Pair {
                        index: j as u32,
                        gradient,
                    });
                });
            }
        });
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
    pairs: BlockLists<FluidPair<D>>,
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
        is_fluid: impl Fn(usize) -> bool + Sync,
    ) {
        self.pairs.build(wet.len(), |k, out| {
            grid.for_each_neighbour(position, wet[k] as usize, |j, offset, r2| {
                if is_fluid(j) {
                    out.push(FluidPair {
                        index: j as u32,
                        offset,
                        weight: kernel.w(r2),
                    });
                }
            });
        });
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
