//! Append-only CSV logs: a generic [`CsvTable`] and the per-solid
//! [`ForceLog`].
//!
//! Floating-point values are written in Rust's shortest round-trip
//! representation (plain notation for moderate magnitudes, exponent notation
//! otherwise), so parsing a field with `str::parse::<f64>` gives back the
//! exact value. Text fields containing `,`, `"`, CR or LF are quoted with
//! doubled quotes (RFC 4180).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use super::{OutputError, fmt_f64};

/// One field of a CSV row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CsvValue<'a> {
    /// A floating-point number, written so that it round-trips exactly.
    Float(f64),
    /// An integer.
    Int(i64),
    /// Text, quoted if necessary.
    Text(&'a str),
}

impl From<f64> for CsvValue<'_> {
    fn from(x: f64) -> Self {
        CsvValue::Float(x)
    }
}

impl From<i64> for CsvValue<'_> {
    fn from(x: i64) -> Self {
        CsvValue::Int(x)
    }
}

impl<'a> From<&'a str> for CsvValue<'a> {
    fn from(s: &'a str) -> Self {
        CsvValue::Text(s)
    }
}

fn write_text<W: Write>(w: &mut W, s: &str) -> std::io::Result<()> {
    if s.contains([',', '"', '\n', '\r']) {
        w.write_all(b"\"")?;
        w.write_all(s.replace('"', "\"\"").as_bytes())?;
        w.write_all(b"\"")
    } else {
        w.write_all(s.as_bytes())
    }
}

/// A CSV file with a fixed header, written row by row.
///
/// Rows are buffered; call [`flush`](Self::flush) to push them to the file
/// (the buffer is also flushed, ignoring errors, when the table is dropped).
#[derive(Debug)]
pub struct CsvTable {
    path: PathBuf,
    columns: usize,
    writer: BufWriter<File>,
}

impl CsvTable {
    /// Creates (truncates) `path` and writes the header line.
    pub fn create(path: &Path, columns: &[&str]) -> Result<Self, OutputError> {
        let file = File::create(path).map_err(|e| OutputError::io(path, e))?;
        let mut table = CsvTable {
            path: path.to_path_buf(),
            columns: columns.len(),
            writer: BufWriter::with_capacity(1 << 16, file),
        };
        let header: Vec<CsvValue> = columns.iter().map(|c| CsvValue::Text(c)).collect();
        table.push_row(&header)?;
        Ok(table)
    }

    /// Reopens a table written before a checkpoint: cuts `path` back to its first `len` bytes
    /// (what it held at the checkpoint; rows written after it are dropped) and appends from
    /// there. The header must be `columns` ([`OutputError::Malformed`] otherwise).
    pub fn resume(path: &Path, columns: &[&str], len: u64) -> Result<Self, OutputError> {
        let io = |e| OutputError::io(path, e);
        let mut file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .open(path)
            .map_err(io)?;
        let mut first = String::new();
        {
            use std::io::BufRead;
            let mut reader = std::io::BufReader::new(&mut file);
            reader.read_line(&mut first).map_err(io)?;
        }
        if first.trim_end() != columns.join(",") {
            return Err(OutputError::malformed(path, "its header is not this scene's"));
        }
        if (file.metadata().map_err(io)?.len()) < len {
            return Err(OutputError::malformed(path, "shorter than at the checkpoint"));
        }
        file.set_len(len).map_err(io)?;
        use std::io::Seek;
        file.seek(std::io::SeekFrom::End(0)).map_err(io)?;
        Ok(CsvTable {
            path: path.to_path_buf(),
            columns: columns.len(),
            writer: BufWriter::with_capacity(1 << 16, file),
        })
    }

    /// Flushes and returns the file's length [bytes] (kept with a checkpoint).
    pub fn len_on_disk(&mut self) -> Result<u64, OutputError> {
        self.flush()?;
        let file = self.writer.get_ref();
        file.metadata()
            .map(|m| m.len())
            .map_err(|e| OutputError::io(&self.path, e))
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Appends one row; it must have exactly as many fields as the header
    /// ([`OutputError::RowLength`] otherwise, nothing written).
    pub fn push_row(&mut self, row: &[CsvValue]) -> Result<(), OutputError> {
        if row.len() != self.columns {
            return Err(OutputError::RowLength {
                path: self.path.clone(),
                expected: self.columns,
                found: row.len(),
            });
        }
        // The row is formatted whole and handed to the buffer in one piece, so the buffer only
        // ever writes complete rows to the file: a run killed at any moment leaves whole lines.
        let mut line: Vec<u8> = Vec::with_capacity(16 * row.len());
        let result = (|| {
            for (i, v) in row.iter().enumerate() {
                if i > 0 {
                    line.write_all(b",")?;
                }
                match v {
                    CsvValue::Float(x) => line.write_all(fmt_f64(*x).as_bytes())?,
                    CsvValue::Int(x) => write!(line, "{x}")?,
                    CsvValue::Text(s) => write_text(&mut line, s)?,
                }
            }
            line.write_all(b"\n")?;
            self.writer.write_all(&line)
        })();
        result.map_err(|e| OutputError::io(&self.path, e))
    }

    /// Flushes buffered rows to the file.
    pub fn flush(&mut self) -> Result<(), OutputError> {
        self.writer.flush().map_err(|e| OutputError::io(&self.path, e))
    }
}

/// Log of the hydrodynamic force on each named solid over time, with header
/// `t,solid,fx,fy,fz` (time in s, force in N, or N/m in 2D; `fz = 0` in 2D).
#[derive(Debug)]
pub struct ForceLog {
    table: CsvTable,
}

impl ForceLog {
    /// The header columns.
    pub const COLUMNS: [&'static str; 5] = ["t", "solid", "fx", "fy", "fz"];

    /// Creates (truncates) `path` and writes the header.
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        Ok(ForceLog {
            table: CsvTable::create(path, &Self::COLUMNS)?,
        })
    }

    /// Reopens `path` at its length `len` at a checkpoint ([`CsvTable::resume`]).
    pub fn resume(path: &Path, len: u64) -> Result<Self, OutputError> {
        Ok(ForceLog {
            table: CsvTable::resume(path, &Self::COLUMNS, len)?,
        })
    }

    /// Flushes and returns the file's length [bytes].
    pub fn len_on_disk(&mut self) -> Result<u64, OutputError> {
        self.table.len_on_disk()
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        self.table.path()
    }

    /// Appends the force on solid `solid` at time `t`.
    pub fn push(&mut self, t: f64, solid: &str, force: [f64; 3]) -> Result<(), OutputError> {
        self.table.push_row(&[
            CsvValue::Float(t),
            CsvValue::Text(solid),
            CsvValue::Float(force[0]),
            CsvValue::Float(force[1]),
            CsvValue::Float(force[2]),
        ])
    }

    /// Flushes buffered rows to the file (call after each output frame).
    pub fn flush(&mut self) -> Result<(), OutputError> {
        self.table.flush()
    }
}
