//! VTK XML `PolyData` (`.vtp`) surfaces with raw appended binary data: the free surface of
//! [`crate::surface`], triangles (`Polys`) in 3D and line segments (`Lines`) in 2D, with the
//! outward unit normals as the point array `Normals`.
//!
//! Layout (little-endian, each block preceded by a `UInt64` byte count, as in [`super::vtu`]):
//! `FieldData/TimeValue` (Float64, ascii), `PointData/Normals` (Float32 × 3), `Points`
//! (Float32 × 3, 2D padded with z = 0), then `Polys` or `Lines` with `connectivity` and
//! `offsets` (Int64). [`read_vtp`] reads such files back.

use std::io::Write;
use std::path::Path;

use super::vtu::VtkType;
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

/// Writes `mesh` at simulated time `time` [s] to `path` atomically (temporary file + rename).
/// Errors: [`OutputError::UnsupportedDimension`] unless `D` is 2 or 3, [`OutputError::Io`].
pub fn write_vtp<const D: usize>(path: &Path, mesh: &SurfaceMesh<D>, time: f64) -> Result<(), OutputError> {
    if D != 2 && D != 3 {
        return Err(OutputError::UnsupportedDimension(D));
    }
    let n = mesh.positions.len() as u64;
    let m = mesh.elements.len() as u64;
    let (section, count_attr) = if D == 3 {
        ("Polys", "NumberOfPolys")
    } else {
        ("Lines", "NumberOfLines")
    };
    let sizes = [n * 12, n * 12, m * D as u64 * 8, m * 8];
    let mut offsets = [0u64; 4];
    for i in 1..4 {
        offsets[i] = offsets[i - 1] + 8 + sizes[i - 1];
    }
    let header = format!(
        "<?xml version=\"1.0\"?>\n\
<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n\
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
  </PolyData>\n\
  <AppendedData encoding=\"raw\">\n   _",
        time = fmt_f64(time),
        o0 = offsets[0],
        o1 = offsets[1],
        o2 = offsets[2],
        o3 = offsets[3],
    );
    write_atomically(path, |w| {
        w.write_all(header.as_bytes())?;
        for (block, vectors) in [&mesh.normals, &mesh.positions].into_iter().enumerate() {
            w.write_all(&sizes[block].to_le_bytes())?;
            // Normals may be absent (an unprocessed mesh): write zeros rather than short data.
            for i in 0..mesh.positions.len() {
                let mut xyz = [0f32; 3];
                if let Some(v) = vectors.get(i) {
                    for k in 0..D {
                        xyz[k] = v[k];
                    }
                }
                for c in xyz {
                    w.write_all(&c.to_le_bytes())?;
                }
            }
        }
        w.write_all(&sizes[2].to_le_bytes())?;
        for e in &mesh.elements {
            for &v in e {
                w.write_all(&i64::from(v).to_le_bytes())?;
            }
        }
        w.write_all(&sizes[3].to_le_bytes())?;
        for i in 1..=m {
            w.write_all(&((i * D as u64) as i64).to_le_bytes())?;
        }
        w.write_all(b"\n  </AppendedData>\n</VTKFile>\n")
    })
}

/// Reads a raw-appended, uncompressed, single-piece `.vtp` file such as [`write_vtp`] writes.
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
    let block = |offset: &str, ty: VtkType| -> Result<Vec<f64>, OutputError> {
        let off: usize = offset.trim().parse().map_err(|_| bad("bad DataArray offset"))?;
        let len_bytes = appended
            .get(off..off + 8)
            .ok_or_else(|| bad("block offset past end of file"))?;
        let mut len = [0u8; 8];
        len.copy_from_slice(len_bytes);
        let len = usize::try_from(u64::from_le_bytes(len)).map_err(|_| bad("block too long"))?;
        let body = off
            .checked_add(8 + len)
            .and_then(|end| appended.get(off + 8..end))
            .ok_or_else(|| bad("block runs past end of file"))?;
        if body.len() % ty.size() != 0 {
            return Err(bad("block is not a whole number of values"));
        }
        Ok(ty.decode_le(body))
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
                if tag.attr("header_type") != Some("UInt64") || tag.attr("byte_order") != Some("LittleEndian")
                {
                    return Err(bad("only little-endian files with UInt64 block headers are read"));
                }
                saw_polydata = true;
            }
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
                let values = block(offset, ty)?;
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
    fn surface_vtp_round_trips_triangles_and_segments() {
        let dir = std::env::temp_dir().join(format!("sph_vtp_test_{}", std::process::id()));
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
        write_vtp(&dir.join("t.vtp"), &tri, 0.25).unwrap();
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
        write_vtp(&dir.join("s.vtp"), &seg, 1.0).unwrap();
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
