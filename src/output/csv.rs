//! Append-only CSV logs: a generic [`CsvTable`] and the per-solid [`ForceLog`]; files are read
//! back with [`super::csv_read::CsvFile`].
//!
//! Floating-point values are written in Rust's shortest round-trip representation (plain
//! notation for moderate magnitudes, exponent notation otherwise), so parsing a field with
//! `str::parse::<f64>` gives back the exact value; non-finite values are written `NaN`, `inf`,
//! `-inf`. Text fields containing `,`, `"`, CR or LF are quoted with doubled quotes (RFC 4180).
//!
//! # Column convention
//!
//! Every CSV file the program writes has one header row, and every column that holds a quantity
//! with a unit ends in the unit: `_s` (seconds), `_m` (metres), `_N` (newtons), `_m_per_s`,
//! `_per_s` (per second), `_B` (bytes). Forces of a 2D run are per metre of depth and their
//! columns say so: `_N_per_m` in 2D, `_N` in 3D ([`force_unit`]); a 2D file has no `z`
//! component. Counts, names and dimensionless ratios carry no unit and are named for what they
//! are (`step`, `particles`, `correction_iterations`, `max_compression`, `speedup`).
//!
//! The files, and their columns:
//! - `steps.csv` (`sph run`, one row per step): `step`, `t_s` (time at the step's end), `dt_s`,
//!   `limit` (the criterion that chose `dt`), `max_speed_m_per_s`, `max_compression`,
//!   `max_surface_deficit`, `correction_iterations`. The two density columns are taken on the
//!   state at the step's start (see `crate::output::summary::Summary::max_compression`):
//!   `max_compression` = max over fluid particles of `max(ρ − ρ0, 0)/ρ0`, `max_surface_deficit`
//!   = max over fluid particles of `max(ρ0 − ρ, 0)/ρ0`.
//! - `forces.csv` (`sph run`, one row per solid per step): 3D `t_s, solid, fx_N, fy_N, fz_N`;
//!   2D `t_s, solid, fx_N_per_m, fy_N_per_m` (the force of the fluid on the solid).
//! - `probes.csv` (`sph run` with `[[probe]]`): `t_s`, then per probe `<probe>_m` (a front) or
//!   `<probe>_N` (a force; `<probe>_N_per_m` in 2D).
//! - `sweep.csv` (`sph sweep`, one row per variant): `variant`, one column per swept scene key
//!   (named by the key, the value as given), `wall_s`, `wall_s_per_simulated_s`,
//!   `particle_steps_per_s`, `steps`, `correction_iterations_mean`, `correction_iterations_max`,
//!   `velocity_iterations_mean`, `operator_applications_per_stage`, `unconverged_stages`,
//!   `max_compression`, `max_surface_deficit`, per reference probe
//!   `<probe>_relative_error_max` and `<probe>_relative_error_mean`, and `status`; a value not
//!   measured is an empty cell.
//! - `bench.csv` (`sph bench`, one row per size and backend): `particles`, `backend`, `device`,
//!   `spacing_m`, `step_time_s`, `sweep_time_s`, `sweeps_per_step`, `particle_steps_per_s`,
//!   `interactions_per_s`, `memory_B_per_particle`, `peak_resident_B_per_particle`,
//!   `neighbours`, `speedup` (empty for the CPU rows).
//! - `bench_stages.csv` (`sph bench`): `particles`, `backend`, `stage`, `stage_time_per_step_s`.
//!
//! The experimental reference records (`martin_moyce_1952_surge_front.csv`,
//! `yeh_petroff_column_force_*.csv`) are external data with their own columns, described in
//! their `SOURCES.md`; they are read, never written.

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
    /// Creates `path` and writes the header line; an existing file or link of that name is an
    /// error ([`super::safe_file::create_new`]).
    pub fn create(path: &Path, columns: &[&str]) -> Result<Self, OutputError> {
        let file = super::safe_file::create_new(path).map_err(|e| OutputError::io(path, e))?;
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
        let mut file = super::safe_file::open_existing(path).map_err(io)?;
        let mut first = String::new();
        {
            use std::io::BufRead;
            let mut reader = std::io::BufReader::new(&mut file);
            reader.read_line(&mut first).map_err(io)?;
        }
        if first.trim_end() != columns.join(",") {
            return Err(OutputError::malformed(path, "its header is not this scene's"));
        }
        let on_disk = file.metadata().map_err(io)?.len();
        if on_disk < len {
            return Err(OutputError::malformed(
                path,
                format!("{on_disk} bytes, shorter than the {len} it held at the checkpoint"),
            ));
        }
        // The cut must keep the header and end on a whole row.
        if len < first.len() as u64 || !ends_a_line(&mut file, len).map_err(io)? {
            return Err(OutputError::malformed(
                path,
                format!("the checkpoint cuts it at byte {len}, which is not the end of a row"),
            ));
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
        let result = write_fields(&mut line, row).and_then(|()| self.writer.write_all(&line));
        result.map_err(|e| OutputError::io(&self.path, e))
    }

    /// Flushes buffered rows to the file.
    pub fn flush(&mut self) -> Result<(), OutputError> {
        self.writer.flush().map_err(|e| OutputError::io(&self.path, e))
    }
}

/// Whether byte `len - 1` of `file` is a newline (a cut at `len` keeps whole rows).
fn ends_a_line(file: &mut File, len: u64) -> std::io::Result<bool> {
    use std::io::{Read, Seek};
    if len == 0 {
        return Ok(false);
    }
    file.seek(std::io::SeekFrom::Start(len - 1))?;
    let mut last = [0u8];
    file.read_exact(&mut last)?;
    Ok(last[0] == b'\n')
}

/// The unit suffix of force columns in a `dimension`-D run: `N`, or `N_per_m` in 2D (a 2D
/// force is per metre of depth).
pub fn force_unit(dimension: usize) -> &'static str {
    if dimension == 2 { "N_per_m" } else { "N" }
}

/// Writes one row as CSV text (fields as [`CsvTable::push_row`] writes them, a final `\n`).
pub fn format_row(row: &[CsvValue]) -> String {
    let mut line: Vec<u8> = Vec::with_capacity(16 * row.len());
    // Writing into a Vec<u8> cannot fail.
    let _ = write_fields(&mut line, row);
    String::from_utf8_lossy(&line).into_owned()
}

fn write_fields<W: Write>(line: &mut W, row: &[CsvValue]) -> std::io::Result<()> {
    for (i, v) in row.iter().enumerate() {
        if i > 0 {
            line.write_all(b",")?;
        }
        match v {
            CsvValue::Float(x) => line.write_all(fmt_f64(*x).as_bytes())?,
            CsvValue::Int(x) => write!(line, "{x}")?,
            CsvValue::Text(s) => write_text(line, s)?,
        }
    }
    line.write_all(b"\n")
}

/// Log of the hydrodynamic force on each named solid over time: `forces.csv`, with header
/// `t_s,solid,fx_N,fy_N,fz_N` in 3D and `t_s,solid,fx_N_per_m,fy_N_per_m` in 2D (time in s,
/// force in N, or N per metre of depth in 2D).
#[derive(Debug)]
pub struct ForceLog {
    table: CsvTable,
    dimension: usize,
}

impl ForceLog {
    /// The header columns of a `dimension`-D run (see the type's documentation).
    pub fn columns(dimension: usize) -> Vec<String> {
        let unit = force_unit(dimension);
        let mut columns = vec!["t_s".to_string(), "solid".to_string()];
        columns.extend(
            ["fx", "fy", "fz"]
                .iter()
                .take(dimension.clamp(2, 3))
                .map(|c| format!("{c}_{unit}")),
        );
        columns
    }

    /// Creates `path` (which must not exist) and writes the header of a `dimension`-D run.
    pub fn create(path: &Path, dimension: usize) -> Result<Self, OutputError> {
        let columns = Self::columns(dimension);
        let columns: Vec<&str> = columns.iter().map(String::as_str).collect();
        Ok(ForceLog {
            table: CsvTable::create(path, &columns)?,
            dimension,
        })
    }

    /// Reopens `path` at its length `len` at a checkpoint ([`CsvTable::resume`]).
    pub fn resume(path: &Path, dimension: usize, len: u64) -> Result<Self, OutputError> {
        let columns = Self::columns(dimension);
        let columns: Vec<&str> = columns.iter().map(String::as_str).collect();
        Ok(ForceLog {
            table: CsvTable::resume(path, &columns, len)?,
            dimension,
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

    /// Appends the force on solid `solid` at time `t` [s] (`force[2]` is not written in 2D).
    pub fn push(&mut self, t: f64, solid: &str, force: [f64; 3]) -> Result<(), OutputError> {
        let mut row = vec![CsvValue::Float(t), CsvValue::Text(solid)];
        row.extend(
            force
                .iter()
                .take(self.dimension.clamp(2, 3))
                .map(|&f| CsvValue::Float(f)),
        );
        self.table.push_row(&row)
    }

    /// Flushes buffered rows to the file (call after each output frame).
    pub fn flush(&mut self) -> Result<(), OutputError> {
        self.table.flush()
    }
}
