//! Meshes the tests write: boxes, spheres and cylinders as triangle lists, and scene texts
//! around one solid.

use std::f64::consts::PI;
use std::fmt::Write;
use std::path::Path;

pub use sph::geometry::Triangle;
pub use sph::geometry::mesh::box_triangles;

/// An icosphere of `radius` about the origin: the icosahedron subdivided `levels` times, its
/// vertices pushed onto the sphere (20 · 4^levels triangles, outward).
pub fn icosphere(radius: f64, levels: u32) -> Vec<Triangle> {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<[f64; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .to_vec();
    let mut f: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let norm = |p: [f64; 3]| {
        let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        p.map(|c| c / n)
    };
    for p in &mut v {
        *p = norm(*p);
    }
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::new();
        let mut midpoint = |a: usize, b: usize, v: &mut Vec<[f64; 3]>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (v[a], v[b]);
                v.push(norm([
                    (p[0] + q[0]) / 2.0,
                    (p[1] + q[1]) / 2.0,
                    (p[2] + q[2]) / 2.0,
                ]));
                v.len() - 1
            })
        };
        for &[a, b, c] in &f {
            let ab = midpoint(a, b, &mut v);
            let bc = midpoint(b, c, &mut v);
            let ca = midpoint(c, a, &mut v);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = next;
    }
    f.iter().map(|t| t.map(|i| v[i].map(|c| c * radius))).collect()
}

/// A cylinder of `radius` and `length` about the origin along y, its circle a regular polygon
/// of `sides` vertices (a multiple of 4, so that the polygon reaches ±radius along x and z
/// exactly), capped by fans (outward).
pub fn cylinder_y(radius: f64, length: f64, sides: usize) -> Vec<Triangle> {
    let ring = |k: usize, y: f64| {
        let k = k % sides;
        let a = 2.0 * PI * k as f64 / sides as f64;
        // Exact extremes: cos and sin of multiples of π/2 are not exact in f64.
        let (c, s) = if (4 * k) % sides == 0 {
            [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][4 * k / sides]
        } else {
            (a.cos(), a.sin())
        };
        [radius * c, y, radius * s]
    };
    let (lo, hi) = (-0.5 * length, 0.5 * length);
    let (bottom, top) = ([0.0, lo, 0.0], [0.0, hi, 0.0]);
    let mut t = Vec::new();
    for k in 0..sides {
        // Seen from +y, increasing k runs clockwise (x then −z); the side faces point outward.
        let (a0, a1, b0, b1) = (ring(k, lo), ring(k + 1, lo), ring(k, hi), ring(k + 1, hi));
        t.push([a0, b0, a1]);
        t.push([a1, b0, b1]);
        t.push([top, b1, b0]);
        t.push([bottom, a0, a1]);
    }
    t
}

/// ASCII STL text of `triangles`, coordinates written so that they read back exactly.
pub fn ascii_stl(triangles: &[Triangle]) -> String {
    let mut s = String::from("solid test\n");
    for tri in triangles {
        s.push_str("  facet normal 0 0 0\n    outer loop\n");
        for v in tri {
            let _ = writeln!(s, "      vertex {:?} {:?} {:?}", v[0], v[1], v[2]);
        }
        s.push_str("    endloop\n  endfacet\n");
    }
    s.push_str("endsolid test\n");
    s
}

/// Writes `triangles` to `dir/name` as ASCII STL (`.stl`) or binary (`.bin.stl` suffix not
/// used: `binary` chooses), returning the path as a TOML string.
pub fn write_stl(dir: &Path, name: &str, triangles: &[Triangle], binary: bool) -> String {
    let path = dir.join(name);
    if binary {
        std::fs::write(&path, sph::geometry::read::stl_binary_bytes(triangles)).expect("write STL");
    } else {
        std::fs::write(&path, ascii_stl(triangles)).expect("write STL");
    }
    path.to_str().expect("utf-8 temp path").replace('\\', "/")
}

/// A 3D scene without gravity: domain `[0, 1]^3`, one fluid box in a corner, and `solid`
/// (the lines of one `[[solid]]` table, name "body"), spacing `dx`.
pub fn scene_3d(dx: f64, solid: &str) -> String {
    format!(
        r#"
dimension = 3
[domain]
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
[particles]
spacing = {dx}
smoothing_ratio = 2.0
[fluid]
rho0 = 1000.0
sound_speed = 20.0
[[fluid_box]]
min = [0.9, 0.9, 0.9]
max = [1.0, 1.0, 1.0]
[[solid]]
name = "body"
{solid}
[solver]
kind = "wcsph"
end_time = 0.01
"#
    )
}

/// The 2D counterpart of [`scene_3d`]: domain `[0, 1]^2`.
pub fn scene_2d(dx: f64, solid: &str) -> String {
    format!(
        r#"
dimension = 2
[domain]
min = [0.0, 0.0]
max = [1.0, 1.0]
[particles]
spacing = {dx}
smoothing_ratio = 2.0
[fluid]
rho0 = 1000.0
sound_speed = 20.0
[[fluid_box]]
min = [0.9, 0.9]
max = [1.0, 1.0]
[[solid]]
name = "body"
{solid}
[solver]
kind = "wcsph"
end_time = 0.01
"#
    )
}
