//! Cost of the effect pipeline: the step time of the 3D column scene with only the
//! effects it needs, with each optional effect switched on, and with each of its own optional
//! terms switched off.
//!
//! Scene: `scenes/dam_break_column_3d.toml` at `particles.spacing=0.014` (100,990 particles, as in
//! `benches/stages.rs`), `wcsph`, CPU backend. It needs gravity, viscosity (17) and artificial
//! viscosity ([M92]); that set is `base`. Each variant edits the scene document before
//! validation (keys are added or removed with their effect, so every variant is a valid scene):
//!
//! | id                  | effects                                           |
//! |---------------------|---------------------------------------------------|
//! | `base`              | gravity, viscosity, artificial_viscosity          |
//! | `no_viscosity`      | base without viscosity (17)                       |
//! | `no_artificial`     | base without artificial viscosity                 |
//! | `+rotating_frame`   | base + Coriolis/centrifugal at Ω = 0.5 rad/s (z)  |
//! | `+surface_tension`  | base + surface tension, σ = 0.072 N/m (default model, the surface stress) |
//! | `+surface_tension_akinci` | base + [AAT13] surface tension, σ = 0.072 N/m |
//! | `+multiphase`       | base + [HA06] phases (the one box keeps ρ0 = 1000: the variants' cost alone) |
//! | `base_again`        | base, measured last: turning effects off returns here |
//!
//! Each variant is built, stepped [`WARM_STEPS`] times, then `Simulation::step` is timed (ids
//! `full_step/cpu/column_3d/<variant>`). The step is adaptive, so the variants take slightly
//! different `dt`, which does not change the work per step. Run with
//! `cargo bench --bench effects -- --noplot` (about 45 s on 2 cores after the build); the table
//! "What an effect costs" of docs/effects.md comes from it.

use criterion::{BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main};
use sph::scene::parse_scene;
use sph::solver::Simulation;
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

/// Steps taken before measuring, so that the fields are cell-sorted and moving.
const WARM_STEPS: usize = 3;

/// The scene, relative to the crate root.
const SCENE: &str = "scenes/dam_break_column_3d.toml";

/// One benchmarked configuration: an edit of the scene document.
struct Variant {
    /// Name in the benchmark ids.
    label: &'static str,
    /// Edits the parsed scene document (effects and their keys).
    edit: fn(&mut toml::Table),
}

/// The scene's `effects` array.
fn effects(doc: &mut toml::Table) -> &mut Vec<toml::Value> {
    doc.get_mut("effects")
        .and_then(toml::Value::as_array_mut)
        .expect("the column scene lists its effects")
}

/// The scene's `[fluid]` table.
fn fluid(doc: &mut toml::Table) -> &mut toml::Table {
    doc.get_mut("fluid")
        .and_then(toml::Value::as_table_mut)
        .expect("the column scene has a [fluid] table")
}

/// Removes effect `name` and its key `key` in `[fluid]`.
fn switch_off(doc: &mut toml::Table, name: &str, key: &str) {
    effects(doc).retain(|e| e.as_str() != Some(name));
    fluid(doc).remove(key);
}

/// Adds effect `name`.
fn switch_on(doc: &mut toml::Table, name: &str) {
    effects(doc).push(toml::Value::from(name));
}

const VARIANTS: &[Variant] = &[
    Variant {
        label: "base",
        edit: |_| {},
    },
    Variant {
        label: "no_viscosity",
        edit: |doc| switch_off(doc, "viscosity", "viscosity"),
    },
    Variant {
        label: "no_artificial",
        edit: |doc| switch_off(doc, "artificial_viscosity", "artificial_viscosity"),
    },
    Variant {
        label: "+rotating_frame",
        edit: |doc| {
            switch_on(doc, "rotating_frame");
            let omega = toml::Value::Array(vec![0.0.into(), 0.0.into(), 0.5.into()]);
            fluid(doc).insert("angular_velocity".into(), omega);
        },
    },
    Variant {
        label: "+surface_tension",
        edit: |doc| {
            switch_on(doc, "surface_tension");
            fluid(doc).insert("surface_tension".into(), 0.072.into());
        },
    },
    Variant {
        label: "+surface_tension_akinci",
        edit: |doc| {
            switch_on(doc, "surface_tension");
            fluid(doc).insert("surface_tension".into(), 0.072.into());
            fluid(doc).insert("surface_tension_model".into(), "akinci".into());
        },
    },
    Variant {
        label: "+multiphase",
        edit: |doc| {
            switch_on(doc, "multiphase");
            let boxes = doc
                .get_mut("fluid_box")
                .and_then(toml::Value::as_array_mut)
                .expect("the column scene has a fluid box");
            for b in boxes.iter_mut().filter_map(toml::Value::as_table_mut) {
                b.insert("rho0".into(), 1000.0.into());
            }
        },
    },
    Variant {
        label: "base_again",
        edit: |_| {},
    },
];

/// The column scene at 100,990 particles with `variant`'s edit, stepped [`WARM_STEPS`] times.
fn prepared(variant: &Variant) -> (Simulation<3>, f64) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(SCENE);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {SCENE}: {e}"));
    let mut doc: toml::Table = text
        .parse()
        .unwrap_or_else(|e| panic!("cannot parse {SCENE}: {e}"));
    (variant.edit)(&mut doc);
    let edited = toml::to_string(&doc).expect("a TOML table serialises");
    let sets = vec!["particles.spacing=0.014".to_string()];
    let what = format!("{SCENE} ({})", variant.label);
    let scene = parse_scene(&edited, &what, &sets).unwrap_or_else(|e| panic!("invalid {what}: {e}"));
    let mut sim =
        sph::run::simulation_from_scene::<3>(&scene).unwrap_or_else(|e| panic!("cannot build {what}: {e}"));
    for _ in 0..WARM_STEPS {
        sim.step(scene.end_time)
            .unwrap_or_else(|e| panic!("warm-up step of {what} failed: {e}"));
    }
    (sim, scene.end_time)
}

fn effects_cost(c: &mut Criterion) {
    let mut group = c.benchmark_group("full_step");
    group
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(4));
    for variant in VARIANTS {
        let (mut sim, end_time) = prepared(variant);
        group.throughput(Throughput::Elements(sim.fields.len() as u64));
        let id = BenchmarkId::new("cpu", format!("column_3d/{}", variant.label));
        group.bench_function(id, |b| {
            b.iter(|| black_box(sim.step(end_time).expect("a step of a warmed scene succeeds")));
        });
    }
    group.finish();
}

criterion_group!(benches, effects_cost);
criterion_main!(benches);
