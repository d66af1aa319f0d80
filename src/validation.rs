//! Reference data for validation runs and curve comparison.
//!
//! Readers for the digitised experiments in the user's reference directory
//! (`scene::references`; docs/validation.md gives each file's public source, columns and
//! normalisation):
//! - [`read_surge_front`]: Martin & Moyce (1952) surge front Z(T) of a
//!   collapsing water column, `martin_moyce_1952_surge_front.csv`, five
//!   digitisations for n² = 1 and n² = 2, with T = n t sqrt(g/a), Z = z/a.
//! - [`read_column_force`]: Yeh & Petroff dam break against a tall square
//!   column, net streamwise force on the column,
//!   `yeh_petroff_column_force_pysph.csv` and `yeh_petroff_column_force_anuga.csv`.
//! - [`read_curves`]: any long-format record of a time and a value column named by the scene,
//!   with an optional `series` column, e.g. Buchner's (2002) wall pressure
//!   `buchner2002_2d_dambreak_wall_pressure.csv`.
//!
//! And two comparisons: [`interpolate`] (piecewise linear) and
//! [`relative_error`] of a simulated curve against reference points.
//!
//! The files are read with the program's one CSV reader ([`crate::output::CsvFile`]):
//! columns are found by header name, never by position, and every cell a point needs must be a
//! finite number.

use crate::output::CsvFile;
use std::path::Path;

/// Errors produced while reading reference data: the CSV reader's, each naming the file, line
/// and column.
pub type ValidationError = crate::output::CsvReadError;

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
/// a cell that is not a finite number, or a row of another length than the
/// header.
pub fn read_surge_front(path: &Path) -> Result<Vec<FrontPoint>, ValidationError> {
    let table = CsvFile::read(path)?;
    let series = table.column("series")?;
    let n2 = table.column("n2_height_over_width")?;
    let t = table.column("T_n_t_sqrt_g_over_a")?;
    let z = table.column("Z_front_over_a")?;
    (0..table.len())
        .map(|row| {
            Ok(FrontPoint {
                series: table.text(row, series).to_string(),
                n2: table.finite_number(row, n2)?,
                t: table.finite_number(row, t)?,
                z: table.finite_number(row, z)?,
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
/// (`time_s`, `force_x_N`), a cell that is not a finite number, or a row of another length than the
/// header.
pub fn read_column_force(path: &Path) -> Result<Vec<ForcePoint>, ValidationError> {
    let table = CsvFile::read(path)?;
    let time = table.column("time_s")?;
    let force = table.column("force_x_N")?;
    (0..table.len())
        .map(|row| {
            Ok(ForcePoint {
                time: table.finite_number(row, time)?,
                force: table.finite_number(row, force)?,
            })
        })
        .collect()
}

/// One point of a long-format reference record: a time and a value in the file's own units.
#[derive(Debug, Clone, PartialEq)]
pub struct CurvePoint {
    /// Name of the record (column `series`; the file's stem when it has no such column).
    pub series: String,
    /// Time, in the file's unit (e.g. `T = t sqrt(g/H)`, or seconds).
    pub t: f64,
    /// Value, in the file's unit (e.g. `p/(ρ0 g H)`, or pascals).
    pub value: f64,
}

/// Reads a long-format reference record, one [`CurvePoint`] per row in file order, from the
/// columns `time` and `value` named by the scene and an optional `series` column (as
/// `buchner2002_2d_dambreak_wall_pressure.csv`: `series`, `T_t_sqrt_g_over_H`,
/// `p_over_rho_g_H`).
///
/// # Errors
/// [`ValidationError`] naming the file: I/O failure, a missing `time` or `value` column, a cell
/// that is not a finite number, or a row of another length than the header.
pub fn read_curves(path: &Path, time: &str, value: &str) -> Result<Vec<CurvePoint>, ValidationError> {
    let table = CsvFile::read(path)?;
    let series = table.header().iter().position(|c| c == "series");
    let stem = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let (t, v) = (table.column(time)?, table.column(value)?);
    (0..table.len())
        .map(|row| {
            Ok(CurvePoint {
                series: series.map_or_else(|| stem.clone(), |c| table.text(row, c).to_string()),
                t: table.finite_number(row, t)?,
                value: table.finite_number(row, v)?,
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
