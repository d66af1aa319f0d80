//! The flap wave maker's scene keys (`motion = { kind = "flap", ... }`, `boundary::flap`): the
//! shipped flap flume resolves to the angle of first-order flap theory, bad keys are reported at
//! their keys, and a checkpoint taken while the flap swings restarts bit for bit.

use crate::common::scene::{edit, parse, problems, with_key};
use sph::boundary::flap::FlapAmplitude;
use sph::physics::waves::flap_height_per_stroke;
use sph::run::simulation_from_scene;
use sph::scene::{Motion, load_scene};
use std::path::Path;

const SCENE: &str = "scenes/wave_flap_2d.toml";

/// The shipped flap: hinged at the bed at (0, 0), its stroke at the still-water level makes
/// H = 0.04 m by the bed-hinged flap's H/S (to f64 rounding; 0.639 at kd = 1.198, so
/// S = 0.0626 m), its angle atan(S/2d) = 0.104 rad, and its arm the paddle's far corner.
#[test]
fn flap_resolves_to_the_angle_of_flap_theory() {
    let scene = load_scene(Path::new(SCENE), &[]).expect("shipped scene");
    let Some(Motion::Flap(f)) = scene.solids[1].motion.clone() else {
        panic!("a flap: {:?}", scene.solids[1].motion)
    };
    assert_eq!(f.hinge, vec![0.0, 0.0]);
    assert_eq!(
        f.amplitude,
        FlapAmplitude::Wave {
            wave_height: 0.04,
            depth: 0.3,
            hinge_height: 0.0,
            gravity: 9.81
        }
    );
    let kd = f.wavenumber().expect("a wave") * 0.3;
    let stroke = f.stroke().expect("a wave");
    assert!((stroke * flap_height_per_stroke(kd, 0.0) / 0.04 - 1.0).abs() < 1e-12);
    assert!((stroke - 0.0626).abs() < 1e-4, "stroke {stroke}");
    assert!((f.angle() - 0.104).abs() < 1e-3, "angle {}", f.angle());
    assert!((f.arm - 0.1f64.hypot(0.5)).abs() < 1e-12, "arm {}", f.arm);
    assert_eq!((f.period, f.ramp), (1.1, 2.2));
}

/// Keys of other kinds, a missing hinge, `angle` with `wave_height`, a hinge at the still-water
/// level, and the flap's keys on a piston are errors at their keys; `angle` alone is a flap.
#[test]
fn bad_flap_keys_are_reported_at_their_keys() {
    let text = std::fs::read_to_string(SCENE).expect("shipped scene");
    let key = "solid[1].motion";
    let p = problems(parse(&edit(
        &text,
        "ramp = 2.2 }",
        "ramp = 2.2, direction = [1.0, 0.0] }",
    )));
    assert!(
        with_key(&p, &format!("{key}.direction"))
            .reason
            .contains("not a key")
    );
    let p = problems(parse(&edit(&text, "hinge = [0.0, 0.0], ", "")));
    assert!(with_key(&p, &format!("{key}.hinge")).reason.contains("required"));
    let p = problems(parse(&edit(&text, "ramp = 2.2 }", "ramp = 2.2, angle = 0.1 }")));
    assert!(with_key(&p, &format!("{key}.angle")).reason.contains("not both"));
    let p = problems(parse(&edit(&text, "hinge_height = 0.0", "hinge_height = 0.3")));
    assert!(
        with_key(&p, &format!("{key}.hinge_height"))
            .reason
            .contains("below")
    );
    let angle = edit(
        &text,
        "wave_height = 0.04, period = 1.1, depth = 0.3, hinge_height = 0.0,",
        "angle = 0.05, period = 1.1,",
    );
    let scene = parse(&angle).expect("an angle alone is a flap");
    let Some(Motion::Flap(f)) = &scene.solids[1].motion else {
        panic!("a flap")
    };
    assert_eq!(f.angle(), 0.05);
    let piston = std::fs::read_to_string("scenes/wave_flume_2d.toml").expect("shipped scene");
    let p = problems(parse(&edit(
        &piston,
        "ramp = 2.2 }",
        "ramp = 2.2, hinge = [0.0, 0.0] }",
    )));
    assert!(with_key(&p, "solid[1].motion.hinge").reason.contains("not a key"));
}

/// A hinge height that puts the bed outside the domain (`hinge_height = -1e6`), and a wave
/// shorter than ten particle spacings, are errors at their keys.
#[test]
fn flap_values_beyond_the_flume_are_refused_at_their_keys() {
    let text = std::fs::read_to_string(SCENE).expect("shipped scene");
    let p = problems(parse(&edit(&text, "hinge_height = 0.0", "hinge_height = -1e6")));
    assert!(
        with_key(&p, "solid[1].motion.hinge_height")
            .reason
            .contains("puts the bed at")
    );
    let p = problems(parse(&edit(&text, "period = 1.1,", "period = 1e-9,")));
    assert!(
        with_key(&p, "solid[1].motion.period")
            .reason
            .contains("particle spacings")
    );
}

/// A checkpoint taken while the flap swings (no ramp: full speed from the first step; a coarse
/// 0.04 m lattice) restarts bit for bit: 40 steps straight against 20 + checkpoint + restore
/// into a fresh simulation + 20. The flap's turn is recomputed from the time, so nothing of it
/// is stored.
#[test]
fn restart_while_the_flap_swings_is_bit_identical() {
    let sets = [
        "solid.1.motion.ramp=0".to_string(),
        "particles.spacing=0.04".to_string(),
    ];
    let scene = load_scene(Path::new(SCENE), &sets).expect("scene");
    let build = || simulation_from_scene::<2>(&scene).expect("builds");
    let run = |sim: &mut sph::solver::Simulation<2>, n: usize| {
        for _ in 0..n {
            sim.step(f64::INFINITY).expect("step");
        }
    };
    let mut straight = build();
    run(&mut straight, 40);
    let mut first = build();
    run(&mut first, 20);
    let checkpoint = first.checkpoint(serde_json::Value::Null).expect("state");
    let mut resumed = build();
    resumed.restore(checkpoint).expect("same scene");
    run(&mut resumed, 20);
    assert_eq!(straight.clock(), resumed.clock());
    assert_eq!(straight.solid_forces(), resumed.solid_forces());
    let bits = |s: &sph::solver::Simulation<2>| -> Vec<u32> {
        let f = &s.fields;
        f.position
            .iter()
            .chain(&f.velocity)
            .flat_map(|x| x.iter().map(|c| c.to_bits()))
            .chain(f.density.iter().chain(&f.pressure).map(|c| c.to_bits()))
            .chain(f.id.iter().copied())
            .collect()
    };
    assert!(bits(&straight) == bits(&resumed), "the restarted run differs");
    let k = straight.solid_kinematics()[1];
    let top = straight
        .solid_reference()
        .position
        .iter()
        .map(|x| k.position(x) - x)
        .fold(0.0f32, |m, d| m.max(d.norm()));
    assert!(top > 1e-3, "the flap turned: its top moved {top} m");
}
