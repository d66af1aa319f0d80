//! Closed triangle meshes: the checks a solid's mesh must pass, its volume, and which lattice
//! points lie inside it.
//!
//! A mesh is accepted when it is *closed and consistently oriented*: after welding vertices
//! with bitwise-equal coordinates, every edge is shared by exactly two triangles that traverse
//! it in opposite directions. Then the inside is well defined and is found by casting rays
//! along +z (the parity / winding-number test, e.g. O'Rourke, *Computational Geometry in C*,
//! 2nd ed., section 7.4): the winding number of a point is the number of triangles crossed
//! below it whose normal points down (entries) minus those whose normal points up (exits).
//! Points of non-zero winding are inside.
//!
//! A ray that passes exactly through an edge or a vertex is decided by the top-left rule of
//! rasterisers (each projected point belongs to exactly one of two triangles that meet along an
//! edge from opposite sides), with edge functions computed in a canonical vertex order so that
//! both triangles see the same value: no crossing is counted twice or missed.
//!
//! A mesh traversed inside out (all triangles clockwise seen from outside, negative volume) is
//! flipped, not refused: it encloses the same region.

use std::collections::HashMap;

use nalgebra::{Rotation3, Vector3};

/// A triangle: three vertices \[m\] (or file units before placing), counter-clockwise seen
/// from outside.
pub type Triangle = [[f64; 3]; 3];

/// Why a mesh cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// The file cannot be read.
    #[error("cannot read the file: {0}")]
    Read(String),
    /// The file is not a mesh of a known format, or is malformed.
    #[error("{0}")]
    Format(String),
    /// No triangles.
    #[error("empty mesh: the file holds no triangles")]
    Empty,
    /// A coordinate is not finite.
    #[error("triangle {triangle} has a non-finite coordinate")]
    NonFinite {
        /// Index of the triangle (0-based, file order).
        triangle: usize,
    },
    /// A triangle with two equal vertices.
    #[error(
        "degenerate mesh: {count} triangles have two equal vertices, the first (triangle {first}) at {at:?}"
    )]
    Degenerate {
        /// How many.
        count: usize,
        /// The first one (0-based).
        first: usize,
        /// Its repeated vertex.
        at: [f64; 3],
    },
    /// Edges used by a single triangle.
    #[error(
        "open mesh: {count} boundary edges (used by one triangle only), the first from {from:?} to {to:?}"
    )]
    Open {
        /// How many.
        count: usize,
        /// The first edge's ends.
        from: [f64; 3],
        /// Its other end.
        to: [f64; 3],
    },
    /// An edge shared by more than two triangles.
    #[error(
        "non-manifold mesh: the edge from {from:?} to {to:?} is shared by {triangles} triangles (2 expected)"
    )]
    NonManifold {
        /// The edge's ends.
        from: [f64; 3],
        /// Its other end.
        to: [f64; 3],
        /// Triangles sharing it.
        triangles: usize,
    },
    /// An edge traversed twice in the same direction: neighbouring triangles face opposite ways.
    #[error(
        "inconsistent orientation: the edge from {from:?} to {to:?} is used twice in the same direction \
             ({count} such edges; neighbouring triangles must list their shared edge in opposite orders)"
    )]
    Inconsistent {
        /// How many edges.
        count: usize,
        /// The first edge's ends.
        from: [f64; 3],
        /// Its other end.
        to: [f64; 3],
    },
    /// The enclosed volume is zero (a flat mesh).
    #[error("the mesh encloses no volume")]
    Flat,
}

/// A closed, consistently and outward oriented triangle mesh in scene coordinates \[m\].
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    triangles: Vec<Triangle>,
    volume: f64,
    min: [f64; 3],
    max: [f64; 3],
}

/// How a mesh is placed in the scene: `x' = R (S x) + t`.
#[derive(Debug, Clone, PartialEq)]
pub struct Placement {
    /// Per-axis scale factors S (> 0; dimensionless, file units to m).
    pub scale: [f64; 3],
    /// Rotation R.
    pub rotation: Rotation3<f64>,
    /// Translation t \[m\].
    pub translation: [f64; 3],
}

/// Coordinates as a hashable key; `-0.0` and `0.0` weld.
fn key(v: &[f64; 3]) -> [u64; 3] {
    v.map(|c| if c == 0.0 { 0 } else { c.to_bits() })
}

/// Signed volume of a closed mesh, `Σ a · (b × c) / 6` (divergence theorem) \[m³\].
fn signed_volume(triangles: &[Triangle]) -> f64 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(Vector3::from);
            a.dot(&b.cross(&c)) / 6.0
        })
        .sum()
}

impl Mesh {
    /// Places `triangles` (file units) by `placement`, checks that the result is closed and
    /// consistently oriented (module doc), and flips it if it is inside out.
    ///
    /// # Errors
    /// The [`MeshError`] naming the first kind of problem found, in the order: empty,
    /// non-finite, degenerate, open, non-manifold, inconsistent, flat.
    pub fn new(triangles: &[Triangle], placement: &Placement) -> Result<Mesh, MeshError> {
        if triangles.is_empty() {
            return Err(MeshError::Empty);
        }
        let s = Vector3::from(placement.scale);
        let t = Vector3::from(placement.translation);
        let mut placed = Vec::with_capacity(triangles.len());
        for (i, tri) in triangles.iter().enumerate() {
            if tri.iter().flatten().any(|c| !c.is_finite()) {
                return Err(MeshError::NonFinite { triangle: i });
            }
            placed.push(tri.map(|v| {
                let x = placement.rotation * Vector3::from(v).component_mul(&s) + t;
                [x.x, x.y, x.z]
            }));
        }
        check_closed(&placed)?;
        let mut volume = signed_volume(&placed);
        if volume < 0.0 {
            for tri in &mut placed {
                tri.swap(1, 2);
            }
            volume = -volume;
        }
        let mut min = [f64::INFINITY; 3];
        let mut max = [f64::NEG_INFINITY; 3];
        for v in placed.iter().flatten() {
            for k in 0..3 {
                min[k] = min[k].min(v[k]);
                max[k] = max[k].max(v[k]);
            }
        }
        let bounds: f64 = (0..3).map(|k| max[k] - min[k]).product();
        // A closed mesh of positive extent but a volume at rounding level is flat (NaN too).
        if volume.partial_cmp(&(1e-12 * bounds)) != Some(std::cmp::Ordering::Greater) {
            return Err(MeshError::Flat);
        }
        Ok(Mesh {
            triangles: placed,
            volume,
            min,
            max,
        })
    }

    /// The enclosed volume \[m³\].
    pub fn volume(&self) -> f64 {
        self.volume
    }

    /// Lower corner of the bounding box \[m\].
    pub fn min(&self) -> [f64; 3] {
        self.min
    }

    /// Upper corner of the bounding box \[m\].
    pub fn max(&self) -> [f64; 3] {
        self.max
    }

    /// The triangles, outward oriented \[m\].
    pub fn triangles(&self) -> &[Triangle] {
        &self.triangles
    }

    /// Whether `p` \[m\] is inside: its winding number (module doc) is not zero.
    pub fn contains(&self, p: [f64; 3]) -> bool {
        let mut winding = 0i64;
        for tri in &self.triangles {
            if let Some((z, exit)) = crossing(tri, &p) {
                if z < p[2] {
                    winding -= i64::from(exit);
                }
            }
        }
        winding != 0
    }

    /// The inside of the lattice `x_k = min_k + (i_k + 0.5) dx`, `i_k in 0..n_k`, as intervals
    /// of `i_2` per column `(i_0, i_1)` (module doc's ray test along +z).
    pub fn columns(&self, min: [f64; 3], n: [i64; 3], dx: f64) -> Columns {
        let columns = (n[0].max(0) * n[1].max(0)) as usize;
        let coordinate = |k: usize, i: i64| min[k] + (i as f64 + 0.5) * dx;
        // First and last lattice index whose coordinate lies in [lo, hi] along axis k.
        let range = |k: usize, lo: f64, hi: f64| {
            let first = (((lo - min[k]) / dx - 0.5).ceil() as i64).max(0);
            let last = (((hi - min[k]) / dx - 0.5).floor() as i64).min(n[k] - 1);
            (first, last)
        };
        let mut crossings: Vec<(usize, f64, i8)> = Vec::new();
        for tri in &self.triangles {
            let lo = |k: usize| tri[0][k].min(tri[1][k]).min(tri[2][k]);
            let hi = |k: usize| tri[0][k].max(tri[1][k]).max(tri[2][k]);
            let (i0, i1) = range(0, lo(0), hi(0));
            let (j0, j1) = range(1, lo(1), hi(1));
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let p = [coordinate(0, i), coordinate(1, j), 0.0];
                    if let Some((z, exit)) = crossing(tri, &p) {
                        crossings.push(((i + n[0] * j) as usize, z, exit));
                    }
                }
            }
        }
        crossings.sort_unstable_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
        let mut start = Vec::with_capacity(columns + 1);
        let mut intervals = Vec::new();
        let mut next = 0;
        for column in 0..columns {
            start.push(intervals.len());
            let mut winding = 0i64;
            let mut from = 0i64;
            while let Some(&(col, z, exit)) = crossings.get(next) {
                if col != column {
                    break;
                }
                next += 1;
                let before = winding;
                winding -= i64::from(exit);
                // Lattice points strictly above the crossing have the new winding.
                let k = (((z - min[2]) / dx - 0.5).floor() as i64 + 1).clamp(0, n[2]);
                match (before != 0, winding != 0) {
                    (false, true) => from = k,
                    (true, false) if k > from => intervals.push((from, k)),
                    _ => {}
                }
            }
            if winding != 0 && n[2] > from {
                intervals.push((from, n[2]));
            }
        }
        start.push(intervals.len());
        Columns {
            n0: n[0],
            start,
            intervals,
        }
    }
}

/// Per column of a lattice, the `i_2` intervals inside a mesh ([`Mesh::columns`]).
#[derive(Debug, Clone)]
pub struct Columns {
    n0: i64,
    start: Vec<usize>,
    intervals: Vec<(i64, i64)>,
}

impl Columns {
    /// Whether lattice point `(i_0, i_1, i_2)` is inside.
    pub fn contains(&self, idx: [i64; 3]) -> bool {
        let column = (idx[0] + self.n0 * idx[1]) as usize;
        let (Some(&a), Some(&b)) = (self.start.get(column), self.start.get(column + 1)) else {
            return false;
        };
        self.intervals
            .get(a..b)
            .unwrap_or_default()
            .iter()
            .any(|&(lo, hi)| (lo..hi).contains(&idx[2]))
    }
}

/// Where the vertical line through `(p_0, p_1)` crosses `tri`: the height z \[m\] and `+1` if
/// the triangle faces up (the line leaves the solid going up), `-1` if it faces down; `None`
/// if the line misses it (top-left rule on its edges) or the triangle is vertical.
fn crossing(tri: &Triangle, p: &[f64; 3]) -> Option<(f64, i8)> {
    let [a, b, c] = *tri;
    let area = orient(&a, &b, &c);
    if area == 0.0 {
        return None;
    }
    // Counter-clockwise in the projection.
    let (a, b, c, exit) = if area > 0.0 { (a, b, c, 1) } else { (a, c, b, -1) };
    let (wa, wb, wc) = (orient(&b, &c, p), orient(&c, &a, p), orient(&a, &b, p));
    if covers(wa, &b, &c) && covers(wb, &c, &a) && covers(wc, &a, &b) {
        Some(((wa * a[2] + wb * b[2] + wc * c[2]) / (wa + wb + wc), exit))
    } else {
        None
    }
}

/// Twice the signed area of the projection of `(a, b, p)` on the xy plane, computed with the
/// edge's ends in a canonical order so that the edge `(b, a)` gives exactly the negated value.
fn orient(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3]) -> f64 {
    let raw = |a: &[f64; 3], b: &[f64; 3]| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
    if (a[0], a[1]) <= (b[0], b[1]) {
        raw(a, b)
    } else {
        -raw(b, a)
    }
}

/// Whether a point with edge function `w` for the counter-clockwise edge `u → v` is on the
/// triangle's side: inside, or on the edge and the edge is a top or left one (the top-left
/// rule: of two triangles meeting along an edge from opposite sides exactly one claims it).
fn covers(w: f64, u: &[f64; 3], v: &[f64; 3]) -> bool {
    if w != 0.0 {
        return w > 0.0;
    }
    let (dx, dy) = (v[0] - u[0], v[1] - u[1]);
    dy < 0.0 || (dy == 0.0 && dx < 0.0)
}

/// The closed-and-oriented check of the module doc.
fn check_closed(triangles: &[Triangle]) -> Result<(), MeshError> {
    let mut ids: HashMap<[u64; 3], usize> = HashMap::new();
    let mut points: Vec<[f64; 3]> = Vec::new();
    let mut degenerate: Option<(usize, [f64; 3])> = None;
    let mut degenerate_count = 0;
    // Undirected edge (low id, high id) -> (traversals low→high, traversals high→low).
    let mut edges: HashMap<(usize, usize), (usize, usize)> = HashMap::new();
    for (t, tri) in triangles.iter().enumerate() {
        let v = tri.map(|p| {
            let next = points.len();
            *ids.entry(key(&p)).or_insert_with(|| {
                points.push(p);
                next
            })
        });
        if v[0] == v[1] || v[1] == v[2] || v[2] == v[0] {
            degenerate_count += 1;
            let at = if v[0] == v[1] || v[0] == v[2] {
                tri[0]
            } else {
                tri[1]
            };
            degenerate.get_or_insert((t, at));
            continue;
        }
        for (a, b) in [(v[0], v[1]), (v[1], v[2]), (v[2], v[0])] {
            let e = edges.entry((a.min(b), a.max(b))).or_insert((0, 0));
            if a < b {
                e.0 += 1;
            } else {
                e.1 += 1;
            }
        }
    }
    if let Some((first, at)) = degenerate {
        return Err(MeshError::Degenerate {
            count: degenerate_count,
            first,
            at,
        });
    }
    // Report in a reproducible order: by vertex ids (file order of first appearance).
    let mut sorted: Vec<_> = edges.into_iter().collect();
    sorted.sort_unstable();
    let ends = |(a, b): (usize, usize)| (points[a], points[b]);
    let open: Vec<_> = sorted.iter().filter(|(_, (f, r))| f + r == 1).collect();
    if let Some(&&(e, _)) = open.first() {
        let (from, to) = ends(e);
        return Err(MeshError::Open {
            count: open.len(),
            from,
            to,
        });
    }
    if let Some(&(e, (f, r))) = sorted.iter().find(|(_, (f, r))| f + r > 2) {
        let (from, to) = ends(e);
        return Err(MeshError::NonManifold {
            from,
            to,
            triangles: f + r,
        });
    }
    let same: Vec<_> = sorted.iter().filter(|(_, (f, r))| *f != 1 || *r != 1).collect();
    if let Some(&&(e, _)) = same.first() {
        let (from, to) = ends(e);
        return Err(MeshError::Inconsistent {
            count: same.len(),
            from,
            to,
        });
    }
    Ok(())
}

/// The 12 outward triangles of the box `[min, max]` \[m\].
pub fn box_triangles(min: [f64; 3], max: [f64; 3]) -> Vec<Triangle> {
    let corner = |i: usize| {
        [
            if i & 1 == 0 { min[0] } else { max[0] },
            if i & 2 == 0 { min[1] } else { max[1] },
            if i & 4 == 0 { min[2] } else { max[2] },
        ]
    };
    // Each face as four corners counter-clockwise seen from outside.
    let faces = [
        [0, 4, 6, 2], // x = min
        [1, 3, 7, 5], // x = max
        [0, 1, 5, 4], // y = min
        [2, 6, 7, 3], // y = max
        [0, 2, 3, 1], // z = min
        [4, 5, 7, 6], // z = max
    ];
    faces
        .iter()
        .flat_map(|f| {
            [
                [corner(f[0]), corner(f[1]), corner(f[2])],
                [corner(f[0]), corner(f[2]), corner(f[3])],
            ]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn identity() -> Placement {
        Placement {
            scale: [1.0; 3],
            rotation: Rotation3::identity(),
            translation: [0.0; 3],
        }
    }

    #[test]
    fn unit_box_is_closed_with_volume_one() {
        let m = Mesh::new(&box_triangles([0.0; 3], [1.0; 3]), &identity()).unwrap();
        // Exact: the divergence sum of a unit cube's faces is 1 up to f64 rounding.
        assert!((m.volume() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn inside_out_box_is_flipped() {
        let mut t = box_triangles([0.0; 3], [2.0; 3]);
        for tri in &mut t {
            tri.swap(0, 1);
        }
        let m = Mesh::new(&t, &identity()).unwrap();
        assert!((m.volume() - 8.0).abs() < 1e-12);
    }

    #[test]
    fn missing_and_flipped_triangles_are_named() {
        let mut t = box_triangles([0.0; 3], [1.0; 3]);
        t.pop();
        assert!(matches!(
            Mesh::new(&t, &identity()),
            Err(MeshError::Open { count: 3, .. })
        ));
        let mut t = box_triangles([0.0; 3], [1.0; 3]);
        t[0].swap(1, 2);
        assert!(matches!(
            Mesh::new(&t, &identity()),
            Err(MeshError::Inconsistent { count: 3, .. })
        ));
    }
}
