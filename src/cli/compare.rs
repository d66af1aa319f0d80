//! `sph compare SCENE --run LABEL=DIR ... --probe NAME --out FIG.png`: one probe of several
//! finished runs (their `probes.csv`) on one figure with the scene's reference data, and each
//! run's error or force peak printed. For comparing resolutions, solvers or backends after the
//! fact (the Yeh & Petroff figure of docs/validation.md).

use crate::output::plot::write_png;
use crate::probe::{ProbeComparison, front_figure};
use crate::sweep::comparisons_from_csv;
use anyhow::Context;
use std::path::{Path, PathBuf};

/// Keeps the points with `t <= t_max` (the curve's own time axis).
fn clip(points: &[(f64, f64)], t_max: Option<f64>) -> Vec<(f64, f64)> {
    points
        .iter()
        .copied()
        .filter(|(t, _)| t_max.is_none_or(|m| *t <= m))
        .collect()
}

/// Runs the comparison.
pub fn compare(
    scene_path: &Path,
    runs: &[String],
    probe: &str,
    out: &Path,
    t_max: Option<f64>,
    sets: &[String],
    reference_dir: Option<&Path>,
) -> anyhow::Result<()> {
    anyhow::ensure!(!runs.is_empty(), "give at least one --run LABEL=DIR");
    let scene = super::load_located(scene_path, sets, reference_dir, true)
        .with_context(|| format!("loading scene {}", scene_path.display()))?;
    if let Some(skipped) = crate::scene::skipped_references(&scene)
        .into_iter()
        .find(|s| s.probe == probe)
    {
        anyhow::bail!("{skipped}: sph compare draws runs against their reference data");
    }
    let mut found: Vec<(String, ProbeComparison)> = Vec::new();
    for run in runs {
        let (label, dir) = run
            .rsplit_once('=')
            .with_context(|| format!("--run {run:?}: expected LABEL=DIR"))?;
        let csv = PathBuf::from(dir).join("probes.csv");
        let comparisons =
            comparisons_from_csv(&scene, &csv).with_context(|| format!("reading {}", csv.display()))?;
        let mut c = comparisons
            .into_iter()
            .find(|c| c.name == probe)
            .with_context(|| format!("{} has no probe {probe} with reference data", csv.display()))?;
        match (&c.error, &c.peak) {
            _ if c.signal.is_some() => {
                let entry = crate::probe::signal::summary_json(&c);
                for line in crate::probe::signal::summary_lines(label, &entry) {
                    println!("{line}");
                }
            }
            (Some(e), _) => println!(
                "{label}: error max {:.1} %, mean {:.1} %",
                100.0 * e.max,
                100.0 * e.mean
            ),
            (None, Some(p)) => {
                print!(
                    "{label}: peak {:.2} N at {:.3} s; reference {:.2} N at {:.3} s ({:+.1} %, {:+.3} s)",
                    p.simulated.1,
                    p.simulated.0,
                    p.reference.1,
                    p.reference.0,
                    100.0 * (p.simulated.1 - p.reference.1) / p.reference.1,
                    p.simulated.0 - p.reference.0
                );
                match (p.onset, p.rise_time_error()) {
                    (Some((sim, reference)), Some(rise)) => {
                        println!("; onset {sim:.3} s, reference {reference:.3} s; onset to peak {rise:+.3} s")
                    }
                    _ => println!(),
                }
            }
            (None, None) => println!("{label}: no reference point inside the simulated time"),
        }
        c.simulated = clip(&c.simulated, t_max);
        for (_, pts) in &mut c.reference {
            *pts = clip(pts, t_max);
        }
        found.push((label.to_string(), c));
    }
    let runs: Vec<(String, &ProbeComparison)> = found.iter().map(|(l, c)| (l.clone(), c)).collect();
    let figure = front_figure(
        &format!("{}: {probe}", scene.name.as_deref().unwrap_or("scene")),
        &runs,
    );
    write_png(&figure, out, (900, 600)).with_context(|| format!("writing {}", out.display()))?;
    println!("wrote {}", out.display());
    Ok(())
}
