//! Reference data for validation runs and curve comparison.
//!
//! Readers for the digitised experiments in `../shared/validation` (see its
//! `SOURCES.md` for provenance, columns and normalisation):
//! - [`read_surge_front`]: Martin & Moyce (1952) surge front Z(T) of a
//!   collapsing water column, `martin_moyce_1952_surge_front.csv`, five
//!   digitisations for n² = 1 and n² = 2, with T = n t sqrt(g/a), Z = z/a.
//! - [`read_column_force`]: Yeh & Petroff dam break against a tall square
//!   column, net streamwise force on the column,
//!   `yeh_petroff_column_force_pysph.csv` and `yeh_petroff_column_force_anuga.csv`.
//!
//! And two comparisons: [`interpolate`] (piecewise linear) and
//! [`relative_error`] of a simulated curve against reference points.
//!
//! The files are plain CSV: a header row, comma-separated fields, no quoting
//! and no comments, so a small reader suffices; it rejects quoted fields
//! rather than misreading them. Columns are found by header name, never by
//! position. Blank lines are skipped; CRLF line ends are accepted.

use std::path::{Path, PathBuf};

/// Errors produced while reading reference data.
#[derive(Debug, thiserror::Error)]
pub enum ValidationError {
    /// Reading the file failed.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file being read.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The header row has no column of this name.
    #[error("{}: no column `{column}` in the header", path.display())]
    MissingColumn {
        /// The file being read.
        path: PathBuf,
        /// The column that was looked for.
        column: String,
    },
    /// A cell that must hold a number does not.
    #[error("{}:{line}: column `{column}`: `{text}` is not a number", path.display())]
    BadNumber {
        /// The file being read.
        path: PathBuf,
        /// Line number, counted from 1 (the header is line 1).
        line: usize,
        /// Name of the column.
        column: String,
        /// The offending cell, as written.
        text: String,
    },
    /// The file is not plain CSV of the expected shape (no header, a row
    /// with the wrong number of fields, a quoted field).
    #[error("{}:{line}: {reason}", path.display())]
    Malformed {
        /// The file being read.
        path: PathBuf,
        /// Line number, counted from 1.
        line: usize,
        /// What is wrong.
        reason: String,
    },
}

/// One digitised point of Martin & Moyce's surge front: T = n t sqrt(g/a), Z = x/a.
///
/// `a` is the initial column width \[m\], `n² a` its height, `t` the time since
/// release \[s\], `x` the front position measured from the back wall \[m\] and
/// g = 9.81 m/s².
#[derive(Debug, Clone, PartialEq)]
pub struct FrontPoint {
    /// Name of the digitisation, e.g. `MM1952_n2-1_jaxsph` (column `series`).
    pub series: String,
    /// Aspect ratio n² = height / width of the initial column \[-\]
    /// (column `n2_height_over_width`).
    pub n2: f64,
    /// Dimensionless time T = n t sqrt(g/a) \[-\] (column `T_n_t_sqrt_g_over_a`).
    pub t: f64,
    /// Dimensionless front position Z = x/a \[-\]; 1 at release (column `Z_front_over_a`).
    pub z: f64,
}

/// Yeh & Petroff column force: time \[s\], force \[N\]
///
/// One point of the net streamwise force on the square column; the file
/// holds a single record, so there is no series field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForcePoint {
    /// Time since the gate opened \[s\] (column `time_s`).
    pub time: f64,
    /// Net force on the column along the flow (x) \[N\] (column `force_x_N`).
    pub force: f64,
}

/// Error of a simulated curve against reference points, as returned by
/// [`relative_error`]; relative errors are fractions (0.05 = 5 %).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveError {
    /// Largest |sim − ref| / |ref| over the compared points \[-\].
    pub max: f64,
    /// Mean of |sim − ref| / |ref| over the compared points \[-\].
    pub mean: f64,
    /// Number of reference points compared.
    pub count: usize,
}

/// Reads `martin_moyce_1952_surge_front.csv`: one [`FrontPoint`] per row, in
/// file order (series after series, T increasing within each).
///
/// # Errors
/// [`ValidationError`] naming the file: I/O failure, a missing column
/// (`series`, `n2_height_over_width`, `T_n_t_sqrt_g_over_a`, `Z_front_over_a`),
/// a cell that is not a number, or a malformed row.
pub fn read_surge_front(path: &Path) -> Result<Vec<FrontPoint>, ValidationError> {
    let table = Table::read(path)?;
    let series = table.column("series")?;
    let n2 = table.column("n2_height_over_width")?;
    let t = table.column("T_n_t_sqrt_g_over_a")?;
    let z = table.column("Z_front_over_a")?;
    table
        .rows
        .iter()
        .map(|row| {
            Ok(FrontPoint {
                series: row.text(series).to_string(),
                n2: table.number(row, n2)?,
                t: table.number(row, t)?,
                z: table.number(row, z)?,
            })
        })
        .collect()
}

/// Reads a Yeh & Petroff column-force record
/// (`yeh_petroff_column_force_pysph.csv` or `yeh_petroff_column_force_anuga.csv`):
/// one [`ForcePoint`] per row, in file order.
///
/// The PySPH file is sorted by time; the ANUGA file is not (several traced
/// segments, kept in source order), so sort by time before [`interpolate`].
///
/// # Errors
/// [`ValidationError`] naming the file: I/O failure, a missing column
/// (`time_s`, `force_x_N`), a cell that is not a number, or a malformed row.
pub fn read_column_force(path: &Path) -> Result<Vec<ForcePoint>, ValidationError> {
    let table = Table::read(path)?;
    let time = table.column("time_s")?;
    let force = table.column("force_x_N")?;
    table
        .rows
        .iter()
        .map(|row| {
            Ok(ForcePoint {
                time: table.number(row, time)?,
                force: table.number(row, force)?,
            })
        })
        .collect()
}

/// Linear interpolation of a reference curve (sorted by x) at x; None outside its range.
///
/// `points` must be sorted by increasing x (equal x allowed: a jump, where
/// the first point of that x is returned). Also `None` for an empty curve, a
/// non-finite `x` or a non-finite result. Unsorted input gives an
/// unspecified value but never panics.
pub fn interpolate(points: &[(f64, f64)], x: f64) -> Option<f64> {
    if !x.is_finite() {
        return None;
    }
    // First point with p.x >= x.
    let i = points.partition_point(|p| p.0 < x);
    let value = match points.get(i) {
        None => return None,
        Some(&(xi, yi)) if xi == x => yi,
        Some(_) if i == 0 => return None,
        Some(&(x1, y1)) => {
            let (x0, y0) = points[i - 1];
            y0 + (y1 - y0) * (x - x0) / (x1 - x0)
        }
    };
    value.is_finite().then_some(value)
}

/// Error of a simulated curve against reference points: for each reference
/// point with x in `range`, the simulated value interpolated at that x;
/// returns max and mean of |sim - ref| / |ref| and the count.
///
/// `range` = (low, high) is inclusive at both ends and in the units of x.
/// `simulated` must be sorted by x (see [`interpolate`]); `reference` may
/// be in any order. Reference points are skipped where the simulated curve
/// does not cover their x, where the reference value is zero (no relative
/// error exists) or where either value is not finite. `None` when no point
/// is left to compare.
pub fn relative_error(
    simulated: &[(f64, f64)],
    reference: &[(f64, f64)],
    range: (f64, f64),
) -> Option<CurveError> {
    let (low, high) = range;
    let errors = reference
        .iter()
        .filter(|&&(x, y)| x >= low && x <= high && y.is_finite() && y != 0.0)
        .filter_map(|&(x, y)| interpolate(simulated, x).map(|s| ((s - y) / y).abs()));
    let (max, sum, count) = errors.fold((0.0_f64, 0.0, 0_usize), |(max, sum, count), e| {
        (max.max(e), sum + e, count + 1)
    });
    (count > 0).then(|| CurveError {
        max,
        mean: sum / count as f64,
        count,
    })
}

/// A plain CSV file: header names and data rows, with line numbers kept
/// for error messages.
struct Table {
    /// The file read.
    path: PathBuf,
    /// Column names from the header row.
    header: Vec<String>,
    /// Data rows, each with exactly `header.len()` fields.
    rows: Vec<Row>,
}

/// One data row of a [`Table`].
struct Row {
    /// Line number in the file, from 1.
    line: usize,
    /// The fields, trimmed of surrounding blanks.
    fields: Vec<String>,
}

impl Row {
    /// The text of field `column`.
    fn text(&self, column: usize) -> &str {
        // In range: `Table::read` keeps only rows with as many fields as the
        // header, and `column` comes from `Table::column`.
        &self.fields[column]
    }
}

impl Table {
    /// Reads and splits the whole file; checks the shape, not the values.
    fn read(path: &Path) -> Result<Self, ValidationError> {
        let text = std::fs::read_to_string(path).map_err(|source| ValidationError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let malformed = |line: usize, reason: String| ValidationError::Malformed {
            path: path.to_path_buf(),
            line,
            reason,
        };
        let mut header: Option<Vec<String>> = None;
        let mut rows = Vec::new();
        for (index, raw) in text.lines().enumerate() {
            let line = index + 1;
            let raw = if line == 1 {
                raw.trim_start_matches('\u{feff}')
            } else {
                raw
            };
            if raw.trim().is_empty() {
                continue;
            }
            if raw.contains('"') {
                return Err(malformed(line, "quoted fields are not supported".to_string()));
            }
            let fields: Vec<String> = raw.split(',').map(|f| f.trim().to_string()).collect();
            match &header {
                None => header = Some(fields),
                Some(names) if fields.len() != names.len() => {
                    return Err(malformed(
                        line,
                        format!("{} fields, the header has {}", fields.len(), names.len()),
                    ));
                }
                Some(_) => rows.push(Row { line, fields }),
            }
        }
        let header = header.ok_or_else(|| malformed(1, "no header row".to_string()))?;
        Ok(Table {
            path: path.to_path_buf(),
            header,
            rows,
        })
    }

    /// Index of the column named `name`.
    fn column(&self, name: &str) -> Result<usize, ValidationError> {
        self.header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| ValidationError::MissingColumn {
                path: self.path.clone(),
                column: name.to_string(),
            })
    }

    /// Field `column` of `row` as a finite number.
    fn number(&self, row: &Row, column: usize) -> Result<f64, ValidationError> {
        let text = row.text(column);
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(ValidationError::BadNumber {
                path: self.path.clone(),
                line: row.line,
                column: self.header[column].clone(),
                text: text.to_string(),
            }),
        }
    }
}
