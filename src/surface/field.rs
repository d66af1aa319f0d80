//! Eq. (25) on a sparse Eulerian grid: `F(x_g) = sqrt( Σ_j (1 − r_gj/h)² )` over particles within
//! `h` of node `x_g`.
//!
//! Nodes sit at `x_g = g · c` for integer `g` and node spacing `c` [m]. They are grouped into
//! cubic blocks of `B^D` nodes; a block exists only when it holds a node within `h + c` of a
//! particle, so memory and work grow with the particle count, not with the empty domain.
//! Particles are binned by the same blocks (hashed by block coordinates after a sort), so a
//! block's nodes receive contributions only from the particles of the blocks within
//! `reach = ⌈h / (B c)⌉`. Each node is owned by exactly one block and computed once, so the
//! marching stage sees one value per node however it walks the blocks (no cracks from rounding).
//!
//! The solver's [`crate::grid::Grid`] is not reused: it answers "neighbours of particle i" in its
//! own sorted order, while this field needs "particles near grid node g" and "particles near an
//! arbitrary point" (for the normals).

use crate::math::{Real, Vector};
use rayon::prelude::*;
use std::collections::HashMap;
use std::ops::Range;

use super::SurfaceError;

/// Coordinates beyond this many cells from the origin are refused (i64 node indices, with room
/// for the block arithmetic).
const MAX_CELLS: f64 = 1.0e15;

/// Eq. (25) sampled on the nodes of the blocks near the particles.
#[derive(Debug, Clone)]
pub struct SparseField<const D: usize> {
    /// Node spacing c [m].
    cell_size: f64,
    /// Kernel support h [m].
    smoothing_length: f64,
    /// Nodes per block and axis (B).
    block: i64,
    /// Particle bins within which a block's contributors lie, per axis.
    reach: i64,
    /// Particle positions [m], grouped by bin.
    particles: Vec<[f64; D]>,
    /// Range of `particles` of each occupied bin (bins are blocks).
    bins: HashMap<[i64; D], Range<usize>>,
    /// Keys of the blocks, ascending.
    blocks: Vec<[i64; D]>,
    /// Index of each block in `blocks`.
    block_index: HashMap<[i64; D], usize>,
    /// F at every node of every block, block after block, x fastest within a block.
    values: Vec<Real>,
}

/// Calls `f(index)` for every integer point of the box `lo..=hi` (x fastest).
pub(crate) fn for_each_in_box<const D: usize>(lo: [i64; D], hi: [i64; D], mut f: impl FnMut([i64; D])) {
    if (0..D).any(|k| lo[k] > hi[k]) {
        return;
    }
    let mut p = lo;
    loop {
        f(p);
        let mut k = 0;
        loop {
            if k == D {
                return;
            }
            p[k] += 1;
            if p[k] <= hi[k] {
                break;
            }
            p[k] = lo[k];
            k += 1;
        }
    }
}

impl<const D: usize> SparseField<D> {
    /// Bins the particles at `positions` [m] and evaluates eq. (25) with support
    /// `smoothing_length` [m] on every node, spacing `cell_size` [m], of the blocks near them.
    /// Both lengths must be positive and finite (see [`super::SurfaceParams::validate`]).
    pub fn build(
        positions: &[Vector<D>],
        smoothing_length: f64,
        cell_size: f64,
    ) -> Result<Self, SurfaceError> {
        let c = cell_size;
        let h = smoothing_length;
        // A block at least h wide keeps the reach at one bin for the default parameters.
        let block = ((h / c).ceil() as i64).clamp(4, 32);
        let reach = (h / (block as f64 * c)).ceil() as i64;
        let block_len = block as f64 * c;

        let mut keyed = Vec::with_capacity(positions.len());
        for (i, x) in positions.iter().enumerate() {
            let mut p = [0.0f64; D];
            let mut key = [0i64; D];
            for k in 0..D {
                p[k] = f64::from(x[k]);
                if !p[k].is_finite() {
                    return Err(SurfaceError::NonFinitePosition { particle: i });
                }
                let cells = (p[k] / c).abs();
                if cells > MAX_CELLS {
                    return Err(SurfaceError::OutOfRange { particle: i, cells });
                }
                key[k] = (p[k] / block_len).floor() as i64;
            }
            keyed.push((key, i, p));
        }
        // Sorting by (bin, index) makes every sum below run in one fixed order.
        keyed.par_sort_unstable_by(|a, b| (a.0, a.1).cmp(&(b.0, b.1)));
        let mut bins = HashMap::new();
        let mut start = 0;
        for i in 1..=keyed.len() {
            if i == keyed.len() || keyed[i].0 != keyed[start].0 {
                bins.insert(keyed[start].0, start..i);
                start = i;
            }
        }
        let particles: Vec<[f64; D]> = keyed.iter().map(|e| e.2).collect();

        // Blocks holding a node within h of a bin's particles, padded by one node below so that
        // every grid cell with a non-zero corner has its lower corner in a block.
        let mut blocks: Vec<[i64; D]> = bins
            .keys()
            .collect::<Vec<_>>()
            .par_iter()
            .flat_map_iter(|bin| {
                let mut lo = [0i64; D];
                let mut hi = [0i64; D];
                for k in 0..D {
                    let first = ((bin[k] as f64 * block_len - h) / c).floor() as i64 - 1;
                    let last = (((bin[k] + 1) as f64 * block_len + h) / c).ceil() as i64;
                    lo[k] = first.div_euclid(block);
                    hi[k] = last.div_euclid(block);
                }
                let mut out = Vec::new();
                for_each_in_box(lo, hi, |b| out.push(b));
                out
            })
            .collect();
        blocks.par_sort_unstable();
        blocks.dedup();
        let block_index = blocks.iter().enumerate().map(|(i, &b)| (b, i)).collect();

        let mut field = SparseField {
            cell_size: c,
            smoothing_length: h,
            block,
            reach,
            particles,
            bins,
            blocks,
            block_index,
            values: Vec::new(),
        };
        let per_block = field.nodes_per_block();
        let mut values = vec![0.0 as Real; field.blocks.len() * per_block];
        values
            .par_chunks_mut(per_block.max(1))
            .zip(field.blocks.par_iter())
            .for_each(|(out, key)| field.fill_block(*key, out));
        field.values = values;
        Ok(field)
    }

    /// Nodes per block, `B^D`.
    pub fn nodes_per_block(&self) -> usize {
        (self.block as usize).pow(D as u32)
    }

    /// Nodes per block and axis (B).
    pub fn block_size(&self) -> i64 {
        self.block
    }

    /// Node spacing c [m].
    pub fn cell_size(&self) -> f64 {
        self.cell_size
    }

    /// Keys of the blocks, ascending; block `b` holds nodes `b·B ..= b·B + B − 1` on each axis.
    pub fn blocks(&self) -> &[[i64; D]] {
        &self.blocks
    }

    /// Number of nodes evaluated (a measure of the work done).
    pub fn node_count(&self) -> usize {
        self.values.len()
    }

    /// Position of node `g` [m]: `g · c`.
    pub fn node_position(&self, g: [i64; D]) -> [f64; D] {
        g.map(|i| i as f64 * self.cell_size)
    }

    /// Eq. (25) at node `g` (dimensionless); 0 for nodes outside every block, which are farther
    /// than `h` from every particle.
    pub fn value(&self, g: [i64; D]) -> Real {
        let key = g.map(|i| i.div_euclid(self.block));
        match self.block_index.get(&key) {
            Some(&b) => self.values[b * self.nodes_per_block() + self.local_index(g)],
            None => 0.0,
        }
    }

    /// F at the nodes `b·B ..= b·B + B` of block `block` (its own nodes plus the first layer of
    /// the next blocks, `(B+1)^D` values, x fastest): the corners of every cell whose lower
    /// corner the block owns.
    pub(crate) fn block_with_upper_layer(&self, block: usize) -> Vec<Real> {
        let b = self.block;
        let lo = self.blocks[block].map(|k| k * b);
        let own = &self.values[block * self.nodes_per_block()..(block + 1) * self.nodes_per_block()];
        let mut out = Vec::with_capacity((b as usize + 1).pow(D as u32));
        for_each_in_box([0; D], [b; D], |l| {
            if l.iter().all(|&i| i < b) {
                let mut index = 0usize;
                for k in (0..D).rev() {
                    index = index * b as usize + l[k] as usize;
                }
                out.push(own[index]);
            } else {
                out.push(self.value(std::array::from_fn(|k| lo[k] + l[k])));
            }
        });
        out
    }

    /// Index of node `g` within its block (x fastest).
    fn local_index(&self, g: [i64; D]) -> usize {
        let mut index = 0usize;
        for k in (0..D).rev() {
            index = index * self.block as usize + g[k].rem_euclid(self.block) as usize;
        }
        index
    }

    /// Eq. (25) at every node of block `key`, written into `out` (x fastest).
    fn fill_block(&self, key: [i64; D], out: &mut [Real]) {
        let (c, h) = (self.cell_size, self.smoothing_length);
        let lo = key.map(|k| k * self.block);
        let hi = lo.map(|l| l + self.block - 1);
        // Sums of (1 − r/h)² in f64; the square root is taken once per node at the end.
        let mut sum = vec![0.0f64; out.len()];
        let b = self.block as usize;
        for_each_in_box(key.map(|k| k - self.reach), key.map(|k| k + self.reach), |bin| {
            let Some(range) = self.bins.get(&bin) else { return };
            for p in &self.particles[range.clone()] {
                let mut a = [0i64; D];
                let mut z = [0i64; D];
                for k in 0..D {
                    a[k] = ((p[k] - h) / c).ceil().max(lo[k] as f64) as i64;
                    z[k] = ((p[k] + h) / c).floor().min(hi[k] as f64) as i64;
                }
                for_each_in_box(a, z, |g| {
                    let mut r2 = 0.0;
                    let mut index = 0usize;
                    for k in (0..D).rev() {
                        let d = g[k] as f64 * c - p[k];
                        r2 += d * d;
                        index = index * b + (g[k] - lo[k]) as usize;
                    }
                    if r2 < h * h {
                        let w = 1.0 - r2.sqrt() / h;
                        sum[index] += w * w;
                    }
                });
            }
        });
        for (o, s) in out.iter_mut().zip(sum) {
            *o = s.sqrt() as Real;
        }
    }

    /// Gradient of F² at `x` [m] (units 1/m): `∇F² = −(2/h) Σ_j (1 − r/h) (x − x_j)/r` over
    /// particles with `0 < r < h`. The outward normal of the surface is `−∇F²/|∇F²|`.
    pub fn gradient_squared(&self, x: [f64; D]) -> [f64; D] {
        let h = self.smoothing_length;
        let block_len = self.block as f64 * self.cell_size;
        let home = x.map(|v| (v / block_len).floor() as i64);
        let mut grad = [0.0f64; D];
        for_each_in_box(
            home.map(|k| k - self.reach),
            home.map(|k| k + self.reach),
            |bin| {
                let Some(range) = self.bins.get(&bin) else { return };
                for p in &self.particles[range.clone()] {
                    let mut d = [0.0f64; D];
                    let mut r2 = 0.0;
                    for k in 0..D {
                        d[k] = x[k] - p[k];
                        r2 += d[k] * d[k];
                    }
                    // A particle exactly at x has no direction; its term is zero by symmetry.
                    if r2 < h * h && r2 > 0.0 {
                        let r = r2.sqrt();
                        let s = -2.0 / h * (1.0 - r / h) / r;
                        for k in 0..D {
                            grad[k] += s * d[k];
                        }
                    }
                }
            },
        );
        grad
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Eq. (25) by brute force over all particles.
    fn value_naive<const D: usize>(positions: &[Vector<D>], x: [f64; D], h: f64) -> f64 {
        positions
            .iter()
            .map(|p| {
                let r2: f64 = (0..D).map(|k| (x[k] - f64::from(p[k])).powi(2)).sum();
                if r2 < h * h {
                    (1.0 - r2.sqrt() / h).powi(2)
                } else {
                    0.0
                }
            })
            .sum::<f64>()
            .sqrt()
    }

    fn scattered_3d() -> Vec<Vector<3>> {
        // A deterministic scatter (golden-ratio sequence) over a 0.3 m cube straddling the origin.
        (0..400)
            .map(|i| {
                let f = |a: f64| ((i as f64 * a).fract() - 0.5) as Real * 0.3;
                Vector::<3>::new(f(0.618_034), f(0.754_877), f(0.569_840))
            })
            .collect()
    }

    #[test]
    fn sparse_field_equals_brute_force_sum_at_every_node() {
        let positions = scattered_3d();
        let (h, c) = (0.05, 0.013);
        let field = SparseField::<3>::build(&positions, h, c).unwrap();
        let mut checked = 0;
        for_each_in_box([-14; 3], [14; 3], |g| {
            let expected = value_naive(&positions, field.node_position(g), h);
            let got = f64::from(field.value(g));
            // f32 storage of an f64 sum: relative 1e-6.
            assert!(
                (got - expected).abs() <= 1e-6 * expected.max(1.0),
                "node {g:?}: {got} vs {expected}"
            );
            checked += usize::from(expected > 0.0);
        });
        assert!(checked > 1000, "only {checked} non-zero nodes checked");
    }

    #[test]
    fn blocks_follow_the_particles_not_the_domain() {
        // Two particles 100 m apart: a dense grid would hold (100 m / 5 mm)² = 4e8 nodes; the
        // sparse one holds at most 5 × 5 blocks of 4 × 4 nodes around each particle.
        let positions = [Vector::<2>::new(0.0, 0.0), Vector::<2>::new(100.0, 0.0)];
        let field = SparseField::<2>::build(&positions, 0.02, 0.005).unwrap();
        assert!(field.node_count() <= 2 * 25 * 16, "{} nodes", field.node_count());
        assert!(field.value([0, 0]) > 0.99);
        assert_eq!(field.value([10_000, 0]), 0.0);
    }

    #[test]
    fn gradient_matches_finite_difference() {
        let positions = scattered_3d();
        let field = SparseField::<3>::build(&positions, 0.05, 0.013).unwrap();
        let x = [0.031, -0.017, 0.006];
        let g = field.gradient_squared(x);
        let e = 1e-6;
        for k in 0..3 {
            let (mut a, mut b) = (x, x);
            a[k] += e;
            b[k] -= e;
            let fd = (value_naive(&positions, a, 0.05).powi(2) - value_naive(&positions, b, 0.05).powi(2))
                / (2.0 * e);
            assert!(
                (g[k] - fd).abs() <= 1e-5 * fd.abs().max(1.0),
                "axis {k}: {} vs {fd}",
                g[k]
            );
        }
    }

    #[test]
    fn non_finite_position_is_named() {
        let positions = [Vector::<2>::new(0.0, 0.0), Vector::<2>::new(Real::NAN, 0.0)];
        let err = SparseField::<2>::build(&positions, 0.02, 0.005).unwrap_err();
        assert_eq!(err, SurfaceError::NonFinitePosition { particle: 1 });
    }
}
