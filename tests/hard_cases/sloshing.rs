//! Violent sloshing (hard cases): a closed tank swayed at its first natural period
//! (`scenes/hard/sloshing_2d.toml`, `sloshing_3d.toml`), with `wcsph` and `corrected`, checked
//! after every step:
//! - the step succeeds: every field finite and every fluid particle inside the domain (the
//!   solver's own guards return an error otherwise, which fails the test);
//! - the tank's particles stand exactly at `x0 + d(t)` (bitwise, `x0` from the scene's own
//!   particle generation, `d` from `Sway` evaluated here) with velocity `d'(t)`, where `t` is the
//!   time the step last placed them (`Simulation::solids_placed_at`): the step's start for
//!   `wcsph` (symplectic Euler), its end for `corrected` (placed before the last correction);
//! - no fluid particle past the centres of the tank's innermost wall layer (half a spacing
//!   outside the inside box), measured in the tank's frame, i.e. against where the wall
//!   particles actually are;
//! - the fluid's mass bitwise unchanged;
//! - `corrected`: no stage at the iteration cap and every stage's compression below δ.
//!
//! No energy bound applies, unlike the suite (`suite.rs`): the walls do work on the fluid.
//! Instead the physics of the forcing is checked: the fluid's kinetic energy grows far above
//! that of the same tank left at rest, and the horizontal force on the tank oscillates at the
//! forcing period. A unit test of the motion formula is in `src/boundary/motion.rs`.

use sph::fields::FLUID;
use sph::math::Vector;
use sph::run::AnySimulation;
use sph::scene::{Scene, generate, load_scene};
use sph::solver::Simulation;
use std::path::Path;

/// The scene file of `scenes/hard/` with the solver `solver`; for `corrected` a cap of 1,000
/// sweeps per stage (as the suite, `suite.rs`) and δ = 1e-3, the recommended tolerance
/// (it buys most of the accuracy of 1e-4 at a quarter of the sweeps, which keeps the run short).
fn scene(file: &str, solver: &str) -> Scene {
    let path = format!("{}/scenes/hard/{file}", env!("CARGO_MANIFEST_DIR"));
    let mut sets = vec![format!("solver.kind={solver}")];
    if solver == "corrected" {
        sets.push("solver.max_iterations=1000".into());
        sets.push("solver.delta=1e-3".into());
    }
    load_scene(Path::new(&path), &sets).expect("sloshing scene")
}

/// Mean kinetic energy per unit mass of the fluid [J/kg].
fn kinetic_energy<const D: usize>(sim: &Simulation<D>) -> f64 {
    let f = &sim.fields;
    let (mut e, mut m) = (0.0, 0.0);
    for i in (0..f.len()).filter(|&i| f.kind[i] == FLUID) {
        let u2: f64 = f.velocity[i].iter().map(|c| f64::from(*c).powi(2)).sum();
        e += 0.5 * f64::from(f.mass[i]) * u2;
        m += f64::from(f.mass[i]);
    }
    e / m
}

/// What a run recorded after each step: time [s], the tank's horizontal force [N] (2D: [N/m])
/// and the fluid's kinetic energy per unit mass [J/kg].
struct Record {
    time: Vec<f64>,
    force_x: Vec<f64>,
    kinetic: Vec<f64>,
    /// Largest height of a fluid particle above the tank's floor [m].
    crest: f64,
}

/// Runs `scene` to its end with every per-step check of the module doc; returns the record.
fn run_checked<const D: usize>(scene: &Scene, mut sim: Simulation<D>) -> Record {
    let name = format!(
        "{} ({})",
        scene.name.clone().unwrap_or_default(),
        scene.solver.kind.name()
    );
    assert_eq!(scene.solids.len(), 1, "{name}: one tank");
    let tank = &scene.solids[0];
    let sway = tank
        .motion
        .as_ref()
        .expect("the tank moves")
        .sway()
        .expect("a sway");
    // x0 of every solid particle from the scene's own generation: solids follow the fluid's ids.
    let layout = generate::<D>(scene).expect("generates");
    let first = layout.fluid_position.len();
    let x0: Vec<Vector<D>> = layout.solids.iter().flat_map(|s| s.position.clone()).collect();
    let corrected = sim.config().correction.is_some();
    let mass = sim.fluid_mass();
    let dx = scene.spacing;
    let (lo, hi) = (&tank.region.min, &tank.region.max);
    let mut record = Record {
        time: Vec::new(),
        force_x: Vec::new(),
        kinetic: Vec::new(),
        crest: f64::NEG_INFINITY,
    };
    let mut steps = 0u64;
    while sim.clock().time < scene.end_time {
        let start = sim.clock().time;
        sim.step(scene.end_time).unwrap_or_else(|e| panic!("{name}: {e}"));
        steps += 1;
        let now = sim.clock().time;
        // The walls: exactly x0 + d(t), velocity d'(t), at the time this step last placed them.
        let placed = sim.solids_placed_at().expect("the tank was placed");
        assert_eq!(
            placed,
            if corrected { now } else { start },
            "{name}: step {steps}: placement time"
        );
        let k = sway.kinematics::<D>(placed);
        let f = &sim.fields;
        for i in (0..f.len()).filter(|&i| f.kind[i] != FLUID) {
            let at = x0[f.id[i] as usize - first] + k.displacement;
            assert!(
                f.position[i] == at && f.velocity[i] == k.velocity,
                "{name}: step {steps}: wall particle {} at {:?} moving {:?}, not x0 + d = {at:?}, d' = {:?}",
                f.id[i],
                f.position[i],
                f.velocity[i],
                k.velocity
            );
        }
        // The fluid: inside the innermost wall layer's centres, in the tank's frame.
        for i in (0..f.len()).filter(|&i| f.kind[i] == FLUID) {
            let mut x = [0.0f64; 3];
            for (a, c) in x.iter_mut().enumerate().take(D) {
                *c = f64::from(f.position[i][a]) - f64::from(k.displacement[a]);
            }
            let x = &x[..D];
            let out = (0..D).find(|&a| x[a] <= lo[a] - 0.5 * dx || x[a] >= hi[a] + 0.5 * dx);
            if let Some(a) = out {
                panic!(
                    "{name}: step {steps}, t = {now:.4} s: fluid particle {} at {x:?} in the tank's frame \
                     is past the innermost wall layer on axis {a} (inside box {lo:?}..{hi:?}, dx = {dx})",
                    f.id[i]
                );
            }
            record.crest = record.crest.max(x[D - 1] - lo[D - 1]);
        }
        assert_eq!(
            sim.fluid_mass().to_bits(),
            mass.to_bits(),
            "{name}: fluid mass changed"
        );
        record.time.push(now);
        record.force_x.push(sim.solid_forces()[0][0]);
        record.kinetic.push(kinetic_energy(&sim));
    }
    if let Some(c) = sim.config().correction {
        let s = sim.stats().correction;
        eprintln!(
            "{name}: {steps} steps, {:.1} sweeps per stage (max {}), compression left {:.2e}; \
             {:.1} velocity sweeps per solve, {} of {} solves given up",
            s.mean_iterations(),
            s.max_iterations,
            s.max_compression_after,
            s.mean_velocity_iterations(),
            s.velocity_solves_given_up,
            s.velocity_solves
        );
        assert_eq!(s.unconverged_stages, 0, "{name}: stages at the iteration cap");
        assert!(
            s.max_compression_after < c.delta,
            "{name}: compression {} left",
            s.max_compression_after
        );
    } else {
        eprintln!("{name}: {steps} steps");
    }
    record
}

/// Amplitude [N] of the component of `f(t)` at angular frequency `w` over `t >= from`:
/// `2/T |∫ f e^{-iwt} dt|` (the trapezoid-free sum over the steps' own `dt`), after removing the
/// mean.
fn amplitude_at(time: &[f64], f: &[f64], from: f64, w: f64) -> f64 {
    let pairs: Vec<(f64, f64, f64)> = time
        .windows(2)
        .zip(&f[1..])
        .filter(|(t, _)| t[0] >= from)
        .map(|(t, &v)| (t[1], t[1] - t[0], v))
        .collect();
    let span: f64 = pairs.iter().map(|p| p.1).sum();
    let mean = pairs.iter().map(|p| p.1 * p.2).sum::<f64>() / span;
    let (mut re, mut im) = (0.0, 0.0);
    for &(t, dt, v) in &pairs {
        re += (v - mean) * (w * t).cos() * dt;
        im += (v - mean) * (w * t).sin() * dt;
    }
    2.0 / span * (re * re + im * im).sqrt()
}

/// The sinusoidal motion of the scene's tank (its one solid).
fn tank_sway(scene: &Scene) -> sph::scene::Sway {
    scene.solids[0]
        .motion
        .as_ref()
        .expect("the tank moves")
        .sway()
        .expect("a sway")
}

/// The end [s] of the second period after the ramp (or the scene's end): the window of the
/// kinetic-energy checks.
fn second_period_end(scene: &Scene) -> f64 {
    let sway = tank_sway(scene);
    (sway.ramp + 2.0 * sway.period).min(scene.end_time)
}

/// The physics of the forcing, for the scene's run `moving`. Over the second period after the
/// ramp (ending at [`second_period_end`]), the fluid's mean kinetic energy per kg is at least
/// twice that of the tank's own sway, `½ (|A| ω)²/2` (at resonance the sloshing carries more
/// than the rigid motion; measured 7–11 times), and, where the same tank's run at rest is given
/// (`rest_kinetic`, its largest value in that period [J/kg]; the long version), at least 20
/// times that (measured 440–8,660 times). And the horizontal force on the
/// tank oscillates at the forcing frequency (the largest spectral amplitude over 0.4–2.5 ω lies
/// within 10 % of ω) with at least half the amplitude `M |A| ω²` that the fluid's mass alone,
/// carried rigidly, would need.
fn check_forcing(scene: &Scene, moving: &Record, rest_kinetic: Option<f64>, fluid_mass: f64) {
    let name = scene.name.clone().unwrap_or_default();
    let sway = tank_sway(scene);
    let w = sway.omega();
    let after_ramp = sway.ramp;
    let at = second_period_end(scene);
    // Time-weighted mean over the period before `at`.
    let (mut sum, mut span) = (0.0, 0.0);
    for (t, e) in moving.time.windows(2).zip(&moving.kinetic[1..]) {
        if t[1] > at - sway.period && t[1] <= at {
            sum += e * (t[1] - t[0]);
            span += t[1] - t[0];
        }
    }
    let mean_kinetic = sum / span;
    let peak_kinetic = moving.kinetic.iter().copied().fold(0.0, f64::max);
    let a = sway.amplitude.iter().map(|c| c * c).sum::<f64>().sqrt();
    let rigid = 0.5 * (a * w).powi(2) * 0.5; // mean of ½ (A ω cos)² over a period
    eprintln!(
        "{name} ({}): kinetic energy per kg: mean over the period to {at:.2} s {mean_kinetic:.3e}, \
         peak {peak_kinetic:.3e}, rigid sway {rigid:.3e}, tank at rest at most {} J/kg; \
         crest {:.3} m above the floor",
        scene.solver.kind.name(),
        rest_kinetic.map_or("(not run)".to_string(), |e| format!("{e:.3e}")),
        moving.crest
    );
    assert!(
        mean_kinetic >= 2.0 * rigid,
        "{name}: the forcing does too little work: {mean_kinetic:.3e} J/kg, rigid sway {rigid:.3e}"
    );
    if let Some(rest_kinetic) = rest_kinetic {
        assert!(
            mean_kinetic >= 20.0 * rest_kinetic,
            "{name}: the forcing makes too little difference: {mean_kinetic:.3e} J/kg, \
             {rest_kinetic:.3e} J/kg in the tank at rest"
        );
    }
    let scan: Vec<(f64, f64)> = (0..=210)
        .map(|i| {
            let wi = w * (0.4 + 0.01 * i as f64);
            (wi, amplitude_at(&moving.time, &moving.force_x, after_ramp, wi))
        })
        .collect();
    let (w_peak, amp) = scan
        .iter()
        .copied()
        .fold((0.0, 0.0), |b, s| if s.1 > b.1 { s } else { b });
    let inertia = fluid_mass * a * w * w;
    eprintln!(
        "{name} ({}): force spectrum peak at {:.3} ω, amplitude {amp:.1} N against M|A|ω² = {inertia:.1} N",
        scene.solver.kind.name(),
        w_peak / w
    );
    assert!(
        (w_peak / w - 1.0).abs() <= 0.1,
        "{name}: the tank's force peaks at {:.3} of the forcing frequency",
        w_peak / w
    );
    assert!(
        amp >= 0.5 * inertia,
        "{name}: force amplitude {amp} below half of M|A|ω² = {inertia}"
    );
}

/// `scene` with the tank left at rest (its motion removed), run to [`second_period_end`]: the
/// largest kinetic energy per kg [J/kg] in the period before.
fn rest_kinetic<const D: usize>(scene: &Scene) -> f64 {
    let at = second_period_end(scene);
    let mut rest = scene.clone();
    let sway = rest.solids[0]
        .motion
        .take()
        .expect("moves")
        .sway()
        .expect("a sway");
    let mut sim = build::<D>(&rest);
    assert!(
        !sim.plan().iter().any(|s| s.name() == "move_solids"),
        "a tank at rest has no move_solids stage"
    );
    let mut largest = 0.0f64;
    while sim.clock().time < at {
        sim.step(at).expect("the tank at rest runs");
        if sim.clock().time > at - sway.period {
            largest = largest.max(kinetic_energy(&sim));
        }
    }
    largest
}

fn build<const D: usize>(scene: &Scene) -> Simulation<D> {
    match (AnySimulation::from_scene(scene).expect("builds"), D) {
        (AnySimulation::D2(s), 2) => *(Box::new(s) as Box<dyn std::any::Any>)
            .downcast::<Simulation<D>>()
            .expect("2D"),
        (AnySimulation::D3(s), 3) => *(Box::new(s) as Box<dyn std::any::Any>)
            .downcast::<Simulation<D>>()
            .expect("3D"),
        _ => panic!("dimension {D} does not match the scene"),
    }
}

/// The swayed tank under every per-step check and the forcing's physics; with `against_rest`
/// also the same tank at rest, run as far as the kinetic window (the long version: it costs
/// about as much again as the swayed run).
fn case<const D: usize>(file: &str, solver: &str, against_rest: bool) {
    let scene = scene(file, solver);
    let sim = build::<D>(&scene);
    assert_eq!(
        sim.plan()[0].name(),
        "move_solids",
        "a moving tank is placed first"
    );
    let mass = sim.fluid_mass();
    let clock = std::time::Instant::now();
    let record = run_checked(&scene, sim);
    eprintln!(
        "{file} ({solver}): the swayed tank took {:.1} s",
        clock.elapsed().as_secs_f64()
    );
    let rest = against_rest.then(|| rest_kinetic::<D>(&scene));
    check_forcing(&scene, &record, rest, mass);
}

#[test]
fn sloshing_2d_wcsph() {
    case::<2>("sloshing_2d.toml", "wcsph", false);
}

#[test]
fn sloshing_2d_corrected() {
    case::<2>("sloshing_2d.toml", "corrected", false);
}

#[test]
fn sloshing_3d_wcsph() {
    case::<3>("sloshing_3d.toml", "wcsph", false);
}

#[test]
fn sloshing_3d_corrected() {
    case::<3>("sloshing_3d.toml", "corrected", false);
}

// The long version (`cargo test --release -- --ignored`): the same runs, and the same tank at
// rest for the comparison of kinetic energies.

#[test]
#[ignore = "long: the four cases with the tank at rest, about 4 minutes in release on 2 cores"]
fn long_sloshing_against_the_tank_at_rest() {
    for solver in ["wcsph", "corrected"] {
        case::<2>("sloshing_2d.toml", solver, true);
        case::<3>("sloshing_3d.toml", solver, true);
    }
}

/// A checkpoint taken while the tank moves restarts bit for bit: 60 steps straight against
/// 30 + checkpoint (in memory) + restore into a fresh simulation of the scene + 30, with the
/// `corrected` solver (whose walls are placed twice per stage) and with `wcsph`.
#[test]
fn restart_while_the_tank_moves_is_bit_identical() {
    for solver in ["wcsph", "corrected"] {
        let scene = scene("sloshing_2d.toml", solver);
        let run = |sim: &mut Simulation<2>, n: usize| {
            for _ in 0..n {
                sim.step(f64::INFINITY).expect("step");
            }
        };
        let mut straight = build::<2>(&scene);
        run(&mut straight, 60);
        let mut first = build::<2>(&scene);
        run(&mut first, 30);
        let checkpoint = first.checkpoint(serde_json::Value::Null).expect("state");
        let mut resumed = build::<2>(&scene);
        resumed.restore(checkpoint).expect("same scene");
        run(&mut resumed, 30);
        assert_eq!(straight.clock(), resumed.clock(), "{solver}");
        assert_eq!(straight.solid_forces(), resumed.solid_forces(), "{solver}");
        let bits = |s: &Simulation<2>| -> Vec<u32> {
            let f = &s.fields;
            f.position
                .iter()
                .chain(&f.velocity)
                .flat_map(|x| x.iter().map(|c| c.to_bits()))
                .chain(f.density.iter().chain(&f.pressure).map(|c| c.to_bits()))
                .chain(f.id.iter().copied())
                .collect()
        };
        assert!(
            bits(&straight) == bits(&resumed),
            "{solver}: the restarted run differs"
        );
        assert!(
            straight.solid_kinematics()[0].displacement.norm() > 0.0,
            "{solver}: the tank moved"
        );
    }
}
