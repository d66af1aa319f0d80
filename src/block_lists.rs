//! Variable-length lists of `T` per item, filled in one parallel walk: items are taken in blocks
//! of [`BLOCK`], and each block's task pushes its items' entries onto vectors of its own, so no
//! counting pass comes first. The neighbour search's candidate lists (`crate::grid`) and the
//! velocity solve's pair lists (`crate::neighbour_list`) are built so, once per sort or solve,
//! and read many times. The blocks keep their capacity between builds.

use rayon::prelude::*;

/// Items per block: enough work per task to hide its cost, few enough blocks per thread to
/// balance the load at a few thousand items.
const BLOCK: usize = 256;

/// The lists of `len` items.
#[derive(Debug, Clone)]
pub(crate) struct BlockLists<T> {
    blocks: Vec<Block<T>>,
    len: usize,
}

/// The lists of one block: its item `k` has `entries[start[k]..start[k + 1]]`.
#[derive(Debug, Clone)]
struct Block<T> {
    start: Vec<u32>,
    entries: Vec<T>,
}

impl<T> Default for Block<T> {
    fn default() -> Self {
        Self {
            start: Vec::new(),
            entries: Vec::new(),
        }
    }
}

impl<T> Default for BlockLists<T> {
    fn default() -> Self {
        Self {
            blocks: Vec::new(),
            len: 0,
        }
    }
}

impl<T: Send + Sync> BlockLists<T> {
    /// Lists for items `0..items`: `walk(k, out)` pushes item `k`'s entries onto `out`.
    ///
    /// # Panics
    /// When one block holds `u32::MAX` entries or more.
    pub(crate) fn build(&mut self, items: usize, walk: impl Fn(usize, &mut Vec<T>) + Sync) {
        self.blocks.resize_with(items.div_ceil(BLOCK), Block::default);
        self.blocks.par_iter_mut().enumerate().for_each(|(b, block)| {
            block.start.clear();
            block.entries.clear();
            for k in b * BLOCK..((b + 1) * BLOCK).min(items) {
                block.start.push(offset(block.entries.len()));
                walk(k, &mut block.entries);
            }
            block.start.push(offset(block.entries.len()));
        });
        self.len = items;
    }

    /// Item `k`'s entries, in the order `walk` pushed them.
    #[inline(always)]
    pub(crate) fn of(&self, k: usize) -> &[T] {
        let block = &self.blocks[k / BLOCK];
        let k = k % BLOCK;
        &block.entries[block.start[k] as usize..block.start[k + 1] as usize]
    }

    /// Number of items listed by the last build.
    pub(crate) fn items(&self) -> usize {
        self.len
    }

    /// Forgets the entries (keeps the capacity).
    pub(crate) fn clear(&mut self) {
        for block in &mut self.blocks {
            block.start.clear();
            block.entries.clear();
        }
        self.len = 0;
    }

    /// Bytes held by the lists.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.blocks
            .iter()
            .map(|b| b.start.capacity() * 4 + b.entries.capacity() * std::mem::size_of::<T>())
            .sum::<usize>()
            + self.blocks.capacity() * std::mem::size_of::<Block<T>>()
    }
}

/// An entry offset within a block.
fn offset(n: usize) -> u32 {
    u32::try_from(n).expect("a block of 256 items holds fewer than 2^32 entries")
}
