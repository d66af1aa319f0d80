//! `sph waves RUN_DIR` (`cli::waves::analyse`): the shipped flume's gauges read from a
//! `probes.csv` of a known wave pattern give that pattern back, and what cannot be analysed is an
//! error that says why.

use sph::cli::waves::{WaveOptions, analyse};
use sph::nalgebra::Complex;
use sph::physics::waves::wavenumber;
use sph::scene::load_scene;
use std::f64::consts::TAU;
use std::path::Path;

/// The shipped flume's scene (gauges g1..g6 at x = 0.5..2.5 m, piston T = 1.1 s, d = 0.3 m).
fn flume() -> sph::scene::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/wave_flume_2d.toml");
    load_scene(&path, &[]).expect("the flume loads")
}

/// Writes `probes.csv` into `dir`: the six gauges' record of an incident wave of height 0.04 m
/// decaying by `kappa` [1/m] and a reflection of `K_r = kr` at x = 3 m, on a still level of
/// 0.3 m, every 0.01 s for 12 s; g3 has no sample on odd rows (a slower gauge's blanks).
fn write_record(dir: &Path, kappa: f64, kr: f64) -> f64 {
    let (period, depth) = (1.1, 0.3);
    let omega = TAU / period;
    let k = wavenumber(omega, depth, 9.81);
    let incident = Complex::new(0.02, 0.0);
    let reflected = Complex::from_polar(kr * 0.02 * (-2.0 * kappa * 3.0).exp(), 1.3);
    let xs = [0.5, 0.9, 1.3, 1.7, 2.1, 2.5];
    let mut text = String::from("t_s,g1_m,g2_m,g3_m,g4_m,g5_m,g6_m,paddle_force_N_per_m\n");
    for n in 0..1200 {
        let t = n as f64 * 0.01;
        text.push_str(&format!("{t}"));
        for (j, &x) in xs.iter().enumerate() {
            let z = incident * Complex::new(-kappa * x, -k * x).exp()
                + reflected * Complex::new(kappa * x, k * x).exp();
            let eta = 0.3 + (z * Complex::new(0.0, omega * t).exp()).re;
            if j == 2 && n % 2 == 1 {
                text.push(',');
            } else {
                text.push_str(&format!(",{eta}"));
            }
        }
        text.push_str(",0\n");
    }
    std::fs::write(dir.join("probes.csv"), text).expect("writes");
    k
}

#[test]
fn the_gauges_of_a_known_pattern_give_it_back() {
    let dir = crate::common::scratch_dir("waves");
    let k = write_record(&dir, 0.3, 0.15);
    let report = analyse(&dir, &flume(), &WaveOptions::default()).expect("analysed");
    assert_eq!(report.period, 1.1);
    assert_eq!(report.gauges.len(), 6);
    assert!((report.window.1 - 11.99).abs() < 1e-9 && (report.window.0 - (11.99 - 4.4)).abs() < 1e-9);
    // The grid search's steps: k to 0.25 %, κ to 0.01 1/m.
    assert!(
        (report.fit.k / k - 1.0).abs() < 0.003,
        "k {} vs {k}",
        report.fit.k
    );
    assert!((report.fit.kappa - 0.3).abs() < 1e-9);
    let at_zone = report.fit.reflection_at(3.0);
    assert!((at_zone / 0.15 - 1.0).abs() < 0.02, "K_r {at_zone}");
    // At the last gauge (the default place) the reflection is K_r e^{−2κ (3 − 2.5)}.
    assert_eq!(report.at, 2.5);
    let want = 0.15 * (-2.0 * 0.3 * 0.5f64).exp();
    assert!(
        (report.reflection / want - 1.0).abs() < 0.02,
        "{}",
        report.reflection
    );
    assert!((report.fit.incident_height_at(0.0) / 0.04 - 1.0).abs() < 0.02);

    // Chosen gauges, window and place.
    let options = WaveOptions {
        gauges: vec!["g1".into(), "g4".into(), "g6".into()],
        from: Some(2.0),
        to: Some(2.0 + 3.0 * 1.1),
        at: Some(3.0),
        ..WaveOptions::default()
    };
    let report = analyse(&dir, &flume(), &options).expect("analysed");
    assert_eq!(
        report.gauges.iter().map(|g| g.name.as_str()).collect::<Vec<_>>(),
        ["g1", "g4", "g6"]
    );
    assert!(
        (report.reflection / 0.15 - 1.0).abs() < 0.02,
        "{}",
        report.reflection
    );
}

#[test]
fn what_cannot_be_analysed_is_an_error_that_says_why() {
    let dir = crate::common::scratch_dir("waves");
    let error = |o: WaveOptions| format!("{:#}", analyse(&dir, &flume(), &o).expect_err("refused"));
    // No record yet.
    assert!(error(WaveOptions::default()).contains("probes.csv"));
    write_record(&dir, 0.0, 0.1);
    let e = error(WaveOptions {
        gauges: vec!["g9".into()],
        ..WaveOptions::default()
    });
    assert!(e.contains("g9"), "{e}");
    let e = error(WaveOptions {
        gauges: vec!["g1".into()],
        ..WaveOptions::default()
    });
    assert!(e.contains("at least two"), "{e}");
    let e = error(WaveOptions {
        from: Some(20.0),
        to: Some(30.0),
        ..WaveOptions::default()
    });
    assert!(e.contains("fewer than three samples"), "{e}");
    let e = error(WaveOptions {
        period: Some(-1.0),
        ..WaveOptions::default()
    });
    assert!(e.contains("positive"), "{e}");
    // A scene without a wave maker needs the period.
    let mut still = flume();
    still.solids.iter_mut().for_each(|s| s.motion = None);
    let e = format!(
        "{:#}",
        analyse(&dir, &still, &WaveOptions::default()).expect_err("refused")
    );
    assert!(e.contains("--period"), "{e}");
}
