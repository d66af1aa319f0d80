//! The paper's Fig. 1 case against experiment: the 2D dam break (square column a = 0.25 m,
//! `scenes/dam_break_2d.toml` as shipped: dx = a/50 = 5 mm, h = 2 dx, corrected solver with
//! delta = 1e-4, SSP-RK3, CFL 0.2 on the flow speed) run to T = t sqrt(g/a) = 3.
//!
//! Asserted: the surge front (largest fluid x) stays within 8 % of Martin & Moyce's square-column
//! data (both n^2 = 1 digitisations in `../shared/validation`) at every data point with
//! 1 <= T <= 3; every correction stage converged; the compression after correction stays below
//! delta. Measured when written: 4.9 % max, 3.8 % mean (the front runs ahead of the experiment,
//! as in most SPH and MPS results; Martin & Moyce's release was not instantaneous).

use sph::run::{RunOptions, run_scene};
use sph::scene::load_scene;
use std::path::Path;

#[test]
fn corrected_dam_break_front_within_8_percent_of_martin_moyce() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/dam_break_2d.toml");
    // T = 3 is t = 3 sqrt(a/g) = 0.4789 s.
    let scene = load_scene(&path, &["solver.end_time=0.48".to_string()]).expect("scene loads");
    let options = RunOptions {
        out_dir: None,
        backend: Default::default(),
        threads: rayon::current_num_threads(),
        scene_name: "dam_break_2d".into(),
    };
    let summary = run_scene(&scene, &options, &mut |_| {}).expect("runs");
    assert_eq!(summary.status, "completed");
    let e = &summary.extra;
    let front = &e["probe_errors"]["front"];
    let points = front["points"].as_u64().expect("front compared");
    let max = front["error_max"].as_f64().expect("error");
    assert!(points >= 18, "only {points} reference points in 1 <= T <= 3");
    assert!(
        max < 0.08,
        "front error {:.1} % against Martin & Moyce",
        100.0 * max
    );
    assert_eq!(e["unconverged_stages"].as_u64(), Some(0));
    let after = e["max_compression_after_correction"].as_f64().expect("stat");
    assert!(after < 1e-4, "compression after correction {after:e}");
    let seen = e["max_compression"].as_f64().expect("stat");
    assert!(seen < 1e-4, "compression at step starts {seen:e}");
}
