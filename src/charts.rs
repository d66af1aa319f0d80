//! Charts of a finished (or stopped) run's CSV logs (`sph plot RUN_DIR`): the force on each
//! solid over time (the paper's Fig. 4), each probe over time, and per step the density error,
//! the correction iterations (section 2, eq. (24)) and the time step.
//!
//! Files read from the run directory: `forces.csv` (`t,solid,fx,fy,fz`, one row per solid per
//! step), `probes.csv` (`t_s` and one `<probe>_m` or `<probe>_N` column per probe) and
//! `steps.csv` (`step,t_s,dt_s,limit,…`). A missing file is skipped; a run with none of them is
//! an error. With the scene, probes that name reference data are also drawn against it,
//! normalised as [`crate::probe::compare_samples`] does (validation/SOURCES.md).
//!
//! The per-step force of a particle method is noisy: each force curve is the mean over groups
//! of consecutive steps, the group size chosen so that a curve has at most
//! [`FORCE_POINTS`] points.

use crate::output::OutputError;
use crate::output::plot::{Figure, PlotError, Series, SeriesStyle, write_png};
use crate::probe::front_figure;
use crate::scene::Scene;
use crate::sweep::{SweepError, comparisons_from_csv};
use std::path::{Path, PathBuf};

/// Most points of one force curve (see the module documentation).
pub const FORCE_POINTS: usize = 1000;

/// Size of every chart [px].
pub const CHART_SIZE: (u32, u32) = (900, 600);

/// Errors of [`write_run_charts`].
#[derive(Debug, thiserror::Error)]
pub enum ChartError {
    /// The run directory does not exist.
    #[error("run directory {} does not exist", dir.display())]
    NoRunDir {
        /// The directory asked for.
        dir: PathBuf,
    },
    /// The run directory holds none of the logs.
    #[error("{} has no forces.csv, probes.csv or steps.csv", dir.display())]
    NoLogs {
        /// The run directory.
        dir: PathBuf,
    },
    /// A log could not be read or is malformed.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A probe's reference data could not be compared.
    #[error(transparent)]
    Reference(#[from] SweepError),
    /// A chart could not be drawn or written.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// A CSV log read back: its header and rows of text fields.
#[derive(Debug, Clone, PartialEq)]
pub struct CsvLog {
    path: PathBuf,
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl CsvLog {
    /// Reads `path` (header line, then rows; RFC 4180 quoting as [`crate::output::CsvTable`]
    /// writes it). Every row must have as many fields as the header.
    pub fn read(path: &Path) -> Result<Self, OutputError> {
        let text = std::fs::read_to_string(path).map_err(|e| OutputError::io(path, e))?;
        let mut lines = text.lines().filter(|l| !l.trim().is_empty());
        let header = split_csv_line(lines.next().unwrap_or_default());
        if header.iter().all(|h| h.is_empty()) {
            return Err(OutputError::malformed(path, "no header line"));
        }
        let rows = lines
            .enumerate()
            .map(|(i, line)| {
                let row = split_csv_line(line);
                if row.len() == header.len() {
                    Ok(row)
                } else {
                    Err(OutputError::malformed(
                        path,
                        format!(
                            "row {} has {} fields, the header {}",
                            i + 1,
                            row.len(),
                            header.len()
                        ),
                    ))
                }
            })
            .collect::<Result<_, _>>()?;
        Ok(CsvLog {
            path: path.to_path_buf(),
            header,
            rows,
        })
    }

    /// The column names.
    pub fn header(&self) -> &[String] {
        &self.header
    }

    /// Index of column `name`.
    pub fn column(&self, name: &str) -> Result<usize, OutputError> {
        self.header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| OutputError::malformed(&self.path, format!("no column `{name}`")))
    }

    /// Column `k` of row `r` as a number.
    fn number(&self, r: usize, k: usize) -> Result<f64, OutputError> {
        let field = &self.rows[r][k];
        field.trim().parse::<f64>().map_err(|_| {
            OutputError::malformed(
                &self.path,
                format!("row {}: `{}` = {field:?} is not a number", r + 1, self.header[k]),
            )
        })
    }

    /// The points `(x, y)` of columns `x` and `y` over the rows for which `keep` holds.
    fn points(
        &self,
        x: usize,
        y: usize,
        keep: impl Fn(&[String]) -> bool,
    ) -> Result<Vec<(f64, f64)>, OutputError> {
        (0..self.rows.len())
            .filter(|&r| keep(&self.rows[r]))
            .map(|r| Ok((self.number(r, x)?, self.number(r, y)?)))
            .collect()
    }
}

/// Splits one CSV line into fields, undoing RFC 4180 quoting.
fn split_csv_line(line: &str) -> Vec<String> {
    let mut fields = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => fields.push(std::mem::take(&mut field)),
            _ => field.push(c),
        }
    }
    fields.push(field);
    fields
}

/// The means of consecutive groups of points, the group size chosen so that at most `max`
/// points remain (points unchanged when there are no more than `max`).
pub fn group_means(points: &[(f64, f64)], max: usize) -> (Vec<(f64, f64)>, usize) {
    let group = points.len().div_ceil(max.max(1)).max(1);
    let means = points
        .chunks(group)
        .map(|c| {
            let n = c.len() as f64;
            let (sx, sy) = c.iter().fold((0.0, 0.0), |(a, b), p| (a + p.0, b + p.1));
            (sx / n, sy / n)
        })
        .collect();
    (means, group)
}

/// The force unit of a `dimension`-D run (2D forces are per unit depth).
fn force_unit(dimension: Option<usize>) -> &'static str {
    match dimension {
        Some(2) => "N/m",
        Some(_) => "N",
        None => "N (3D) or N/m (2D)",
    }
}

/// One chart per solid of `forces.csv`: its force components over time (the paper's Fig. 4;
/// `fz` only in 3D). Returned as `(file stem, figure)`.
pub fn force_figures(log: &CsvLog, dimension: Option<usize>) -> Result<Vec<(String, Figure)>, OutputError> {
    let (t, solid) = (log.column("t")?, log.column("solid")?);
    let mut solids: Vec<&str> = Vec::new();
    for row in &log.rows {
        if !solids.contains(&row[solid].as_str()) {
            solids.push(&row[solid]);
        }
    }
    let components: &[&str] = if dimension == Some(2) {
        &["fx", "fy"]
    } else {
        &["fx", "fy", "fz"]
    };
    let unit = force_unit(dimension);
    let mut figures = Vec::new();
    for name in solids {
        let mut series = Vec::new();
        for component in components {
            let k = log.column(component)?;
            let points = log.points(t, k, |row| row[solid] == name)?;
            let (means, group) = group_means(&points, FORCE_POINTS);
            let label = if group > 1 {
                format!("{component} (mean of {group} steps)")
            } else {
                component.to_string()
            };
            series.push(Series {
                label,
                points: means,
                style: SeriesStyle::Line,
            });
        }
        figures.push((
            format!("force_{}", file_safe(name)),
            Figure {
                title: format!("force of the fluid on {name}"),
                x_label: "t [s]".into(),
                y_label: format!("force [{unit}]"),
                series,
                ..Figure::default()
            },
        ));
    }
    Ok(figures)
}

/// One chart per probe column of `probes.csv` over time, as recorded (unnormalised).
pub fn probe_figures(log: &CsvLog, dimension: Option<usize>) -> Result<Vec<(String, Figure)>, OutputError> {
    let t = log.column("t_s")?;
    let mut figures = Vec::new();
    for (k, column) in log.header().iter().enumerate() {
        if k == t {
            continue;
        }
        let (name, y_label) = match column.rsplit_once('_') {
            Some((name, "m")) => (name, "front position [m]".to_string()),
            Some((name, "N")) => (
                name,
                format!("force, mean over each sample [{}]", force_unit(dimension)),
            ),
            _ => (column.as_str(), column.clone()),
        };
        figures.push((
            format!("probe_{}", file_safe(name)),
            Figure {
                title: format!("probe {name}"),
                x_label: "t [s]".into(),
                y_label,
                series: vec![Series {
                    label: String::new(),
                    points: log.points(t, k, |_| true)?,
                    style: SeriesStyle::Line,
                }],
                ..Figure::default()
            },
        ));
    }
    Ok(figures)
}

/// From `steps.csv`: the largest density error per step (log scale when all positive), the
/// correction iterations per step (only when some step corrected), and the time step.
pub fn step_figures(log: &CsvLog) -> Result<Vec<(String, Figure)>, OutputError> {
    let t = log.column("t_s")?;
    let line = |points| {
        vec![Series {
            label: String::new(),
            points,
            style: SeriesStyle::Line,
        }]
    };
    let error = log.points(t, log.column("max_density_error")?, |_| true)?;
    let iterations = log.points(t, log.column("correction_iterations")?, |_| true)?;
    let dt = log.points(t, log.column("dt_s")?, |_| true)?;
    let mut figures = vec![(
        "density_error".to_string(),
        Figure {
            title: "largest density error per step".into(),
            x_label: "t [s]".into(),
            y_label: "max |rho - rho0| / rho0 [-]".into(),
            log_y: !error.is_empty() && error.iter().all(|p| p.1 > 0.0),
            series: line(error),
            ..Figure::default()
        },
    )];
    if iterations.iter().any(|p| p.1 > 0.0) {
        figures.push((
            "correction_iterations".to_string(),
            Figure {
                title: "position-correction iterations per step (eqs. 23-24)".into(),
                x_label: "t [s]".into(),
                y_label: "iterations [-]".into(),
                series: line(iterations),
                ..Figure::default()
            },
        ));
    }
    figures.push((
        "time_step".to_string(),
        Figure {
            title: "time step".into(),
            x_label: "t [s]".into(),
            y_label: "dt [s]".into(),
            series: line(dt),
            ..Figure::default()
        },
    ));
    Ok(figures)
}

/// A solid or probe name as part of a file name: characters other than letters, digits, `-`
/// and `_` become `_`.
fn file_safe(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Writes the charts of the run in `run_dir` into `out_dir` (created if needed), and with
/// `scene` (the run's scene) each probe against its reference data as
/// `<probe>_reference.png`. Returns the files written.
///
/// # Errors
/// [`ChartError::NoRunDir`], [`ChartError::NoLogs`], [`ChartError::Output`] for a malformed
/// log, [`ChartError::Reference`] for unreadable reference data, [`ChartError::Plot`].
pub fn write_run_charts(
    run_dir: &Path,
    out_dir: &Path,
    scene: Option<&Scene>,
) -> Result<Vec<PathBuf>, ChartError> {
    if !run_dir.is_dir() {
        return Err(ChartError::NoRunDir {
            dir: run_dir.to_path_buf(),
        });
    }
    let dimension = match run_dir.join("summary.json") {
        p if p.is_file() => Some(crate::output::read_summary(&p)?.dimension),
        _ => scene.map(|s| s.dimension),
    };
    let read = |name: &str| {
        let path = run_dir.join(name);
        path.is_file().then(|| CsvLog::read(&path)).transpose()
    };
    let (forces, probes, steps) = (read("forces.csv")?, read("probes.csv")?, read("steps.csv")?);
    if forces.is_none() && probes.is_none() && steps.is_none() {
        return Err(ChartError::NoLogs {
            dir: run_dir.to_path_buf(),
        });
    }
    let mut figures = Vec::new();
    if let Some(log) = &forces {
        figures.extend(force_figures(log, dimension)?);
    }
    if let Some(log) = &probes {
        figures.extend(probe_figures(log, dimension)?);
        if let Some(scene) = scene {
            for c in comparisons_from_csv(scene, &log.path)? {
                let title = format!(
                    "{}: {} against reference data",
                    scene.name.as_deref().unwrap_or("run"),
                    c.name
                );
                let figure = front_figure(&title, &[("simulation".to_string(), &c)]);
                figures.push((format!("{}_reference", file_safe(&c.name)), figure));
            }
        }
    }
    if let Some(log) = &steps {
        figures.extend(step_figures(log)?);
    }
    std::fs::create_dir_all(out_dir).map_err(|e| OutputError::io(out_dir, e))?;
    let mut written = Vec::new();
    for (stem, figure) in figures {
        if figure.series.iter().all(|s| s.points.is_empty()) {
            // A log with a header but no rows yet (a run stopped at once): nothing to draw.
            continue;
        }
        let path = out_dir.join(format!("{stem}.png"));
        write_png(&figure, &path, CHART_SIZE)?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_lines_split_with_quotes() {
        assert_eq!(
            split_csv_line("1,\"a,b\",\"say \"\"hi\"\"\",x"),
            ["1", "a,b", "say \"hi\"", "x"]
        );
        assert_eq!(split_csv_line(""), [""]);
    }

    #[test]
    fn group_means_average_and_bound_the_count() {
        let points: Vec<(f64, f64)> = (0..10).map(|i| (f64::from(i), f64::from(i % 2))).collect();
        let (means, group) = group_means(&points, 5);
        assert_eq!(group, 2);
        assert_eq!(
            means,
            vec![(0.5, 0.5), (2.5, 0.5), (4.5, 0.5), (6.5, 0.5), (8.5, 0.5)]
        );
        let (same, one) = group_means(&points, 100);
        assert_eq!((same, one), (points, 1));
    }

    #[test]
    fn file_names_are_safe() {
        assert_eq!(file_safe("column/front face"), "column_front_face");
    }
}
