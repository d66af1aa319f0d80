//! Each particle's neighbour candidates, listed once per sort (a Verlet list over the grid's
//! cells). Why: the grid's `3^D` cells of side `h` hold about 216 candidates per particle in 3D
//! at `h = 2 dx` (27 in 2D), of which about 33 (13) lie within `h`, and the CPU backend visits
//! the neighbours of every particle in several passes per sort (density, wall pressure, gradient
//! moment, forces, the correction's sweeps and lists). The list keeps the candidates within
//! `(1 + CANDIDATE_SKIN) h` at the sort's positions, in the cells' visiting order, so a pass that
//! tests `r < h` over the list visits exactly the pairs, in the same order, that it would find in
//! the cells while no two particles have drifted apart by more than `CANDIDATE_SKIN · h` since
//! the sort: the list changes the speed of a pass, not its sums.

use rayon::prelude::*;

/// Extra reach of the candidate lists beyond `h`, in units of `h`. It covers a drift of
/// `CANDIDATE_SKIN / 2 · h` of each particle of a pair since the sort; the solver re-sorts at
/// half of that (`solver::step::RESORT_DRIFT`), so rounding has a factor 2 of room.
pub const CANDIDATE_SKIN: f32 = 0.02;

/// Particles per block of the lists: each block is filled by one task in one walk over the
/// cells, without a counting pass.
const BLOCK: usize = 256;

/// The candidate lists of `len` particles, in blocks of [`BLOCK`] particles.
#[derive(Debug, Clone, Default)]
pub(super) struct Candidates {
    blocks: Vec<Block>,
}

/// The lists of one block: particle `k` of the block has `index[start[k]..start[k + 1]]`.
#[derive(Debug, Clone, Default)]
struct Block {
    start: Vec<u32>,
    index: Vec<u32>,
}

impl Candidates {
    /// Lists for particles `0..n`: `walk(i, out)` pushes particle `i`'s candidates onto `out`.
    /// Blocks keep their capacity between builds.
    pub(super) fn build(&mut self, n: usize, walk: impl Fn(usize, &mut Vec<u32>) + Sync) {
        self.blocks.resize_with(n.div_ceil(BLOCK), Block::default);
        self.blocks.par_iter_mut().enumerate().for_each(|(b, block)| {
            block.start.clear();
            block.index.clear();
            for i in b * BLOCK..((b + 1) * BLOCK).min(n) {
                block.start.push(block.index.len() as u32);
                walk(i, &mut block.index);
            }
            block.start.push(block.index.len() as u32);
        });
    }

    /// Particle `i`'s candidates (sorted indices), in the cells' visiting order.
    #[inline(always)]
    pub(super) fn of(&self, i: usize) -> &[u32] {
        let block = &self.blocks[i / BLOCK];
        let k = i % BLOCK;
        &block.index[block.start[k] as usize..block.start[k + 1] as usize]
    }

    /// Bytes held by the lists.
    pub(super) fn heap_bytes(&self) -> usize {
        self.blocks
            .iter()
            .map(|b| (b.start.capacity() + b.index.capacity()) * 4)
            .sum::<usize>()
            + self.blocks.capacity() * std::mem::size_of::<Block>()
    }
}
