//! `sph bench`: the paper's Fig. 5 as a command. For each particle count and backend, a scene is
//! rescaled (its particle spacing, and with it the smoothing length) to about that many particles
//! and timed: seconds per sweep (one density pass, the equation of state and one force pass over
//! every particle), seconds per step of the scene's own solver, sweeps per step, particle-steps
//! and neighbour interactions per second, and memory per particle; the GPU's speedup over the
//! CPU at each size where both ran.
//!
//! Interactions are the pairs `(i, j)`, `i ≠ j`, closer than `h`, counted once on the CPU grid for
//! each size; a sweep visits each twice (density and forces).

use crate::backend::BackendKind;
use crate::error::Error;
use crate::grid::Grid;
use crate::output::plot::{Figure, Series, SeriesStyle};
use crate::output::{CsvValue, format_row};
use crate::run::AnySimulation;
use crate::scene::{Scene, generate::count_particles, load_scene};
use crate::solver::Simulation;
use std::path::Path;
use std::time::Instant;

/// One measured row of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchRow {
    /// Particles (fluid and solid).
    pub particles: u64,
    /// Backend name (`"cpu"`, `"cuda"`).
    pub backend: String,
    /// Where it ran (`"16 threads"`, the GPU's name).
    pub device: String,
    /// Particle spacing used [m].
    pub spacing: f64,
    /// Seconds per step of the scene's solver (mean over the timed steps).
    pub seconds_per_step: f64,
    /// Seconds per sweep (density + equation of state + forces).
    pub seconds_per_sweep: f64,
    /// Neighbour passes per step: force stages plus correction iterations (the position
    /// correction's and the velocity solve's sweeps).
    pub sweeps_per_step: f64,
    /// Particles times steps per wall second.
    pub particle_steps_per_second: f64,
    /// Neighbour pairs visited per wall second in sweeps (two passes per sweep).
    pub interactions_per_second: f64,
    /// Memory the backend holds per particle [B] (host for the CPU, device for CUDA).
    pub bytes_per_particle: f64,
    /// Peak resident set of the process while the row's simulation was measured, per particle
    /// [B] (`memory::peak_resident_bytes`, reset once the simulation is built; includes the
    /// program itself, a few MB, which dominates below about 1e5 particles); NaN where the
    /// system does not report it.
    pub peak_resident_per_particle: f64,
    /// Mean neighbours per particle (pairs closer than h, self excluded).
    pub neighbours: f64,
    /// This row's speedup over the CPU row of the same size, for GPU rows.
    pub speedup: Option<f64>,
    /// Seconds per step in each stage of the plan (timed in extra steps, each stage waiting for
    /// the backend to finish).
    pub stages: Vec<(String, f64)>,
    /// Position-correction sweeps and velocity-solve sweeps per step in those extra steps
    /// (zero for `wcsph`): with `stages`' `correct_positions` and `velocity_solve`, the cost of
    /// one sweep of each kind.
    pub stage_sweeps: (f64, f64),
}

/// What to measure.
#[derive(Clone, Debug)]
pub struct BenchOptions {
    /// Particle counts to aim for.
    pub sizes: Vec<u64>,
    /// Backends, in order.
    pub backends: Vec<BackendKind>,
    /// Timed steps per row (after one untimed step).
    pub steps: usize,
    /// Timed sweeps per row (after one untimed sweep).
    pub sweeps: usize,
    /// CPU worker threads (for the device column).
    pub threads: usize,
}

/// The scene at `path` with its spacing scaled so that it has about `target` particles.
///
/// # Errors
/// [`Error::Scene`] when the scene or a rescaled version of it does not validate.
pub fn scaled_scene(path: &Path, sets: &[String], target: u64) -> Result<Scene, Error> {
    let base = load_scene(path, sets)?;
    let n0 = count_particles(&base)?.total.max(1) as f64;
    let dx0 = base.spacing;
    let dim = base.dimension as f64;
    let mut dx = dx0 * (n0 / target.max(1) as f64).powf(1.0 / dim);
    // Coarser spacings thicken the walls: widen the domain by a margin of the coarsest walls.
    let ratio = base.smoothing_length / dx0;
    let with_spacing = |dx: f64| -> Vec<String> {
        let margin = 2.0 * ratio * dx.max(dx0);
        let lo: Vec<String> = base
            .domain
            .min
            .iter()
            .map(|v| format!("{:e}", v - margin))
            .collect();
        let hi: Vec<String> = base
            .domain
            .max
            .iter()
            .map(|v| format!("{:e}", v + margin))
            .collect();
        let mut s = sets.to_vec();
        s.push(format!("particles.spacing={dx:e}"));
        s.push(format!("domain.min=[{}]", lo.join(",")));
        s.push(format!("domain.max=[{}]", hi.join(",")));
        s
    };
    // Boxes snap to whole spacings: correct with the count the spacing gives.
    for _ in 0..2 {
        let scene = load_scene(path, &with_spacing(dx))?;
        let n = count_particles(&scene)?.total.max(1) as f64;
        dx *= (n / target.max(1) as f64).powf(1.0 / dim);
    }
    Ok(load_scene(path, &with_spacing(dx))?)
}

/// Pairs closer than `h` (self excluded), per particle, on the CPU grid.
fn neighbours_per_particle<const D: usize>(sim: &Simulation<D>) -> f64 {
    let f = &sim.fields;
    let h = sim.step_params().h;
    let mut grid = Grid::<D>::default();
    let Ok(perm) = grid.sort(&f.position, h) else {
        return f64::NAN;
    };
    let position: Vec<_> = perm.iter().map(|&p| f.position[p as usize]).collect();
    let id: Vec<u32> = perm.iter().map(|&p| f.id[p as usize]).collect();
    grid.link(&id, &position);
    use rayon::prelude::*;
    // Every particle up to 200,000; beyond, an even sample of 200,000 (the mean converges long
    // before, and counting 1e8 particles would take longer than the benchmark).
    let every = (position.len() / 200_000).max(1);
    let sampled = position.len().div_ceil(every);
    let pairs: u64 = (0..sampled)
        .into_par_iter()
        .map(|k| k * every)
        .map(|i| {
            let mut c = 0u64;
            grid.for_each_neighbour(&position, i, |j, _, _| c += u64::from(j != i));
            c
        })
        .sum();
    pairs as f64 / sampled.max(1) as f64
}

fn measure<const D: usize>(
    mut sim: Simulation<D>,
    scene: &Scene,
    backend: BackendKind,
    options: &BenchOptions,
) -> Result<BenchRow, Error> {
    let particles = sim.fields.len() as u64;
    let neighbours = neighbours_per_particle(&sim);
    // The peak from here on: the simulation and its backend, not the scene's generation or
    // the neighbour count's own grid (both freed by now).
    crate::memory::reset_peak_resident();
    sim.use_backend(backend)?;
    let seconds_per_sweep = sim.time_sweeps(options.sweeps)?;
    sim.step(f64::INFINITY)?;
    // Position-correction and velocity-solve sweeps so far.
    let counts = |sim: &Simulation<D>| {
        let c = sim.stats().correction;
        (c.iterations as f64, c.velocity_iterations as f64)
    };
    let sweeps = |sim: &Simulation<D>| {
        let (position, velocity) = counts(sim);
        position + velocity
    };
    let before = sweeps(&sim);
    let start = Instant::now();
    for _ in 0..options.steps {
        sim.step(f64::INFINITY)?;
    }
    sim.synchronize()?;
    let seconds_per_step = start.elapsed().as_secs_f64() / options.steps.max(1) as f64;
    let iterations = (sweeps(&sim) - before) / options.steps.max(1) as f64;
    let counted = counts(&sim);
    sim.time_stages(true);
    for _ in 0..options.steps {
        sim.step(f64::INFINITY)?;
    }
    let per_step = options.steps.max(1) as f64;
    let stage_sweeps = {
        let after = counts(&sim);
        ((after.0 - counted.0) / per_step, (after.1 - counted.1) / per_step)
    };
    let stages = sim
        .stage_seconds()
        .iter()
        .map(|(name, s)| (name.to_string(), s / options.steps.max(1) as f64))
        .collect();
    sim.time_stages(false);
    let force_stages = sim.config().integrator.stages().len() as f64;
    let device = match backend {
        BackendKind::Cpu => format!("{} threads", options.threads),
        BackendKind::Cuda => sim.backend_device().unwrap_or_else(|| "GPU".into()),
    };
    Ok(BenchRow {
        particles,
        backend: sim.backend_name().into(),
        device,
        spacing: scene.spacing,
        seconds_per_step,
        seconds_per_sweep,
        sweeps_per_step: force_stages + iterations,
        particle_steps_per_second: particles as f64 / seconds_per_step,
        interactions_per_second: 2.0 * neighbours * particles as f64 / seconds_per_sweep,
        bytes_per_particle: sim.backend_bytes() as f64 / particles.max(1) as f64,
        peak_resident_per_particle: crate::memory::peak_resident_bytes()
            .map_or(f64::NAN, |b| b as f64 / particles.max(1) as f64),
        neighbours,
        speedup: None,
        stages,
        stage_sweeps,
    })
}

/// Measures every size on every backend, reporting each row as it is done.
///
/// # Errors
/// The first scene, setup, step or backend error.
pub fn bench(
    path: &Path,
    sets: &[String],
    options: &BenchOptions,
    report: &mut dyn FnMut(&BenchRow),
) -> Result<Vec<BenchRow>, Error> {
    let mut rows: Vec<BenchRow> = Vec::new();
    for &size in &options.sizes {
        let scene = scaled_scene(path, sets, size)?;
        for &backend in &options.backends {
            let mut row = match AnySimulation::from_scene(&scene)? {
                AnySimulation::D2(sim) => measure(sim, &scene, backend, options)?,
                AnySimulation::D3(sim) => measure(sim, &scene, backend, options)?,
            };
            if backend != BackendKind::Cpu {
                row.speedup = rows
                    .iter()
                    .find(|r| r.particles == row.particles && r.backend == "cpu")
                    .map(|cpu| cpu.seconds_per_step / row.seconds_per_step);
            }
            report(&row);
            rows.push(row);
        }
    }
    Ok(rows)
}

/// Columns of `bench_stages.csv` ([`stages_csv`]).
pub const STAGE_COLUMNS: [&str; 4] = ["particles", "backend", "stage", "stage_time_per_step_s"];

/// Columns of `bench.csv` ([`to_csv`]).
pub const BENCH_COLUMNS: [&str; 13] = [
    "particles",
    "backend",
    "device",
    "spacing_m",
    "step_time_s",
    "sweep_time_s",
    "sweeps_per_step",
    "particle_steps_per_s",
    "interactions_per_s",
    "memory_B_per_particle",
    "peak_resident_B_per_particle",
    "neighbours",
    "speedup",
];

/// The per-stage breakdown as CSV ([`STAGE_COLUMNS`]): particles, backend, stage, seconds per
/// step.
pub fn stages_csv(rows: &[BenchRow]) -> String {
    let header: Vec<CsvValue> = STAGE_COLUMNS.iter().map(|c| CsvValue::Text(c)).collect();
    let mut s = format_row(&header);
    for r in rows {
        for (stage, t) in &r.stages {
            s.push_str(&format_row(&[
                CsvValue::Int(r.particles as i64),
                CsvValue::Text(&r.backend),
                CsvValue::Text(stage),
                CsvValue::Float(*t),
            ]));
        }
    }
    s
}

/// The table as CSV ([`BENCH_COLUMNS`]; header and one line per row, `speedup` empty for the
/// CPU rows).
pub fn to_csv(rows: &[BenchRow]) -> String {
    let header: Vec<CsvValue> = BENCH_COLUMNS.iter().map(|c| CsvValue::Text(c)).collect();
    let mut s = format_row(&header);
    for r in rows {
        s.push_str(&format_row(&[
            CsvValue::Int(r.particles as i64),
            CsvValue::Text(&r.backend),
            CsvValue::Text(&r.device),
            CsvValue::Float(r.spacing),
            CsvValue::Float(r.seconds_per_step),
            CsvValue::Float(r.seconds_per_sweep),
            CsvValue::Float(r.sweeps_per_step),
            CsvValue::Float(r.particle_steps_per_second),
            CsvValue::Float(r.interactions_per_second),
            CsvValue::Float(r.bytes_per_particle),
            CsvValue::Float(r.peak_resident_per_particle),
            CsvValue::Float(r.neighbours),
            r.speedup.map_or(CsvValue::Text(""), CsvValue::Float),
        ]));
    }
    s
}

/// The paper's Fig. 5 as a chart: seconds per step against particle count, log–log, one line
/// per backend (its device in the legend), in the order the backends first appear.
pub fn timing_figure(rows: &[BenchRow]) -> Figure {
    let mut series: Vec<Series> = Vec::new();
    for r in rows {
        let label = format!("{} ({})", r.backend, r.device);
        let point = (r.particles as f64, r.seconds_per_step);
        match series.iter_mut().find(|s| s.label == label) {
            Some(s) => s.points.push(point),
            None => series.push(Series {
                label,
                points: vec![point],
                style: SeriesStyle::LineMarkers,
            }),
        }
    }
    for s in &mut series {
        s.points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    Figure {
        title: "time per step against particle count (Fig. 5)".into(),
        x_label: "particles N".into(),
        y_label: "time per step [s]".into(),
        log_x: true,
        log_y: true,
        series,
        ..Figure::default()
    }
}
