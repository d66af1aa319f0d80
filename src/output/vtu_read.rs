//! Reading `.vtu` frames back: the header ([`read_vtu_header`]), every array
//! ([`read_vtu`]) or the points with the point data ([`read_vtu_points`]), in the layout
//! [`super::vtu::write_vtu`] writes and in any encoding (module doc of [`super::vtu`]).

use std::path::Path;

use super::OutputError;
use super::encoding::{BlockFormat, read_block};
use super::vtu::{APPENDED_TAG, VtkType, VtuArray, VtuArrayInfo, VtuData, VtuHeader, VtuSection};
use super::xml::{self, TagKind};

fn section_of(tag: &str) -> Option<VtuSection> {
    Some(match tag {
        "FieldData" => VtuSection::FieldData,
        "PointData" => VtuSection::PointData,
        "CellData" => VtuSection::CellData,
        "Points" => VtuSection::Points,
        "Cells" => VtuSection::Cells,
        _ => return None,
    })
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

fn parse_attr<T: std::str::FromStr>(
    path: &Path,
    tag: &xml::Tag,
    key: &str,
) -> Result<Option<T>, OutputError> {
    match tag.attr(key) {
        None => Ok(None),
        Some(v) => v
            .trim()
            .parse::<T>()
            .map(Some)
            .map_err(|_| OutputError::malformed(path, format!("bad {key}=\"{v}\" in <{}>", tag.name))),
    }
}

/// Parses the XML header of an in-memory `.vtu` file with appended data.
fn parse_header(path: &Path, data: &[u8]) -> Result<VtuHeader, OutputError> {
    let bad = |reason: String| OutputError::malformed(path, reason);
    let app = find(data, APPENDED_TAG).ok_or_else(|| {
        bad("no <AppendedData> element (only files with appended data are supported)".into())
    })?;
    let after_tag = &data[app..];
    let gt = after_tag
        .iter()
        .position(|&b| b == b'>')
        .ok_or_else(|| bad("unterminated <AppendedData> tag".into()))?;
    let underscore = after_tag[gt + 1..]
        .iter()
        .position(|&b| !b.is_ascii_whitespace())
        .map(|p| app + gt + 1 + p)
        .filter(|&p| data[p] == b'_')
        .ok_or_else(|| bad("missing '_' marker at start of appended data".into()))?;
    let head = std::str::from_utf8(&data[..app + gt + 1])
        .map_err(|_| bad("XML header is not valid UTF-8".into()))?;
    let tags = xml::scan(head).map_err(bad)?;

    let mut header = VtuHeader {
        number_of_points: 0,
        number_of_cells: 0,
        time: None,
        header_u64: false,
        zlib: false,
        base64: false,
        arrays: Vec::new(),
        appended_start: (underscore + 1) as u64,
        file_len: data.len() as u64,
    };
    let mut saw_file = false;
    let mut pieces = 0usize;
    let mut section: Option<VtuSection> = None;
    for tag in &tags {
        match (tag.name.as_str(), tag.kind) {
            ("VTKFile", TagKind::Start) => {
                saw_file = true;
                if tag.attr("type") != Some("UnstructuredGrid") {
                    return Err(bad("VTKFile type is not UnstructuredGrid".into()));
                }
                match tag.attr("byte_order") {
                    Some("LittleEndian") | None => {}
                    Some(o) => return Err(bad(format!("unsupported byte_order {o}"))),
                }
                header.header_u64 = match tag.attr("header_type") {
                    Some("UInt64") => true,
                    Some("UInt32") | None => false,
                    Some(h) => return Err(bad(format!("unsupported header_type {h}"))),
                };
                header.zlib = match tag.attr("compressor") {
                    None | Some("") => false,
                    Some("vtkZLibDataCompressor") => true,
                    Some(c) => {
                        return Err(bad(format!(
                            "unsupported compressor {c} (only vtkZLibDataCompressor)"
                        )));
                    }
                };
            }
            ("Piece", TagKind::Start | TagKind::Empty) => {
                pieces += 1;
                if pieces > 1 {
                    return Err(bad("more than one Piece is not supported".into()));
                }
                header.number_of_points = parse_attr(path, tag, "NumberOfPoints")?.unwrap_or(0);
                header.number_of_cells = parse_attr(path, tag, "NumberOfCells")?.unwrap_or(0);
            }
            ("AppendedData", TagKind::Start) => {
                header.base64 = match tag.attr("encoding") {
                    Some("raw") => false,
                    Some("base64") => true,
                    other => {
                        return Err(bad(format!(
                            "AppendedData encoding {:?} is neither raw nor base64",
                            other.unwrap_or("")
                        )));
                    }
                };
            }
            ("DataArray", TagKind::Start | TagKind::Empty) => {
                let sec = section.ok_or_else(|| bad("DataArray outside a known section".into()))?;
                let ty_name = tag.attr("type").unwrap_or("");
                let data_type = VtkType::parse(ty_name)
                    .ok_or_else(|| bad(format!("unknown DataArray type \"{ty_name}\"")))?;
                let name = match tag.attr("Name") {
                    Some(n) => n.to_owned(),
                    None if sec == VtuSection::Points => "Points".to_owned(),
                    None => return Err(bad("DataArray without Name".into())),
                };
                let components: usize = parse_attr(path, tag, "NumberOfComponents")?.unwrap_or(1);
                if components == 0 {
                    return Err(bad(format!("array {name} has 0 components")));
                }
                let mut info = VtuArrayInfo {
                    section: sec,
                    name,
                    data_type,
                    components,
                    offset: None,
                    ascii_values: Vec::new(),
                };
                match tag.attr("format") {
                    Some("appended") => {
                        info.offset =
                            Some(parse_attr(path, tag, "offset")?.ok_or_else(|| {
                                bad(format!("appended array {} without offset", info.name))
                            })?);
                    }
                    Some("ascii") => {
                        if tag.kind == TagKind::Start {
                            info.ascii_values = tag
                                .text
                                .split_whitespace()
                                .map(|t| t.parse::<f64>())
                                .collect::<Result<_, _>>()
                                .map_err(|_| bad(format!("bad ascii values in {}", info.name)))?;
                        }
                        if sec == VtuSection::FieldData && info.name == "TimeValue" {
                            header.time = info.ascii_values.first().copied();
                        }
                    }
                    other => {
                        return Err(bad(format!(
                            "unsupported DataArray format {:?} for {}",
                            other.unwrap_or(""),
                            info.name
                        )));
                    }
                }
                header.arrays.push(info);
            }
            (name, TagKind::Start) if section_of(name).is_some() => {
                section = section_of(name);
            }
            (name, TagKind::End) if section_of(name).is_some() => {
                section = None;
            }
            _ => {}
        }
    }
    if !saw_file {
        return Err(bad("no <VTKFile> element".into()));
    }
    if pieces == 0 {
        return Err(bad("no <Piece> element".into()));
    }
    Ok(header)
}

/// Reads and parses only the XML header of a `.vtu` file written by
/// [`write_vtu`] (or any single-piece little-endian unstructured grid whose
/// arrays are appended, raw or base64, uncompressed or zlib-compressed).
pub fn read_vtu_header(path: &Path) -> Result<VtuHeader, OutputError> {
    let data = std::fs::read(path).map_err(|e| OutputError::io(path, e))?;
    parse_header(path, &data)
}

/// Reads a `.vtu` file written by [`write_vtu`] in any [`Encoding`] (or any
/// single-piece little-endian unstructured grid whose arrays are appended, raw
/// or base64, uncompressed or zlib-compressed).
///
/// Every appended block is bounds-checked and its size checked against the
/// header (`NumberOfPoints` x components for points and point data); any
/// inconsistency is reported as [`OutputError::Malformed`].
pub fn read_vtu(path: &Path) -> Result<VtuData, OutputError> {
    let data = std::fs::read(path).map_err(|e| OutputError::io(path, e))?;
    let header = parse_header(path, &data)?;
    let bad = |reason: String| OutputError::malformed(path, reason);
    let start = header.appended_start as usize;
    let appended = &data[start.min(data.len())..];
    let format = BlockFormat {
        header_u64: header.header_u64,
        zlib: header.zlib,
        base64: header.base64,
    };

    let mut out = VtuData {
        points: Vec::new(),
        point_data: Vec::new(),
        cells: Vec::new(),
        header: header.clone(),
    };
    let mut saw_points = false;
    for info in &header.arrays {
        let Some(offset) = info.offset else { continue };
        let tuple_bytes = info.data_type.size() * info.components;
        let expected = match info.section {
            VtuSection::Points | VtuSection::PointData => Some(header.number_of_points),
            VtuSection::CellData => Some(header.number_of_cells),
            VtuSection::Cells if info.name == "types" || info.name == "offsets" => {
                Some(header.number_of_cells)
            }
            _ => None,
        };
        // zlib inflates at most 1032-fold, which bounds an array of unknown length.
        let max_bytes = match expected {
            Some(e) => (e as u64).saturating_mul(tuple_bytes as u64),
            None => (appended.len() as u64).saturating_mul(1032),
        };
        let off = usize::try_from(offset)
            .map_err(|_| bad(format!("offset of {} lies beyond end of file", info.name)))?;
        let body = read_block(appended, off, format, max_bytes)
            .map_err(|e| bad(format!("array {}: {e}", info.name)))?;
        if body.len() % tuple_bytes != 0 {
            return Err(bad(format!(
                "block of {} has {} bytes, not a whole number of tuples",
                info.name,
                body.len()
            )));
        }
        let tuples = body.len() / tuple_bytes;
        if let Some(e) = expected
            && e != tuples
        {
            return Err(bad(format!(
                "array {} has {tuples} tuples, expected {e}",
                info.name
            )));
        }
        let values = info.data_type.decode_le(&body);
        match info.section {
            VtuSection::Points => {
                if saw_points {
                    return Err(bad("more than one Points array".into()));
                }
                saw_points = true;
                if info.components != 3 {
                    return Err(bad("Points array must have 3 components".into()));
                }
                out.points = values
                    .chunks_exact(3)
                    .map(|c| [c[0] as f32, c[1] as f32, c[2] as f32])
                    .collect();
            }
            section => {
                let arr = VtuArray {
                    name: info.name.clone(),
                    data_type: info.data_type,
                    components: info.components,
                    values,
                };
                match section {
                    VtuSection::PointData => out.point_data.push(arr),
                    VtuSection::Cells => out.cells.push(arr),
                    _ => {}
                }
            }
        }
    }
    if !saw_points && header.number_of_points > 0 {
        return Err(bad("no Points array".into()));
    }
    Ok(out)
}

/// `PointData` arrays as `(name, components, values)` triples.
pub type NamedArrays = Vec<(String, usize, Vec<f64>)>;

/// Minimal convenience reader: point coordinates plus the `PointData`
/// arrays as `(name, components, values)`.
pub fn read_vtu_points(path: &Path) -> Result<(Vec<[f32; 3]>, NamedArrays), OutputError> {
    let data = read_vtu(path)?;
    let arrays = data
        .point_data
        .into_iter()
        .map(|a| (a.name, a.components, a.values))
        .collect();
    Ok((data.points, arrays))
}
