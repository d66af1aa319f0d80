//! `sph bench`: rescaling a scene to a particle count, and one measured row on the CPU.

use sph::backend::BackendKind;
use sph::bench::{BenchOptions, bench, scaled_scene, to_csv};
use sph::scene::generate::count_particles;
use std::path::Path;

const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/dam_break_column_3d.toml");

#[test]
fn scaled_scene_has_about_the_asked_particle_count() {
    for target in [5_000u64, 40_000] {
        let scene = scaled_scene(Path::new(SCENE), &[], target).expect("rescales");
        let n = count_particles(&scene).expect("counts").total as f64;
        // Boxes snap to whole spacings, so the count moves in steps of a layer: within 15 %.
        assert!((n / target as f64 - 1.0).abs() < 0.15, "{n} for {target}");
        assert!(
            (scene.smoothing_length / scene.spacing - 2.0).abs() < 1e-9,
            "h follows dx"
        );
    }
}

/// One row of about 3,000 particles on the CPU, one timed step and sweep, one thread.
fn small_cpu_options() -> BenchOptions {
    BenchOptions {
        sizes: vec![3_000],
        backends: vec![BackendKind::Cpu],
        steps: 1,
        sweeps: 1,
        threads: 1,
    }
}

#[test]
fn one_cpu_row_is_measured_and_written() {
    let options = small_cpu_options();
    let mut reported = 0;
    let rows = bench(Path::new(SCENE), &[], &options, &mut |_| reported += 1).expect("runs");
    assert_eq!((rows.len(), reported), (1, 1));
    let r = &rows[0];
    assert_eq!(r.backend, "cpu");
    assert!(r.seconds_per_step > 0.0 && r.seconds_per_sweep > 0.0);
    assert_eq!(
        r.sweeps_per_step, 1.0,
        "wcsph with symplectic Euler: one force pass per step"
    );
    // A 3D lattice with h = 2 dx has 32 neighbours inside; walls and the free surface have fewer.
    assert!(r.neighbours > 10.0 && r.neighbours < 33.0, "{}", r.neighbours);
    assert!(r.bytes_per_particle > 50.0 && r.bytes_per_particle < 600.0);
    // The process's peak (Linux): at least what the backend holds, and the binary's few MB.
    if !r.peak_resident_per_particle.is_nan() {
        assert!(
            r.peak_resident_per_particle > r.bytes_per_particle,
            "{} vs {}",
            r.peak_resident_per_particle,
            r.bytes_per_particle
        );
    }
    assert_eq!(r.speedup, None);
    let names: Vec<&str> = r.stages.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "sort_by_cell",
            "density",
            "equation_of_state",
            "wall_pressure",
            "wall_velocity",
            "forces",
            "solid_forces",
            "time_step",
            "integrate"
        ],
        "the wcsph plan with walls and viscosity (no-slip walls: wall_velocity), in order"
    );
    assert!(r.stages.iter().all(|(_, t)| *t >= 0.0));
    assert_eq!(r.stage_sweeps, (0.0, 0.0), "wcsph has no correction sweeps");
    let csv = to_csv(&rows);
    assert_eq!(csv.lines().count(), 2);
    assert!(csv.starts_with("particles,backend,device,"));
}

/// A `corrected` row times the position sweeps (`correct_positions`) and the velocity solve
/// (`velocity_solve`) as separate stages and counts the sweeps of each in the same steps, so
/// that `sph bench` can give the cost of one sweep of each kind.
#[test]
fn corrected_row_times_position_and_velocity_sweeps_apart() {
    let options = small_cpu_options();
    let sets = ["solver.kind=corrected".to_string()];
    let rows = bench(Path::new(SCENE), &sets, &options, &mut |_| {}).expect("runs");
    let r = &rows[0];
    let time = |name: &str| r.stages.iter().find(|(n, _)| n == name).map(|(_, t)| *t);
    let (position, velocity) = r.stage_sweeps;
    assert!(
        position >= 3.0,
        "at least one position sweep per RK3 stage: {position}"
    );
    assert!(velocity >= 1.0, "the velocity solve sweeps too: {velocity}");
    assert!(
        time("correct_positions").is_some_and(|t| t > 0.0),
        "{:?}",
        r.stages
    );
    assert!(time("velocity_solve").is_some_and(|t| t > 0.0), "{:?}", r.stages);
}
