//! The reconstructed surface as one indexed mesh: welding the marching output, vertex normals,
//! and the geometric measures the tests check (enclosed volume by the divergence theorem,
//! area, watertightness).
//!
//! An element is a simplex of dimension `D − 1` with `D` vertices: a triangle in 3D, a segment in
//! 2D, oriented so that its right-hand normal points out of the fluid.

use crate::math::{Real, Vector};
use rayon::prelude::*;
use std::collections::HashMap;

use super::field::SparseField;

/// Identifies a vertex of the unwelded marching output: `(node, slot)`, where slot `< D` is the
/// grid edge from node `node` along axis `slot`, and slot `D + k` is the centre vertex of the
/// `k`-th polygon of the cell whose lower corner is `node`. Equal keys are the same vertex.
pub(crate) type VertexKey<const D: usize> = ([i64; D], u8);

/// Marching output before welding: vertices (with duplicates, one per cell that made them) and
/// elements referring to them by key.
#[derive(Debug, Default)]
pub(crate) struct Pieces<const D: usize> {
    /// Vertex keys and positions [m].
    pub vertices: Vec<(VertexKey<D>, [f64; D])>,
    /// Elements as vertex keys, oriented outward.
    pub elements: Vec<[VertexKey<D>; D]>,
}

impl<const D: usize> FromIterator<Pieces<D>> for Pieces<D> {
    /// The pieces of several blocks of cells, in order.
    fn from_iter<I: IntoIterator<Item = Pieces<D>>>(parts: I) -> Self {
        let mut all = Pieces::default();
        for p in parts {
            all.vertices.extend(p.vertices);
            all.elements.extend(p.elements);
        }
        all
    }
}

/// A reconstructed surface: triangles in 3D, line segments in 2D.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SurfaceMesh<const D: usize> {
    /// Vertex positions [m].
    pub positions: Vec<Vector<D>>,
    /// Unit outward normal at each vertex (dimensionless).
    pub normals: Vec<Vector<D>>,
    /// Elements: `D` vertex indices each (triangles in 3D, segments in 2D), outward by the
    /// right-hand rule in 3D and with the fluid on the left of `a → b` in 2D.
    pub elements: Vec<[u32; D]>,
}

/// Merges vertices with equal keys (a grid edge's crossing is made by every cell around that
/// edge) and turns the elements' keys into indices, so the mesh is closed where the fluid is.
pub(crate) fn weld<const D: usize>(mut pieces: Pieces<D>) -> SurfaceMesh<D> {
    pieces.vertices.par_sort_unstable_by(|a, b| a.0.cmp(&b.0));
    pieces.vertices.dedup_by(|a, b| a.0 == b.0);
    let keys: Vec<VertexKey<D>> = pieces.vertices.iter().map(|v| v.0).collect();
    let index = |k: &VertexKey<D>| {
        // Every element key was emitted together with its vertex, so the search finds it.
        keys.binary_search(k).map_or(u32::MAX, |i| i as u32)
    };
    let elements = pieces
        .elements
        .par_iter()
        .map(|e| std::array::from_fn(|i| index(&e[i])))
        .collect();
    SurfaceMesh {
        positions: pieces
            .vertices
            .iter()
            .map(|v| Vector::<D>::from_fn(|k, _| v.1[k] as Real))
            .collect(),
        normals: Vec::new(),
        elements,
    }
}

/// Outward unit normal of each vertex: `−∇F²/|∇F²|` of eq. (25) at the vertex; where the gradient
/// vanishes (a symmetric spot), the normalised sum of the adjacent elements' normals.
pub(crate) fn vertex_normals<const D: usize>(
    field: &SparseField<D>,
    mesh: &SurfaceMesh<D>,
) -> Vec<Vector<D>> {
    let mut fallback = vec![Vector::<D>::zeros(); mesh.positions.len()];
    for e in &mesh.elements {
        let n = mesh.element_normal(e);
        for &v in e {
            fallback[v as usize] += n;
        }
    }
    mesh.positions
        .par_iter()
        .zip(fallback.par_iter())
        .map(|(x, alt)| {
            let g = field.gradient_squared(std::array::from_fn(|k| f64::from(x[k])));
            let norm = g.iter().map(|v| v * v).sum::<f64>().sqrt();
            if norm > 1e-12 && norm.is_finite() {
                Vector::<D>::from_fn(|k, _| (-g[k] / norm) as Real)
            } else {
                alt.try_normalize(0.0).unwrap_or_else(Vector::<D>::zeros)
            }
        })
        .collect()
}

impl<const D: usize> SurfaceMesh<D> {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// `true` when there is no element.
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    fn point(&self, v: u32) -> [f64; 3] {
        let p = &self.positions[v as usize];
        std::array::from_fn(|k| if k < D { f64::from(p[k]) } else { 0.0 })
    }

    /// Normal of an element scaled by its measure (area in 3D [m²], length in 2D [m]).
    fn element_normal(&self, e: &[u32; D]) -> Vector<D> {
        let n = if D == 3 {
            let (a, b, c) = (self.point(e[0]), self.point(e[1]), self.point(e[2]));
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            [
                u[1] * w[2] - u[2] * w[1],
                u[2] * w[0] - u[0] * w[2],
                u[0] * w[1] - u[1] * w[0],
            ]
            .map(|x| 0.5 * x)
        } else {
            // The fluid is on the left of a → b, so the outward normal is the right-hand side.
            let (a, b) = (self.point(e[0]), self.point(e[1]));
            [b[1] - a[1], a[0] - b[0], 0.0]
        };
        Vector::<D>::from_fn(|k, _| n[k] as Real)
    }

    /// Measure of each element (area in 3D [m²], length in 2D [m]), in f64.
    pub fn element_measures(&self) -> Vec<f64> {
        self.elements
            .iter()
            .map(|e| {
                let a = self.point(e[0]);
                let b = self.point(e[1]);
                let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                if D == 3 {
                    let c = self.point(e[2]);
                    let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
                    let n = [
                        u[1] * w[2] - u[2] * w[1],
                        u[2] * w[0] - u[0] * w[2],
                        u[0] * w[1] - u[1] * w[0],
                    ];
                    0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
                } else {
                    (u[0] * u[0] + u[1] * u[1]).sqrt()
                }
            })
            .collect()
    }

    /// Total measure of the surface: area in 3D [m²], perimeter in 2D [m].
    pub fn boundary_measure(&self) -> f64 {
        self.element_measures().iter().sum()
    }

    /// Measure enclosed by the surface by the divergence theorem: volume in 3D [m³]
    /// (`Σ a·(b×c)/6`), area in 2D [m²] (`Σ (a_x b_y − a_y b_x)/2`). Positive for a closed,
    /// outward-oriented surface; meaningful only when [`Self::open_facets`] is 0.
    pub fn enclosed_measure(&self) -> f64 {
        self.elements
            .iter()
            .map(|e| {
                let a = self.point(e[0]);
                let b = self.point(e[1]);
                if D == 3 {
                    let c = self.point(e[2]);
                    let bc = [
                        b[1] * c[2] - b[2] * c[1],
                        b[2] * c[0] - b[0] * c[2],
                        b[0] * c[1] - b[1] * c[0],
                    ];
                    (a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2]) / 6.0
                } else {
                    0.5 * (a[0] * b[1] - a[1] * b[0])
                }
            })
            .sum()
    }

    /// Number of element facets (edges of triangles in 3D, end points of segments in 2D) that are
    /// not matched by exactly one oppositely oriented facet of another element. 0 means the mesh
    /// is closed, manifold and consistently oriented (watertight).
    pub fn open_facets(&self) -> usize {
        // Facet (a, b) of a triangle counts +1 on the directed edge; in 2D a segment's end
        // counts +1 on its head and −1 on its tail. A matched facet sums to 0 with 2 uses.
        let mut uses: HashMap<(u32, u32), (i32, u32)> = HashMap::new();
        for e in &self.elements {
            if D == 3 {
                for (a, b) in [(e[0], e[1]), (e[1], e[2]), (e[2], e[0])] {
                    let (key, sign) = if a < b { ((a, b), 1) } else { ((b, a), -1) };
                    let u = uses.entry(key).or_default();
                    u.0 += sign;
                    u.1 += 1;
                }
            } else {
                for (v, sign) in [(e[0], -1), (e[1], 1)] {
                    let u = uses.entry((v, v)).or_default();
                    u.0 += sign;
                    u.1 += 1;
                }
            }
        }
        uses.values()
            .filter(|&&(sum, count)| sum != 0 || count != 2)
            .count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube's surface as 12 outward triangles.
    fn cube() -> SurfaceMesh<3> {
        let positions = (0..8)
            .map(|i| Vector::<3>::new((i & 1) as Real, ((i >> 1) & 1) as Real, ((i >> 2) & 1) as Real))
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let elements = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        SurfaceMesh {
            positions,
            normals: Vec::new(),
            elements,
        }
    }

    #[test]
    fn unit_cube_measures_are_exact() {
        let mut mesh = cube();
        assert!((mesh.enclosed_measure() - 1.0).abs() < 1e-12);
        assert!((mesh.boundary_measure() - 6.0).abs() < 1e-12);
        assert_eq!(mesh.open_facets(), 0);
        // Flipping one triangle breaks the orientation of its three edges.
        mesh.elements[0].swap(1, 2);
        assert_eq!(mesh.open_facets(), 3);
        mesh.elements.pop();
        assert!(mesh.open_facets() > 3);
    }

    #[test]
    fn unit_square_measures_are_exact() {
        let positions = vec![
            Vector::<2>::new(0.0, 0.0),
            Vector::<2>::new(1.0, 0.0),
            Vector::<2>::new(1.0, 1.0),
            Vector::<2>::new(0.0, 1.0),
        ];
        let mut mesh = SurfaceMesh {
            positions,
            normals: Vec::new(),
            elements: vec![[0, 1], [1, 2], [2, 3], [3, 0]],
        };
        assert!((mesh.enclosed_measure() - 1.0).abs() < 1e-12);
        assert!((mesh.boundary_measure() - 4.0).abs() < 1e-12);
        assert_eq!(mesh.open_facets(), 0);
        mesh.elements.pop();
        assert_eq!(mesh.open_facets(), 2);
    }
}
