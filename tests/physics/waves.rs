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
//! `K_r = |A_R e^{(ik+κ)x_z}| / |A_I e^{−(ik+κ)x_z}|` at its entrance `x_z`.

use sph::boundary::flap::FlapAmplitude;
use sph::physics::waves::wavenumber;
use sph::probe::{ProbeSpace, measure};
use sph::run::simulation_from_scene;
use sph::scene::{Motion, Probe, Scene, load_scene};
use std::f64::consts::TAU;
use std::path::Path;

/// Gauge records are sampled this often [s] (1/110 of the period: a crest is read within
/// `1 − cos(π/110) = 0.04 %` of its height).
const SAMPLE: f64 = 0.01;

/// A complex number `(re, im)`.
type Complex = (f64, f64);

fn mul(a: Complex, b: Complex) -> Complex {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}
fn sub(a: Complex, b: Complex) -> Complex {
    (a.0 - b.0, a.1 - b.1)
}
fn abs(a: Complex) -> f64 {
    a.0.hypot(a.1)
}

/// The least-squares `(Z, c)` of `η = Re(Z e^{iωt}) + c` over the samples in `[t0, t1)`.
fn harmonic(samples: &[(f64, f64)], omega: f64, t0: f64, t1: f64) -> (Complex, f64) {
    // Normal equations of the basis (cos ωt, sin ωt, 1), solved by Cramer's rule.
    let mut m = [[0.0f64; 3]; 3];
    let mut r = [0.0f64; 3];
    for &(t, eta) in samples.iter().filter(|(t, _)| *t >= t0 && *t < t1) {
        let basis = [(omega * t).cos(), (omega * t).sin(), 1.0];
        for i in 0..3 {
            r[i] += basis[i] * eta;
            for j in 0..3 {
                m[i][j] += basis[i] * basis[j];
            }
        }
    }
    let det = |m: &[[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(&m);
    let solve = |col: usize| {
        let mut mc = m;
        for i in 0..3 {
            mc[i][col] = r[i];
        }
        det(&mc) / d
    };
    let (a, b, c) = (solve(0), solve(1), solve(2));
    ((a, -b), c)
}

/// The mean crest-to-trough height [m] over the whole periods `T` from `t0` to `t1`.
fn crest_to_trough(samples: &[(f64, f64)], period: f64, t0: f64, t1: f64) -> f64 {
    let n = ((t1 - t0) / period).floor() as usize;
    let heights: Vec<f64> = (0..n)
        .map(|j| {
            let (a, b) = (t0 + j as f64 * period, t0 + (j + 1) as f64 * period);
            let window = samples.iter().filter(|(t, _)| *t >= a && *t < b).map(|s| s.1);
            let (lo, hi) = window.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
            hi - lo
        })
        .collect();
    heights.iter().sum::<f64>() / n as f64
}

fn add(a: Complex, b: Complex) -> Complex {
    (a.0 + b.0, a.1 + b.1)
}
fn conj(a: Complex) -> Complex {
    (a.0, -a.1)
}
fn div(a: Complex, b: Complex) -> Complex {
    let d = b.0 * b.0 + b.1 * b.1;
    ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
}

/// An incident and a reflected wave decaying along their way: `Z(x) = A_I e^{−(ik+κ)x} +
/// A_R e^{(ik+κ)x}`.
#[derive(Clone, Copy, Debug)]
struct TwoWaves {
    k: f64,
    kappa: f64,
    incident: Complex,
    reflected: Complex,
    /// The residual's norm over the data's.
    misfit: f64,
}

impl TwoWaves {
    /// `|A_R(x)| / |A_I(x)|` at `x` [m].
    fn reflection_at(&self, x: f64) -> f64 {
        abs(self.reflected) * (self.kappa * x).exp() / (abs(self.incident) * (-self.kappa * x).exp())
    }

    /// `2 |A_I(x)|` [m], the incident wave's height at `x`.
    fn incident_height_at(&self, x: f64) -> f64 {
        2.0 * abs(self.incident) * (-self.kappa * x).exp()
    }
}

/// The least-squares [`TwoWaves`] of the complex amplitudes `z` at the gauges `x` [m], for `k`
/// within ±15 % of `k_theory` [1/m] (steps of 0.25 %) and `κ` in [0, 1] 1/m (steps of 0.01).
fn two_waves(z: &[Complex], x: &[f64], k_theory: f64) -> TwoWaves {
    let mut best: Option<TwoWaves> = None;
    let norm = z.iter().map(|z| abs(*z).powi(2)).sum::<f64>().sqrt();
    for i in 0..=120 {
        let k = k_theory * (0.85 + 0.0025 * i as f64);
        for j in 0..=100 {
            let kappa = 0.01 * j as f64;
            // Columns e^{s(ik+κ)x}, s = −1, 1; normal equations M^H M a = M^H z.
            let col = |x: f64, s: f64| {
                let m = (s * kappa * x).exp();
                (m * (s * k * x).cos(), m * (s * k * x).sin())
            };
            let (mut g11, mut g12, mut g22) = ((0.0, 0.0), (0.0, 0.0), (0.0, 0.0));
            let (mut r1, mut r2) = ((0.0, 0.0), (0.0, 0.0));
            for (&zj, &xj) in z.iter().zip(x) {
                let (c1, c2) = (col(xj, -1.0), col(xj, 1.0));
                g11 = add(g11, mul(conj(c1), c1));
                g12 = add(g12, mul(conj(c1), c2));
                g22 = add(g22, mul(conj(c2), c2));
                r1 = add(r1, mul(conj(c1), zj));
                r2 = add(r2, mul(conj(c2), zj));
            }
            let det = sub(mul(g11, g22), mul(g12, conj(g12)));
            let incident = div(sub(mul(g22, r1), mul(g12, r2)), det);
            let reflected = div(sub(mul(g11, r2), mul(conj(g12), r1)), det);
            let misfit = z
                .iter()
                .zip(x)
                .map(|(&zj, &xj)| {
                    let fit = add(mul(incident, col(xj, -1.0)), mul(reflected, col(xj, 1.0)));
                    abs(sub(zj, fit)).powi(2)
                })
                .sum::<f64>()
                .sqrt()
                / norm;
            if best.is_none_or(|b| misfit < b.misfit) {
                best = Some(TwoWaves {
                    k,
                    kappa,
                    incident,
                    reflected,
                    misfit,
                });
            }
        }
    }
    best.expect("a grid")
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
    let z: Vec<Complex> = records.iter().map(|r| harmonic(r, omega, t0, t1).0).collect();
    let lag = (z[0].1.atan2(z[0].0) - z[3].1.atan2(z[3].0)).rem_euclid(TAU);
    let k_measured = lag / (x[3] - x[0]);
    let early = two_waves(&z, &x, k);
    // Incident and reflected: the reflection of the far end has reached the gauges.
    let (s0, s1) = (10.6, 10.6 + 4.0 * period);
    let z_late: Vec<Complex> = records.iter().map(|r| harmonic(r, omega, s0, s1).0).collect();
    let late = two_waves(&z_late, &x, k);
    let kr = late.reflection_at(ZONE_START);
    let heights = |z: &[Complex]| {
        z.iter()
            .map(|z| (2.0 * abs(*z) * 1e4).round() / 1e4)
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
    let z: Vec<Complex> = records.iter().map(|r| harmonic(r, omega, t0, t1).0).collect();
    let height = 2.0 * abs(z[0]);
    let lag = (z[0].1.atan2(z[0].0) - z[3].1.atan2(z[3].0)).rem_euclid(TAU);
    let k_measured = lag / (x[3] - x[0]);
    let fit = two_waves(&z, &x, k);
    let heights: Vec<f64> = z.iter().map(|z| (2.0 * abs(*z) * 1e4).round() / 1e4).collect();
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
    let z: Vec<Complex> = xs
        .iter()
        .map(|&x| harmonic(&record(&|t| eta(x, t)), omega, t0, t1).0)
        .collect();
    let fit = two_waves(&z, &xs, k_theory);
    assert!((fit.k / k - 1.0).abs() < 1e-3, "k {}", fit.k);
    assert!((fit.kappa - kappa).abs() < 1e-3, "kappa {}", fit.kappa);
    assert!(
        (abs(fit.incident) / a_i - 1.0).abs() < 1e-3,
        "incident {:?}",
        fit.incident
    );
    assert!(
        (abs(fit.reflected) / a_r - 1.0).abs() < 1e-3,
        "reflected {:?}",
        fit.reflected
    );
    let want = a_r * (kappa * ZONE_START).exp() / (a_i * (-kappa * ZONE_START).exp());
    assert!((fit.reflection_at(ZONE_START) / want - 1.0).abs() < 1e-3);
    // Without reflection the lag is k Δx exactly, and the height 2 a.
    let pure = |x: f64| record(&move |t: f64| a_i * (omega * t - k * x).cos());
    let (p0, p3) = (
        harmonic(&pure(xs[0]), omega, t0, t1).0,
        harmonic(&pure(xs[3]), omega, t0, t1).0,
    );
    let lag = (p0.1.atan2(p0.0) - p3.1.atan2(p3.0)).rem_euclid(TAU);
    assert!((lag / (k * 1.2) - 1.0).abs() < 1e-3, "lag {lag}");
    let height = crest_to_trough(&pure(xs[0]), period, t0, t1);
    assert!((height / (2.0 * a_i) - 1.0).abs() < 1e-3, "height {height}");
}
