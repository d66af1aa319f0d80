//! VTK XML `PolyData` (`.vtp`) surfaces: the free surface of [`crate::surface`], triangles
//! (`Polys`) in 3D and line segments (`Lines`, one 2-point cell per segment) in 2D, with the
//! outward unit normals as the point array `Normals`. ParaView, VTK and vtkio read both.
//!
//! Layout (little-endian, `header_type="UInt64"`, the arrays appended in the run's
//! [`Encoding`], block layouts in [`super::encoding`]): `FieldData/TimeValue` (Float64, ascii)
//! [s], `PointData/Normals` (Float32 × 3), `Points` (Float32 × 3 [m], 2D padded with z = 0), then
//! `Polys` or `Lines` with `connectivity` and `offsets` (Int64). [`read_vtp`] reads such files
//! back.

use std::io::Write;
use std::path::Path;

use super::encoding::{AppendedWriter, BlockFormat, Encoding, le_bytes, read_block};
use super::vtu::{VtkType, vec3_bytes};
use super::xml::{self, TagKind};
use super::{OutputError, fmt_f64, write_atomically};
use crate::surface::SurfaceMesh;

/// A `.vtp` surface read back by [`read_vtp`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VtpSurface {
    /// The `TimeValue` field, if present [s].
    pub time: Option<f64>,
    /// Point coordinates [m].
    pub points: Vec<[f32; 3]>,
    /// The `Normals` point array (empty if absent).
    pub normals: Vec<[f32; 3]>,
    /// Cells (triangles from `Polys`, segments from `Lines`) as point indices.
    pub cells: Vec<Vec<u64>>,
    /// `true` if the cells came from `Lines`, `false` for `Polys`.
    pub lines: bool,
}

/// Writes `mesh` at simulated time `time` [s] to `path` atomically (temporary file + rename),
/// its arrays stored in `encoding`.
/// Errors: [`OutputError::UnsupportedDimension`] unless `D` is 2 or 3, [`OutputError::Io`].
pub fn write_vtp<const D: usize>(
    path: &Path,
    mesh: &SurfaceMesh<D>,
    time: f64,
    encoding: Encoding,
) -> Result<(), OutputError> {
    if D != 2 && D != 3 {
        return Err(OutputError::UnsupportedDimension(D));
    }
    let n = mesh.positions.len();
    let m = mesh.elements.len();
    let (section, count_attr) = if D == 3 {
        ("Polys", "NumberOfPolys")
    } else {
        ("Lines", "NumberOfLines")
    };
    // Normals may be absent (an unprocessed mesh): zeros rather than short data.
    let mut normals = mesh.normals.clone();
    normals.resize(n, nalgebra::SVector::zeros());
    let connectivity: Vec<i64> = mesh.elements.iter().flatten().map(|&v| i64::from(v)).collect();
    let offsets: Vec<i64> = (1..=m as i64).map(|i| i * D as i64).collect();
    let mut appended = AppendedWriter::new(encoding);
    let o = [
        appended.push(&vec3_bytes(&normals)),
        appended.push(&vec3_bytes(&mesh.positions)),
        appended.push(&le_bytes(&connectivity, i64::to_le_bytes)),
        appended.push(&le_bytes(&offsets, i64::to_le_bytes)),
    ];
    let header = format!(
        "<?xml version=\"1.0\"?>\n\
<VTKFile type=\"PolyData\" {attributes}>\n\
  <PolyData>\n\
    <FieldData>\n\
      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{time}</DataArray>\n\
    </FieldData>\n\
    <Piece NumberOfPoints=\"{n}\" {count_attr}=\"{m}\">\n\
      <PointData Normals=\"Normals\">\n\
        <DataArray type=\"Float32\" Name=\"Normals\" NumberOfComponents=\"3\" format=\"appended\" offset=\"{o0}\"/>\n\
      </PointData>\n\
      <Points>\n\
        <DataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\" format=\"appended\" offset=\"{o1}\"/>\n\
      </Points>\n\
      <{section}>\n\
        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\"{o2}\"/>\n\
        <DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"{o3}\"/>\n\
      </{section}>\n\
    </Piece>\n\
  </PolyData>\n",
        attributes = appended.file_attributes(),
        time = fmt_f64(time),
        o0 = o[0],
        o1 = o[1],
        o2 = o[2],
        o3 = o[3],
    );
    write_atomically(path, |w| {
        w.write_all(header.as_bytes())?;
        appended.write_to(w)?;
        w.write_all(b"</VTKFile>\n")
    })
}

/// Reads a single-piece little-endian `.vtp` file such as [`write_vtp`] writes, in any
/// [`Encoding`] (appended arrays, raw or base64, uncompressed or zlib-compressed).
/// Every block is bounds-checked; inconsistencies are [`OutputError::Malformed`].
pub fn read_vtp(path: &Path) -> Result<VtpSurface, OutputError> {
    let data = std::fs::read(path).map_err(|e| OutputError::io(path, e))?;
    let bad = |reason: &str| OutputError::malformed(path, reason);
    let app = data
        .windows(13)
        .position(|w| w == b"<AppendedData")
        .ok_or_else(|| bad("no <AppendedData> element"))?;
    let gt = data[app..]
        .iter()
        .position(|&b| b == b'>')
        .ok_or_else(|| bad("unterminated <AppendedData>"))?;
    let underscore = data[app + gt + 1..]
        .iter()
        .position(|&b| !b.is_ascii_whitespace())
        .map(|p| app + gt + 1 + p)
        .filter(|&p| data[p] == b'_')
        .ok_or_else(|| bad("missing '_' before the appended data"))?;
    let head = std::str::from_utf8(&data[..app + gt + 1]).map_err(|_| bad("header is not UTF-8"))?;
    let tags = xml::scan(head).map_err(|e| OutputError::malformed(path, e))?;
    let appended = &data[underscore + 1..];
    // zlib inflates at most 1032-fold, which bounds what a block header may claim.
    let max_bytes = (appended.len() as u64).saturating_mul(1032);
    let mut format = BlockFormat {
        header_u64: true,
        zlib: false,
        base64: false,
    };
    let mut out = VtpSurface::default();
    let mut section = "";
    let (mut connectivity, mut offsets) = (None, None);
    let mut saw_polydata = false;
    for tag in &tags {
        match (tag.name.as_str(), tag.kind) {
            ("VTKFile", TagKind::Start) => {
                if tag.attr("type") != Some("PolyData") {
                    return Err(bad("VTKFile type is not PolyData"));
                }
                if tag.attr("byte_order").is_some_and(|o| o != "LittleEndian") {
                    return Err(bad("only little-endian files are read"));
                }
                format.header_u64 = match tag.attr("header_type") {
                    Some("UInt64") => true,
                    Some("UInt32") | None => false,
                    Some(_) => return Err(bad("header_type is neither UInt32 nor UInt64")),
                };
                format.zlib = match tag.attr("compressor") {
                    None | Some("") => false,
                    Some("vtkZLibDataCompressor") => true,
                    Some(_) => return Err(bad("unsupported compressor (only vtkZLibDataCompressor)")),
                };
                saw_polydata = true;
            }
            ("AppendedData", TagKind::Start) => {
                format.base64 = match tag.attr("encoding") {
                    Some("raw") => false,
                    Some("base64") => true,
                    _ => return Err(bad("AppendedData encoding is neither raw nor base64")),
                };
            }
            _ => {}
        }
    }
    for tag in &tags {
        match (tag.name.as_str(), tag.kind) {
            ("DataArray", TagKind::Start | TagKind::Empty) => {
                let ty = tag
                    .attr("type")
                    .and_then(VtkType::parse)
                    .ok_or_else(|| bad("unknown DataArray type"))?;
                let name = tag.attr("Name").unwrap_or("");
                if name == "TimeValue" {
                    out.time = tag.text.trim().parse().ok();
                    continue;
                }
                let Some(offset) = tag.attr("offset") else {
                    continue;
                };
                let offset: usize = offset.trim().parse().map_err(|_| bad("bad DataArray offset"))?;
                let body = read_block(appended, offset, format, max_bytes)
                    .map_err(|e| OutputError::malformed(path, format!("array {name}: {e}")))?;
                if body.len() % ty.size() != 0 {
                    return Err(bad("block is not a whole number of values"));
                }
                let values = ty.decode_le(&body);
                let triples = |v: Vec<f64>| -> Result<Vec<[f32; 3]>, OutputError> {
                    if v.len() % 3 != 0 {
                        return Err(bad("a 3-component array has a partial tuple"));
                    }
                    Ok(v.chunks_exact(3)
                        .map(|c| [c[0] as f32, c[1] as f32, c[2] as f32])
                        .collect())
                };
                match (section, name) {
                    ("Points", _) => out.points = triples(values)?,
                    ("PointData", "Normals") => out.normals = triples(values)?,
                    ("Polys" | "Lines", "connectivity") => connectivity = Some(values),
                    ("Polys" | "Lines", "offsets") => offsets = Some(values),
                    _ => {}
                }
            }
            (name @ ("Points" | "PointData" | "Polys" | "Lines"), TagKind::Start) => {
                section = name;
                out.lines |= name == "Lines";
            }
            (_, TagKind::End) => section = "",
            _ => {}
        }
    }
    if !saw_polydata {
        return Err(bad("no <VTKFile type=\"PolyData\">"));
    }
    if let (Some(conn), Some(offs)) = (connectivity, offsets) {
        let mut start = 0usize;
        for end in offs {
            let end = end as usize;
            let cell = conn
                .get(start..end)
                .ok_or_else(|| bad("cell offsets are not increasing within connectivity"))?;
            if cell.iter().any(|&i| i < 0.0 || i as usize >= out.points.len()) {
                return Err(bad("a cell refers to a point that does not exist"));
            }
            out.cells.push(cell.iter().map(|&i| i as u64).collect());
            start = end;
        }
    }
    if !out.normals.is_empty() && out.normals.len() != out.points.len() {
        return Err(bad("Normals and Points differ in length"));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vector;

    #[test]
    fn surface_vtp_round_trips_triangles_and_segments_in_every_encoding() {
        for encoding in Encoding::ALL {
            round_trip(encoding);
        }
    }

    fn round_trip(encoding: Encoding) {
        let dir =
            std::env::temp_dir().join(format!("sph_vtp_test_{}_{}", std::process::id(), encoding.name()));
        std::fs::create_dir_all(&dir).unwrap();
        let tri = SurfaceMesh::<3> {
            positions: vec![
                Vector::<3>::new(0.0, 0.0, 0.0),
                Vector::<3>::new(1.0, 0.0, 0.0),
                Vector::<3>::new(0.0, 1.0, 0.5),
            ],
            normals: vec![Vector::<3>::new(0.0, 0.0, 1.0); 3],
            elements: vec![[0, 1, 2]],
        };
        write_vtp(&dir.join("t.vtp"), &tri, 0.25, encoding).unwrap();
        let back = read_vtp(&dir.join("t.vtp")).unwrap();
        assert_eq!(back.time, Some(0.25));
        assert_eq!(
            back.points,
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.5]]
        );
        assert_eq!(back.normals, vec![[0.0, 0.0, 1.0]; 3]);
        assert_eq!((back.cells, back.lines), (vec![vec![0, 1, 2]], false));
        let seg = SurfaceMesh::<2> {
            positions: vec![Vector::<2>::new(0.5, 0.0), Vector::<2>::new(0.0, 2.0)],
            normals: vec![Vector::<2>::new(1.0, 0.0); 2],
            elements: vec![[0, 1], [1, 0]],
        };
        write_vtp(&dir.join("s.vtp"), &seg, 1.0, encoding).unwrap();
        let back = read_vtp(&dir.join("s.vtp")).unwrap();
        assert_eq!(back.points, vec![[0.5, 0.0, 0.0], [0.0, 2.0, 0.0]]);
        assert_eq!((back.cells, back.lines), (vec![vec![0, 1], vec![1, 0]], true));
        // A truncated file is refused, not misread.
        let bytes = std::fs::read(dir.join("s.vtp")).unwrap();
        std::fs::write(dir.join("cut.vtp"), &bytes[..bytes.len() - 40]).unwrap();
        assert!(matches!(
            read_vtp(&dir.join("cut.vtp")),
            Err(OutputError::Malformed { .. })
        ));
        std::fs::remove_dir_all(&dir).ok();
    }
}
