//! Scene texts in code: parsing with a fake file name, the problems of an expected error, the
//! line a problem points at, one-place edits, and the check the scene fuzzers apply to every
//! parse. Used by the scene-loader tests (`tests/scenes/`).

use sph::scene::{Location, Problem, Scene, SceneError, count_particles, generate, parse_scene};

/// `text` parsed as the file `test.toml`, without overrides.
pub fn parse(text: &str) -> Result<Scene, SceneError> {
    parse_scene(text, "test.toml", &[])
}

/// `text` parsed as the file `test.toml` with the `--set` overrides `sets`.
pub fn parse_set(text: &str, sets: &[&str]) -> Result<Scene, SceneError> {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    parse_scene(text, "test.toml", &sets)
}

/// The problems of an expected error (panics on a scene, or on an error without problems).
pub fn problems(r: Result<Scene, SceneError>) -> Vec<Problem> {
    match r {
        Ok(s) => panic!("expected an error, got {s:#?}"),
        Err(e) => {
            assert!(!e.problems().is_empty(), "no problems in {e}");
            e.problems().to_vec()
        }
    }
}

/// The problem with `key` (panics with the full list if missing).
pub fn with_key<'a>(ps: &'a [Problem], key: &str) -> &'a Problem {
    ps.iter()
        .find(|p| p.key == key)
        .unwrap_or_else(|| panic!("no problem with key {key:?} in {ps:#?}"))
}

/// 1-based line of the `nth` (0-based) line of `text` containing `needle`.
pub fn line_of(text: &str, needle: &str, nth: usize) -> usize {
    text.lines()
        .enumerate()
        .filter(|(_, l)| l.contains(needle))
        .nth(nth)
        .map(|(i, _)| i + 1)
        .unwrap_or_else(|| panic!("{needle:?} not in text"))
}

/// The line a problem points at (panics if it has no line).
pub fn line(p: &Problem) -> usize {
    match p.location {
        Location::Line { line, .. } => line,
        ref other => panic!("expected a line location, got {other:?} for {p:?}"),
    }
}

/// `text` with exactly one occurrence of `from` replaced (panics unless it occurs once).
pub fn edit(text: &str, from: &str, to: &str) -> String {
    assert_eq!(text.matches(from).count(), 1, "{from:?} must occur once");
    text.replace(from, to)
}

/// Values that break a number, a type or a range, for the fuzzers' replacements.
pub const GARBAGE: [&str; 10] = [
    "nan",
    "-inf",
    "1e400",
    "\"x\"",
    "[",
    "",
    "-0",
    "1e-300",
    "99999999999999999999",
    "{}",
];

/// What every parse of fuzzed input must give: an error carrying at least one usable problem,
/// or a scene whose particles can be counted and, below 200,000 of them, generated.
pub fn check_result(r: Result<Scene, SceneError>) {
    match r {
        Ok(scene) => {
            if let Ok(c) = count_particles(&scene)
                && c.total < 200_000
            {
                if scene.dimension == 2 {
                    generate::<2>(&scene).unwrap();
                } else {
                    generate::<3>(&scene).unwrap();
                }
            }
        }
        Err(e) => {
            let _ = e.to_string();
            assert!(
                e.problems()
                    .iter()
                    .any(|p| !p.key.is_empty() || !p.reason.is_empty()),
                "{e:?}"
            );
        }
    }
}

/// A 2D scene without walls or effects in the unit square (spacing 0.02 m, h = 2 dx,
/// ρ0 = 1000 kg/m³, c = 50 m/s, `wcsph`), named `name`: `boxes` are the keys of its first
/// `[[fluid_box]]` (further tables may follow them), `solver` the keys of `[solver]` besides
/// its kind, and `interval` the output interval [s].
pub fn unwalled_2d(name: &str, boxes: &str, solver: &str, interval: f64) -> String {
    format!(
        r#"name = "{name}"
dimension = 2
effects = []

[domain]
min = [0.0, 0.0]
max = [1.0, 1.0]

[particles]
spacing = 0.02
smoothing_ratio = 2.0

[fluid]
rho0 = 1000.0
sound_speed = 50.0

[[fluid_box]]
{boxes}

[solver]
kind = "wcsph"
{solver}

[output]
interval = {interval}
"#
    )
}
