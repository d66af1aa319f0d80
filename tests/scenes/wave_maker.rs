//! The wave flume's scene keys: a solid's `motion` of kind `"piston"` (its stroke from
//! first-order wave-maker theory) and the `[damping_zone]` table, each resolved and each bad
//! value reported at its key.

use crate::common::scene::{edit, parse, problems, with_key};
use sph::physics::waves::piston_height_per_stroke;
use sph::scene::{DampingZoneSpec, Motion, load_scene};
use std::path::Path;

fn flume() -> String {
    std::fs::read_to_string("scenes/wave_flume_2d.toml").expect("shipped scene")
}

const PISTON: &str = r#"motion = { kind = "piston", wave_height = 0.04, period = 1.1, depth = 0.3, direction = [1.0, 0.0], ramp = 2.2 }"#;

/// The shipped flume's piston resolves to a sway of half the stroke Biésel's function gives
/// (to f64 rounding), along +x; its zone to the table's values.
#[test]
fn piston_resolves_to_the_stroke_of_wave_maker_theory() {
    let scene = load_scene(Path::new("scenes/wave_flume_2d.toml"), &[]).expect("shipped scene");
    let Some(Motion::Piston(p)) = scene.solids[1].motion.clone() else {
        panic!("a piston: {:?}", scene.solids[1].motion)
    };
    assert_eq!(
        (p.wave_height, p.period, p.depth, p.gravity),
        (0.04, 1.1, 0.3, 9.81)
    );
    let kd = p.wavenumber() * p.depth;
    // Dean & Dalrymple's numbers for this wave: kd = 1.198, H/S = 1.157 (by hand).
    assert!((kd - 1.198).abs() < 1e-3, "kd {kd}");
    let sway = Motion::Piston(p.clone()).sway().expect("a sine");
    let stroke = 2.0 * sway.amplitude[0];
    assert!((stroke * piston_height_per_stroke(kd) / 0.04 - 1.0).abs() < 1e-12);
    assert!((stroke - 0.0346).abs() < 1e-4, "stroke {stroke}");
    assert_eq!(sway.amplitude[1], 0.0);
    assert_eq!((sway.period, sway.ramp), (1.1, 2.2));
    assert_eq!(
        scene.damping_zone,
        Some(DampingZoneSpec {
            start: vec![3.0, 0.0],
            end: vec![5.0, 0.0],
            strength: 10.0
        })
    );
}

/// A sway's keys keep working without `kind`; keys of the other kind, missing keys, a zero
/// direction and a piston without gravity are errors at their keys.
#[test]
fn bad_piston_keys_are_reported_at_their_keys() {
    let text = flume();
    let mixed = edit(&text, "ramp = 2.2 }", "ramp = 2.2, amplitude = [0.01, 0.0] }");
    let p = with_key(&problems(parse(&mixed)), "solid[1].motion.amplitude").clone();
    assert!(
        p.reason.contains("not a key of motion.kind = \"piston\""),
        "{p:?}"
    );
    let missing = edit(&text, "wave_height = 0.04, ", "");
    let p = with_key(&problems(parse(&missing)), "solid[1].motion.wave_height").clone();
    assert!(p.reason.contains("required"), "{p:?}");
    let zero = edit(&text, "direction = [1.0, 0.0]", "direction = [0.0, 0.0]");
    with_key(&problems(parse(&zero)), "solid[1].motion.direction");
    let negative = edit(&text, "depth = 0.3,", "depth = -0.3,");
    with_key(&problems(parse(&negative)), "solid[1].motion.depth");
    let sway_with_depth = edit(
        &text,
        PISTON,
        "motion = { amplitude = [0.01, 0.0], period = 1.1, depth = 0.3 }",
    );
    let p = with_key(&problems(parse(&sway_with_depth)), "solid[1].motion.depth").clone();
    assert!(p.reason.contains("\"sway\""), "{p:?}");
    let sway = edit(
        &text,
        PISTON,
        "motion = { amplitude = [0.01, 0.0], period = 1.1 }",
    );
    let scene = parse(&sway).expect("a sway without kind");
    assert!(matches!(scene.solids[1].motion, Some(Motion::Sway(_))));
    let weightless = edit(
        &edit(&text, "effects = [\"gravity\", ", "effects = ["),
        "gravity = [0.0, -9.81]\n",
        "",
    );
    let weightless = weightless.replace("initial_state = \"hydrostatic\"", "");
    let p = with_key(&problems(parse(&weightless)), "solid[1].motion.kind").clone();
    assert!(p.reason.contains("needs gravity"), "{p:?}");
}

/// Values the flume cannot hold are refused at the key that sets them, before any computation,
/// with numbers that say why: a wave shorter than ten particle spacings (a period of 1e-9 s or
/// 0.12 s), a depth deeper than the domain is high, and a period so long that the stroke leaves
/// the domain (finite numbers, not `inf`/`NaN`).
#[test]
fn piston_values_beyond_the_flume_are_refused_at_their_keys() {
    let text = flume();
    for period in ["1e-9", "0.12"] {
        let short = edit(&text, "period = 1.1,", &format!("period = {period},"));
        let p = with_key(&problems(parse(&short)), "solid[1].motion.period").clone();
        assert!(
            p.reason.contains("shorter than 10 particle spacings") && p.reason.contains("particles.spacing"),
            "{p:?}"
        );
    }
    let deep = edit(&text, "depth = 0.3,", "depth = 1e6,");
    let p = with_key(&problems(parse(&deep)), "solid[1].motion.depth").clone();
    assert!(p.reason.contains("more than the domain is high"), "{p:?}");
    let long = edit(&text, "period = 1.1,", "period = 1e30,");
    let p = with_key(&problems(parse(&long)), "solid[1].motion.wave_height").clone();
    assert!(
        p.reason.contains("the stroke") && !p.reason.contains("inf") && !p.reason.contains("NaN"),
        "{p:?}"
    );
}

/// `[damping_zone]`: `strength` defaults to DualSPHysics' 10 1/s; equal ends, a wrong length
/// and a non-positive strength are errors at their keys; an unknown key is refused.
#[test]
fn damping_zone_keys_are_checked() {
    let text = flume();
    let default = edit(&text, "strength = 10.0 ", "");
    let scene = parse(&default).expect("default strength");
    assert_eq!(
        scene.damping_zone.map(|z| z.strength),
        Some(DampingZoneSpec::DEFAULT_STRENGTH)
    );
    let same = edit(&text, "end = [5.0, 0.0]", "end = [3.0, 0.0]");
    with_key(&problems(parse(&same)), "damping_zone.end");
    let short = edit(&text, "end = [5.0, 0.0]", "end = [5.0]");
    with_key(&problems(parse(&short)), "damping_zone.end");
    let weak = edit(&text, "strength = 10.0", "strength = 0.0");
    with_key(&problems(parse(&weak)), "damping_zone.strength");
    let unknown = edit(&text, "strength = 10.0", "strength = 10.0\nwidth = 1.0");
    assert!(parse(&unknown).is_err(), "unknown key in [damping_zone]");
}

/// A piston driven by a displacement series: the flume with `kind = "series"` and a CSV of the
/// piston's own sine (0.0173 m, T = 1.1 s, every 10 ms, no ramp) moves as the sine does, to the
/// spline's interpolation error (1e-4 of the amplitude here); a missing file, a device and a bad
/// line are errors at `motion.file` naming the file.
#[test]
fn a_series_piston_follows_its_samples() {
    let dir = crate::common::scratch_dir("wave_maker_series");
    let (a, w) = (0.0173, std::f64::consts::TAU / 1.1);
    let mut csv = String::from("t_s,x_m\n");
    for i in 0..=1000 {
        let t = f64::from(i) * 0.01;
        csv += &format!("{t},{}\n", a * (w * t).sin());
    }
    std::fs::write(dir.join("stroke.csv"), csv).expect("writable");
    let series = r#"motion = { kind = "series", file = "stroke.csv", direction = [2.0, 0.0] }"#;
    let text = edit(&flume(), PISTON, series);
    std::fs::write(dir.join("flume.toml"), &text).expect("writable");
    let scene = load_scene(&dir.join("flume.toml"), &[]).expect("a series piston");
    let motion = scene.solids[1].motion.clone().expect("moves");
    assert!(matches!(motion, Motion::Series(_)), "{motion:?}");
    for i in 1..200 {
        let t = 0.5 + f64::from(i) * 0.037;
        let k = motion.kinematics::<2>(t);
        let want = a * (w * t).sin();
        assert!(
            (f64::from(k.displacement[0]) - want).abs() < 1e-4 * a + 1e-8,
            "d at {t}"
        );
        assert!(
            (f64::from(k.velocity[0]) - a * w * (w * t).cos()).abs() < 1e-3 * a * w,
            "d' at {t}"
        );
        assert_eq!(k.displacement[1], 0.0);
    }
    let reach = motion.reach();
    assert!(reach[0] >= a && reach[0] < 1.02 * a, "{reach:?}");
    let missing = text.replace("stroke.csv", "nowhere.csv");
    std::fs::write(dir.join("missing.toml"), &missing).expect("writable");
    let e = load_scene(&dir.join("missing.toml"), &[]).expect_err("no file");
    let p = with_key(e.problems(), "solid[1].motion.file").clone();
    assert!(p.reason.contains("nowhere.csv"), "{p:?}");
    // Only a regular file is read: a link to /dev/zero would never end.
    #[cfg(unix)]
    {
        let _ = std::fs::remove_file(dir.join("zero.csv"));
        std::os::unix::fs::symlink("/dev/zero", dir.join("zero.csv")).expect("a link");
        let zero = text.replace("stroke.csv", "zero.csv");
        std::fs::write(dir.join("zero.toml"), &zero).expect("writable");
        let e = load_scene(&dir.join("zero.toml"), &[]).expect_err("a device");
        let p = with_key(e.problems(), "solid[1].motion.file").clone();
        assert!(
            p.reason
                .contains("zero.csv is a character device, not a regular file"),
            "{p:?}"
        );
    }
    std::fs::write(dir.join("bad.csv"), "t_s,x_m\n0,0\n0.1\n").expect("writable");
    let bad = text.replace("stroke.csv", "bad.csv");
    std::fs::write(dir.join("bad.toml"), &bad).expect("writable");
    let e = load_scene(&dir.join("bad.toml"), &[]).expect_err("bad line");
    let p = with_key(e.problems(), "solid[1].motion.file").clone();
    assert!(
        p.reason.contains("bad.csv") && p.reason.contains("line 3"),
        "{p:?}"
    );
    let timed = text.replace(
        "direction = [2.0, 0.0] }",
        "direction = [2.0, 0.0], period = 1.0 }",
    );
    let p = with_key(&problems(parse(&timed)), "solid[1].motion.period").clone();
    assert!(p.reason.contains("\"series\""), "{p:?}");
}
