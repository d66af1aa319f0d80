//! Scene texts in code: parsing with a fake file name, the problems of an expected error, the
//! line a problem points at, one-place edits, the check the scene fuzzers apply to every
//! parse, and the scenes several test binaries start from ([`Tank2d`], [`unwalled_2d`]).

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

/// A 2D water column in a 1.6 × 0.8 m open container under gravity (domain
/// [-0.05, 1.65] × [-0.05, 1.0], h = 2 dx, ρ0 = 1000 kg/m³, c = 30 m/s): the scene the loader,
/// solver-key and probe tests edit. One fixture, so a change of the scene format is made once.
pub struct Tank2d<'a> {
    /// Lines before `dimension` (a `name`).
    pub head: &'a str,
    /// The `effects` array.
    pub effects: &'a str,
    /// Particle spacing [m].
    pub spacing: f64,
    /// `[fluid]` lines after `gravity`.
    pub fluid: &'a str,
    /// Width of the water column [m] (0.5 m high, from the origin).
    pub width: f64,
    /// Text after the tank's `[[solid]]` (further solids, starting with a blank line).
    pub solids: &'a str,
    /// The keys of `[solver]`.
    pub solver: &'a str,
    /// Text after `[solver]` (probes, starting with a blank line).
    pub tail: &'a str,
}

impl Default for Tank2d<'_> {
    fn default() -> Self {
        Self {
            head: "",
            effects: r#"["gravity"]"#,
            spacing: 0.02,
            fluid: "",
            width: 0.26,
            solids: "",
            solver: "kind = \"wcsph\"\nend_time = 1.0\n",
            tail: "",
        }
    }
}

impl Tank2d<'_> {
    /// The scene file's text.
    pub fn text(&self) -> String {
        let Self {
            head,
            effects,
            spacing,
            fluid,
            width,
            solids,
            solver,
            tail,
        } = self;
        format!(
            r#"{head}dimension = 2
effects = {effects}

[domain]
min = [-0.05, -0.05]
max = [1.65, 1.0]

[particles]
spacing = {spacing}
smoothing_ratio = 2.0

[fluid]
rho0 = 1000.0
sound_speed = 30.0
gravity = [0.0, -9.81]
{fluid}
[[fluid_box]]
min = [0.0, 0.0]
max = [{width}, 0.5]

[[solid]]
name = "tank"
shape = "container"
min = [0.0, 0.0]
max = [1.6, 0.8]
{solids}
[solver]
{solver}{tail}"#
        )
    }
}

/// [`Tank2d`] with a 0.1 × 0.3 m box `post` at x = 1 m and two probes, `front` (`front` is
/// its further keys) and `post_force` (the post's x force); `solver` is the keys of `[solver]`.
pub fn tank_2d_with_post(solver: &str, front: &str) -> String {
    Tank2d {
        solids: "\n[[solid]]\nname = \"post\"\nshape = \"box\"\nmin = [1.0, 0.0]\nmax = [1.1, 0.3]\n",
        solver,
        tail: &format!(
            "\n[[probe]]\nname = \"front\"\nkind = \"front\"\n{front}\n[[probe]]\nname = \"post_force\"\nkind = \"force\"\nsolid = \"post\"\naxis = \"x\"\n"
        ),
        ..Tank2d::default()
    }
    .text()
}

/// The problem with `key` of parsing `text`, checked to point at the first line holding
/// `needle` and to give a reason containing `reason` (`""`: any).
pub fn problem_at(text: &str, key: &str, needle: &str, reason: &str) -> Problem {
    located(&problems(parse(text)), text, key, needle, reason)
}

/// [`problem_at`], checked to be the only problem of `text`.
pub fn only_problem_at(text: &str, key: &str, needle: &str, reason: &str) -> Problem {
    let ps = problems(parse(text));
    assert_eq!(ps.len(), 1, "{ps:#?}");
    located(&ps, text, key, needle, reason)
}

/// The problem with `key` of parsing `text`, checked to give a reason containing `reason`.
pub fn problem_with(text: &str, key: &str, reason: &str) -> Problem {
    with_reason(&problems(parse(text)), key, reason)
}

fn with_reason(ps: &[Problem], key: &str, reason: &str) -> Problem {
    let p = with_key(ps, key);
    assert!(p.reason.contains(reason), "{key}: {}", p.reason);
    p.clone()
}

fn located(ps: &[Problem], text: &str, key: &str, needle: &str, reason: &str) -> Problem {
    let p = with_reason(ps, key, reason);
    assert_eq!(line(&p), line_of(text, needle, 0), "{key}: {p:?}");
    p
}
