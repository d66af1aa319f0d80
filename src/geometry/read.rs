//! Triangle meshes from files: STL (binary or ASCII) and Wavefront OBJ.
//!
//! Both formats are read here, without a crate: each is a few lines of text or a fixed binary
//! record, and the solver needs only the vertex positions of the triangles (STL's stored
//! normals are ignored; orientation comes from the vertex order, as the STL specification
//! requires it to agree with the normal). OBJ polygons are split into fans of triangles.
//!
//! References: the STL format as specified by 3D Systems (1989, "StereoLithography Interface
//! Specification"): an 80-byte header, a `u32` triangle count, then 50 bytes per triangle
//! (normal, three vertices as `f32` little-endian, a `u16` attribute); the ASCII form
//! `solid … facet normal … outer loop vertex x y z … endloop endfacet … endsolid`. OBJ: the
//! Wavefront `v x y z` and `f i j k …` records (1-based indices, negative ones counted from
//! the end, `i/t/n` forms).

use std::path::Path;

use super::mesh::{MeshError, Triangle};

/// Largest mesh file read \[bytes\]: 1 GiB, about 20 million STL triangles.
pub const MAX_MESH_BYTES: u64 = 1 << 30;

/// Reads the triangles of the STL or OBJ file at `path` (chosen by its extension, `.stl` or
/// `.obj`, any case), in file units.
///
/// # Errors
/// [`MeshError::Read`] if the file cannot be read, is not a regular file or is too large, [`MeshError::Format`] if it
/// is neither format or malformed.
pub fn read_triangles(path: &Path) -> Result<Vec<Triangle>, MeshError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    // Only a regular file, at most `MAX_MESH_BYTES` (`crate::bounded_read`).
    let read = |path: &Path| -> Result<Vec<u8>, MeshError> {
        crate::bounded_read::read_regular_file(path, MAX_MESH_BYTES)
            .map_err(|e| MeshError::Read(e.to_string()))
    };
    match ext.as_deref() {
        Some("stl") => stl(&read(path)?),
        Some("obj") => {
            let bytes = read(path)?;
            let text = std::str::from_utf8(&bytes)
                .map_err(|e| MeshError::Format(format!("OBJ file is not UTF-8 text: {e}")))?;
            obj(text)
        }
        _ => Err(MeshError::Format(
            "unknown mesh format: the file name must end in .stl or .obj".into(),
        )),
    }
}

/// An STL file's triangles: binary when its size is exactly `84 + 50 n` for the count `n` in
/// its header (an ASCII file that happens to match is read as binary, as every STL reader
/// does), else ASCII.
pub fn stl(bytes: &[u8]) -> Result<Vec<Triangle>, MeshError> {
    if let Some(count) = bytes.get(80..84) {
        let n = u32::from_le_bytes([count[0], count[1], count[2], count[3]]) as u64;
        if 84 + 50 * n == bytes.len() as u64 {
            return Ok(stl_binary(&bytes[84..]));
        }
    }
    let text = std::str::from_utf8(bytes).map_err(|_| {
        MeshError::Format(format!(
            "not a binary STL (its size {} is not 84 + 50 x the triangle count in its header) \
             and not ASCII STL text",
            bytes.len()
        ))
    })?;
    stl_ascii(text)
}

/// The 50-byte records of a binary STL (their number already checked).
fn stl_binary(records: &[u8]) -> Vec<Triangle> {
    let f = |b: &[u8]| f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    records
        .chunks_exact(50)
        .map(|r| {
            // Bytes 0..12 are the stored normal, 12..48 the vertices, 48..50 the attribute.
            std::array::from_fn(|v| std::array::from_fn(|k| f(&r[12 + 12 * v + 4 * k..])))
        })
        .collect()
}

/// ASCII STL: every `vertex x y z` line, in groups of three (one group per `facet`).
fn stl_ascii(text: &str) -> Result<Vec<Triangle>, MeshError> {
    if !text.trim_start().starts_with("solid") {
        return Err(MeshError::Format(
            "not an STL file: an ASCII STL starts with `solid`, a binary one has 84 + 50 x n bytes".into(),
        ));
    }
    let mut vertices = Vec::new();
    let mut facets = 0usize;
    for (line_no, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("facet") => facets += 1,
            Some("vertex") => {
                let v = coordinates(words, line_no + 1)?;
                vertices.push(v);
            }
            _ => {}
        }
    }
    if vertices.len() != 3 * facets {
        return Err(MeshError::Format(format!(
            "ASCII STL has {facets} facets but {} vertices (3 per facet expected)",
            vertices.len()
        )));
    }
    Ok(vertices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

/// Three numbers from `words`; `line` (1-based) names the line in the error.
fn coordinates<'a>(mut words: impl Iterator<Item = &'a str>, line: usize) -> Result<[f64; 3], MeshError> {
    let mut v = [0.0; 3];
    for c in &mut v {
        let word = words
            .next()
            .ok_or_else(|| MeshError::Format(format!("line {line}: expected three coordinates")))?;
        *c = word
            .parse()
            .map_err(|_| MeshError::Format(format!("line {line}: `{word}` is not a number")))?;
    }
    Ok(v)
}

/// Wavefront OBJ: `v` vertices and `f` faces (fans for polygons); other records are skipped.
pub fn obj(text: &str) -> Result<Vec<Triangle>, MeshError> {
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut triangles = Vec::new();
    for (line_no, line) in text.lines().enumerate() {
        let line_no = line_no + 1;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => vertices.push(coordinates(words, line_no)?),
            Some("f") => {
                let mut corners = Vec::new();
                for word in words {
                    let index = word.split('/').next().unwrap_or_default();
                    let i: i64 = index.parse().map_err(|_| {
                        MeshError::Format(format!("line {line_no}: `{word}` is not a vertex index"))
                    })?;
                    // 1-based; negative indices count back from the last vertex read so far.
                    let resolved = if i > 0 {
                        usize::try_from(i - 1).ok()
                    } else {
                        usize::try_from(i.unsigned_abs())
                            .ok()
                            .and_then(|back| vertices.len().checked_sub(back))
                    };
                    let v = resolved.and_then(|r| vertices.get(r)).ok_or_else(|| {
                        MeshError::Format(format!(
                            "line {line_no}: vertex index {i} is not among the {} vertices read so far",
                            vertices.len()
                        ))
                    })?;
                    corners.push(*v);
                }
                if corners.len() < 3 {
                    return Err(MeshError::Format(format!(
                        "line {line_no}: a face needs at least 3 vertices, found {}",
                        corners.len()
                    )));
                }
                for k in 1..corners.len() - 1 {
                    triangles.push([corners[0], corners[k], corners[k + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok(triangles)
}

/// A binary STL of `triangles` (normals from the vertex order, attribute 0): what tests and
/// `scenes/meshes` use to write meshes.
pub fn stl_binary_bytes(triangles: &[Triangle]) -> Vec<u8> {
    let mut out = Vec::with_capacity(84 + 50 * triangles.len());
    let mut header = [b' '; 80];
    let title = b"binary STL written by sph";
    header[..title.len()].copy_from_slice(title);
    out.extend_from_slice(&header);
    out.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for t in triangles {
        let [a, b, c] = t.map(nalgebra::Vector3::from);
        let n = (b - a).cross(&(c - a));
        let n = if n.norm() > 0.0 { n.normalize() } else { n };
        for x in n.iter().chain(a.iter()).chain(b.iter()).chain(c.iter()) {
            out.extend_from_slice(&(*x as f32).to_le_bytes());
        }
        out.extend_from_slice(&0u16.to_le_bytes());
    }
    out
}
