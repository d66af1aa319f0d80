//! `sph waves RUN_DIR`: the regular waves a run's level gauges recorded (`probe::waves`): each
//! gauge's height (first harmonic and crest to trough) over a window of whole periods, and the
//! incident and reflected waves fitted to all of them, with the reflection coefficient and the
//! wavenumber against the dispersion relation.
//!
//! The gauges are the scene's `level` probes (or those `--gauges` names), placed along the
//! flume by their point's coordinate on `--axis` (default x). The period and depth default to
//! those of the scene's wave maker (`motion.kind = "piston"`, or `"flap"` with a target wave);
//! without one they are required.
//! The window defaults to the last four whole periods of the record.

use crate::boundary::flap::FlapAmplitude;
use crate::boundary::motion::Motion;
use crate::output::CsvFile;
use crate::physics::waves::wavenumber;
use crate::probe::waves::{crest_to_trough, harmonic, two_waves};
use crate::scene::{ProbeKind, Scene};
use anyhow::{Context, bail};
use std::f64::consts::TAU;
use std::path::Path;

/// What `sph waves` was asked (the command line's options).
#[derive(Debug, Clone, Default)]
pub struct WaveOptions {
    /// Wave period [s]; default the wave maker's.
    pub period: Option<f64>,
    /// Still-water depth [m]; default the wave maker's.
    pub depth: Option<f64>,
    /// The gauges to use, by probe name; default every `level` probe.
    pub gauges: Vec<String>,
    /// Window start [s]; default four periods before its end.
    pub from: Option<f64>,
    /// Window end [s]; default the record's last time.
    pub to: Option<f64>,
    /// Where along the flume [m] the reflection coefficient is given; default the last gauge.
    pub at: Option<f64>,
    /// The flume's axis, 0 (x), 1 (y) or 2 (z).
    pub axis: usize,
}

/// One gauge's reading.
#[derive(Debug, Clone, PartialEq)]
pub struct GaugeReading {
    /// Probe name.
    pub name: String,
    /// Position along the flume [m].
    pub x: f64,
    /// `2|Z|` [m], the first harmonic's height.
    pub harmonic_height: f64,
    /// Mean crest-to-trough height over the window's periods [m].
    pub crest_to_trough: f64,
}

/// The analysis of a run's gauges.
#[derive(Debug, Clone, PartialEq)]
pub struct WaveReport {
    /// Period [s] and depth [m] used.
    pub period: f64,
    /// Still-water depth [m].
    pub depth: f64,
    /// The window `[from, to)` [s].
    pub window: (f64, f64),
    /// Every gauge's reading, in order along the flume.
    pub gauges: Vec<GaugeReading>,
    /// `k` of the dispersion relation [1/m].
    pub k_theory: f64,
    /// The fit of incident and reflected waves (`probe::waves::TwoWaves`).
    pub fit: crate::probe::waves::TwoWaves,
    /// Where [m] `reflection` is given.
    pub at: f64,
    /// `K_r` at `at`.
    pub reflection: f64,
}

/// The period [s], depth [m] and `|g|` [m/s²] of the scene's first wave maker (a piston, or a
/// flap driven by a target wave).
fn wave_maker(scene: &Scene) -> Option<(f64, f64, f64)> {
    scene.solids.iter().find_map(|s| match s.motion.as_ref()? {
        Motion::Piston(p) => Some((p.period, p.depth, p.gravity)),
        Motion::Flap(f) => match f.amplitude {
            FlapAmplitude::Wave { depth, gravity, .. } => Some((f.period, depth, gravity)),
            FlapAmplitude::Angle(_) => None,
        },
        Motion::Sway(_) | Motion::Series(_) | Motion::Sea(_) => None,
    })
}

/// Analyses the level gauges of the run in `run_dir` whose scene is `scene`.
pub fn analyse(run_dir: &Path, scene: &Scene, o: &WaveOptions) -> anyhow::Result<WaveReport> {
    let maker = wave_maker(scene);
    let period = o.period.or(maker.map(|m| m.0)).context(
        "the scene has no wave maker with a target wave: give the wave period with --period (and the depth with --depth)",
    )?;
    let depth = o
        .depth
        .or(maker.map(|m| m.1))
        .context("the scene has no wave maker with a target wave: give the still-water depth with --depth")?;
    if !(period > 0.0 && period.is_finite() && depth > 0.0 && depth.is_finite()) {
        bail!("--period and --depth must be positive and finite (got {period} s, {depth} m)");
    }
    let g = maker
        .map(|m| m.2)
        .or_else(|| {
            scene
                .gravity
                .as_ref()
                .map(|g| g.iter().map(|c| c * c).sum::<f64>().sqrt())
        })
        .filter(|g| *g > 0.0)
        .context("the scene has no gravity: waves need it")?;
    if o.axis >= scene.dimension {
        bail!(
            "--axis {} is not an axis of this {}D scene",
            o.axis,
            scene.dimension
        );
    }
    let probes: Vec<_> = scene
        .probes
        .iter()
        .filter(|p| p.kind == ProbeKind::Level && (o.gauges.is_empty() || o.gauges.contains(&p.name)))
        .collect();
    for name in &o.gauges {
        if !probes.iter().any(|p| &p.name == name) {
            bail!("--gauges: the scene has no level probe named {name:?}");
        }
    }
    if probes.len() < 2 {
        bail!(
            "{} level gauge(s) in the scene: separating incident and reflected waves needs at least two",
            probes.len()
        );
    }
    let path = run_dir.join("probes.csv");
    let csv = CsvFile::read(&path)?;
    let time = csv.column("t_s")?;
    let end = match o.to {
        Some(t) => t,
        None => csv
            .numbers(time)?
            .last()
            .copied()
            .context("probes.csv has no rows")?,
    };
    let window = (o.from.unwrap_or(end - 4.0 * period), end);
    let omega = TAU / period;
    let mut gauges = Vec::new();
    let mut amplitudes = Vec::new();
    for p in probes {
        let column = csv.column(&crate::probe::column_name(p, scene.dimension))?;
        let mut samples = Vec::new();
        for r in 0..csv.len() {
            if let Some(v) = csv.optional_number(r, column)? {
                samples.push((csv.number(r, time)?, v));
            }
        }
        let h = harmonic(&samples, omega, window).with_context(|| {
            format!(
                "gauge {}: fewer than three samples in the window {:.3}–{:.3} s",
                p.name, window.0, window.1
            )
        })?;
        let x = p.point.as_ref().map_or(0.0, |point| point[o.axis]);
        gauges.push(GaugeReading {
            name: p.name.clone(),
            x,
            harmonic_height: 2.0 * h.amplitude.norm(),
            crest_to_trough: crest_to_trough(&samples, period, window).unwrap_or(f64::NAN),
        });
        amplitudes.push((x, h.amplitude));
    }
    let mut order: Vec<usize> = (0..gauges.len()).collect();
    order.sort_by(|&a, &b| gauges[a].x.total_cmp(&gauges[b].x));
    let gauges: Vec<GaugeReading> = order.iter().map(|&i| gauges[i].clone()).collect();
    let (x, z): (Vec<f64>, Vec<_>) = order.iter().map(|&i| amplitudes[i]).unzip();
    let k_theory = wavenumber(omega, depth, g);
    let fit = two_waves(&z, &x, k_theory).context(
        "the gauges do not separate incident and reflected waves (two gauges half a wavelength apart, or all at one place)",
    )?;
    let at = o.at.unwrap_or(x[x.len() - 1]);
    Ok(WaveReport {
        period,
        depth,
        window,
        gauges,
        k_theory,
        fit,
        at,
        reflection: fit.reflection_at(at),
    })
}

/// `sph waves`: prints the analysis.
pub fn waves(run_dir: &Path, scene: Option<&Scene>, o: &WaveOptions) -> anyhow::Result<()> {
    let scene = scene.context(
        "the run's scene is needed for its gauges: give it with --scene (summary.json names no scene that loads)",
    )?;
    let r = analyse(run_dir, scene, o)?;
    println!(
        "regular waves: T = {} s, d = {} m, window {:.3}–{:.3} s ({:.1} periods)",
        r.period,
        r.depth,
        r.window.0,
        r.window.1,
        (r.window.1 - r.window.0) / r.period
    );
    println!(
        "{:<16} {:>10} {:>12} {:>16}",
        "gauge", "x [m]", "2|Z| [m]", "crest-trough [m]"
    );
    for g in &r.gauges {
        println!(
            "{:<16} {:>10.4} {:>12.5} {:>16.5}",
            g.name, g.x, g.harmonic_height, g.crest_to_trough
        );
    }
    let f = &r.fit;
    println!(
        "fit (Mansard & Funke with decay): k = {:.4} 1/m ({:+.1} % against the dispersion relation's {:.4}), decay {:.2} 1/m, misfit {:.3}",
        f.k,
        100.0 * (f.k / r.k_theory - 1.0),
        r.k_theory,
        f.kappa,
        f.misfit
    );
    println!(
        "incident height {:.5} m, reflected {:.5} m, reflection coefficient {:.3} at x = {} m",
        f.incident_height_at(r.at),
        f.reflected_height_at(r.at),
        r.reflection,
        r.at
    );
    Ok(())
}
