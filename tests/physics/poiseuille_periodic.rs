//! Plane Poiseuille start-up in a periodic channel (`sph::periodic`): the scene of
//! `poiseuille.rs` (walls y = 0 and y = L = 0.1 m, F = 0.4 m/s² along x, ν = 0.01 m²/s,
//! u0 = 0.05 m/s, dx = L/20, h = 2 dx, `wcsph`), but the channel is one period 3 L long in x
//! instead of a free block 6 L long: fluid and walls fill the period, and particles that leave
//! at x = 3 L enter at x = 0. With no ends, every x sees the infinite channel, so the whole
//! fluid is measured (the walled test measures the middle L of its block, away from the ends).
//!
//! Target: the walled test's, every bin's mean `u_x` within 5 % of u0 of the series at
//! t = 0.02, 0.05, 0.1, 0.2 and 0.6 s (its reasoning: the lattice-calibrated viscosity and the
//! no-slip walls leave under 1 % of u0; 5 % is the validation target of SOURCES.md 7.3). The
//! period holds all its particles (none removed, mass exact) and the fluid stays in it.

use super::poiseuille::{TARGET, TIMES, WIDTH, body_force, series};
use crate::common::tolerance::CLOCK_SLACK;
use sph::fields::FLUID;
use sph::model::pair_terms::PairTerm;
use sph::run::simulation_from_scene;
use sph::scene::{Scene, load_scene};
use std::path::Path;

/// The scene: `scenes/poiseuille_2d.toml` made periodic (its comments give the reasons).
fn scene() -> Scene {
    let path = format!(
        "{}/tests/scenes/poiseuille_periodic_2d.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    load_scene(Path::new(&path), &[]).expect("a valid periodic scene")
}

#[test]
fn periodic_channel_follows_the_series_within_5_percent_of_u0() {
    let scene = scene();
    let f = body_force(&scene);
    let nu = scene.pair_terms.get(PairTerm::Viscosity).expect("viscosity") / scene.rho0;
    let u0 = f * WIDTH * WIDTH / (8.0 * nu);
    let mut sim = simulation_from_scene::<2>(&scene).expect("the scene builds");
    let (count, mass) = (
        sim.fields.len(),
        sim.fields.mass.iter().map(|&m| f64::from(m)).sum::<f64>(),
    );
    let dx = scene.spacing;
    let bins = (WIDTH / dx).round() as usize;
    let mut errors = Vec::new();
    for &t in &TIMES {
        while sim.clock().time < t - CLOCK_SLACK {
            sim.step(t).expect("the step succeeds");
        }
        sim.sync_fields().expect("CPU fields");
        let fields = &sim.fields;
        let (mut sum, mut n) = (vec![0.0; bins], vec![0usize; bins]);
        for i in (0..fields.len()).filter(|&i| fields.kind[i] == FLUID) {
            let (x, y) = (fields.position[i][0], f64::from(fields.position[i][1]));
            assert!(
                (0.0..0.3).contains(&x),
                "fluid particle at x = {x} left the period"
            );
            let b = ((y / dx).floor().max(0.0) as usize).min(bins - 1);
            sum[b] += f64::from(fields.velocity[i][0]);
            n[b] += 1;
        }
        let worst = (0..bins)
            .map(|b| {
                let y = (b as f64 + 0.5) * dx;
                (sum[b] / n[b] as f64 - series(y, t, f, nu)).abs() / u0
            })
            .fold(0.0, f64::max);
        errors.push((t, worst));
    }
    println!("periodic: worst bin / u0 at each time [s]: {errors:.4?}");
    assert_eq!(sim.fields.len(), count, "no particle removed");
    let after: f64 = sim.fields.mass.iter().map(|&m| f64::from(m)).sum();
    assert_eq!(after, mass, "mass kept exactly");
    assert!(
        errors.iter().all(|&(_, e)| e <= TARGET),
        "worst bin / u0 at each time [s] (target {TARGET}): {errors:.3?}"
    );
}

/// A restart is exact across the periodic face: with the fluid started at 0.5 m/s along x, a run
/// restored from a checkpoint after 30 steps takes the next 30 (in which particles cross the
/// face at x = 0.3 m and enter at 0) bit for bit as the run that went on.
#[test]
fn a_periodic_restart_is_bit_identical_across_the_face() {
    let path = format!(
        "{}/tests/scenes/poiseuille_periodic_2d.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let sets = ["fluid_box.0.velocity=[0.5, 0.0]".to_string()];
    let scene = load_scene(Path::new(&path), &sets).expect("a valid periodic scene");
    let mut sim = simulation_from_scene::<2>(&scene).expect("builds");
    for _ in 0..30 {
        sim.step(scene.end_time).expect("stable step");
    }
    let saved = sim.checkpoint(serde_json::Value::Null).expect("cpu checkpoint");
    let before: Vec<(u32, f32)> = (0..sim.fields.len())
        .map(|i| (sim.fields.id[i], sim.fields.position[i][0]))
        .collect();
    let mut restored = simulation_from_scene::<2>(&scene).expect("builds");
    restored.restore(saved).expect("same scene");
    for _ in 0..30 {
        sim.step(scene.end_time).expect("stable step");
        restored.step(scene.end_time).expect("stable step");
    }
    assert_eq!(sim.fields.position, restored.fields.position);
    assert_eq!(sim.fields.velocity, restored.fields.velocity);
    assert_eq!(sim.fields.density, restored.fields.density);
    assert_eq!(sim.clock(), restored.clock());
    // Particles crossed the face in the steps compared: their x fell by most of a period.
    let x_after: std::collections::HashMap<u32, f32> = (0..sim.fields.len())
        .map(|i| (sim.fields.id[i], sim.fields.position[i][0]))
        .collect();
    let crossed = before.iter().filter(|(id, x)| x - x_after[id] > 0.2).count();
    assert!(crossed > 0, "no particle crossed the periodic face");
    println!("{crossed} particles crossed the face after the checkpoint");
}
