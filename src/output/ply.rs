//! Binary little-endian PLY surfaces: the free surface of [`crate::surface`] for mesh tools
//! (Blender, MeshLab) that do not read VTK.
//!
//! Vertices carry `x y z nx ny nz` (float32; 2D padded with z = 0 and nz = 0). A 3D surface has
//! `element face` with `property list uchar int vertex_indices` (triangles, counter-clockwise
//! seen from outside the fluid); a 2D curve has the standard `element edge` with `vertex1
//! vertex2` (int32, the fluid on the left of vertex1 → vertex2). [`read_ply`] reads such files.

use std::io::Write;
use std::path::Path;

use super::{OutputError, fmt_f64, write_atomically};
use crate::surface::SurfaceMesh;

/// A PLY surface read back by [`read_ply`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PlySurface {
    /// Vertex positions [m].
    pub positions: Vec<[f32; 3]>,
    /// Vertex normals.
    pub normals: Vec<[f32; 3]>,
    /// Faces (3D) or edges (2D) as vertex indices.
    pub elements: Vec<Vec<u32>>,
    /// `true` for an `edge` element (2D), `false` for `face` (3D).
    pub edges: bool,
}

/// Writes `mesh` (simulated time `time` [s], recorded as a comment) to `path` atomically.
/// Errors: [`OutputError::UnsupportedDimension`] unless `D` is 2 or 3, [`OutputError::Io`].
pub fn write_ply<const D: usize>(path: &Path, mesh: &SurfaceMesh<D>, time: f64) -> Result<(), OutputError> {
    if D != 2 && D != 3 {
        return Err(OutputError::UnsupportedDimension(D));
    }
    let elements = if D == 3 {
        "element face {m}\nproperty list uchar int vertex_indices\n"
    } else {
        "element edge {m}\nproperty int vertex1\nproperty int vertex2\n"
    }
    .replace("{m}", &mesh.elements.len().to_string());
    let header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment sph free surface (eq. 25), time {} s\n\
element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
property float nx\nproperty float ny\nproperty float nz\n{elements}end_header\n",
        fmt_f64(time),
        mesh.positions.len()
    );
    write_atomically(path, |w| {
        w.write_all(header.as_bytes())?;
        for (i, x) in mesh.positions.iter().enumerate() {
            let mut row = [0f32; 6];
            for k in 0..D {
                row[k] = x[k];
                row[3 + k] = mesh.normals.get(i).map_or(0.0, |n| n[k]);
            }
            for c in row {
                w.write_all(&c.to_le_bytes())?;
            }
        }
        for e in &mesh.elements {
            if D == 3 {
                w.write_all(&[3u8])?;
            }
            for &v in e {
                // Vertex counts stay far below i32::MAX for any mesh that fits in memory as PLY.
                w.write_all(&(v as i32).to_le_bytes())?;
            }
        }
        Ok(())
    })
}

/// Reads a PLY file with exactly the layout [`write_ply`] writes; anything else is
/// [`OutputError::Malformed`] naming what differs.
pub fn read_ply(path: &Path) -> Result<PlySurface, OutputError> {
    let data = std::fs::read(path).map_err(|e| OutputError::io(path, e))?;
    let bad = |reason: String| OutputError::malformed(path, reason);
    let marker = b"end_header\n";
    let end = data
        .windows(marker.len())
        .position(|w| w == marker)
        .ok_or_else(|| bad("no end_header line".into()))?;
    let head = std::str::from_utf8(&data[..end]).map_err(|_| bad("header is not UTF-8".into()))?;
    let mut lines = head.lines();
    if lines.next() != Some("ply") || lines.next() != Some("format binary_little_endian 1.0") {
        return Err(bad("not a binary little-endian PLY file".into()));
    }
    let (mut vertices, mut elements, mut edges) = (None, None, false);
    for line in lines {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["element", "vertex", n] => vertices = n.parse::<usize>().ok(),
            ["element", kind @ ("face" | "edge"), n] => {
                elements = n.parse::<usize>().ok();
                edges = *kind == "edge";
            }
            _ => {}
        }
    }
    let (nv, ne) = vertices
        .zip(elements)
        .ok_or_else(|| bad("missing vertex or face/edge counts".into()))?;
    let mut body = &data[end + marker.len()..];
    let mut take = |n: usize| -> Result<&[u8], OutputError> {
        if body.len() < n {
            return Err(bad("body shorter than the header's counts".into()));
        }
        let (a, b) = body.split_at(n);
        body = b;
        Ok(a)
    };
    let f32_at =
        |b: &[u8], i: usize| f32::from_le_bytes([b[4 * i], b[4 * i + 1], b[4 * i + 2], b[4 * i + 3]]);
    let mut out = PlySurface {
        edges,
        ..PlySurface::default()
    };
    for _ in 0..nv {
        let row = take(24)?;
        out.positions
            .push([f32_at(row, 0), f32_at(row, 1), f32_at(row, 2)]);
        out.normals.push([f32_at(row, 3), f32_at(row, 4), f32_at(row, 5)]);
    }
    for _ in 0..ne {
        let count = if edges { 2 } else { usize::from(take(1)?[0]) };
        let row = take(4 * count)?;
        let mut element = Vec::with_capacity(count);
        for i in 0..count {
            let v = i32::from_le_bytes([row[4 * i], row[4 * i + 1], row[4 * i + 2], row[4 * i + 3]]);
            let v = u32::try_from(v).ok().filter(|&v| (v as usize) < nv);
            element.push(v.ok_or_else(|| bad("an element refers to a vertex that does not exist".into()))?);
        }
        out.elements.push(element);
    }
    if !body.is_empty() {
        return Err(bad(format!("{} bytes after the last element", body.len())));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vector;

    #[test]
    fn surface_ply_round_trips_faces_and_edges() {
        let dir = std::env::temp_dir().join(format!("sph_ply_test_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let tri = SurfaceMesh::<3> {
            positions: vec![
                Vector::<3>::new(0.0, 0.0, 0.0),
                Vector::<3>::new(1.0, 0.0, 0.0),
                Vector::<3>::new(0.0, 1.0, 0.5),
            ],
            normals: vec![Vector::<3>::new(0.0, 0.6, 0.8); 3],
            elements: vec![[0, 1, 2], [2, 1, 0]],
        };
        write_ply(&dir.join("t.ply"), &tri, 0.5).unwrap();
        let back = read_ply(&dir.join("t.ply")).unwrap();
        assert_eq!(
            back.positions,
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.5]]
        );
        assert_eq!(back.normals, vec![[0.0, 0.6, 0.8]; 3]);
        assert_eq!(
            (back.elements, back.edges),
            (vec![vec![0, 1, 2], vec![2, 1, 0]], false)
        );
        let seg = SurfaceMesh::<2> {
            positions: vec![Vector::<2>::new(0.5, 0.0), Vector::<2>::new(0.0, 2.0)],
            normals: vec![Vector::<2>::new(1.0, 0.0); 2],
            elements: vec![[0, 1]],
        };
        write_ply(&dir.join("s.ply"), &seg, 0.0).unwrap();
        let back = read_ply(&dir.join("s.ply")).unwrap();
        assert_eq!(
            (back.positions[1], back.elements.clone(), back.edges),
            ([0.0, 2.0, 0.0], vec![vec![0, 1]], true)
        );
        // A truncated body is refused.
        let bytes = std::fs::read(dir.join("s.ply")).unwrap();
        std::fs::write(dir.join("cut.ply"), &bytes[..bytes.len() - 3]).unwrap();
        assert!(matches!(
            read_ply(&dir.join("cut.ply")),
            Err(OutputError::Malformed { .. })
        ));
        std::fs::remove_dir_all(&dir).ok();
    }
}
