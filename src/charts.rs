//! Charts of a finished (or stopped) run's CSV logs (`sph plot RUN_DIR`): the force on each
//! solid over time (the paper's Fig. 4), each probe over time, and per step the largest
//! compression and free-surface deficit (`compression_and_deficit.png`), the correction
//! iterations (section 2, eq. (24)) and the time step.
//!
//! Files read from the run directory (columns as in [`crate::output::csv`]): `forces.csv`
//! (`t_s`, `solid` and `fx_N`, `fy_N`, `fz_N`, or in 2D `fx_N_per_m`, `fy_N_per_m`; one row per
//! solid per step), `probes.csv` (`t_s` and one `<probe>_m`, `<probe>_N` or `<probe>_N_per_m`
//! column per probe) and `steps.csv` (`t_s`, `dt_s`, `max_compression`, `max_surface_deficit`,
//! `correction_iterations`, …). The unit of each force column is read from its name. A missing
//! file is skipped; a run with none of them is an error. With the scene, probes that name
//! reference data are also drawn against it, normalised as [`crate::probe::compare_samples`]
//! does (validation/SOURCES.md).
//!
//! The per-step force of a particle method is noisy: each force curve is the mean over groups
//! of consecutive steps, the group size chosen so that a curve has at most
//! [`FORCE_POINTS`] points.

use crate::output::plot::{Figure, PlotError, Series, SeriesStyle, write_png};
use crate::output::{CsvFile, CsvReadError, OutputError};
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

/// The column of force component `component` (`fx`, `fy`, `fz`) in `log` and its unit for an
/// axis label: `<component>_N` [N] or `<component>_N_per_m` [N/m]; `None` when absent.
fn force_column(log: &CsvFile, component: &str) -> Option<(usize, &'static str)> {
    [("N", "N"), ("N_per_m", "N/m")]
        .into_iter()
        .find_map(|(suffix, unit)| Some((log.column(&format!("{component}_{suffix}")).ok()?, unit)))
}

/// One chart per solid of `forces.csv`: its force components over time (the paper's Fig. 4).
/// Returned as `(file stem, figure)`.
///
/// # Errors
/// A missing `t_s`, `solid` or `fx` column, or a cell that is not a number.
pub fn force_figures(log: &CsvFile) -> Result<Vec<(String, Figure)>, OutputError> {
    let (t, solid) = (log.column("t_s")?, log.column("solid")?);
    let mut solids: Vec<&str> = Vec::new();
    for r in 0..log.len() {
        if !solids.contains(&log.text(r, solid)) {
            solids.push(log.text(r, solid));
        }
    }
    // `fx` must be there; `fz` is absent in 2D.
    let Some((_, unit)) = force_column(log, "fx") else {
        return Err(CsvReadError::MissingColumn {
            path: log.path().to_path_buf(),
            column: "fx_N (or fx_N_per_m)".into(),
            header: log.header().to_vec(),
        }
        .into());
    };
    let components: Vec<(&str, usize)> = ["fx", "fy", "fz"]
        .into_iter()
        .filter_map(|c| force_column(log, c).map(|(k, _)| (c, k)))
        .collect();
    let mut figures = Vec::new();
    for name in solids {
        let mut series = Vec::new();
        for &(component, k) in &components {
            let points = log.points(t, k, |r| log.text(r, solid) == name)?;
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
pub fn probe_figures(log: &CsvFile) -> Result<Vec<(String, Figure)>, OutputError> {
    let t = log.column("t_s")?;
    let mut figures = Vec::new();
    for (k, column) in log.header().iter().enumerate() {
        if k == t {
            continue;
        }
        let (name, y_label) = if let Some(name) = column.strip_suffix("_N_per_m") {
            (name, "force, mean over each sample [N/m]".to_string())
        } else if let Some(name) = column.strip_suffix("_N") {
            (name, "force, mean over each sample [N]".to_string())
        } else if let Some(name) = column.strip_suffix("_m") {
            (name, "front position [m]".to_string())
        } else {
            (column.as_str(), column.clone())
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

/// From `steps.csv`: the largest compression and the largest free-surface deficit per step
/// (log scale when all positive), the correction iterations per step (only when some step
/// corrected), and the time step.
pub fn step_figures(log: &CsvFile) -> Result<Vec<(String, Figure)>, OutputError> {
    let t = log.column("t_s")?;
    let line = |points| {
        vec![Series {
            label: String::new(),
            points,
            style: SeriesStyle::Line,
        }]
    };
    let compression = log.points(t, log.column("max_compression")?, |_| true)?;
    let deficit = log.points(t, log.column("max_surface_deficit")?, |_| true)?;
    let iterations = log.points(t, log.column("correction_iterations")?, |_| true)?;
    let dt = log.points(t, log.column("dt_s")?, |_| true)?;
    let positive = |p: &[(f64, f64)]| !p.is_empty() && p.iter().all(|p| p.1 > 0.0);
    let log_y = positive(&compression) && positive(&deficit);
    let mut figures = vec![(
        "compression_and_deficit".to_string(),
        Figure {
            title: "largest compression and free-surface deficit per step".into(),
            x_label: "t [s]".into(),
            y_label: "relative density deviation [-]".into(),
            log_y,
            series: vec![
                Series {
                    label: "max compression max(rho - rho0, 0)/rho0".into(),
                    points: compression,
                    style: SeriesStyle::Line,
                },
                Series {
                    label: "max surface deficit max(rho0 - rho, 0)/rho0".into(),
                    points: deficit,
                    style: SeriesStyle::Line,
                },
            ],
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
    let read = |name: &str| {
        let path = run_dir.join(name);
        path.is_file()
            .then(|| CsvFile::read(&path).map_err(OutputError::from))
            .transpose()
    };
    let (forces, probes, steps) = (read("forces.csv")?, read("probes.csv")?, read("steps.csv")?);
    if forces.is_none() && probes.is_none() && steps.is_none() {
        return Err(ChartError::NoLogs {
            dir: run_dir.to_path_buf(),
        });
    }
    let mut figures = Vec::new();
    if let Some(log) = &forces {
        figures.extend(force_figures(log)?);
    }
    if let Some(log) = &probes {
        figures.extend(probe_figures(log)?);
        if let Some(scene) = scene {
            for c in comparisons_from_csv(scene, log.path())? {
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
