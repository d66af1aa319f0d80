//! The paper's Fig. 1 case against experiment: the 2D dam break (square column a = 0.25 m,
//! `scenes/dam_break_2d.toml` as shipped: dx = a/50 = 5 mm, h = 2 dx, corrected solver with
//! delta = 1e-4, SSP-RK3, CFL 0.2 on the flow speed) run to T = t sqrt(g/a) = 3.
//!
//! Asserted: the surge front (largest fluid x) stays within 8 % of Martin & Moyce's square-column
//! data (both n^2 = 1 digitisations, in `SPH_REFERENCE_DIR`) at every data point with
//! 1 <= T <= 3 (measured: 4.7 % max, 3.8 % mean; the front runs ahead of the experiment, as in
//! most SPH and MPS results; Martin & Moyce's release was not instantaneous). The correction
//! converges in all but a few of the ~1500 stages (measured: one stage at t = 0.038 s, a particle
//! pressed against the back wall during the collapse, left at compression 2.0e-4 after the
//! 200-sweep cap), so at most 0.2 % of stages may hit the cap and the compression after
//! correction must stay below 3 delta; at the start of every step it is asserted below 3 delta too.

//!
//! Part of the validation suite: `cargo test --release --features validation-data`.

mod reference_data;

use sph::run::{RunOptions, run_scene};
use sph::scene::{load_scene, locate_references};
use std::path::Path;

#[test]
fn corrected_dam_break_front_within_8_percent_of_martin_moyce() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/dam_break_2d.toml");
    // T = 3 is t = 3 sqrt(a/g) = 0.4789 s.
    let mut scene = load_scene(&path, &["solver.end_time=0.48".to_string()]).expect("scene loads");
    reference_data::reference_file("martin_moyce_1952_surge_front.csv");
    let skipped = locate_references(&mut scene, Some(&reference_data::reference_dir()));
    assert!(skipped.is_empty(), "reference data missing: {skipped:?}");
    let options = RunOptions {
        out_dir: None,
        force: false,
        stop: None,
        ranks: None,
        backend: Default::default(),
        threads: rayon::current_num_threads(),
        scene_name: "dam_break_2d".into(),
        restart: Default::default(),
    };
    let summary = run_scene(&scene, &options, &mut |_| {}).expect("runs");
    assert_eq!(summary.status, "completed");
    let e = &summary.extra;
    let front = &e["probe_errors"]["front"];
    let points = front["points"].as_u64().expect("front compared");
    let max = front["error_max"].as_f64().expect("error");
    let mean = front["error_mean"].as_f64().expect("error");
    eprintln!(
        "front against Martin & Moyce: max {:.1} %, mean {:.1} % over {points} points",
        100.0 * max,
        100.0 * mean
    );
    assert!(points >= 18, "only {points} reference points in 1 <= T <= 3");
    assert!(
        max < 0.08,
        "front error {:.1} % against Martin & Moyce",
        100.0 * max
    );
    let stages = e["corrected_stages"].as_u64().expect("stat");
    let unconverged = e["unconverged_stages"].as_u64().expect("stat");
    assert!(
        unconverged * 500 <= stages,
        "{unconverged} of {stages} stages hit the cap"
    );
    let after = e["max_compression_after_correction"].as_f64().expect("stat");
    assert!(after < 3e-4, "compression after correction {after:e}");
    let seen = summary.max_compression;
    assert!(seen < 3e-4, "compression at step starts {seen:e}");
}
