//! The wave makers' `sea` key (`motion = { kind = "piston" | "flap", sea = { ... } }`): the
//! shipped focused flume resolves to its group, an irregular sea and a flap take the same
//! table, and each bad value is reported at its key.

use crate::common::scene::{edit, parse, problems, with_key};
use sph::boundary::sea_maker::{Paddle, SeaMaker};
use sph::physics::sea_state::Sea;
use sph::scene::{Motion, load_scene};
use std::path::Path;

const SCENE: &str = "scenes/wave_flume_focused_2d.toml";
const SEA: &str = r#"sea = { kind = "focused", amplitude = 0.03, focus_position = 1.5, focus_time = 8.0, peak_period = 1.1, gamma = 3.3, components = 128, f_max = 1.82 }"#;

fn focused_flume() -> String {
    std::fs::read_to_string(SCENE).expect("shipped scene")
}

fn sea_maker(motion: &Option<Motion>) -> SeaMaker {
    match motion {
        Some(Motion::Sea(s)) => s.clone(),
        other => panic!("a sea maker: {other:?}"),
    }
}

/// The shipped scene's piston carries the focused group with the band's defaults filled in
/// (f_min = 0.5/T_p), and its linear crest at the focus gauge at t_f is A (1e-12 relative).
#[test]
fn focused_flume_resolves_to_its_group() {
    let scene = load_scene(Path::new(SCENE), &[]).expect("shipped scene");
    let maker = sea_maker(&scene.solids[1].motion);
    assert_eq!(maker.kind_name(), "piston");
    let Sea::Focused {
        amplitude,
        focus_position,
        focus_time,
        band,
    } = &maker.sea
    else {
        panic!("focused: {:?}", maker.sea)
    };
    assert_eq!((*amplitude, *focus_position, *focus_time), (0.03, 1.5, 8.0));
    assert_eq!((band.components, band.gamma, band.f_max), (128, 3.3, 1.82));
    assert!((band.f_min - 0.5 / 1.1).abs() < 1e-15);
    assert_eq!((maker.depth, maker.gravity, maker.ramp), (0.3, 9.81, 1.0));
    let crest = maker.waves.elevation(1.5, 8.0);
    assert!((crest / 0.03 - 1.0).abs() < 1e-12, "{crest}");
    assert!(scene.probes.iter().any(|p| p.name == "focus"));
}

/// A JONSWAP sea on the same piston and on a flap: defaults (γ 3.3, 128 lines, 0.5 to 3 f_p),
/// the seed kept, the flap's arm set from its box; two loads give the same motion bit for bit.
#[test]
fn irregular_sea_drives_a_piston_and_a_flap() {
    let jonswap = r#"sea = { kind = "jonswap", significant_height = 0.03, peak_period = 1.1, seed = 42 }"#;
    let text = edit(&focused_flume(), SEA, jonswap);
    let maker = sea_maker(&parse(&text).expect("a jonswap piston").solids[1].motion);
    let Sea::Irregular { seed, band, .. } = &maker.sea else {
        panic!("irregular")
    };
    assert_eq!((*seed, band.components, band.gamma), (42, 128, 3.3));
    assert!((band.f_max - 3.0 / 1.1).abs() < 1e-15);
    let again = sea_maker(&parse(&text).expect("again").solids[1].motion);
    let k = |m: &SeaMaker, t: f64| m.kinematics::<2>(t);
    for t in [0.5, 3.3, 7.1] {
        assert_eq!(k(&maker, t), k(&again, t));
    }
    let other = edit(&text, "seed = 42", "seed = 43");
    let other = sea_maker(&parse(&other).expect("another seed").solids[1].motion);
    assert_ne!(k(&maker, 3.3), k(&other, 3.3));

    let flap = edit(
        &edit(&text, "kind = \"piston\"", "kind = \"flap\""),
        "direction = [1.0, 0.0], ",
        "hinge = [0.0, 0.0], hinge_height = 0.0, ",
    );
    let flap = flap.replace("min = [-0.1, 0.0]", "min = [-0.05, 0.0]");
    let maker = sea_maker(&parse(&flap).expect("a jonswap flap").solids[1].motion);
    assert_eq!(maker.kind_name(), "flap");
    let Paddle::Flap { arm, .. } = maker.paddle else {
        panic!("a flap")
    };
    assert!((arm - 0.05f64.hypot(0.5)).abs() < 1e-12, "arm {arm}");
}

/// Bad values, each at its key: a negative H_s, γ < 1, too few components, a band without
/// the peak, a missing seed, a focus beyond the domain or too early for the group, the regular
/// wave's keys beside `sea`, and `sea` on a sway.
#[test]
fn bad_sea_keys_are_reported_at_their_keys() {
    let text = focused_flume();
    let at = |from: &str, to: &str, key: &str, words: &str| {
        let bad = edit(&text, from, to);
        let p = with_key(&problems(parse(&bad)), key).clone();
        assert!(p.reason.contains(words), "{key}: {p:?}");
    };
    let sea = "solid[1].motion.sea";
    let jonswap = r#"sea = { kind = "jonswap", significant_height = -0.03, peak_period = 1.1, seed = 1 }"#;
    at(SEA, jonswap, &format!("{sea}.significant_height"), "> 0");
    at("gamma = 3.3", "gamma = 0.8", &format!("{sea}.gamma"), "[1, 7]");
    at(
        "components = 128",
        "components = 8",
        &format!("{sea}.components"),
        "[32, 1024]",
    );
    at(
        "f_max = 1.82",
        "f_max = 0.8",
        &format!("{sea}.f_max"),
        "peak frequency",
    );
    let unseeded = r#"sea = { kind = "jonswap", significant_height = 0.03, peak_period = 1.1 }"#;
    at(SEA, unseeded, &format!("{sea}.seed"), "required");
    at(
        "focus_position = 1.5",
        "focus_position = 6.0",
        &format!("{sea}.focus_position"),
        "beyond the domain",
    );
    at(
        "focus_time = 8.0",
        "focus_time = 1.5",
        &format!("{sea}.focus_time"),
        "group speed",
    );
    at(
        "amplitude = 0.03,",
        "amplitude = 0.03, seed = 3,",
        &format!("{sea}.seed"),
        "not a key of sea.kind = \"focused\"",
    );
    at(
        "depth = 0.3,",
        "depth = 0.3, wave_height = 0.04,",
        "solid[1].motion.wave_height",
        "with `sea`",
    );
    at(
        "depth = 0.3,",
        "period = 1.1,",
        "solid[1].motion.depth",
        "required",
    );
    let sway = r#"motion = { amplitude = [0.01, 0.0], period = 1.1, sea = { kind = "jonswap", significant_height = 0.03, peak_period = 1.1, seed = 1 } }"#;
    let motion_line = text
        .lines()
        .find(|l| l.starts_with("motion = "))
        .expect("the piston's motion");
    at(motion_line, sway, "solid[1].motion.sea", "\"sway\"");
    let unknown = edit(&text, "f_max = 1.82", "f_max = 1.82, spread = 2.0");
    assert!(parse(&unknown).is_err(), "unknown key in sea");
}
