//! Probes on hand-made states: the front is the largest fluid coordinate minus the origin, a
//! force probe reports the time-weighted mean of its solid's force over each sample interval,
//! and a force probe's first peak is found within its reference's time range.

use crate::common::scene::tank_2d_with_post;
use crate::common::tolerance::{F32_ROUNDING, F64_SUM};
use sph::fields::{FLUID, Fields};
use sph::math::Vector;
use sph::probe::{ProbeLog, ProbeSpace, compare_samples, measure};
use sph::scene::parse_scene;

/// The shared tank with a post, the `corrected` solver and the front probe's origin at 0.1 m.
fn scene_text() -> String {
    tank_2d_with_post("kind = \"corrected\"\nend_time = 1.0\n", "origin = 0.1\n")
}

fn fields() -> Fields<2> {
    let mut f = Fields::default();
    for (x, kind) in [(0.3, FLUID), (0.7, FLUID), (0.9, 1), (1.05, 2)] {
        f.push(Vector::<2>::new(x, 0.1), Vector::zeros(), 1.0, 1000.0, kind);
    }
    f
}

#[test]
fn front_and_force_are_measured_from_the_state() {
    let scene = parse_scene(&scene_text(), "probe test", &[]).expect("valid scene");
    let f = fields();
    let forces = [[5.0, 6.0, 0.0], [-2.0, 3.0, 0.0]];
    // The solid particle at x = 0.9 is not fluid: the front is 0.7 - 0.1.
    assert!((measure(&scene.probes[0], &ProbeSpace::of(&scene), &f, &forces) - 0.6).abs() < F32_ROUNDING);
    assert_eq!(
        measure(&scene.probes[1], &ProbeSpace::of(&scene), &f, &forces),
        -2.0
    );
}

#[test]
fn force_probe_reports_the_time_weighted_mean_of_each_interval() {
    let scene = parse_scene(&scene_text(), "probe test", &[]).expect("valid scene");
    let f = fields();
    let mut log = ProbeLog::create(&scene, None, 0.1).expect("log");
    log.record(0.0, 0.0, &f, &[[0.0; 3], [0.0; 3]], true)
        .expect("record");
    // Steps of 0.03, 0.03, 0.05 s with post forces 1, 2, 4 N: the sample at t = 0.11 s is
    // (0.03 + 0.06 + 0.2) / 0.11.
    let mut t = 0.0;
    for (dt, fx) in [(0.03, 1.0), (0.03, 2.0), (0.05, 4.0)] {
        t += dt;
        log.record(t, dt, &f, &[[0.0; 3], [fx, 0.0, 0.0]], false)
            .expect("record");
    }
    let samples = log.samples(1);
    assert_eq!(samples.len(), 2, "{samples:?}");
    assert!((samples[1].0 - 0.11).abs() < F64_SUM);
    assert!((samples[1].1 - 0.29 / 0.11).abs() < F64_SUM, "{samples:?}");
}

#[test]
fn force_peak_is_found_within_the_reference_range() {
    let dir = std::env::temp_dir().join(format!("sph-probe-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let record = dir.join("record.csv");
    std::fs::write(
        &record,
        // Out of time order, as the ANUGA digitisation is.
        "time_s,force_x_N\n0.4,30.0\n0.0,0.0\n0.9,50.0\n0.2,10.0\n0.6,20.0\n",
    )
    .expect("write");
    let text = format!(
        "{}\n[probe.reference]\nfile = {:?}\ntime_range = [0.0, 0.8]\n",
        scene_text(),
        record.display().to_string()
    );
    let mut scene = parse_scene(&text, "probe test", &[]).expect("valid scene");
    // An absolute file needs no reference directory.
    assert!(sph::scene::locate_references(&mut scene, None).is_empty());
    let samples = [(0.1, 1.0), (0.35, 40.0), (0.5, 25.0), (0.85, 99.0)];
    let c = compare_samples(&scene, &scene.probes[1], &samples)
        .expect("reads the record")
        .expect("has a reference");
    let peak = c.peak.expect("peaks in range");
    assert_eq!(peak.simulated, (0.35, 40.0), "0.85 s lies outside the range");
    assert_eq!(peak.reference, (0.4, 30.0), "0.9 s lies outside the range");
    // Onset at 25 % of the reference peak (7.5 N): simulated between (0.1, 1) and (0.35, 40),
    // reference between (0, 0) and (0.2, 10).
    let (sim_onset, ref_onset) = peak.onset.expect("both curves reach 7.5 N");
    assert!(
        (sim_onset - (0.1 + 0.25 * 6.5 / 39.0)).abs() < F64_SUM,
        "{sim_onset}"
    );
    assert!((ref_onset - 0.15).abs() < F64_SUM, "{ref_onset}");
    let rise = peak.rise_time_error().expect("onsets");
    assert!(
        (rise - ((0.35 - sim_onset) - (0.4 - 0.15))).abs() < F64_SUM,
        "{rise}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
