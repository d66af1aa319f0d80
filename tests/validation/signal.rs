//! Pressure, level and velocity probes against reference records (`probe::signal`) on
//! synthetic curves whose peak, rise, arrival and RMS error are known; a transducer's sampling
//! window (`probe::window_mean`, `ProbeLog` with `sampling_rate`); a sensor's face average
//! (`probe::interpolate::face_average`) on prescribed linear and quadratic fields; and the
//! scene errors of the new keys.

use crate::common::tolerance::{F64_FEW_OPERATIONS, F64_SUM};
use sph::fields::Fields;
use sph::probe::interpolate::face_average;
use sph::probe::signal::{ARRIVAL_FRACTION, RISE_FROM, RISE_TO, impulse_in, rms_error, signal_measures};
use sph::probe::{ProbeLog, compare_samples, window_mean};
use sph::scene::{Averaging, ProbeKind, Sensor, parse_scene};

/// A 2D tank scene (g = 9.81, ρ0 = 1000) with `probes` appended.
fn scene_text(probes: &str) -> String {
    format!(
        "dimension = 2\neffects = [\"gravity\"]\n[domain]\nmin = [-0.2, -0.2]\nmax = [1.0, 0.8]\n\
         [particles]\nspacing = 0.02\nsmoothing_ratio = 2.0\n[fluid]\nrho0 = 1000.0\nsound_speed = 20.0\n\
         gravity = [0.0, -9.81]\n[[fluid_box]]\nmin = [0.0, 0.0]\nmax = [0.4, 0.3]\n[[solid]]\nname = \"tank\"\n\
         shape = \"container\"\nmin = [0.0, 0.0]\nmax = [0.8, 0.6]\n[output]\ninterval = 0.05\n\
         [solver]\nkind = \"wcsph\"\nend_time = 1.0\n{probes}\n"
    )
}

/// An impact record: 0 until T = 2.5, a linear rise to 0.7 at T = 2.7, a linear fall to a
/// plateau 0.55 at T = 3.0, flat to T = 5; sampled every 0.01 so that each corner is a sample
/// (linear interpolation then reproduces the curve exactly).
fn impact(shift: f64, scale: f64) -> Vec<(f64, f64)> {
    (0..=500)
        .map(|k| {
            let t = k as f64 * 0.01;
            let v = if t <= 2.5 {
                0.0
            } else if t <= 2.7 {
                0.7 * (t - 2.5) / 0.2
            } else if t <= 3.0 {
                0.7 - 0.15 * (t - 2.7) / 0.3
            } else {
                0.55
            };
            (t + shift, scale * v)
        })
        .collect()
}

#[test]
fn pressure_peak_and_rise_are_recovered_from_a_synthetic_impact() {
    let reference = impact(0.0, 1.0);
    // The simulation 0.05 later and 10 % higher.
    let simulated = impact(0.05, 1.1);
    let m = signal_measures(
        ProbeKind::Pressure,
        &simulated,
        &reference,
        &reference,
        (2.0, 4.5),
    );
    let peak = m.peak.expect("both curves peak in the range");
    // The corners are samples, so the peaks are exact up to the f64 sums of `k · 0.01`.
    assert!((peak.reference.0 - 2.7).abs() < F64_SUM && (peak.reference.1 - 0.7).abs() < F64_SUM);
    assert!((peak.simulated.0 - 2.75).abs() < F64_SUM && (peak.simulated.1 - 0.77).abs() < F64_SUM);
    // The rise from 10 % to 90 % of the peak on a linear ramp of 0.2 is (0.9 − 0.1) · 0.2 for
    // both curves (the rise scales with neither shift nor amplitude).
    let want = (RISE_TO - RISE_FROM) * 0.2;
    let (sim_rise, ref_rise) = peak.rise;
    assert!((ref_rise.expect("rises") - want).abs() < F64_SUM, "{ref_rise:?}");
    assert!((sim_rise.expect("rises") - want).abs() < F64_SUM, "{sim_rise:?}");
    assert!(m.arrival.is_none(), "an arrival is a level's measure");
    // The impulses over 2.0-4.5, both curves spanning it: the reference's rise (0.7 · 0.2 / 2),
    // fall ((0.7 + 0.55) / 2 · 0.3) and plateau (0.55 · 1.5); the simulation's the same shifted
    // by 0.05 (its plateau 0.05 shorter) and 1.1 times higher.
    let (sim_impulse, ref_impulse) = peak.impulse.expect("both curves span the range");
    let corners = 0.07 + 0.1875;
    assert!(
        (ref_impulse - (corners + 0.55 * 1.5)).abs() < F64_SUM,
        "{ref_impulse}"
    );
    assert!(
        (sim_impulse - 1.1 * (corners + 0.55 * 1.45)).abs() < F64_SUM,
        "{sim_impulse}"
    );
}

/// The impulse integrates the linear interpolation between samples, ends interpolated, and is
/// undefined where the points do not span the interval.
#[test]
fn impulse_integrates_the_interpolated_curve_over_its_span() {
    let ramp = [(0.0, 0.0), (1.0, 2.0), (3.0, 2.0)];
    // From 0.5 (value 1) to 2: the ramp's half (1 + 2)/2 · 0.5 and the flat 2 · 1.
    let got = impulse_in(&ramp, 0.5, 2.0).expect("spanned");
    assert!((got - 2.75).abs() < F64_FEW_OPERATIONS, "{got}");
    assert_eq!(impulse_in(&ramp, -0.5, 2.0), None, "starts before the points");
    assert_eq!(impulse_in(&ramp, 1.0, 3.5), None, "ends after them");
    assert_eq!(impulse_in(&ramp, 2.0, 2.0), None, "empty interval");
}

#[test]
fn rms_error_of_a_constant_offset_is_the_offset() {
    let reference = impact(0.0, 1.0);
    let simulated: Vec<(f64, f64)> = reference.iter().map(|&(t, v)| (t, v + 0.02)).collect();
    let (rms, count) = rms_error(&simulated, &reference, (2.0, 4.5)).expect("points in range");
    assert!((rms - 0.02).abs() < F64_SUM, "{rms}");
    // Samples at T = 2.00, 2.01, …, 4.50; the f64 times `k · 0.01` may fall either side of the
    // range's ends, so 250 or 251 points.
    assert!((250..=251).contains(&count), "{count}");
    assert!(
        rms_error(&simulated, &reference, (6.0, 7.0)).is_none(),
        "no points"
    );
}

#[test]
fn level_arrival_is_the_first_rise_above_the_threshold() {
    // A gauge dry until T = 1, then rising linearly by 0.5 per unit T to 0.4 at T = 1.8.
    let gauge = |delay: f64| -> Vec<(f64, f64)> {
        (0..=300)
            .map(|k| {
                let t = k as f64 * 0.01;
                (t, (0.5 * (t - 1.0 - delay)).clamp(0.0, 0.4))
            })
            .collect()
    };
    let reference = gauge(0.0);
    let simulated = gauge(0.2);
    let m = signal_measures(ProbeKind::Level, &simulated, &reference, &reference, (0.0, 3.0));
    let (sim, reference_time) = m.arrival.expect("both arrive");
    // Threshold: 0 + ARRIVAL_FRACTION · 0.4, reached 0.04/0.5 = 0.08 after the rise starts.
    let after = ARRIVAL_FRACTION * 0.4 / 0.5;
    assert!(
        (reference_time - (1.0 + after)).abs() < F64_SUM,
        "{reference_time}"
    );
    assert!((sim.expect("arrives") - (1.2 + after)).abs() < F64_SUM, "{sim:?}");
    assert!(m.peak.is_none(), "a peak is a pressure's measure");
}

#[test]
fn a_pressure_record_is_compared_in_the_normalised_units() {
    let dir = std::env::temp_dir().join(format!("sph-signal-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let record = dir.join("wall.csv");
    let mut csv = String::from("series,T,p\n");
    for (t, p) in impact(0.0, 1.0) {
        csv += &format!("a,{t},{p}\n");
    }
    // A second series, not named by the scene, is ignored.
    csv += "b,2.7,5.0\n";
    std::fs::write(&record, csv).expect("write");
    let text = scene_text(&format!(
        "[[probe]]\nname = \"wall\"\nkind = \"pressure\"\npoint = [0.8, 0.05]\n[probe.reference]\n\
         file = {:?}\ncolumns = [\"T\", \"p\"]\nseries = [\"a\"]\nlength = 0.3\ntime_range = [2.0, 4.5]\n",
        record.display().to_string()
    ));
    let mut scene = parse_scene(&text, "signal test", &[]).expect("valid scene");
    assert!(sph::scene::locate_references(&mut scene, None).is_empty());
    // The record in seconds and pascals: t = T / sqrt(g/H), p = (p/ρ0gH) · ρ0 g H.
    let (g, h, rho) = (9.81_f64, 0.3, 1000.0);
    let samples: Vec<(f64, f64)> = impact(0.0, 1.0)
        .iter()
        .map(|&(t, p)| (t / (g / h).sqrt(), p * rho * g * h))
        .collect();
    let c = compare_samples(&scene, &scene.probes[0], &samples)
        .expect("reads the record")
        .expect("has a reference");
    assert!(c.normalised && c.reference.len() == 1, "{:?}", c.reference.len());
    let m = c.signal.expect("a pressure's measures");
    let (rms, _) = m.rms.expect("points");
    // The same curve back through the scales: only the rounding of a multiply and a divide.
    assert!(rms < 1e-12, "{rms}");
    let peak = m.peak.expect("peaks");
    assert!((peak.simulated.1 - 0.7).abs() < 1e-12 && (peak.simulated.0 - 2.7).abs() < 1e-12);
    let json = sph::probe::signal::summary_json(&c);
    assert_eq!(json["units"], "normalised");
    assert!((json["reference_peak"].as_f64().unwrap() - 0.7).abs() < F64_SUM);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn window_mean_is_the_time_weighted_mean_over_the_window() {
    // Steps of 1 ms with value t at each step's end, a 10 ms window ending at t = 0.1: the
    // steps (0.09, 0.1] … of values 0.091 … 0.1, mean 0.0955.
    let steps: Vec<(f64, f64, f64)> = (1..=100)
        .map(|k| {
            let t = k as f64 * 1e-3;
            (t - 1e-3, t, t)
        })
        .collect();
    let mean = window_mean(&steps, 0.1, 0.01).expect("steps in the window");
    assert!((mean - 0.0955).abs() < F64_SUM, "{mean}");
    // A window of 2.5 steps: half of the step ending at 0.098 counts.
    let mean = window_mean(&steps, 0.1, 0.0025).expect("steps in the window");
    let want = (0.1 + 0.099 + 0.5 * 0.098) / 2.5;
    assert!((mean - want).abs() < F64_SUM, "{mean} against {want}");
}

#[test]
fn a_sampling_rate_averages_the_last_window_and_sets_the_cadence() {
    // A force probe on the tank at 1 kHz: the log samples at least every 1 ms (output.interval
    // / 10 = 5 ms otherwise) and each sample is the mean over the last 1 ms.
    let text =
        scene_text("[[probe]]\nname = \"f\"\nkind = \"force\"\nsolid = \"tank\"\nsampling_rate = 1000.0\n");
    let scene = parse_scene(&text, "signal test", &[]).expect("valid scene");
    assert_eq!(scene.probes[0].averaging, Averaging::Window(1e-3));
    let interval = ProbeLog::interval_for(&scene);
    assert!((interval - 1e-3).abs() < F64_FEW_OPERATIONS, "{interval}");
    let mut log = ProbeLog::create(&scene, None, interval).expect("log");
    let f = Fields::<2>::default();
    log.record(0.0, 0.0, &f, &[[0.0; 3]], true).expect("record");
    // Steps of 0.25 ms, force F(t) = sin(2π 100 t) at each step's end.
    let dt = 2.5e-4;
    let signal = |t: f64| (2.0 * std::f64::consts::PI * 100.0 * t).sin();
    for k in 1..=40 {
        let t = k as f64 * dt;
        log.record(t, dt, &f, &[[signal(t), 0.0, 0.0]], false)
            .expect("record");
    }
    let samples = log.samples(0);
    // t = 0 and every 1 ms up to 10 ms: the schedule sums 1 ms in f64, so the last target
    // may land a rounding above the last step's 0.01 s (10 or 11 samples), but never two
    // samples closer than the 1 ms asked for.
    assert!((10..=11).contains(&samples.len()), "{samples:?}");
    for pair in samples.windows(2) {
        assert!(pair[1].0 - pair[0].0 > 1e-3 - dt / 2.0, "{samples:?}");
    }
    for &(t, v) in &samples[1..] {
        // The mean of the four step values in (t − 1 ms, t].
        let want = (0..4).map(|j| signal(t - j as f64 * dt)).sum::<f64>() / 4.0;
        assert!((v - want).abs() < F64_SUM, "t = {t}: {v} against {want}");
    }
}

#[test]
fn face_average_of_a_linear_field_is_the_centre_value() {
    let linear = |x: &[f64]| 3.0 + 2.0 * x[0] - 5.0 * x[1] + x.get(2).map_or(0.0, |z| 7.0 * z);
    let centre2 = [1.0, 0.2];
    // Normal to x: the segment runs along y, symmetric about the centre.
    let v = face_average::<2>(&centre2, 0, 0.1, 0.005, linear);
    // A sum of ~40 terms of order 1: rounding near 1e-14.
    assert!((v - linear(&centre2)).abs() < 1e-13, "{v}");
    let centre3 = [1.0, 0.2, 0.3];
    let v = face_average::<3>(&centre3, 2, 0.1, 0.005, linear);
    assert!((v - linear(&centre3)).abs() < 1e-13, "{v}");
}

#[test]
fn face_average_of_a_quadratic_field_is_the_analytic_mean() {
    // 2D: p = y² over the segment y ∈ c ± d/2: mean c² + d²/12 (Gauss-2 is exact for it).
    let (c, d) = (0.2, 0.1);
    let v = face_average::<2>(&[1.0, c], 0, d, 0.005, |x| x[1] * x[1]);
    assert!((v - (c * c + d * d / 12.0)).abs() < 1e-14, "{v}");
    // 3D disc of radius R normal to z centred at the origin: the mean of x² is R²/4, of
    // x² + y² R²/2; Gauss-2 in r (exact for r³) and ≥ 4 equal angles (exact for cos²).
    let r = 0.05;
    let v = face_average::<3>(&[0.0, 0.0, 0.3], 2, 2.0 * r, 0.005, |x| x[0] * x[0]);
    assert!((v - r * r / 4.0).abs() < 1e-15, "{v}");
    let v = face_average::<3>(&[0.0, 0.0, 0.3], 2, 2.0 * r, 0.005, |x| x[0] * x[0] + x[1] * x[1]);
    assert!((v - r * r / 2.0).abs() < 1e-15, "{v}");
}

#[test]
fn new_probe_keys_are_checked() {
    let problem = |probe: &str| -> String {
        match parse_scene(&scene_text(probe), "probe keys", &[]) {
            Ok(_) => String::new(),
            Err(e) => e.to_string(),
        }
    };
    let ok = "[[probe]]\nname = \"p\"\nkind = \"pressure\"\npoint = [0.8, 0.1]\ndiameter = 0.02\nnormal = \"x\"\nsampling_rate = 20000.0\n";
    assert_eq!(problem(ok), "", "a valid face sensor");
    let scene = parse_scene(&scene_text(ok), "t", &[]).expect("valid");
    assert_eq!(
        scene.probes[0].sensor,
        Sensor::Face {
            diameter: 0.02,
            normal: 0
        }
    );
    for (probe, key, says) in [
        (
            "kind = \"pressure\"\npoint = [0.8, 0.1]\ndiameter = 0.02",
            "probe[0].normal",
            "required with diameter",
        ),
        (
            "kind = \"pressure\"\npoint = [0.8, 0.1]\nnormal = \"x\"",
            "probe[0].diameter",
            "required with normal",
        ),
        (
            "kind = \"pressure\"\npoint = [0.8, 0.1]\ndiameter = -0.02\nnormal = \"x\"",
            "probe[0].diameter",
            "",
        ),
        (
            "kind = \"pressure\"\npoint = [0.8, 0.1]\ndiameter = 0.02\nnormal = \"z\"",
            "probe[0].normal",
            "\"x\" or \"y\"",
        ),
        (
            "kind = \"level\"\npoint = [0.2, 0.0]\ndiameter = 0.02\nnormal = \"x\"",
            "probe[0].diameter",
            "only with kind = \"pressure\"",
        ),
        (
            "kind = \"front\"\nsampling_rate = 100.0",
            "probe[0].sampling_rate",
            "not with kind = \"front\"",
        ),
        // Sizes and rates bounded by the scene: a face or a section larger than the domain,
        // and a rate that would take more than `MAX_SAMPLES` samples (issue 51: each spun).
        (
            "kind = \"pressure\"\npoint = [0.8, 0.1]\ndiameter = 1e6\nnormal = \"x\"",
            "probe[0].diameter",
            "outside the domain",
        ),
        (
            "kind = \"flow_rate\"\npoint = [0.2, 0.1]\nsize = [1e6]",
            "probe[0].size[0]",
            "outside the domain",
        ),
        (
            "kind = \"pressure\"\npoint = [0.8, 0.1]\nsampling_rate = 1e30",
            "probe[0].sampling_rate",
            "samples, more than the limit",
        ),
        (
            "kind = \"velocity\"\npoint = [0.2, 0.1]\nsampling_rate = 0.0",
            "probe[0].sampling_rate",
            "",
        ),
        (
            "kind = \"pressure\"\npoint = [0.8, 0.1]\n[probe.reference]\nfile = \"r.csv\"",
            "probe[0].reference.columns",
            "required",
        ),
        (
            "kind = \"pressure\"\npoint = [0.8, 0.1]\n[probe.reference]\nfile = \"r.csv\"\ncolumns = [\"t\"]",
            "probe[0].reference.columns",
            "expected 2",
        ),
        (
            "kind = \"flow_rate\"\npoint = [0.2, 0.1]\nsize = [0.1]\n[probe.reference]\nfile = \"r.csv\"",
            "probe[0].reference",
            "flow_rate",
        ),
        (
            "kind = \"force\"\nsolid = \"tank\"\n[probe.reference]\nfile = \"r.csv\"\ncolumns = [\"t\", \"f\"]",
            "probe[0].reference.columns",
            "only for",
        ),
        (
            "kind = \"level\"\npoint = [0.2, 0.0]\n[probe.reference]\nfile = \"r.csv\"\ncolumns = [\"t\", \"h\"]\nlength = 0.0",
            "probe[0].reference.length",
            "",
        ),
    ] {
        let e = problem(&format!("[[probe]]\nname = \"p\"\n{probe}\n"));
        assert!(
            e.contains(key) && e.contains(says),
            "{probe:?}: wants {key} ({says}), got: {e}"
        );
    }
}

/// The shipped instrumented dam break: its wall sensors compare with Buchner's record in the
/// normalised units, the face sensor reads a 2 kHz window, and the log samples at that rate.
#[test]
fn the_wall_dam_break_scene_carries_its_sensors() {
    let scene = sph::scene::load_scene(std::path::Path::new("scenes/dam_break_wall_2d.toml"), &[])
        .expect("valid scene");
    let wall = scene.probes.iter().find(|p| p.name == "p_02H").expect("p_02H");
    let r = wall.reference.as_ref().expect("reference");
    assert_eq!(r.length, Some(0.3));
    assert_eq!(
        r.columns,
        Some(("T_t_sqrt_g_over_H".into(), "p_over_rho_g_H".into()))
    );
    let face = scene
        .probes
        .iter()
        .find(|p| p.name == "p_02H_face")
        .expect("face");
    assert_eq!(
        face.sensor,
        Sensor::Face {
            diameter: 0.03,
            normal: 0
        }
    );
    assert_eq!(face.averaging, Averaging::Window(1.0 / 2000.0));
    let interval = ProbeLog::interval_for(&scene);
    assert!((interval - 5e-4).abs() < F64_FEW_OPERATIONS, "{interval}");
}
