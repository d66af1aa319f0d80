//! The wave flume (`scenes/wave_flume_2d.toml`): a piston wave maker (`boundary::motion::Piston`)
//! makes regular waves that a damping zone (`physics::damping_zone`) absorbs at the far end.
//! Measured by the scene's level gauges against linear wave theory (Dean & Dalrymple 1991):
//! the wave height, the wavelength from the phase lag between two gauges, and the reflection
//! coefficient of the damping zone.
//!
//! Each gauge's record over a window of whole periods is fitted by least squares with
//! `η(t) = a cos ωt + b sin ωt + c` at the paddle's `ω`: its complex amplitude `Z = a − i b`
//! (`η = Re(Z e^{iωt})`). The reflection is separated from the incident wave as in the
//! least-squares method of Mansard & Funke (1980), `Z(x) = A_I e^{−ikx} + A_R e^{ikx}` over all
//! gauges, here with the waves' spatial decay `κ` [1/m] (the numerical dissipation of a coarse
//! SPH flume, which the constant-amplitude two-gauge method of Goda & Suzuki (1976) would read
//! as reflection): `Z(x) = A_I e^{−(ik+κ)x} + A_R e^{(ik+κ)x}`, `k` and `κ` by a grid search,
//! `A_I`, `A_R` by linear least squares. The zone's reflection coefficient is
//! `K_r = |A_R e^{(ik+κ)x_z}| / |A_I e^{−(ik+κ)x_z}|` at its entrance `x_z`. The analysis is
//! the library's (`probe::waves`), the one `sph waves` prints.

use sph::boundary::flap::FlapAmplitude;
use sph::nalgebra::Complex;
use sph::physics::waves::wavenumber;
use sph::probe::waves::{self, TwoWaves};
use sph::probe::{ProbeSpace, measure};
use sph::run::simulation_from_scene;
use sph::scene::{Motion, Probe, Scene, load_scene};
use std::f64::consts::TAU;
use std::path::Path;

/// Gauge records are sampled this often [s] (1/110 of the period: a crest is read within
/// `1 − cos(π/110) = 0.04 %` of its height).
const SAMPLE: f64 = 0.01;

/// The record's first harmonic `Z` at `omega` over `[t0, t1)` (`probe::waves::harmonic`).
fn harmonic(samples: &[(f64, f64)], omega: f64, t0: f64, t1: f64) -> Complex<f64> {
    waves::harmonic(samples, omega, (t0, t1))
        .expect("samples in the window")
        .amplitude
}

/// The mean crest-to-trough height over the window's whole periods (`probe::waves`).
fn crest_to_trough(samples: &[(f64, f64)], period: f64, t0: f64, t1: f64) -> f64 {
    waves::crest_to_trough(samples, period, (t0, t1)).expect("whole periods")
}

/// Incident and reflected decaying waves fitted to the gauges (`probe::waves::two_waves`).
fn two_waves(z: &[Complex<f64>], x: &[f64], k_theory: f64) -> TwoWaves {
    waves::two_waves(z, x, k_theory).expect("a fit")
}

/// Runs `scene` to `end` [s] on the CPU and records the level gauges `probes` every
/// [`SAMPLE`]: their positions `x` [m] and records `(t, η)` [s, m].
fn gauge_records(scene: &Scene, probes: &[Probe], end: f64) -> (Vec<f64>, Vec<Vec<(f64, f64)>>) {
    let x: Vec<f64> = probes
        .iter()
        .map(|p| p.point.as_ref().expect("a point")[0])
        .collect();
    let space = ProbeSpace::of(scene);
    let mut sim = simulation_from_scene::<2>(scene).expect("builds");
    let mut records: Vec<Vec<(f64, f64)>> = vec![Vec::new(); probes.len()];
    let mut next = 0.0;
    while sim.clock().time < end {
        sim.step(end).expect("stable step");
        let t = sim.clock().time;
        if t + 1e-9 < next {
            continue;
        }
        next += SAMPLE;
        sim.sync_fields().expect("cpu backend");
        for (record, probe) in records.iter_mut().zip(probes) {
            record.push((t, measure(probe, &space, &sim.fields, &[])));
        }
    }
    (x, records)
}

/// The scene's six level gauges `g1`..`g6`.
fn gauges(scene: &Scene) -> Vec<Probe> {
    let probes: Vec<_> = scene
        .probes
        .iter()
        .filter(|p| p.name.starts_with('g'))
        .cloned()
        .collect();
    assert_eq!(probes.len(), 6, "six gauges");
    probes
}

/// Entrance of the shipped flume's damping zone [m] (`[damping_zone] start`).
const ZONE_START: f64 = 3.0;

/// `scenes/wave_flume_2d.toml` (d = 0.3 m, H = 0.04 m, T = 1.1 s: kd = 1.198, L = 1.574 m;
/// dx = d/15, wcsph with density diffusion, artificial viscosity α = 0.01), run for 15 s.
/// Gauges at x = 0.5 to 2.5 m, 0.4 m apart; the damping zone from 3 to 5 m.
///
/// Asserts, after the ramp (2.2 s) and the run of the wave front to the gauges:
/// - the mean crest-to-trough height at the first gauge (x = 0.5 m, 1.7 d from the paddle:
///   its evanescent modes are down to 1 %) over 4 periods from 4.4 s, before anything
///   reflected by the far end returns (about 10 s), is within 10 % of `H` (the first-order
///   theory's target; 10 %: the accuracy the issue asks for, above the second-order
///   corrections at H/L = 0.025);
/// - the wavenumber from the phase lag between the first and fourth gauge (1.2 m, 0.76 L: the
///   lag is unique for k within ±30 %) in the same window is within 5 % of the dispersion
///   relation's;
/// - the damping zone's reflection coefficient at its entrance, from the fit of an incident
///   and a reflected decaying wave to all six gauges over 4 periods from 10.6 s (the wave
///   reflected by the far end has reached every gauge), is below 10 %.
///
/// Measured (CPU): H = 0.0379 m at x = 0.5 m (5 % low); k = 3.906 1/m from the lag (2.2 %
/// below 3.993; the fits give 3.923 early, 3.763 late); the waves decay by κ = 0.27–0.34 1/m
/// (2|Z| falls from 0.036 m at 0.5 m to 0.017 m at 2.5 m); K_r = 0.091 at the zone's entrance,
/// 0.024 at the first gauge. Why the decay, and the margins: at dx = d/12 the same flume gives
/// H = 0.033–0.035 m at 0.5 m (13–16 % low) and κ = 0.35–0.37 1/m; at d/20, 2|Z| = 0.039 m and
/// κ = 0.19–0.20 1/m (K_r 0.05–0.08 at the entrance) but a surface noisy enough that the raw
/// crest-to-trough reads 0.051 m. The damping is numerical (two particles a wave height at
/// d/15), and falls with resolution; α = 0.003 instead of 0.01 and δ = 0.02 instead of 0.1
/// changed it little at d/12.
#[test]
fn piston_makes_the_target_wave_and_the_damping_zone_absorbs_it() {
    let scene = load_scene(Path::new("scenes/wave_flume_2d.toml"), &[]).expect("shipped scene");
    let piston = scene
        .solids
        .iter()
        .find_map(|s| match &s.motion {
            Some(Motion::Piston(p)) => Some(p.clone()),
            _ => None,
        })
        .expect("a piston");
    assert_eq!(scene.damping_zone.as_ref().map(|z| z.start[0]), Some(ZONE_START));
    let (g, omega) = (piston.gravity, TAU / piston.period);
    let k = wavenumber(omega, piston.depth, g);
    let probes = gauges(&scene);
    let (x, records) = gauge_records(&scene, &probes, scene.end_time);
    let period = piston.period;
    // The incident wave alone: after the ramp and the front's run to the gauges.
    let (t0, t1) = (4.4, 4.4 + 4.0 * period);
    let height = crest_to_trough(&records[0], period, t0, t1);
    let z: Vec<Complex<f64>> = records.iter().map(|r| harmonic(r, omega, t0, t1)).collect();
    let lag = (z[0].arg() - z[3].arg()).rem_euclid(TAU);
    let k_measured = lag / (x[3] - x[0]);
    let early = two_waves(&z, &x, k);
    // Incident and reflected: the reflection of the far end has reached the gauges.
    let (s0, s1) = (10.6, 10.6 + 4.0 * period);
    let z_late: Vec<Complex<f64>> = records.iter().map(|r| harmonic(r, omega, s0, s1)).collect();
    let late = two_waves(&z_late, &x, k);
    let kr = late.reflection_at(ZONE_START);
    let heights = |z: &[Complex<f64>]| {
        z.iter()
            .map(|z| (2.0 * z.norm() * 1e4).round() / 1e4)
            .collect::<Vec<_>>()
    };
    eprintln!(
        "wave flume: H at x = {} m {height:.4} m (target {}); 2|Z| at the gauges {:?} (from {t0} s), {:?} (from {s0} s)",
        x[0],
        piston.wave_height,
        heights(&z),
        heights(&z_late),
    );
    eprintln!(
        "wave flume: k from the lag {k_measured:.3} 1/m, from the fits {:.3} and {:.3} (theory {k:.3}); \
         decay {:.2} and {:.2} 1/m; incident H at x = {} m {:.4} m; Kr at the zone entrance {kr:.3}, \
         at the first gauge {:.3} (misfits {:.3}, {:.3})",
        early.k,
        late.k,
        early.kappa,
        late.kappa,
        x[0],
        late.incident_height_at(x[0]),
        late.reflection_at(x[0]),
        early.misfit,
        late.misfit,
    );
    assert!(
        (height / piston.wave_height - 1.0).abs() <= 0.10,
        "wave height {height:.4} m, target {} m",
        piston.wave_height
    );
    assert!(
        (k_measured / k - 1.0).abs() <= 0.05,
        "wavenumber {k_measured:.3} 1/m from the phase lag, dispersion relation {k:.3}"
    );
    assert!(kr < 0.10, "reflection coefficient {kr:.3} at the zone's entrance");
}

/// `scenes/wave_flap_2d.toml`: the same flume and gauges with a flap hinged at the bed
/// (`boundary::flap`; H = 0.04 m, T = 1.1 s, d = 0.3 m: the bed-hinged flap's H/S = 0.639, a
/// swing of ±0.104 rad), at dx = d/20 (0.015 m), run to 8.9 s: the incident wave's window only
/// (the far end's reflection returns at about 10 s).
///
/// Asserts over 4 periods from 4.4 s (as for the piston, with the same reasons for the
/// tolerances): the first-order wave height at the first gauge, `2|Z|` of the fundamental
/// (the least-squares harmonic at the flap's ω), within 10 % of `H`; and the wavenumber from
/// the phase lag between the first and fourth gauge within 5 % of the dispersion relation's.
/// Why d/20 and the harmonic: at the piston's d/15 the flap's wave is 13 % low at the first
/// gauge (H = 0.0349 m crest to trough, 2|Z| = 0.0325 m; k = 3.797 1/m, 4.9 % low): the flap
/// drives the surface harder than the piston (its stroke at the still-water level is 1.8 times
/// the piston's for the same wave) and a coarse lattice loses more of it; at d/20 the raw
/// surface carries particle noise (crest to trough 0.056 m, as the piston's at d/20), which the
/// fundamental filters out.
///
/// Measured (CPU, d/20): 2|Z| = 0.0392 m at x = 0.5 m (2 % low), k = 4.109 1/m from the lag
/// (2.9 % above 3.993).
#[test]
fn flap_makes_the_target_wave() {
    let sets = ["particles.spacing=0.015".to_string()];
    let scene = load_scene(Path::new("scenes/wave_flap_2d.toml"), &sets).expect("shipped scene");
    let flap = scene
        .solids
        .iter()
        .find_map(|s| match &s.motion {
            Some(Motion::Flap(f)) => Some(f.clone()),
            _ => None,
        })
        .expect("a flap");
    let FlapAmplitude::Wave { wave_height, .. } = flap.amplitude else {
        panic!("a flap set by its wave")
    };
    let (k, omega, period) = (flap.wavenumber().expect("a wave"), TAU / flap.period, flap.period);
    let (t0, t1) = (4.4, 4.4 + 4.0 * period);
    let (x, records) = gauge_records(&scene, &gauges(&scene), t1 + 0.1);
    let raw = crest_to_trough(&records[0], period, t0, t1);
    let z: Vec<Complex<f64>> = records.iter().map(|r| harmonic(r, omega, t0, t1)).collect();
    let height = 2.0 * z[0].norm();
    let lag = (z[0].arg() - z[3].arg()).rem_euclid(TAU);
    let k_measured = lag / (x[3] - x[0]);
    let fit = two_waves(&z, &x, k);
    let heights: Vec<f64> = z.iter().map(|z| (2.0 * z.norm() * 1e4).round() / 1e4).collect();
    eprintln!(
        "flap flume: 2|Z| at x = {} m {height:.4} m (target {wave_height}; crest to trough {raw:.4} m); \
         2|Z| at the gauges {heights:?}; k from the lag {k_measured:.3} 1/m, from the fit {:.3} \
         (theory {k:.3}); decay {:.2} 1/m",
        x[0], fit.k, fit.kappa,
    );
    assert!(
        (height / wave_height - 1.0).abs() <= 0.10,
        "first-order wave height {height:.4} m, target {wave_height} m"
    );
    assert!(
        (k_measured / k - 1.0).abs() <= 0.05,
        "wavenumber {k_measured:.3} 1/m from the phase lag, dispersion relation {k:.3}"
    );
}

/// The analysis on synthetic records at six gauges 0.4 m apart, sampled as the test samples:
/// an incident wave of amplitude 0.02 m and a reflected one of 0.003 m, both decaying at
/// κ = 0.3 1/m, at kd = 1.2 (k on the fit's grid). The fit recovers k, κ and both amplitudes
/// (to 1e-3 relative; the harmonic fit over whole periods is exact up to rounding); without
/// reflection the lag is `k Δx` and the crest-to-trough height `2a` (to 1e-3: the sampling's
/// 0.04 % on the crests).
#[test]
fn the_flume_analysis_recovers_a_known_decaying_pattern() {
    let (omega, k_theory, a_i, a_r, kappa) = (5.712, 4.0, 0.02, 0.003, 0.3);
    let k = k_theory * 0.97;
    let eta = |x: f64, t: f64| {
        a_i * (-kappa * x).exp() * (omega * t - k * x).cos()
            + a_r * (kappa * x).exp() * (omega * t + k * x + 0.7).cos()
            + 0.3
    };
    let xs = [0.5, 0.9, 1.3, 1.7, 2.1, 2.5];
    let record = |f: &dyn Fn(f64) -> f64| -> Vec<(f64, f64)> {
        (0..1500)
            .map(|i| (i as f64 * SAMPLE, f(i as f64 * SAMPLE)))
            .collect()
    };
    let period = TAU / omega;
    let (t0, t1) = (2.0, 2.0 + 4.0 * period);
    let z: Vec<Complex<f64>> = xs
        .iter()
        .map(|&x| harmonic(&record(&|t| eta(x, t)), omega, t0, t1))
        .collect();
    let fit = two_waves(&z, &xs, k_theory);
    assert!((fit.k / k - 1.0).abs() < 1e-3, "k {}", fit.k);
    assert!((fit.kappa - kappa).abs() < 1e-3, "kappa {}", fit.kappa);
    assert!(
        (fit.incident.norm() / a_i - 1.0).abs() < 1e-3,
        "incident {:?}",
        fit.incident
    );
    assert!(
        (fit.reflected.norm() / a_r - 1.0).abs() < 1e-3,
        "reflected {:?}",
        fit.reflected
    );
    let want = a_r * (kappa * ZONE_START).exp() / (a_i * (-kappa * ZONE_START).exp());
    assert!((fit.reflection_at(ZONE_START) / want - 1.0).abs() < 1e-3);
    // Without reflection the lag is k Δx exactly, and the height 2 a.
    let pure = |x: f64| record(&move |t: f64| a_i * (omega * t - k * x).cos());
    let (p0, p3) = (
        harmonic(&pure(xs[0]), omega, t0, t1),
        harmonic(&pure(xs[3]), omega, t0, t1),
    );
    let lag = (p0.arg() - p3.arg()).rem_euclid(TAU);
    assert!((lag / (k * 1.2) - 1.0).abs() < 1e-3, "lag {lag}");
    let height = crest_to_trough(&pure(xs[0]), period, t0, t1);
    assert!((height / (2.0 * a_i) - 1.0).abs() < 1e-3, "height {height}");
}
