//! Criterion benchmarks of the solver's stages on the CPU backend, one group per stage, for two
//! shipped scenes:
//!
//! - `column_3d`: `scenes/dam_break_column_3d.toml` (wcsph) with `particles.spacing=0.014` m,
//!   which gives 100,990 particles (52,374 fluid, 48,616 solid) instead of the shipped 195,885;
//! - `dam_2d`: `scenes/dam_break_2d.toml` as shipped (corrected, RK3), 3,408 particles.
//!
//! Benchmark ids are `<stage>/cpu/<scene>/<particles>`; throughput is particles per second.
//!
//! | group              | what one iteration does                                                  |
//! |--------------------|--------------------------------------------------------------------------|
//! | `sort_by_cell`     | neighbour search and reorder: hash, radix sort, permute every field, link |
//! | `density`          | eq. (18), density by summation                                           |
//! | `forces_pressure`  | eqs. (15)–(16), (6): the force stage with no viscous term                |
//! | `forces_viscosity` | the same plus eq. (17); the difference to `forces_pressure` is (17)'s cost |
//! | `correction_sweep` | one iteration of the position correction (23)–(24), as the loop runs it  |
//! | `integrate`        | symplectic Euler, one step `dt`                                          |
//! | `rk_stage`         | one SSP-RK3 Shu–Osher stage (the second: `a = 3/4`, `b = 1/4`)           |
//! | `write_frame`      | one `.vtu` frame of every particle (output), to a temporary folder       |
//! | `full_step`        | one `Simulation::step`: `column_3d` as wcsph, `dam_2d` as both solvers   |
//!
//! Each scene is stepped [`WARM_STEPS`] times first, so the particles are in the order and state
//! of a running simulation rather than the initial lattice; every stage but `sort_by_cell` and
//! `full_step` then runs on that state after one sort, density, equation of state (wcsph only)
//! and wall pressure, the inputs the solver's force stage sees.
//!
//! The 3D scene's `full_step` as `corrected` (`--set solver.kind=corrected`) is left out: one
//! step took about 14 s on 2 cores (criterion's estimate after a 0.5 s warm-up, on a loaded
//! machine), so 10 samples would take minutes, and its warm-up steps (the start-up settle and
//! three RK3 steps of up to 200 sweeps per stage) minutes more. `correction_sweep` times its unit.
//!
//! Run with `cargo bench --bench stages` (estimated 2–3 minutes on 2 cores from per-group runs,
//! not timed end to end), or one group with e.g.
//! `cargo bench --bench stages -- density`; add `--noplot` where criterion's plotters backend
//! finds no fonts (it panics otherwise). Every run builds and warms both scenes first, whatever
//! the filter. Sample sizes are criterion's minimum (10) and the times short: on a shared 2-core
//! machine the confidence intervals spanned up to ±30 %; compare runs on the same machine only.

use criterion::measurement::WallTime;
use criterion::{
    BatchSize, BenchmarkGroup, BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group,
    criterion_main,
};
use sph::backend::cpu::CpuBackend;
use sph::backend::{Backend, ForceTerms, SolidForceSource, WallModel};
use sph::fields::Fields;
use sph::model::pair_terms::{PairTerm, PairTerms};
use sph::output::Encoding;
use sph::output::vtu::{Frame, write_vtu};
use sph::physics::lattice::{correction_stiffness, lattice_gradient_moment};
use sph::scene::load_scene;
use sph::smoothing::Smoothing;
use sph::solver::Simulation;
use sph::solver::step::MAX_SWEEP_STEP;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Steps taken before measuring, so that the fields are cell-sorted and moving.
const WARM_STEPS: usize = 3;

/// A benchmarked scene: its file (relative to the crate root) and `--set` overrides.
struct Case {
    /// Name in the benchmark ids.
    label: &'static str,
    /// Scene file, relative to the crate root.
    path: &'static str,
    /// `key=value` overrides, as `sph run --set` takes them.
    sets: &'static [&'static str],
}

/// The 3D column scene at about 1e5 particles (100,990 at dx = 0.014 m, h = 0.028 m).
const COLUMN_3D: Case = Case {
    label: "column_3d",
    path: "scenes/dam_break_column_3d.toml",
    sets: &["particles.spacing=0.014"],
};

/// The 2D dam break as shipped (3,408 particles, dx = 5 mm).
const DAM_2D: Case = Case {
    label: "dam_2d",
    path: "scenes/dam_break_2d.toml",
    sets: &[],
};

/// A warmed simulation of a case, the state the stages start from and the backend whose grid
/// matches that state.
struct Prepared<const D: usize> {
    label: &'static str,
    sim: Simulation<D>,
    /// Time step [s] of the last warm-up step.
    dt: f64,
    /// End time [s] of the scene (bounds `full_step`).
    end_time: f64,
    /// `sim.fields` after a sort, density, equation of state (wcsph) and wall pressure.
    fields: Fields<D>,
    /// Backend whose grid was built for `fields`.
    backend: CpuBackend<D>,
}

impl<const D: usize> Prepared<D> {
    /// Loads `case` with `extra` overrides, steps it [`WARM_STEPS`] times and prepares the
    /// stage inputs.
    fn new(case: &Case, extra: &[&str]) -> Self {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(case.path);
        let sets: Vec<String> = case.sets.iter().chain(extra).map(|s| s.to_string()).collect();
        let what = format!("{} {sets:?}", case.path);
        let scene = load_scene(&path, &sets).unwrap_or_else(|e| panic!("cannot load {what}: {e}"));
        let mut sim = sph::run::simulation_from_scene::<D>(&scene)
            .unwrap_or_else(|e| panic!("cannot build {what}: {e}"));
        let mut dt = 0.0;
        for _ in 0..WARM_STEPS {
            let report = sim
                .step(scene.end_time)
                .unwrap_or_else(|e| panic!("warm-up step of {what} failed: {e}"));
            dt = report.dt;
        }
        let (fields, backend) = stage_inputs(&sim);
        Self {
            label: case.label,
            sim,
            dt,
            end_time: scene.end_time,
            fields,
            backend,
        }
    }

    /// Particles (fluid and solid).
    fn len(&self) -> usize {
        self.fields.len()
    }

    /// Benchmark id `cpu/<scene>/<particles>`.
    fn id(&self) -> BenchmarkId {
        BenchmarkId::new("cpu", format!("{}/{}", self.label, self.len()))
    }

    /// Whether the scene runs the `corrected` solver.
    fn corrected(&self) -> bool {
        self.sim.config().correction.is_some()
    }
}

/// The state the force stage sees: `sim`'s fields sorted, with density (18), the equation of
/// state (19) for wcsph (the corrected solver carries its pressure) and the wall pressure.
fn stage_inputs<const D: usize>(sim: &Simulation<D>) -> (Fields<D>, CpuBackend<D>) {
    let params = sim.step_params();
    let corrected = sim.config().correction.is_some();
    let mut backend = CpuBackend::<D>::new();
    let mut fields = sim.fields.clone();
    backend
        .sort_by_cell(&mut fields, &params)
        .expect("a warmed scene's particles are finite");
    backend.density(&mut fields, &params);
    if !corrected {
        backend.equation_of_state(&mut fields, &params);
    }
    let model = if corrected {
        WallModel::Extrapolated
    } else {
        WallModel::ExtrapolatedOrSummed
    };
    backend.wall_pressure(&mut fields, &params, model, &[]);
    (fields, backend)
}

/// A group for stage `name`: criterion's minimum of 10 samples, short times.
fn group<'a>(c: &'a mut Criterion, name: &str) -> BenchmarkGroup<'a, WallTime> {
    let mut group = c.benchmark_group(name);
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    group
}

/// `sort_by_cell`: each iteration sorts a copy of the fields as the last step left them
/// (sorted one step ago, then moved), like the first stage of a step; the copy is not timed.
fn sort_by_cell<const D: usize>(group: &mut BenchmarkGroup<WallTime>, p: &Prepared<D>) {
    group.throughput(Throughput::Elements(p.len() as u64));
    let params = p.sim.step_params();
    let mut backend = CpuBackend::<D>::new();
    group.bench_function(p.id(), |b| {
        b.iter_batched(
            || p.sim.fields.clone(),
            |mut f| {
                backend
                    .sort_by_cell(&mut f, &params)
                    .expect("the particles are finite");
                f
            },
            BatchSize::LargeInput,
        );
    });
}

/// `density`: eq. (18) over every particle of the prepared state.
fn density<const D: usize>(group: &mut BenchmarkGroup<WallTime>, p: &mut Prepared<D>) {
    group.throughput(Throughput::Elements(p.len() as u64));
    let params = p.sim.step_params();
    let id = p.id();
    let (fields, backend) = (&mut p.fields, &mut p.backend);
    group.bench_function(id, |b| {
        b.iter(|| {
            backend.density(fields, &params);
            black_box(&fields.density);
        });
    });
}

/// The force stage with `terms` on the prepared state (acceleration of every fluid particle).
fn forces<const D: usize>(group: &mut BenchmarkGroup<WallTime>, p: &mut Prepared<D>, terms: ForceTerms) {
    group.throughput(Throughput::Elements(p.len() as u64));
    let params = p.sim.step_params();
    let id = p.id();
    let (fields, backend) = (&mut p.fields, &mut p.backend);
    group.bench_function(id, |b| {
        b.iter(|| {
            backend.forces(fields, &params, terms);
            black_box(&fields.acceleration);
        });
    });
}

/// `correction_sweep`: the first iteration of `Simulation::correct`'s loop for the first RK
/// stage (`τ = dt`, `kick_tau = τ`): density (18), correction error (24), correction pressure
/// (19) with the solver's stiffness `ω K/τ²` (`ω` from the scene, the default 0.5 for wcsph),
/// the correction's force on the solids, and the displacement (23) capped at
/// `MAX_SWEEP_STEP · dx`. Not timed: the copy of the prepared state each iteration starts from
/// (so the grid stays valid), `begin_correction`, and the loop's occasional re-sort and
/// no-penetration guard (`boundary::keep_out`, not reachable from a bench).
fn correction_sweep<const D: usize>(group: &mut BenchmarkGroup<WallTime>, p: &mut Prepared<D>) {
    group.throughput(Throughput::Elements(p.len() as u64));
    let params = p.sim.step_params();
    let config = p.sim.config();
    let kernel = Smoothing::<D>::new(params.h).expect("the simulation was built, so D is 2 or 3");
    let kappa = lattice_gradient_moment(&kernel, config.spacing, config.rho0);
    let k = correction_stiffness(
        &kernel,
        config.spacing,
        config.rho0,
        kappa,
        params.density_weight(),
    );
    let relaxation = config.correction.unwrap_or_default().relaxation;
    let tau = p.dt;
    let stiffness = (relaxation * k / (tau * tau)) as f32;
    let max_step = (MAX_SWEEP_STEP * config.spacing) as f32;
    let solids = p.sim.solid_names().len();
    let id = p.id();
    let (fields, backend) = (&p.fields, &mut p.backend);
    group.bench_function(id, |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let mut f = fields.clone();
                backend.begin_correction(&mut f);
                let start = Instant::now();
                backend.density(&mut f, &params);
                black_box(backend.correction_error(&f, &params));
                backend.correction_pressure(&mut f, &params, stiffness);
                if solids > 0 {
                    black_box(backend.solid_forces(&f, &params, solids, SolidForceSource::Correction));
                }
                black_box(backend.correct_positions(&mut f, &params, tau as f32, tau as f32, max_step));
                total += start.elapsed();
            }
            total
        });
    });
}

/// `integrate`: symplectic Euler with the last warm-up `dt`. The state drifts from iteration
/// to iteration (the stage reads no neighbours, so its cost does not depend on the values).
fn integrate<const D: usize>(group: &mut BenchmarkGroup<WallTime>, p: &Prepared<D>) {
    group.throughput(Throughput::Elements(p.len() as u64));
    let mut fields = p.fields.clone();
    let mut backend = CpuBackend::<D>::new();
    let dt = p.dt as f32;
    group.bench_function(p.id(), |b| {
        b.iter(|| {
            backend.integrate(&mut fields, dt);
            black_box(&fields.position);
        });
    });
}

/// `rk_stage`: the second SSP-RK3 stage (`x ← 3/4 x^n + 1/4 (x + dt u)`, likewise `u`) with the
/// last warm-up `dt`, after `store_step_start` (not timed). The state stays bounded: each
/// iteration pulls it back towards the stored start.
fn rk_stage<const D: usize>(group: &mut BenchmarkGroup<WallTime>, p: &Prepared<D>) {
    group.throughput(Throughput::Elements(p.len() as u64));
    let mut fields = p.fields.clone();
    let mut backend = CpuBackend::<D>::new();
    backend.store_step_start(&mut fields);
    let dt = p.dt as f32;
    group.bench_function(p.id(), |b| {
        b.iter(|| {
            backend.rk_stage(&mut fields, dt, 0.75, 0.25);
            black_box(&fields.position);
        });
    });
}

/// `write_frame`: one `.vtu` frame (positions, velocity, density, pressure, kind, id of every
/// particle, zlib-compressed), as `sph run` writes them by default, overwritten in a temporary folder each iteration.
fn write_frame<const D: usize>(group: &mut BenchmarkGroup<WallTime>, p: &Prepared<D>, dir: &Path) {
    group.throughput(Throughput::Elements(p.len() as u64));
    let f = &p.fields;
    let frame = Frame {
        time: p.sim.clock().time,
        position: &f.position,
        velocity: &f.velocity,
        density: &f.density,
        pressure: &f.pressure,
        kind: &f.kind,
        id: &f.id,
    };
    let path = dir.join(format!("{}.vtu", p.label));
    group.bench_function(p.id(), |b| {
        b.iter(|| write_vtu(&path, &frame, Encoding::default()).expect("the temporary folder is writable"));
    });
}

/// `full_step`: one `Simulation::step` of the warmed scene under id
/// `cpu/<scene>/<solver>/<particles>`. The simulation keeps running from iteration to
/// iteration.
fn full_step<const D: usize>(group: &mut BenchmarkGroup<WallTime>, p: &mut Prepared<D>) {
    group.throughput(Throughput::Elements(p.len() as u64));
    let solver = if p.corrected() { "corrected" } else { "wcsph" };
    let id = BenchmarkId::new("cpu", format!("{}/{solver}/{}", p.label, p.len()));
    let (sim, end_time) = (&mut p.sim, p.end_time);
    group.bench_function(id, |b| {
        b.iter(|| black_box(sim.step(end_time).expect("a step of a warmed scene succeeds")));
    });
}

/// A fresh temporary folder for the frames; removed at the end of the run.
fn frame_dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sph-bench-frames-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
    dir
}

fn stages(c: &mut Criterion) {
    let mut column = Prepared::<3>::new(&COLUMN_3D, &[]);
    let mut dam = Prepared::<2>::new(&DAM_2D, &[]);
    let pressure_only = ForceTerms {
        pair: PairTerms::NONE,
        rotating_frame: false,
    };
    let with_viscosity = ForceTerms {
        pair: PairTerms::NONE.with(PairTerm::Viscosity),
        rotating_frame: false,
    };

    let mut g = group(c, "sort_by_cell");
    sort_by_cell(&mut g, &column);
    sort_by_cell(&mut g, &dam);
    g.finish();

    let mut g = group(c, "density");
    density(&mut g, &mut column);
    density(&mut g, &mut dam);
    g.finish();

    let mut g = group(c, "forces_pressure");
    forces(&mut g, &mut column, pressure_only);
    forces(&mut g, &mut dam, pressure_only);
    g.finish();

    let mut g = group(c, "forces_viscosity");
    forces(&mut g, &mut column, with_viscosity);
    forces(&mut g, &mut dam, with_viscosity);
    g.finish();

    let mut g = group(c, "correction_sweep");
    correction_sweep(&mut g, &mut column);
    correction_sweep(&mut g, &mut dam);
    g.finish();

    let mut g = group(c, "integrate");
    integrate(&mut g, &column);
    integrate(&mut g, &dam);
    g.finish();

    let mut g = group(c, "rk_stage");
    rk_stage(&mut g, &column);
    rk_stage(&mut g, &dam);
    g.finish();

    let dir = frame_dir();
    let mut g = group(c, "write_frame");
    write_frame(&mut g, &column, &dir);
    write_frame(&mut g, &dam, &dir);
    g.finish();
    // Best effort: a leftover folder in the temporary directory is harmless.
    let _ = std::fs::remove_dir_all(&dir);

    // A step is long (30–60 ms for the 3D scene on two cores, ~140 ms for the 2D corrected one
    // with its ~200 sweeps): flat sampling takes the same few iterations per sample.
    let mut g = group(c, "full_step");
    g.sampling_mode(SamplingMode::Flat)
        .measurement_time(Duration::from_secs(5));
    full_step(&mut g, &mut column);
    full_step(&mut g, &mut dam);
    full_step(&mut g, &mut Prepared::<2>::new(&DAM_2D, &["solver.kind=wcsph"]));
    g.finish();
}

criterion_group!(benches, stages);
criterion_main!(benches);
