//! VTK XML `UnstructuredGrid` (`.vtu`) frames: one vertex cell per particle, the arrays
//! appended in the run's [`Encoding`] (`[output] encoding`: zlib-compressed by default, base64
//! or raw; block layouts in [`super::encoding`]). ParaView, VTK and meshio read every encoding;
//! vtkio (splashsurf) reads `base64`.
//!
//! Layout written by [`write_vtu`] (all binary data little-endian, `header_type="UInt64"`,
//! offsets relative to the byte after the `_` marker in `<AppendedData>`):
//!
//! | section     | array          | type              | components |
//! |-------------|----------------|-------------------|------------|
//! | `FieldData` | `TimeValue`    | Float64 (ascii)   | 1          |
//! | `PointData` | `velocity`     | Float32 [m/s]     | 3          |
//! | `PointData` | `density`      | Float32 [kg/m^D]  | 1          |
//! | `PointData` | `pressure`     | Float32 [Pa]      | 1          |
//! | `PointData` | `kind`         | UInt32 (0 fluid, k the k-th solid) | 1 |
//! | `PointData` | `id`           | UInt32 (index in the initial layout, stable over the run) | 1 |
//! | `Points`    | `Points`       | Float32 [m]       | 3          |
//! | `Cells`     | `connectivity` | Int32 (Int64 if N > i32::MAX) | 1 |
//! | `Cells`     | `offsets`      | Int32 (Int64 if N > i32::MAX) | 1 |
//! | `Cells`     | `types`        | UInt8 (= 1, `VTK_VERTEX`)     | 1 |
//!
//! The particles are stored in the solver's order, which changes from frame to frame (they are
//! sorted by grid cell); `id` names the same particle in every frame. Vectors of 1D/2D runs are
//! padded with zeros to three components. [`read_vtu`] reads such files back exactly.

use std::io::Write;
use std::path::Path;

use nalgebra::SVector;

use super::encoding::{AppendedWriter, Encoding, le_bytes};
pub use super::frame::{Frame, FrameSubset};
pub use super::vtk_type::VtkType;
pub use super::vtu_read::{NamedArrays, read_vtu, read_vtu_header, read_vtu_points};
use super::{OutputError, fmt_f64, write_atomically};

/// Which part of the `Piece` a `DataArray` belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VtuSection {
    /// `<FieldData>` (dataset-wide values such as `TimeValue`).
    FieldData,
    /// `<PointData>` (one tuple per point).
    PointData,
    /// `<CellData>` (one tuple per cell).
    CellData,
    /// `<Points>` (point coordinates).
    Points,
    /// `<Cells>` (connectivity, offsets, types).
    Cells,
}

/// Description of one `DataArray` in a `.vtu` header.
#[derive(Debug, Clone, PartialEq)]
pub struct VtuArrayInfo {
    /// Section the array appears in.
    pub section: VtuSection,
    /// The `Name` attribute (`"Points"` if a `Points` array has none).
    pub name: String,
    /// Scalar type.
    pub data_type: VtkType,
    /// `NumberOfComponents` (1 if absent).
    pub components: usize,
    /// Byte offset of the block within the appended data (relative to the
    /// byte after `_`); `None` for inline ascii arrays.
    pub offset: Option<u64>,
    /// Values of an inline ascii array (empty for appended arrays).
    pub ascii_values: Vec<f64>,
}

/// Parsed header of a `.vtu` file with appended data.
#[derive(Debug, Clone, PartialEq)]
pub struct VtuHeader {
    /// `NumberOfPoints` of the (single) piece.
    pub number_of_points: usize,
    /// `NumberOfCells` of the (single) piece.
    pub number_of_cells: usize,
    /// The `TimeValue` field-data value, if present.
    pub time: Option<f64>,
    /// `true` if `header_type="UInt64"`, `false` for `UInt32`.
    pub header_u64: bool,
    /// `true` if the blocks are zlib-compressed (`compressor="vtkZLibDataCompressor"`).
    pub zlib: bool,
    /// `true` if the appended data is base64 text (`encoding="base64"`), `false` for raw bytes.
    pub base64: bool,
    /// All data arrays in document order.
    pub arrays: Vec<VtuArrayInfo>,
    /// Absolute file position of the first appended byte (just after `_`).
    pub appended_start: u64,
    /// Total file length in bytes.
    pub file_len: u64,
}

/// One data array read back from a `.vtu` file.
#[derive(Debug, Clone, PartialEq)]
pub struct VtuArray {
    /// Array name.
    pub name: String,
    /// Scalar type stored in the file.
    pub data_type: VtkType,
    /// Number of components per tuple.
    pub components: usize,
    /// All values, tuple-major, converted to `f64` (exact for `Float32`,
    /// `Float64` and integers up to 32 bits).
    pub values: Vec<f64>,
}

/// Contents of a `.vtu` file read by [`read_vtu`].
#[derive(Debug, Clone, PartialEq)]
pub struct VtuData {
    /// Parsed header.
    pub header: VtuHeader,
    /// Point coordinates (converted to `f32`; exact for `Float32` files).
    pub points: Vec<[f32; 3]>,
    /// `PointData` arrays in document order.
    pub point_data: Vec<VtuArray>,
    /// `Cells` arrays (`connectivity`, `offsets`, `types`) in document order.
    pub cells: Vec<VtuArray>,
}

impl VtuData {
    /// The `PointData` array called `name`.
    pub fn point_array(&self, name: &str) -> Option<&VtuArray> {
        self.point_data.iter().find(|a| a.name == name)
    }

    /// The `Cells` array called `name`.
    pub fn cell_array(&self, name: &str) -> Option<&VtuArray> {
        self.cells.iter().find(|a| a.name == name)
    }
}

/// The opening of the appended-data section.
pub(super) const APPENDED_TAG: &[u8] = b"<AppendedData";

/// Writes `frame` as a VTK XML unstructured grid with its arrays appended in `encoding` (see
/// the [module documentation](self) for the layout).
///
/// The file is written to a unique temporary sibling and then renamed onto
/// `path`. Errors: [`OutputError::LengthMismatch`] if the slices differ in
/// length, [`OutputError::UnsupportedDimension`] if `D > 3`,
/// [`OutputError::Io`] on any file-system failure.
pub fn write_vtu<const D: usize>(
    path: &Path,
    frame: &Frame<D>,
    encoding: Encoding,
) -> Result<(), OutputError> {
    if D > 3 {
        return Err(OutputError::UnsupportedDimension(D));
    }
    let n = frame.checked_len()?;
    let wide = n > i32::MAX as usize;
    let int_type = if wide { VtkType::Int64 } else { VtkType::Int32 };
    let counting = move |first: usize| -> Vec<u8> {
        if wide {
            le_bytes(
                &(first..first + n).map(|i| i as i64).collect::<Vec<_>>(),
                i64::to_le_bytes,
            )
        } else {
            le_bytes(
                &(first..first + n).map(|i| i as i32).collect::<Vec<_>>(),
                i32::to_le_bytes,
            )
        }
    };
    let f32s = |v: &[f32]| le_bytes(v, f32::to_le_bytes);
    let u32s = |v: &[u32]| le_bytes(v, u32::to_le_bytes);
    type Bytes<'a> = Box<dyn Fn() -> Vec<u8> + 'a>;
    // (section, name, type, components, little-endian bytes). Each array's bytes are made
    // when it is encoded and dropped after, so a frame holds one raw array at a time.
    let blocks: [(VtuSection, &str, VtkType, usize, Bytes<'_>); 9] = [
        (
            VtuSection::PointData,
            "velocity",
            VtkType::Float32,
            3,
            Box::new(|| vec3_bytes(frame.velocity)),
        ),
        (
            VtuSection::PointData,
            "density",
            VtkType::Float32,
            1,
            Box::new(|| f32s(frame.density)),
        ),
        (
            VtuSection::PointData,
            "pressure",
            VtkType::Float32,
            1,
            Box::new(|| f32s(frame.pressure)),
        ),
        (
            VtuSection::PointData,
            "kind",
            VtkType::UInt32,
            1,
            Box::new(|| u32s(frame.kind)),
        ),
        (
            VtuSection::PointData,
            "id",
            VtkType::UInt32,
            1,
            Box::new(|| u32s(frame.id)),
        ),
        (
            VtuSection::Points,
            "Points",
            VtkType::Float32,
            3,
            Box::new(|| vec3_bytes(frame.position)),
        ),
        (
            VtuSection::Cells,
            "connectivity",
            int_type,
            1,
            Box::new(move || counting(0)),
        ),
        (
            VtuSection::Cells,
            "offsets",
            int_type,
            1,
            Box::new(move || counting(1)),
        ),
        (
            VtuSection::Cells,
            "types",
            VtkType::UInt8,
            1,
            Box::new(move || vec![VTK_VERTEX; n]),
        ),
    ];
    let mut appended = AppendedWriter::new(encoding);
    let int_size = int_type.size();
    appended.reserve(&[
        12 * n,
        4 * n,
        4 * n,
        4 * n,
        4 * n,
        12 * n,
        int_size * n,
        int_size * n,
        n,
    ]);

    let mut header = String::with_capacity(2048);
    header.push_str("<?xml version=\"1.0\"?>\n");
    header.push_str(&format!(
        "<VTKFile type=\"UnstructuredGrid\" {}>\n",
        appended.file_attributes()
    ));
    header.push_str("  <UnstructuredGrid>\n");
    header.push_str("    <FieldData>\n");
    header.push_str(&format!(
        "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n",
        fmt_f64(frame.time)
    ));
    header.push_str("    </FieldData>\n");
    header.push_str(&format!(
        "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{n}\">\n"
    ));
    let mut open: Option<VtuSection> = None;
    for (section, name, ty, comps, bytes) in &blocks {
        if open != Some(*section) {
            if let Some(prev) = open {
                header.push_str(&format!("      </{}>\n", section_tag(prev)));
            }
            if *section == VtuSection::PointData {
                header.push_str("      <PointData Scalars=\"density\" Vectors=\"velocity\">\n");
            } else {
                header.push_str(&format!("      <{}>\n", section_tag(*section)));
            }
            open = Some(*section);
        }
        let comp_attr = if *comps > 1 {
            format!(" NumberOfComponents=\"{comps}\"")
        } else {
            String::new()
        };
        let offset = appended.push(&bytes());
        header.push_str(&format!(
            "        <DataArray type=\"{}\" Name=\"{name}\"{comp_attr} format=\"appended\" offset=\"{offset}\"/>\n",
            ty.name()
        ));
    }
    drop(blocks);
    if let Some(prev) = open {
        header.push_str(&format!("      </{}>\n", section_tag(prev)));
    }
    header.push_str("    </Piece>\n");
    header.push_str("  </UnstructuredGrid>\n");

    write_atomically(path, |w| {
        w.write_all(header.as_bytes())?;
        appended.write_to(w)?;
        w.write_all(b"</VTKFile>\n")
    })
}

/// VTK's cell type of a single point.
const VTK_VERTEX: u8 = 1;

/// Vectors as three little-endian `f32` components each, zero-padded.
pub(crate) fn vec3_bytes<const D: usize>(v: &[SVector<f32, D>]) -> Vec<u8> {
    let mut out = Vec::with_capacity(12 * v.len());
    for p in v {
        let mut xyz = [0f32; 3];
        for c in 0..D.min(3) {
            xyz[c] = p[c];
        }
        for c in xyz {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    out
}

/// The tag of a `Piece` section.
pub(super) fn section_tag(s: VtuSection) -> &'static str {
    match s {
        VtuSection::FieldData => "FieldData",
        VtuSection::PointData => "PointData",
        VtuSection::CellData => "CellData",
        VtuSection::Points => "Points",
        VtuSection::Cells => "Cells",
    }
}
