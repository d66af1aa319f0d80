//! Pressures a transducer would read on the 2D dam break (`scenes/dam_break_2d.toml`, issue 26):
//! the back wall's load at the start (the hydrostatic initial state, `fluid.initial_state`) and
//! the impact on the far wall.

use sph::math::Real;
use sph::probe::{ProbeSpace, interpolate};
use sph::run::simulation_from_scene;
use sph::scene::parse_scene;
use sph::smoothing::Smoothing;
use std::path::Path;

/// Column height and width `a` [m], rest density [kg/m³] and gravity [m/s²] of the scene.
const A: f64 = 0.25;
const RHO0: f64 = 1000.0;
const G: f64 = 9.81;

/// The shipped dam break with the overrides `sets` (`--set` syntax).
fn dam_break(sets: &[&str]) -> sph::scene::Scene {
    let path = Path::new("scenes/dam_break_2d.toml");
    let text = std::fs::read_to_string(path).expect("shipped scene");
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    parse_scene(&text, "dam_break_2d.toml", &sets).expect("scene with overrides")
}

/// The force of the fluid on the back wall [N/m] at t = 1 ms: minus the x force on the tank
/// (the far wall is dry, the floor pushes along y only).
fn back_wall_load_at_1_ms(solver: &str, initial_state: &str) -> f64 {
    let kind = format!("solver.kind={solver}");
    let state = format!("fluid.initial_state={initial_state}");
    let scene = dam_break(&[&kind, &state, "particles.spacing=0.01"]);
    let mut sim = simulation_from_scene::<2>(&scene).expect("builds");
    let tank = sim.solid_names().iter().position(|n| n == "tank").expect("tank");
    let end = 1e-3;
    while sim.clock().time < end - 1e-12 {
        sim.step(end).expect("stable step");
    }
    -sim.solid_forces()[tank][0]
}

/// With `fluid.initial_state = "hydrostatic"` the wcsph column starts at rest under its own
/// weight, so the back wall carries `ρ0 g a² / 2` (306.6 N/m) at once; from the uniform state
/// it carries about 1 % of it at 1 ms (the column first compresses under gravity). Measured at
/// a/25: 286.3 N/m hydrostatic, 3.8 N/m uniform.
///
/// Tolerance 10 %: the wall's pressure is the [A12] extrapolation from fluid particles within
/// one kernel radius (h = 2 dx = a/12.5 here), and the free surface's top row carries no
/// pressure (its summed density is short of neighbours, clamped at zero): a linear profile cut
/// half a spacing early loses `(dx/2)/a`, 2 %; fluid next to the walls sums the walls' lattice
/// mass, not the heavier hydrostatic one, which costs the bottom corner a few percent more.
///
/// The `corrected` solver is not held to this: it is incompressible, so its column unloads at
/// once to the pressure of the released column ([`incompressible_release_loads`], 180.7 N/m on
/// the back wall), which `corrected_column_loads_its_walls_as_an_incompressible_release`
/// checks.
#[test]
fn hydrostatic_start_loads_the_back_wall_with_the_column_weight() {
    let expected = RHO0 * G * A * A / 2.0;
    let hydrostatic = back_wall_load_at_1_ms("wcsph", "hydrostatic");
    let uniform = back_wall_load_at_1_ms("wcsph", "uniform");
    assert!(
        (hydrostatic - expected).abs() <= 0.10 * expected,
        "hydrostatic start: {hydrostatic:.1} N/m at 1 ms, rho0 g a^2 / 2 = {expected:.1} N/m"
    );
    // What the hydrostatic state fixes: the uniform column has not loaded the wall yet.
    assert!(
        uniform < 0.1 * expected,
        "uniform start: {uniform:.1} N/m at 1 ms"
    );
}

/// The loads [N/m] on the back wall and the floor of a square column `a` high of an
/// incompressible fluid the instant it is released (`t = 0+`, still at rest).
///
/// At rest, momentum gives `∇p = ρ0 g − ρ0 ∂u/∂t` and incompressibility `∇²p = 0`, with
/// `p = 0` on the top `y = a` and the released face `x = a`, and `∂p/∂n = ρ0 g·n` on the wall
/// `x = 0` and the floor `y = 0` (there `∂u/∂t·n = 0`). With `p = ρ0 g (a − y) − q`, `q` is
/// harmonic, zero on the top, without normal gradient on wall and floor, and `ρ0 g (a − y)` on
/// the face: `q = Σ_n A_n cosh(k_n x) cos(k_n y)`, `k_n = (2n + 1) π / (2a)`,
/// `A_n cosh(k_n a) = 2 ρ0 g / (a k_n²)` (the cosine series of `a − y` on `[0, a]`). The back wall
/// carries `ρ0 g a²/2 − Σ A_n (−1)^n / k_n` (0.589 of the hydrostatic load), the floor
/// `ρ0 g a² − Σ A_n sinh(k_n a) / k_n`, half the column's weight: its centre of mass starts
/// falling at g/2. 200 terms: the terms fall as `e^{-k_n a}/k_n³` and `1/k_n³`.
fn incompressible_release_loads(a: f64) -> (f64, f64) {
    let rho_g = RHO0 * G;
    let (mut back, mut floor) = (rho_g * a * a / 2.0, rho_g * a * a);
    for n in 0..200 {
        let k = (2 * n + 1) as f64 * std::f64::consts::PI / (2.0 * a);
        let amplitude = 2.0 * rho_g / (a * k * k);
        let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
        back -= amplitude / (k * a).cosh() * sign / k;
        floor -= amplitude * (k * a).tanh() / k;
    }
    (back, floor)
}

/// The `corrected` solver's column, released from the uniform state, loads the back wall and
/// the floor as the incompressible column does at release ([`incompressible_release_loads`]:
/// 180.7 and 306.6 N/m at a = 0.25 m), not with the hydrostatic 306.6 and 613.1 N/m a weakly
/// compressible column keeps until the release's rarefaction crosses it (a/c0 = 7 ms).
/// Averaged over 5–20 ms (the first steps, each a few ms): measured at a/25, back wall
/// 179.2 N/m (−0.8 %), floor 309.6 N/m (+1.0 %).
///
/// Tolerance 5 %: the hydrostatic wall loads of the same lattice and wall model read 2–3 %
/// low (`hydrostatic_start_loads_the_back_wall_with_the_column_weight`); the column's fall by
/// 20 ms (`g t²/2` ≈ 2 mm, 0.8 % of a) changes the loads by less than 1 %. A solver that kept
/// the hydrostatic load (+70 % on the wall) or lagged like a compressible one fails.
#[test]
fn corrected_column_loads_its_walls_as_an_incompressible_release() {
    let (back_want, floor_want) = incompressible_release_loads(A);
    let scene = dam_break(&["solver.kind=corrected", "particles.spacing=0.01"]);
    let mut sim = simulation_from_scene::<2>(&scene).expect("builds");
    let tank = sim.solid_names().iter().position(|n| n == "tank").expect("tank");
    let (start, end) = (5e-3, 20e-3);
    let (mut impulse, mut duration) = ([0.0; 2], 0.0);
    while sim.clock().time < end - 1e-12 {
        let before = sim.clock().time;
        let report = sim.step(end).expect("stable step");
        // The share of the step inside the window.
        let inside = sim.clock().time.min(end) - before.max(start);
        if inside > 0.0 {
            let f = sim.solid_forces()[tank];
            impulse[0] -= f[0] * inside;
            impulse[1] -= f[1] * inside;
            duration += inside;
        }
        assert!(report.dt > 0.0);
    }
    let (back, floor) = (impulse[0] / duration, impulse[1] / duration);
    eprintln!(
        "corrected release: back wall {back:.1} N/m (incompressible {back_want:.1}), floor {floor:.1} N/m ({floor_want:.1})"
    );
    for (name, got, want) in [("back wall", back, back_want), ("floor", floor, floor_want)] {
        assert!(
            (got / want - 1.0).abs() <= 0.05,
            "{name}: {got:.1} N/m over 5-20 ms, incompressible release {want:.1} N/m"
        );
    }
}

/// One far-wall pressure record: the peak of its 1 ms running mean [Pa] (over at least the
/// step and its two neighbours) and the largest ratio of a step's reading to that mean around
/// it (where the mean is above a tenth of the peak).
#[derive(Debug, Clone, Copy)]
struct Impact {
    peak: f64,
    spike: f64,
    /// When the sensor first reads a pressure [s] (infinite: never).
    arrival: f64,
    /// The pressure impulse `∫ p dt` over the record [Pa s], each step's reading held over it.
    impulse: f64,
}

/// Height of the far-wall sensor above the floor [m]: 0.2 a = 50 mm, above the kernel radius at
/// a/25 (h = 20 mm, so the floor does not cut the probe's support) and low in the impact surge
/// (the front arrives about a/4 thick at x = 5a).
const SENSOR_HEIGHT: f64 = 0.2 * A;

/// The far-wall sensor (x = 5a, y = [`SENSOR_HEIGHT`]) sampled every step until t = 0.8 s: the
/// wcsph front reaches it near t = 0.5 s (T ≈ 3.1; a sensor there read nothing until 0.5 s),
/// the run-up jet follows, and the jet's fall back (T ≈ 6, 1 s) is not yet there.
fn far_wall_impact(sets: &[&str]) -> Impact {
    let mut all = vec!["solver.end_time=0.8", "output.interval=0.8"];
    all.extend_from_slice(sets);
    let scene = dam_break(&all);
    let mut sim = simulation_from_scene::<2>(&scene).expect("builds");
    let kernel = Smoothing::<2>::new(scene.smoothing_length as Real).expect("kernel");
    // The pressure a sensor reads in this solver (`probe::PressureReading`).
    let reading = ProbeSpace::of(&scene).pressure;
    let point = [5.0 * A, SENSOR_HEIGHT];
    let (mut times, mut record) = (Vec::new(), Vec::new());
    let end = 0.8;
    while sim.clock().time < end - 1e-12 {
        sim.step(end).expect("stable step");
        sim.sync_fields().expect("fields");
        let values = reading.values(&sim.fields);
        times.push(sim.clock().time);
        record.push(interpolate::pressure_of(&sim.fields, values, &kernel, &point));
    }
    impact_of(&times, &record)
}

/// A record's peak of its 1 ms mean, its largest step-to-mean ratio and its first reading, from
/// the sensor's reading at the end of each step (`record`) at `times` [s].
fn impact_of(times: &[f64], record: &[f64]) -> Impact {
    // The 1 ms mean, over the step's neighbours at least: `corrected` takes steps of 1-2 ms,
    // where a 1 ms window would hold the step alone and no step could read above its mean.
    let window = 1e-3;
    let mean_around = |k: usize| {
        let t = times[k];
        let near: Vec<f64> = (0..times.len())
            .filter(|&j| (times[j] - t).abs() <= window / 2.0 || j.abs_diff(k) <= 1)
            .map(|j| record[j])
            .collect();
        near.iter().sum::<f64>() / near.len() as f64
    };
    let means: Vec<f64> = (0..times.len()).map(mean_around).collect();
    let peak = means.iter().cloned().fold(0.0, f64::max);
    let spike = record
        .iter()
        .zip(&means)
        .filter(|(_, m)| **m > 0.1 * peak)
        .map(|(p, m)| p / m)
        .fold(0.0, f64::max);
    let arrival = times
        .iter()
        .zip(record)
        .find(|(_, p)| **p > 0.0)
        .map_or(f64::INFINITY, |(t, _)| *t);
    let impulse = (0..times.len())
        .map(|k| record[k] * (times[k] - if k == 0 { 0.0 } else { times[k - 1] }))
        .sum();
    Impact {
        peak,
        spike,
        arrival,
        impulse,
    }
}

/// The far-wall criteria of issue 26 for one solver's runs at a/25 and a/50: their peaks of the
/// 1 ms mean agree within 15 % (a transducer's bandwidth), the sensor reads, and no step reads
/// more than twice the 1 ms mean around it. The failures, in words.
fn far_wall_failures(label: &str, coarse: Impact, fine: Impact) -> Vec<String> {
    let mut failures = Vec::new();
    let agreement = (coarse.peak - fine.peak).abs() / fine.peak;
    // A sensor that never reads (peak 0, agreement NaN) fails too.
    if agreement > 0.15 || agreement.is_nan() {
        failures.push(format!(
            "{label}: peaks {:.0} and {:.0} Pa differ by {:.0} %",
            coarse.peak,
            fine.peak,
            100.0 * agreement
        ));
    }
    for (spacing, run) in [("a/25", coarse), ("a/50", fine)] {
        if run.arrival.is_infinite() {
            failures.push(format!("{label} {spacing}: the sensor never reads a pressure"));
        }
        if run.spike > 2.0 {
            failures.push(format!(
                "{label} {spacing}: a step reads {:.1} x its 1 ms mean",
                run.spike
            ));
        }
    }
    failures
}

/// The far wall's impact at a/25 and a/50 from the hydrostatic state, with the overrides `sets`
/// and then those in the environment variable `FAR_WALL_SETS` (`;`-separated, `--set` syntax:
/// `FAR_WALL_SETS="solver.cfl=0.199"` repeats a run with its steps 0.5 % shorter).
fn far_wall_impacts(sets: &[&str]) -> (Impact, Impact) {
    let extra = std::env::var("FAR_WALL_SETS").unwrap_or_default();
    let run = |spacing: &str| {
        let mut all = vec!["fluid.initial_state=hydrostatic", spacing];
        all.extend_from_slice(sets);
        all.extend(extra.split(';').filter(|s| !s.trim().is_empty()));
        far_wall_impact(&all)
    };
    (run("particles.spacing=0.01"), run("particles.spacing=0.005"))
}

/// Issue 26, `wcsph` with the continuity equation and [F19] density diffusion
/// (`density_diffusion`, δ = 0.1): the far wall's first impact read at dx = a/25 and a/50
/// agrees within 15 % (peak of the 1 ms mean), and no step reads more than twice the 1 ms mean
/// around it ([`far_wall_failures`]).
///
/// Fails, and one run per spacing cannot decide it: the peak is not reproducible. The same runs
/// with the CFL number at 0.198, 0.199, 0.2 and 0.201 (`FAR_WALL_SETS="solver.cfl=0.199"`, AMD
/// EPYC 2-core, commit ea8d078's solver) peak at 3,346–16,798 Pa (a/25) and 6,115–9,936 Pa
/// (a/50), a factor 5 at one spacing; steps read up to 1.27–1.32 (a/25) and 1.82–2.90 (a/50)
/// times their 1 ms mean. The 1 ms peak is the impact's acoustic ringing: at c0 = 35 m/s a
/// pressure wave crosses the 50 mm surge in 1.4 ms, longer than the window (sound speeds 17.5
/// and 70 m/s at CFL 0.2: 9,406/6,386 and 1,565/10,446 Pa). The pressure impulse over the
/// record is reproducible (172–205 and 331–391 Pa s) but doubles from a/25 to a/50 at this
/// height (docs/method.md, "The far-wall sensor run to run").
///
/// Without the effect (density summed by (18)): peaks 2,644 Pa (a/25) and 2,771 Pa (a/50), at
/// a/50 one step at 2.8 times its 1 ms mean.
#[test]
#[ignore = "fails, and cannot be decided by one run per spacing: at CFL 0.198-0.201 the peaks are 3,346-16,798 Pa (a/25) and 6,115-9,936 Pa (a/50); steps at a/50 up to 2.9 times their mean"]
fn far_wall_impact_converges_without_spikes_wcsph_density_diffusion() {
    let (coarse, fine) = far_wall_impacts(&[
        "solver.kind=wcsph",
        r#"effects=["gravity", "viscosity", "artificial_viscosity", "density_diffusion"]"#,
        "fluid.density_diffusion=0.1",
    ]);
    eprintln!("wcsph + density_diffusion: a/25 {coarse:?}, a/50 {fine:?}");
    let failures = far_wall_failures("wcsph + density_diffusion", coarse, fine);
    assert!(failures.is_empty(), "{}", failures.join("; "));
}

/// Issue 26, the `corrected` solver, held to the same criteria, reading the pressure that acted
/// over the last stage (`probe::PressureReading::Acting`: the carried pressure reads 0 through
/// the impact).
///
/// Fails, and the criterion does not apply to an incompressible impact: its peak follows the
/// time step. The velocity solve stops each particle reaching the wall within one stage, so a
/// 1 ms window reads the momentum of the few particles stopped in it over the step's length:
/// at CFL 0.197–0.202 (six runs, `FAR_WALL_SETS="solver.cfl=0.199"`, AMD EPYC 2-core, commit
/// ea8d078's solver) the peaks are 474–715 Pa (a/25) and 559–796 Pa (a/50), steps up to
/// 1.58–2.53 and 2.05–2.52 times their mean; at CFL 0.0499–0.0501 (three runs) 1,138–1,476 Pa
/// and 1,091–3,342 Pa, steps up to 2.6–3.5 times. The pressure impulse does not follow the step
/// ([`corrected_far_wall_pressure_impulse_does_not_depend_on_the_step`]), but at this height it
/// rises from 39–48 Pa s (a/25) to 62–74 Pa s (a/50).
///
/// The artificial viscosity between fluid and wall particles takes most of the impact
/// (docs/method.md, "Impact pressure": 2,436 and 2,162 Pa at α = 0.01).
#[test]
#[ignore = "fails, and the peak follows the step: at CFL 0.197-0.202 it is 474-715 Pa (a/25) and 559-796 Pa (a/50), at CFL 0.05 1,091-3,342 Pa; steps up to 2.5 times their mean"]
fn far_wall_impact_converges_without_spikes_corrected() {
    let (coarse, fine) = far_wall_impacts(&["solver.kind=corrected"]);
    eprintln!("corrected: a/25 {coarse:?}, a/50 {fine:?}");
    let failures = far_wall_failures("corrected", coarse, fine);
    assert!(failures.is_empty(), "{}", failures.join("; "));
}

/// What the `corrected` solver's far-wall sensor does converge to: its pressure impulse
/// `∫ p dt` (to t = 0.8 s, a/25, hydrostatic start) is the same with steps four times shorter
/// (CFL 0.05 against the scene's 0.2), while the peak of its 1 ms mean is not.
///
/// An incompressible fluid meets a wall impulsively: the velocity solve stops each particle
/// that reaches it within one stage, so the pressure it reads over that stage is the particle's
/// momentum over the stage's length, and the peak of any window shorter than the impact grows
/// as the step shrinks. The pressure impulse is the well-posed measure of an impact in an
/// incompressible fluid (Cooker & Peregrine, J. Fluid Mech. 297 (1995) 193): set by the
/// momentum the wall takes, not by how long it takes. Measured (AMD EPYC 2-core, commit
/// ea8d078's solver, six runs at CFL 0.197–0.202 and three at 0.0499–0.0501): impulse 40.9–48.4
/// and 39.2–47.6 Pa s; peak of the 1 ms mean 474–715 and 1,138–1,476 Pa.
///
/// Tolerance 20 %: the impulse of one run moves ±10 % with any change to the particles' paths
/// (the nine runs above); counting the impact twice (the next force stage applying the velocity
/// solve's impulse again) would double it.
#[test]
fn corrected_far_wall_pressure_impulse_does_not_depend_on_the_step() {
    let run = |cfl: &str| {
        far_wall_impact(&[
            "solver.kind=corrected",
            "fluid.initial_state=hydrostatic",
            "particles.spacing=0.01",
            cfl,
        ])
    };
    let (long, short) = (run("solver.cfl=0.2"), run("solver.cfl=0.05"));
    eprintln!("corrected far wall, a/25: CFL 0.2 {long:?}, CFL 0.05 {short:?}");
    for (label, impact) in [("CFL 0.2", long), ("CFL 0.05", short)] {
        assert!(
            impact.arrival.is_finite() && impact.impulse > 0.0,
            "{label}: the sensor never reads a pressure ({impact:?})"
        );
    }
    let ratio = short.impulse / long.impulse;
    assert!(
        (ratio - 1.0).abs() <= 0.2,
        "pressure impulse {:.1} Pa s at CFL 0.05 against {:.1} Pa s at CFL 0.2 (ratio {ratio:.3})",
        short.impulse,
        long.impulse
    );
}

/// A hydrostatic start with a gravity ramp (which starts without weight) or without gravity is
/// a scene error at `fluid.initial_state` that names the clash.
#[test]
fn hydrostatic_start_without_full_gravity_is_an_error_at_its_key() {
    use crate::common::scene::{parse_set, problems, with_key};
    let text = std::fs::read_to_string("scenes/dam_break_2d.toml").expect("shipped scene");
    let ramp = problems(parse_set(
        &text,
        &["fluid.initial_state=hydrostatic", "fluid.gravity_ramp=0.5"],
    ));
    assert!(
        with_key(&ramp, "fluid.initial_state")
            .reason
            .contains("gravity_ramp")
    );
    let weightless = text
        .replace("\"gravity\", ", "")
        .replace("gravity = [0.0, -9.81]", "");
    let none = problems(parse_set(&weightless, &["fluid.initial_state=hydrostatic"]));
    assert!(
        with_key(&none, "fluid.initial_state")
            .reason
            .contains("needs effect \"gravity\"")
    );
}
