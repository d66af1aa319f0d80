//! Marching cubes [LC87]: the isosurface of eq. (25) in 3D as outward triangles.
//!
//! Instead of the classic 256-case table, each cube's surface is built from its faces: every
//! face contributes the segments of `marching_squares::face_segments` (asymptotic decider on
//! ambiguous faces), which join into closed polygons around the cube. Because two cubes sharing
//! a face compute the same segments from the same four values, neighbouring polygons meet edge
//! to edge and the welded mesh is watertight wherever the fluid is closed (the classic table
//! can leave holes on ambiguous faces).
//!
//! A polygon of more than three crossings is fanned from a vertex whose diagonals never join two
//! crossings on one face of the cube; a diagonal inside a face could coincide with one made
//! by the cube across that face and give an edge of four triangles. When no such vertex exists,
//! the polygon is fanned from an extra vertex at its centroid. Crossings lie strictly inside
//! their edges (`EDGE_MARGIN`) and three such points of a cube are never collinear, so no
//! triangle has zero area.

use crate::math::Real;
use rayon::prelude::*;
use std::sync::OnceLock;

use super::field::{SparseField, for_each_in_box};
use super::marching_squares::{edge_vertex, face_segments};
use super::mesh::{Pieces, VertexKey};

/// The cube's fixed geometry. Corner `c` has coordinates `(c & 1, c >> 1 & 1, c >> 2 & 1)`;
/// edge `4·axis + j` runs along `axis` from its `j`-th corner with that bit clear.
struct Cube {
    /// Lower corner and axis of each edge.
    edges: [(usize, usize); 12],
    /// Each face's corners, counter-clockwise seen from outside the cube.
    face_corners: [[usize; 4]; 6],
    /// Each face's edges: edge `k` joins corners `k` and `k + 1` of `face_corners`.
    face_edges: [[usize; 4]; 6],
    /// Bit `f` set when the edge lies on face `f`.
    edge_faces: [u8; 12],
}

fn cube() -> &'static Cube {
    static CUBE: OnceLock<Cube> = OnceLock::new();
    CUBE.get_or_init(|| {
        let mut edges = [(0, 0); 12];
        for axis in 0..3 {
            let lower = (0..8).filter(|c| c & (1 << axis) == 0);
            for (j, corner) in lower.enumerate() {
                edges[4 * axis + j] = (corner, axis);
            }
        }
        let edge_of = |a: usize, b: usize| {
            let (low, high) = (a.min(b), a.max(b));
            let axis = (low ^ high).trailing_zeros() as usize;
            // Every consecutive pair of a face's corners differs in one bit: it is an edge.
            edges.iter().position(|&e| e == (low, axis)).unwrap_or(0)
        };
        let mut face_corners = [[0; 4]; 6];
        let mut face_edges = [[0; 4]; 6];
        let mut edge_faces = [0u8; 12];
        for axis in 0..3 {
            // (u, v, axis) is right-handed, so (0,0) → (1,0) → (1,1) → (0,1) in (u, v) is
            // counter-clockwise seen from +axis; the face on the −axis side is walked backwards.
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            for side in 0..2 {
                let f = 2 * axis + side;
                let mut corners =
                    [(0, 0), (1, 0), (1, 1), (0, 1)].map(|(a, b)| side << axis | a << u | b << v);
                if side == 0 {
                    corners.reverse();
                }
                face_corners[f] = corners;
                for k in 0..4 {
                    let e = edge_of(corners[k], corners[(k + 1) % 4]);
                    face_edges[f][k] = e;
                    edge_faces[e] |= 1 << f;
                }
            }
        }
        Cube {
            edges,
            face_corners,
            face_edges,
            edge_faces,
        }
    })
}

/// The closed polygons of one cube with corner values `v` at level `iso`, as cycles of edge
/// indices, oriented so that their right-hand normal points out of the fluid.
fn polygons(v: &[Real; 8], iso: Real) -> Vec<Vec<usize>> {
    let cube = cube();
    // next[e]: the crossing after edge e's crossing, walking with the fluid on the left of each
    // face seen from outside the cube.
    let mut next = [usize::MAX; 12];
    for f in 0..6 {
        let (segments, n) = face_segments(cube.face_corners[f].map(|c| v[c]), iso);
        for &(exit, entry) in &segments[..n] {
            next[cube.face_edges[f][exit]] = cube.face_edges[f][entry];
        }
    }
    let mut seen = [false; 12];
    let mut out = Vec::new();
    for start in 0..12 {
        if next[start] == usize::MAX || seen[start] {
            continue;
        }
        let mut cycle = Vec::new();
        let mut e = start;
        while e != usize::MAX && !seen[e] {
            seen[e] = true;
            cycle.push(e);
            e = next[e];
        }
        // Walking with the fluid on the left seen from outside turns the right-hand normal
        // into the fluid; reversing makes it point out.
        cycle.reverse();
        out.push(cycle);
    }
    out
}

/// A fan start of `polygon` none of whose diagonals joins two crossings on one cube face.
fn safe_fan_start(polygon: &[usize]) -> Option<usize> {
    let faces = &cube().edge_faces;
    let n = polygon.len();
    (0..n).find(|&s| (2..n - 1).all(|i| faces[polygon[s]] & faces[polygon[(s + i) % n]] == 0))
}

/// Eq. (25)'s isosurface at level `iso` in 3D as outward triangles, one block of cells per rayon
/// task, in block order. Returns nothing unless `D == 3`.
pub(crate) fn extract<const D: usize>(field: &SparseField<D>, iso: Real) -> Pieces<D> {
    if D != 3 {
        return Pieces::default();
    }
    let b = field.block_size();
    let cube = cube();
    let parts: Vec<Pieces<D>> = (0..field.blocks().len())
        .into_par_iter()
        .map(|block| {
            let ext = field.block_with_upper_layer(block);
            let lo = field.blocks()[block].map(|k| k * b);
            let mut out = Pieces::default();
            for_each_in_box([0; D], [b - 1; D], |cell| {
                let v: [Real; 8] = std::array::from_fn(|c| {
                    let mut index = 0;
                    for k in (0..D).rev() {
                        index = index * (b + 1) + cell[k] + ((c >> k) & 1) as i64;
                    }
                    ext[index as usize]
                });
                let inside = v.iter().filter(|&&x| x >= iso).count();
                if inside == 0 || inside == 8 {
                    return;
                }
                let origin: [i64; D] = std::array::from_fn(|k| lo[k] + cell[k]);
                let node = |corner: usize| -> [i64; D] {
                    std::array::from_fn(|k| origin[k] + ((corner >> k) & 1) as i64)
                };
                let vertex = |edge: usize| {
                    let (low, axis) = cube.edges[edge];
                    edge_vertex(field, node(low), axis, v[low], v[low | 1 << axis], iso)
                };
                for (p, polygon) in polygons(&v, iso).iter().enumerate() {
                    let corners: Vec<(VertexKey<D>, [f64; D])> = polygon.iter().map(|&e| vertex(e)).collect();
                    let n = corners.len();
                    let mut triangle = |a: usize, b: usize, c: usize, list: &[(VertexKey<D>, [f64; D])]| {
                        out.elements.push(std::array::from_fn(|i| list[[a, b, c][i]].0));
                    };
                    match (n, safe_fan_start(polygon)) {
                        (3, _) => triangle(0, 1, 2, &corners),
                        (_, Some(s)) => {
                            for i in 1..n - 1 {
                                triangle(s, (s + i) % n, (s + i + 1) % n, &corners);
                            }
                        }
                        (_, None) => {
                            let mut centre = [0.0; D];
                            for (_, x) in &corners {
                                for k in 0..D {
                                    centre[k] += x[k] / n as f64;
                                }
                            }
                            let mut list = corners.clone();
                            list.push(((origin, (D + p) as u8), centre));
                            for i in 0..n {
                                triangle(n, i, (i + 1) % n, &list);
                            }
                            out.vertices.push(list[n]);
                        }
                    }
                    out.vertices.extend(corners);
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
    fn cube_faces_are_counter_clockwise_from_outside() {
        let cube = cube();
        for (f, corners) in cube.face_corners.iter().enumerate() {
            let (axis, side) = (f / 2, f % 2);
            let p = corners.map(|c| [(c & 1) as f64, (c >> 1 & 1) as f64, (c >> 2 & 1) as f64]);
            // Newell normal of the quad.
            let mut n = [0.0; 3];
            for k in 0..4 {
                let (a, b) = (p[k], p[(k + 1) % 4]);
                n[0] += (a[1] - b[1]) * (a[2] + b[2]);
                n[1] += (a[2] - b[2]) * (a[0] + b[0]);
                n[2] += (a[0] - b[0]) * (a[1] + b[1]);
            }
            let outward = if side == 1 { 2.0 } else { -2.0 };
            for k in 0..3 {
                assert_eq!(n[k], if k == axis { outward } else { 0.0 }, "face {f}");
            }
        }
        // Each edge lies on exactly two faces.
        assert!(cube.edge_faces.iter().all(|m| m.count_ones() == 2));
    }

    #[test]
    fn every_corner_pattern_closes_into_polygons_over_all_crossings() {
        let cube = cube();
        for pattern in 0u32..256 {
            let v: [Real; 8] = std::array::from_fn(|c| if pattern >> c & 1 == 1 { 2.0 } else { 0.0 });
            let crossings = cube
                .edges
                .iter()
                .filter(|&&(c, a)| (pattern >> c & 1) != (pattern >> (c | 1 << a) & 1))
                .count();
            let polygons = polygons(&v, 1.0);
            let used: usize = polygons.iter().map(Vec::len).sum();
            assert_eq!(used, crossings, "pattern {pattern:08b}");
            assert!(polygons.iter().all(|p| p.len() >= 3), "pattern {pattern:08b}");
        }
    }

    #[test]
    fn single_inside_corner_gives_one_outward_triangle() {
        // Corner 0 inside: the triangle's normal points away from corner 0, i.e. along +x+y+z.
        let mut v = [0.0; 8];
        v[0] = 2.0;
        let polygons = polygons(&v, 1.0);
        assert_eq!(polygons.len(), 1);
        let p = &polygons[0];
        let mid = |e: usize| {
            let (c, axis) = cube().edges[e];
            let mut x = [(c & 1) as f64, (c >> 1 & 1) as f64, (c >> 2 & 1) as f64];
            x[axis] += 0.5;
            x
        };
        let (a, b, c) = (mid(p[0]), mid(p[1]), mid(p[2]));
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let n = [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ];
        assert!(n.iter().all(|&x| x > 0.0), "normal {n:?}");
    }
}
