//! Marching squares: the iso-line of eq. (25) in 2D as closed, oriented segments, and the
//! per-face rule that marching cubes reuses on each face of a cube.
//!
//! A node is inside the fluid when `F ≥ F_iso`. On a square with corners `c0..c3` in
//! counter-clockwise order, edge `k` runs from `c_k` to `c_(k+1)`; it is an *exit* when `c_k` is
//! inside and `c_(k+1)` outside, an *entry* in the opposite case. Every segment runs from an exit
//! to an entry, so the fluid lies on its left (a closed curve runs counter-clockwise around the
//! fluid). A square with two diagonally opposite inside corners is ambiguous; the asymptotic
//! decider [NH91] joins the inside corners when the bilinear interpolant's saddle value is at
//! least `F_iso`. The rule reads only the four values of the square, so the two cells sharing a
//! face (in 3D) or the squares themselves (in 2D) never disagree: the mesh has no cracks.

use crate::math::Real;
use rayon::prelude::*;

use super::field::{SparseField, for_each_in_box};
use super::mesh::{Pieces, VertexKey};

/// Where an iso-crossing lies on its edge is clamped to `[EDGE_MARGIN, 1 − EDGE_MARGIN]` of the
/// edge, so that no two crossings of one cell coincide at a node (which would make zero-area
/// triangles); the shift is at most 0.1 % of a cell.
pub(crate) const EDGE_MARGIN: f64 = 1e-3;

/// The segments on one square with corner values `v` in counter-clockwise order: pairs
/// `(exit, entry)` of edge positions (edge `k` joins corners `k` and `k + 1`), at most two.
pub(crate) fn face_segments(v: [Real; 4], iso: Real) -> ([(usize, usize); 2], usize) {
    let inside = v.map(|x| x >= iso);
    let mut out = [(0, 0); 2];
    let mut n = 0;
    let crossings = (0..4).filter(|&k| inside[k] != inside[(k + 1) % 4]).count();
    if crossings == 2 {
        let exit = (0..4).find(|&k| inside[k] && !inside[(k + 1) % 4]);
        let entry = (0..4).find(|&k| !inside[k] && inside[(k + 1) % 4]);
        if let (Some(a), Some(b)) = (exit, entry) {
            out[0] = (a, b);
            n = 1;
        }
    } else if crossings == 4 {
        // Saddle of the bilinear interpolant; the denominator is non-zero because one diagonal
        // is at or above the level and the other below it.
        let f = v.map(f64::from);
        let saddle = (f[0] * f[2] - f[1] * f[3]) / (f[0] + f[2] - f[1] - f[3]);
        let join_inside = saddle >= f64::from(iso);
        for k in 0..4 {
            if inside[k] {
                // Exit k meets the next entry (k + 1) when the inside corners are joined,
                // the previous one (k + 3) when each inside corner is cut off alone.
                let entry = if join_inside { (k + 1) % 4 } else { (k + 3) % 4 };
                out[n] = (k, entry);
                n += 1;
            }
        }
    }
    (out, n)
}

/// The crossing of level `iso` on the grid edge from node `lower` along `axis`, with values
/// `v_lower`, `v_upper` on its ends: its key and its position [m] by linear interpolation of F.
pub(crate) fn edge_vertex<const D: usize>(
    field: &SparseField<D>,
    lower: [i64; D],
    axis: usize,
    v_lower: Real,
    v_upper: Real,
    iso: Real,
) -> (VertexKey<D>, [f64; D]) {
    let (a, b) = (f64::from(v_lower), f64::from(v_upper));
    let t = ((f64::from(iso) - a) / (b - a)).clamp(EDGE_MARGIN, 1.0 - EDGE_MARGIN);
    let mut x = field.node_position(lower);
    x[axis] += t * field.cell_size();
    ((lower, axis as u8), x)
}

/// Corners of a square cell in counter-clockwise order, as bit patterns (bit 0 = x, bit 1 = y).
const CYCLE: [usize; 4] = [0b00, 0b01, 0b11, 0b10];

/// Eq. (25)'s iso-line at level `iso` in 2D as segments with the fluid on their left, one block
/// of cells per rayon task, in block order. Returns nothing unless `D == 2`.
pub(crate) fn extract<const D: usize>(field: &SparseField<D>, iso: Real) -> Pieces<D> {
    if D != 2 {
        return Pieces::default();
    }
    let b = field.block_size();
    let parts: Vec<Pieces<D>> = (0..field.blocks().len())
        .into_par_iter()
        .map(|block| {
            let ext = field.block_with_upper_layer(block);
            let lo = field.blocks()[block].map(|k| k * b);
            let mut out = Pieces::default();
            for_each_in_box([0; D], [b - 1; D], |cell| {
                let at = |corner: usize| {
                    let i = cell[0] + (corner & 1) as i64;
                    let j = cell[1] + (corner >> 1) as i64;
                    ext[(i + j * (b + 1)) as usize]
                };
                let v = CYCLE.map(at);
                let (segments, n) = face_segments(v, iso);
                let node = |corner: usize| -> [i64; D] {
                    std::array::from_fn(|k| lo[k] + cell[k] + ((corner >> k) & 1) as i64)
                };
                let vertex = |edge: usize| {
                    let (p, q) = (CYCLE[edge], CYCLE[(edge + 1) % 4]);
                    let (low, high) = if p < q { (p, q) } else { (q, p) };
                    let axis = (low ^ high).trailing_zeros() as usize;
                    edge_vertex(field, node(low), axis, at(low), at(high), iso)
                };
                for &(exit, entry) in &segments[..n] {
                    let (a, b) = (vertex(exit), vertex(entry));
                    out.elements
                        .push(std::array::from_fn(|i| if i == 0 { a.0 } else { b.0 }));
                    out.vertices.push(a);
                    out.vertices.push(b);
                }
            });
            out
        })
        .collect();
    // Blocks in order: the same mesh for any thread count.
    parts.into_iter().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_inside_corner_is_cut_off_with_fluid_on_the_left() {
        // Corner 0 inside: exit on edge 0 (c0 → c1), entry on edge 3 (c3 → c0).
        let (s, n) = face_segments([2.0, 0.0, 0.0, 0.0], 1.0);
        assert_eq!((n, s[0]), (1, (0, 3)));
        // Corner 1 outside: exit on edge 0, entry on edge 1.
        let (s, n) = face_segments([2.0, 0.0, 2.0, 2.0], 1.0);
        assert_eq!((n, s[0]), (1, (0, 1)));
    }

    #[test]
    fn saddle_decides_ambiguous_squares() {
        // Diagonal 0–2 inside. High inside values: the saddle is inside, the corners are joined.
        let (s, n) = face_segments([3.0, 0.5, 3.0, 0.5], 1.0);
        assert_eq!((n, s), (2, [(0, 1), (2, 3)]));
        // Barely inside: the saddle (1.1·1.1 − 0)/(2.2) = 0.55 is outside, each corner alone.
        let (s, n) = face_segments([1.1, 0.0, 1.1, 0.0], 1.0);
        assert_eq!((n, s), (2, [(0, 3), (2, 1)]));
        // Uniform squares have no segment.
        assert_eq!(face_segments([0.0; 4], 1.0).1, 0);
        assert_eq!(face_segments([2.0; 4], 1.0).1, 0);
    }
}
