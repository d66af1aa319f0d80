//! Criterion benchmarks of the solver's stages on the shipped 3D scene
//! `scenes/dam_break_column_3d.toml` (CPU backend): `sort_by_cell` (neighbour search: hash,
//! radix sort, permute every field, link), `density` (eq. 18) and `full_step` (one
//! `Simulation::step`). The scene is stepped a few times first, so the particles are in the
//! order and state of a running simulation rather than the initial lattice.
//!
//! Run with `cargo bench --bench stages`; sample sizes are small so it finishes in minutes.

use criterion::{
    BatchSize, BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main,
};
use sph::backend::Backend;
use sph::backend::cpu::CpuBackend;
use sph::scene::load_scene;
use sph::solver::Simulation;
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

/// The benchmarked scene, relative to the crate root (where `cargo bench` runs).
const SCENE: &str = "scenes/dam_break_column_3d.toml";

/// Steps taken before measuring, so that the fields are cell-sorted and moving.
const WARM_STEPS: usize = 3;

/// The 3D column scene after [`WARM_STEPS`] steps, and its end time.
fn warmed_simulation() -> (Simulation<3>, f64) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(SCENE);
    let scene = load_scene(&path, &[]).unwrap_or_else(|e| panic!("cannot load {SCENE}: {e}"));
    let mut sim =
        sph::run::simulation_from_scene::<3>(&scene).unwrap_or_else(|e| panic!("cannot build {SCENE}: {e}"));
    for _ in 0..WARM_STEPS {
        sim.step(scene.end_time)
            .unwrap_or_else(|e| panic!("warm-up step of {SCENE} failed: {e}"));
    }
    (sim, scene.end_time)
}

fn stages(c: &mut Criterion) {
    let (mut sim, end_time) = warmed_simulation();
    let n = sim.fields.len();
    let params = sim.step_params();

    let mut group = c.benchmark_group("sort_by_cell");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    group.throughput(Throughput::Elements(n as u64));
    group.bench_with_input(BenchmarkId::new("cpu", n), &sim.fields, |b, fields| {
        let mut backend = CpuBackend::<3>::new();
        // Each iteration sorts the fields as the last step left them (sorted one step ago, then
        // moved), like the first stage of a step; the clone is not timed.
        b.iter_batched(
            || fields.clone(),
            |mut f| {
                backend
                    .sort_by_cell(&mut f, params.h)
                    .expect("the scene's particles are finite");
                f
            },
            BatchSize::LargeInput,
        );
    });
    group.finish();

    let mut group = c.benchmark_group("density");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    group.throughput(Throughput::Elements(n as u64));
    let mut backend = CpuBackend::<3>::new();
    let mut fields = sim.fields.clone();
    backend
        .sort_by_cell(&mut fields, params.h)
        .expect("the scene's particles are finite");
    group.bench_function(BenchmarkId::new("cpu", n), |b| {
        b.iter(|| {
            backend.density(&mut fields, &params);
            black_box(&fields.density);
        });
    });
    group.finish();

    let mut group = c.benchmark_group("full_step");
    // One step is long (a good fraction of a second on two cores): flat sampling takes the
    // same few iterations per sample instead of 1, 2, …, 10.
    group
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    group.throughput(Throughput::Elements(n as u64));
    group.bench_function(BenchmarkId::new("cpu", n), |b| {
        b.iter(|| black_box(sim.step(end_time).expect("a step of the column scene succeeds")));
    });
    group.finish();
}

criterion_group!(benches, stages);
criterion_main!(benches);
