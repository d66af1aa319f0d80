//! Parallel VTK frames (`.pvtu`): one `.vtu` piece per rank (as [`super::vtu::write_vtu`]
//! writes it, each rank its own particles) and a small header that lists the pieces and their
//! arrays, which ParaView and VTK's `vtkXMLPUnstructuredGridReader` open as one dataset. A
//! `.pvd` series then lists the `.pvtu` files as it lists `.vtu` frames.
//!
//! The header declares the arrays of the [`super::vtu`] layout (`velocity`, `density`,
//! `pressure`, `kind`, `id`, the points as Float32 with 3 components); `GhostLevel="0"`: the
//! pieces hold owned particles only, never ghosts.

use std::io::Write;
use std::path::Path;

use super::xml::{self, TagKind};
use super::{OutputError, write_atomically};

/// The point arrays every piece holds: (name, VTK type, components).
const POINT_ARRAYS: [(&str, &str, usize); 5] = [
    ("velocity", "Float32", 3),
    ("density", "Float32", 1),
    ("pressure", "Float32", 1),
    ("kind", "UInt32", 1),
    ("id", "UInt32", 1),
];

/// The file name of rank `rank`'s piece of the frame named `stem` (`frame_000010` →
/// `frame_000010_r3.vtu`), beside the header.
pub fn piece_name(stem: &str, rank: usize) -> String {
    format!("{stem}_r{rank}.vtu")
}

/// Writes the header `path` that joins `pieces` (file names relative to the header's folder,
/// in rank order) atomically: a reader never sees a header without its last piece listed.
pub fn write_pvtu(path: &Path, pieces: &[String]) -> Result<(), OutputError> {
    write_atomically(path, |w| {
        w.write_all(b"<?xml version=\"1.0\"?>\n")?;
        w.write_all(
            b"<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n",
        )?;
        w.write_all(b"  <PUnstructuredGrid GhostLevel=\"0\">\n    <PPointData>\n")?;
        for (name, kind, components) in POINT_ARRAYS {
            writeln!(
                w,
                "      <PDataArray type=\"{kind}\" Name=\"{name}\" NumberOfComponents=\"{components}\"/>"
            )?;
        }
        w.write_all(b"    </PPointData>\n    <PPoints>\n")?;
        w.write_all(b"      <PDataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\"/>\n")?;
        w.write_all(b"    </PPoints>\n")?;
        for piece in pieces {
            writeln!(w, "    <Piece Source=\"{}\"/>", xml::escape(piece))?;
        }
        w.write_all(b"  </PUnstructuredGrid>\n</VTKFile>\n")
    })
}

/// The pieces a `.pvtu` header lists, in order (as [`write_pvtu`] writes them).
pub fn read_pvtu_pieces(path: &Path) -> Result<Vec<String>, OutputError> {
    let text = std::fs::read_to_string(path).map_err(|e| OutputError::io(path, e))?;
    let tags = xml::scan(&text).map_err(|e| OutputError::malformed(path, e))?;
    let mut pieces = Vec::new();
    let mut parallel = false;
    for tag in &tags {
        match (tag.name.as_str(), tag.kind) {
            ("VTKFile", TagKind::Start) => {
                if tag.attr("type") != Some("PUnstructuredGrid") {
                    return Err(OutputError::malformed(
                        path,
                        "VTKFile type is not PUnstructuredGrid",
                    ));
                }
                parallel = true;
            }
            ("Piece", TagKind::Start | TagKind::Empty) => {
                let source = tag
                    .attr("Source")
                    .ok_or_else(|| OutputError::malformed(path, "Piece without Source"))?;
                pieces.push(source.to_string());
            }
            _ => {}
        }
    }
    if !parallel {
        return Err(OutputError::malformed(
            path,
            "no <VTKFile type=\"PUnstructuredGrid\">",
        ));
    }
    Ok(pieces)
}
