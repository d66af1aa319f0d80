//! Checkpoint and restart: 200 steps straight and 100 + checkpoint file + restart + 100 give
//! bit-identical states on the CPU backend (the restart also on another thread count), for both
//! solvers; damaged or foreign checkpoints are refused with an error naming the problem.

use crate::common::scratch;
use sph::run::AnySimulation;
use sph::scene::load_scene;
use sph::solver::Simulation;
use sph::solver::checkpoint::{Checkpoint, CheckpointError};
use std::path::Path;

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/dam_break_2d.toml");

fn sim(sets: &[&str]) -> Simulation<2> {
    sim_of(SCENE, sets)
}

fn sim_of(path: &str, sets: &[&str]) -> Simulation<2> {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let scene = load_scene(Path::new(path), &sets).expect("scene");
    match AnySimulation::from_scene(&scene).expect("builds") {
        AnySimulation::D2(s) => s,
        AnySimulation::D3(_) => unreachable!("2D scene"),
    }
}

fn steps(sim: &mut Simulation<2>, n: usize) {
    for _ in 0..n {
        sim.step(f64::INFINITY).expect("step");
    }
}

/// Every field bit for bit, in the same order.
fn assert_identical(a: &Simulation<2>, b: &Simulation<2>) {
    assert_eq!(a.clock(), b.clock());
    assert_eq!(a.stats(), b.stats());
    assert_eq!(a.solid_forces(), b.solid_forces());
    let records = |s: &Simulation<2>| -> Vec<_> {
        s.floating_bodies()
            .iter()
            .map(|b| b.as_ref().map(|b| b.record()))
            .collect()
    };
    assert_eq!(records(a), records(b), "floating bodies");
    let (fa, fb) = (&a.fields, &b.fields);
    assert_eq!(fa.id, fb.id, "same order");
    let bits = |v: &[sph::math::Vector<2>]| -> Vec<u32> {
        v.iter().flat_map(|x| x.iter().map(|c| c.to_bits())).collect()
    };
    let sbits = |v: &[f32]| -> Vec<u32> { v.iter().map(|c| c.to_bits()).collect() };
    assert_eq!(bits(&fa.position), bits(&fb.position), "positions");
    assert_eq!(bits(&fa.velocity), bits(&fb.velocity), "velocities");
    assert_eq!(bits(&fa.acceleration), bits(&fb.acceleration), "accelerations");
    assert_eq!(sbits(&fa.density), sbits(&fb.density), "densities");
    assert_eq!(sbits(&fa.pressure), sbits(&fb.pressure), "pressures");
}

fn straight_and_restarted(name: &str, sets: &[&str], first: usize, second: usize) {
    straight_and_restarted_in(SCENE, name, sets, first, second);
}

fn straight_and_restarted_in(scene: &str, name: &str, sets: &[&str], first: usize, second: usize) {
    let sim = |sets: &[&str]| sim_of(scene, sets);
    let mut straight = sim(sets);
    steps(&mut straight, first + second);

    let mut before = sim(sets);
    steps(&mut before, first);
    let path = scratch(name).join("checkpoint.bin");
    let meta = serde_json::json!({"note": name});
    before
        .checkpoint(meta.clone())
        .expect("state")
        .write(&path)
        .expect("written");
    drop(before);
    let checkpoint = Checkpoint::<2>::read(&path).expect("read back");
    assert_eq!(checkpoint.header.metadata, meta);
    let mut resumed = sim(sets);
    resumed.restore(checkpoint).expect("same scene");
    // The second half on one thread: the CPU backend's sums do not depend on the thread count.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    pool.install(|| steps(&mut resumed, second));
    assert_identical(&straight, &resumed);
    assert!(straight.clock().time > 0.0);
    std::fs::remove_dir_all(path.parent().expect("dir")).ok();
}

#[test]
fn wcsph_restart_is_bit_identical() {
    straight_and_restarted(
        "wcsph",
        &["solver.kind=wcsph", "particles.spacing=0.01"],
        100,
        100,
    );
}

/// With the `density_diffusion` effect the density is state, and symplectic Euler advances it
/// at the start of a step by the last step's `dt` (`Clock::last_dt`): both must come back.
#[test]
fn wcsph_with_density_diffusion_restart_is_bit_identical() {
    for integrator in ["symplectic_euler", "rk3"] {
        let integrator = format!("solver.integrator={integrator}");
        straight_and_restarted(
            "density_diffusion",
            &[
                "solver.kind=wcsph",
                "particles.spacing=0.01",
                r#"effects=["gravity", "viscosity", "artificial_viscosity", "density_diffusion"]"#,
                "fluid.density_diffusion=0.1",
                &integrator,
            ],
            100,
            100,
        );
    }
}

/// A floating box (`scenes/floating_box_2d.toml`): its state and last accelerations are kept.
#[test]
fn floating_body_restart_is_bit_identical() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/floating_box_2d.toml");
    straight_and_restarted_in(scene, "floating", &[], 60, 60);
}

/// Open boundaries (`scenes/open_channel_2d.toml`, the fluid moving at the inflow's speed from
/// the start): the particles created behind the inflow and removed past the outflow between the
/// checkpoint and the end are the same, with the same ids, in the same order.
#[test]
fn open_boundary_restart_is_bit_identical() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/open_channel_2d.toml");
    for integrator in ["symplectic_euler", "rk3"] {
        let integrator = format!("solver.integrator={integrator}");
        let sets = [
            "fluid_box.0.velocity=[0.2, 0.0]",
            "open_boundary.0.ramp=0.001",
            &integrator,
        ];
        straight_and_restarted_in(scene, "open_boundary", &sets, 60, 60);
        // Particles were created and removed after the checkpoint.
        let (mut half, mut whole) = (sim_of(scene, &sets), sim_of(scene, &sets));
        steps(&mut half, 60);
        steps(&mut whole, 120);
        let (h, w) = (half.stats(), whole.stats());
        assert!(
            w.created_particles > h.created_particles && w.outflow_particles > h.outflow_particles,
            "{integrator}: created {} then {}, removed {} then {}",
            h.created_particles,
            w.created_particles,
            h.outflow_particles,
            w.outflow_particles
        );
    }
}

#[test]
fn corrected_restart_is_bit_identical() {
    straight_and_restarted("corrected", &["particles.spacing=0.01"], 15, 15);
}

/// With `solver.warm_start` the velocity solves' records are state: the checkpoint carries them
/// (and a checkpoint of the first steps, before any, carries none), and the resumed run warm
/// starts as the straight one does. Also checks that the warm start is on: fewer velocity
/// iterations than the same steps without it.
#[test]
fn corrected_warm_start_restart_is_bit_identical() {
    let warm = ["particles.spacing=0.01", "solver.warm_start=true"];
    straight_and_restarted("corrected_warm", &warm, 15, 15);
    straight_and_restarted("corrected_warm_early", &warm, 1, 5);
    let iterations = |sets: &[&str]| {
        let mut s = sim(sets);
        steps(&mut s, 30);
        s.stats().correction.velocity_iterations
    };
    let (cold, warm) = (iterations(&["particles.spacing=0.01"]), iterations(&warm));
    assert!(warm < cold, "velocity iterations: {warm} warm, {cold} cold");
}

#[test]
fn damaged_and_foreign_checkpoints_are_refused() {
    let dir = scratch("damaged");
    let path = dir.join("checkpoint.bin");
    let mut s = sim(&["solver.kind=wcsph", "particles.spacing=0.01"]);
    steps(&mut s, 3);
    s.checkpoint(serde_json::Value::Null)
        .expect("state")
        .write(&path)
        .expect("written");
    let bytes = std::fs::read(&path).expect("read");
    for entry in std::fs::read_dir(&dir).expect("folder") {
        let name = entry.expect("entry").file_name().to_string_lossy().into_owned();
        assert!(
            !sph::output::safe_file::is_tmp_name(&name),
            "the temporary file {name} is renamed away"
        );
    }

    // Truncated, and one flipped byte: the checksum catches both.
    for (label, damaged) in [
        ("truncated", bytes[..bytes.len() / 2].to_vec()),
        ("flipped", {
            let mut b = bytes.clone();
            let k = b.len() / 2;
            b[k] ^= 0x40;
            b
        }),
        ("empty", Vec::new()),
        ("foreign", b"<?xml version=\"1.0\"?>".to_vec()),
    ] {
        std::fs::write(&path, &damaged).expect("write");
        match Checkpoint::<2>::read(&path) {
            Err(CheckpointError::Malformed { path: p, .. }) => assert_eq!(p, path, "{label}"),
            other => panic!("{label}: expected Malformed, got {:?}", other.map(|_| ())),
        }
    }
    // A 2D checkpoint read as 3D.
    std::fs::write(&path, &bytes).expect("write");
    let err = Checkpoint::<3>::read(&path).map(|_| ()).expect_err("dimension");
    assert!(err.to_string().contains("2D"), "{err}");
    // Another scene: a different spacing has a different particle count.
    let good = Checkpoint::<2>::read(&path).expect("intact");
    let mut other = sim(&["solver.kind=wcsph", "particles.spacing=0.0125"]);
    let err = other.restore(good).expect_err("another scene");
    assert!(matches!(err, CheckpointError::Mismatch { .. }), "{err}");
    assert!(err.to_string().contains("particles"), "{err}");
    // A missing file names itself.
    let err = Checkpoint::<2>::read(&dir.join("nope.bin"))
        .map(|_| ())
        .expect_err("missing");
    assert!(err.to_string().contains("nope.bin"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
