//! Result output: VTK XML unstructured-grid frames ([`vtu`]), ParaView
//! `.pvd` time series ([`pvd`]), CSV logs ([`csv`], with the column convention; read back
//! by [`csv_read`]) and the JSON run summary ([`summary`]); free-surface meshes as VTK
//! polydata ([`vtp`]). The binary arrays of the VTK files are stored zlib-compressed, base64
//! or raw ([`encoding`]).
//!
//! Every whole-file writer (`.vtu`, `.vtp`, `.pvd`, `.json`) writes to a uniquely named
//! temporary sibling, created exclusively ([`safe_file`]), and then renames it over the
//! target, so a crash never leaves a half-written file behind and a planted link is never
//! written through. CSV logs are append-only, created exclusively and flushed explicitly.
//!
//! No function in this module panics on I/O problems or malformed input;
//! everything is reported through [`OutputError`].

pub mod bodies;
pub mod csv;
pub mod csv_read;
pub mod encoding;
pub mod frame;
pub mod plot;
pub mod pvd;
pub mod pvtu;
pub mod safe_file;
pub mod summary;
pub mod surface_series;
pub mod vtk_type;
pub mod vtp;
pub mod vtu;
pub mod vtu_read;
mod xml;

use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

pub use csv::{CsvTable, CsvValue, ForceLog, force_unit, format_row};
pub use csv_read::{CsvFile, CsvReadError};
pub use encoding::Encoding;
pub use pvd::PvdSeries;
pub use summary::{Summary, read_summary, write_summary};
pub use vtu::{
    Frame, FrameSubset, NamedArrays, VtkType, VtuArray, VtuArrayInfo, VtuData, VtuHeader, VtuSection,
    read_vtu, read_vtu_header, read_vtu_points, write_vtu,
};

/// Errors produced by the output module.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// An operating-system I/O operation on `path` failed.
    #[error("I/O error on {}: {source}", path.display())]
    Io {
        /// The file or directory the failing operation touched.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The per-particle slices of a frame do not all have the same length.
    #[error("frame field `{field}` has {found} entries, expected {expected} (length of `position`)")]
    LengthMismatch {
        /// Name of the offending field.
        field: &'static str,
        /// Number of particles (length of `position`).
        expected: usize,
        /// Length of the offending field.
        found: usize,
    },
    /// The spatial dimension is not supported by the VTK writer (must be at most 3).
    #[error("unsupported spatial dimension {0} (VTK output supports 1, 2 or 3)")]
    UnsupportedDimension(usize),
    /// A CSV row had the wrong number of fields.
    #[error("CSV row for {} has {found} fields, expected {expected}", path.display())]
    RowLength {
        /// The CSV file.
        path: PathBuf,
        /// Number of columns in the header.
        expected: usize,
        /// Number of fields in the rejected row.
        found: usize,
    },
    /// A file being read is not in the expected format.
    #[error("malformed file {}: {reason}", path.display())]
    Malformed {
        /// The file being read.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// A CSV file being read is malformed (naming its line and column).
    #[error(transparent)]
    Csv(#[from] CsvReadError),
    /// JSON (de)serialisation failed.
    #[error("JSON error on {}: {source}", path.display())]
    Json {
        /// The JSON file.
        path: PathBuf,
        /// The underlying serde_json error.
        #[source]
        source: serde_json::Error,
    },
}

impl OutputError {
    /// Builds an [`OutputError::Io`] for `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        OutputError::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    /// Builds an [`OutputError::Malformed`] for `path`.
    pub fn malformed(path: &Path, reason: impl Into<String>) -> Self {
        OutputError::Malformed {
            path: path.to_path_buf(),
            reason: reason.into(),
        }
    }
}

/// Capacity of the buffered writers used for output files (1 MiB).
const BUF_CAPACITY: usize = 1 << 20;

/// Writes a file atomically: `body` writes into a buffered temporary file,
/// which is flushed and then renamed over `path`. On failure the temporary
/// file is removed (best effort) and the target is left untouched.
pub(crate) fn write_atomically<F>(path: &Path, body: F) -> Result<(), OutputError>
where
    F: FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
{
    let tmp = safe_file::unique_tmp_path(path, "");
    let file = safe_file::create_new(&tmp).map_err(|e| OutputError::io(path, e))?;
    let mut writer = BufWriter::with_capacity(BUF_CAPACITY, file);
    let written = body(&mut writer).and_then(|()| writer.flush());
    drop(writer);
    if let Err(e) = written {
        let _ = fs::remove_file(&tmp);
        return Err(OutputError::io(path, e));
    }
    if let Err(e) = fs::rename(&tmp, path) {
        let _ = fs::remove_file(&tmp);
        return Err(OutputError::io(path, e));
    }
    Ok(())
}

/// Formats an `f64` so that parsing the text gives back the identical value
/// (Rust's shortest round-trip representation), using plain notation for
/// moderate magnitudes and exponent notation otherwise.
pub(crate) fn fmt_f64(x: f64) -> String {
    let a = x.abs();
    if !x.is_finite() || a == 0.0 || (1e-5..1e16).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fmt_round_trips() {
        for x in [
            0.0,
            -0.0,
            1.0,
            0.1,
            1e-300,
            -3.5e300,
            f64::MIN_POSITIVE,
            f64::MAX,
            123456.789,
            1e-5,
            9.99e15,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ] {
            let s = fmt_f64(x);
            let y: f64 = s.parse().unwrap();
            assert_eq!(x.to_bits(), y.to_bits(), "{s}");
        }
        assert!(fmt_f64(f64::NAN).parse::<f64>().unwrap().is_nan());
    }
}
