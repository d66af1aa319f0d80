//! The focused wave group of `scenes/wave_flume_focused_2d.toml`: a piston driven by a NewWave
//! group (`physics::sea_state`, Tromans et al. 1991) of linear crest A = 0.03 m at x_f = 1.5 m,
//! t_f = 8 s, in the flume of `scenes/wave_flume_2d.toml` at its spacing d/15. The level gauge
//! at the focus is compared with the linear target `η(x_f, t)` of the same components.

use sph::physics::sea_state::Sea;
use sph::probe::{ProbeSpace, measure};
use sph::run::simulation_from_scene;
use sph::scene::{Motion, load_scene};
use std::path::Path;

/// Gauge records are sampled this often [s] (the shortest component, 1.82 Hz, is read within
/// `1 − cos(π · 0.0182) = 0.2 %` of its crest).
const SAMPLE: f64 = 0.01;

/// Still-water depth of the flume [m] (the gauges read the level above the bed).
const DEPTH: f64 = 0.3;

/// Runs the shipped focused flume to `t_f + 0.6 s` on the CPU and compares the gauge at the
/// focus with the linear target over 5 s to the end (the group's passage; before 5 s the
/// surface there is below 2 mm in both).
///
/// Asserts:
/// - the record's correlation with the linear target is at least 0.9 (measured 0.960; a group in the wrong phase, from the wrong sign of a component's stroke or of
///   `k_i x_f`, correlates near 0, its crests do not meet);
/// - the highest crest comes within 0.1 s of `t_f` (measured 7.97 s: 0.03 s early), and the
///   record's maximum is that crest;
/// - the crest is 0.31 to 0.51 of the linear A: the measured 0.415 A (0.0125 m) within 25 %.
///   Why so far below A: the coarse lattice dissipates the waves (the regular flume's decay
///   rate at d/15 is 0.27–0.34 1/m at the peak period, `tests/physics/waves.rs`), and the
///   crest is also made of components up to 2 f_p, shorter and lower (each a_i below 1.4 mm,
///   a fraction of the 20 mm spacing) that the lattice damps faster: the least-squares gain of
///   the record on the linear target is 0.53 at the focus (0.74 at 0.5 m and 0.36 at 2.5 m in
///   a run of the scene, sampled every 50 ms).
///   The second-order bound harmonics, which would raise the crest by about `k_p A²/2`
///   (0.0018 m, 6 %), are lost in that. The 25 % covers the spread the regular flume's decay
///   rate shows between windows; it is a regression guard of the generation and dissipation
///   at this spacing, not a validation of A.
#[test]
fn focused_group_crests_at_the_focus_at_the_focus_time() {
    let scene = load_scene(Path::new("scenes/wave_flume_focused_2d.toml"), &[]).expect("shipped scene");
    let maker = scene
        .solids
        .iter()
        .find_map(|s| match &s.motion {
            Some(Motion::Sea(m)) => Some(m.clone()),
            _ => None,
        })
        .expect("a sea maker");
    let Sea::Focused {
        amplitude,
        focus_position,
        focus_time,
        ..
    } = maker.sea
    else {
        panic!("a focused group")
    };
    let probe = scene
        .probes
        .iter()
        .find(|p| p.name == "focus")
        .expect("a gauge at the focus")
        .clone();
    assert_eq!(probe.point.as_ref().map(|p| p[0]), Some(focus_position));
    let space = ProbeSpace::of(&scene);
    let mut sim = simulation_from_scene::<2>(&scene).expect("builds");
    let end = focus_time + 0.6;
    let mut record: Vec<(f64, f64)> = Vec::new();
    let mut next = 5.0;
    while sim.clock().time < end {
        sim.step(end).expect("stable step");
        let t = sim.clock().time;
        if t + 1e-9 < next {
            continue;
        }
        next += SAMPLE;
        sim.sync_fields().expect("cpu backend");
        record.push((t, measure(&probe, &space, &sim.fields, &[]) - DEPTH));
    }
    let target: Vec<f64> = record
        .iter()
        .map(|(t, _)| maker.waves.elevation(focus_position, *t))
        .collect();
    let measured: Vec<f64> = record.iter().map(|r| r.1).collect();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (mt, mm) = (mean(&target), mean(&measured));
    let cov: f64 = target
        .iter()
        .zip(&measured)
        .map(|(a, b)| (a - mt) * (b - mm))
        .sum();
    let var = |v: &[f64], m: f64| v.iter().map(|a| (a - m).powi(2)).sum::<f64>();
    let correlation = cov / (var(&target, mt) * var(&measured, mm)).sqrt();
    let gain = target.iter().zip(&measured).map(|(a, b)| a * b).sum::<f64>()
        / target.iter().map(|a| a * a).sum::<f64>();
    let (t_crest, crest) = record
        .iter()
        .copied()
        .filter(|(t, _)| (t - focus_time).abs() <= 0.3)
        .fold((0.0, f64::MIN), |best, r| if r.1 > best.1 { r } else { best });
    let highest = measured.iter().copied().fold(f64::MIN, f64::max);
    eprintln!(
        "focused flume: crest {crest:.4} m at {t_crest:.3} s (linear A = {amplitude} m at {focus_time} s, \
         ratio {:.3}); correlation with the linear target {correlation:.3}, gain {gain:.3}",
        crest / amplitude
    );
    assert!(
        correlation >= 0.9,
        "correlation {correlation:.3} with the linear target"
    );
    assert!((t_crest - focus_time).abs() <= 0.1, "crest at {t_crest:.3} s");
    assert_eq!(highest, crest, "the record's highest point is the focused crest");
    let ratio = crest / amplitude;
    assert!(
        (0.31..=0.51).contains(&ratio),
        "crest {crest:.4} m = {ratio:.3} A"
    );
}
