//! Bad input never panics: the scene parser and validator, fed random bytes, truncated and
//! mutated shipped scenes, and random `--set` overrides, return either a scene or an error that
//! names the file (and, from the TOML reader or the validator, the line or key at fault).

use proptest::prelude::*;
use sph::scene::generate::count_particles;
use sph::scene::{load_scene, parse_scene};
use std::path::Path;

const SHIPPED: [&str; 4] = [
    include_str!("../../scenes/dam_break_2d.toml"),
    include_str!("../../scenes/dam_break_column_3d.toml"),
    include_str!("../../scenes/hydrostatic_2d.toml"),
    include_str!("../../scenes/yeh_petroff_3d.toml"),
];

/// Values that break numbers, types and ranges.
const NASTY: [&str; 16] = [
    "-1",
    "0",
    "1e308",
    "-1e308",
    "nan",
    "inf",
    "-inf",
    "1e-30",
    "\"x\"",
    "[]",
    "[1.0]",
    "true",
    "99999999999999999999",
    "0.0",
    "[[0.0]]",
    "{}",
];

/// Keys of the scene schema that take values.
const KEYS: [&str; 14] = [
    "particles.spacing",
    "particles.smoothing_ratio",
    "fluid.rho0",
    "fluid.sound_speed",
    "fluid.viscosity",
    "fluid.gravity",
    "solver.kind",
    "solver.cfl",
    "solver.dt",
    "solver.delta",
    "solver.end_time",
    "domain.min",
    "fluid_box.0.max",
    "output.interval",
];

/// Whether `msg` names a location: `file:LINE` (the TOML reader, the validator) or a section or
/// key of the schema (checks across keys).
fn names_a_location(msg: &str, file: &str) -> bool {
    let with_line = msg
        .match_indices(&format!("{file}:"))
        .any(|(k, m)| msg[k + m.len()..].starts_with(|c: char| c.is_ascii_digit()));
    const SECTIONS: [&str; 12] = [
        "particles",
        "fluid",
        "solver",
        "domain",
        "solid",
        "fluid_box",
        "output",
        "probe",
        "effects",
        "dimension",
        "name",
        "TOML",
    ];
    with_line || SECTIONS.iter().any(|s| msg.contains(s))
}

/// Applies one of several mutations to `text` (always at a character boundary).
fn mutate(text: &str, kind: u8, at: usize, pick: usize, garbage: &str) -> String {
    let mut cut = at % (text.len() + 1);
    while !text.is_char_boundary(cut) {
        cut -= 1;
    }
    let lines: Vec<&str> = text.lines().collect();
    let line = pick % lines.len().max(1);
    match kind % 6 {
        0 => text[..cut].to_string(),
        1 => format!("{}{garbage}{}", &text[..cut], &text[cut..]),
        2 => lines
            .iter()
            .enumerate()
            .filter(|(k, _)| *k != line)
            .map(|(_, l)| *l)
            .collect::<Vec<_>>()
            .join("\n"),
        3 => {
            let mut v = lines.clone();
            v.insert(line, lines[line]);
            v.join("\n")
        }
        4 => {
            // Replace the value of one `key = value` line by a nasty one.
            let nasty = NASTY[pick % NASTY.len()];
            lines
                .iter()
                .enumerate()
                .map(|(k, l)| match l.split_once('=') {
                    Some((key, _)) if k == line => format!("{key}= {nasty}"),
                    _ => l.to_string(),
                })
                .collect::<Vec<_>>()
                .join("\n")
        }
        _ => text.replacen('.', garbage, 1),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn mutated_scenes_never_panic(
        which in 0usize..4,
        kind in any::<u8>(),
        at in any::<usize>(),
        pick in any::<usize>(),
        garbage in "[ -~\\n]{0,12}",
    ) {
        let text = mutate(SHIPPED[which], kind, at, pick, &garbage);
        match parse_scene(&text, "fuzz.toml", &[]) {
            Ok(scene) => {
                // A scene that validates can be counted without overflow or panic.
                let _ = count_particles(&scene);
            }
            Err(e) => {
                let msg = e.to_string();
                prop_assert!(msg.contains("fuzz.toml"), "error does not name the file: {}", msg);
                prop_assert!(names_a_location(&msg, "fuzz.toml"), "error names no line or key: {}", msg);
            }
        }
    }

    #[test]
    fn random_overrides_never_panic(
        which in 0usize..4,
        key in 0usize..KEYS.len(),
        value in 0usize..NASTY.len(),
    ) {
        let set = format!("{}={}", KEYS[key], NASTY[value]);
        if let Err(e) = parse_scene(SHIPPED[which], "fuzz.toml", std::slice::from_ref(&set)) {
            // The override may be valid on its own and break another entry (a huge spacing
            // makes a box thinner than one particle): the error names that entry instead.
            let msg = e.to_string();
            prop_assert!(msg.contains("fuzz.toml"), "error does not name the file: {}", msg);
            prop_assert!(names_a_location(&msg, "fuzz.toml"), "error names no line or key: {}", msg);
            for line in msg.lines() {
                prop_assert!(line.len() < 300, "a problem is not one readable line: {}", line);
                prop_assert!(names_a_location(line, "fuzz.toml"), "a problem names no line or key: {}", line);
            }
        }
    }

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
        let dir = std::env::temp_dir().join(format!("sph_fuzz_{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("random.toml");
        std::fs::write(&path, &bytes).expect("write");
        if let Err(e) = load_scene(&path, &[]) {
            let msg = e.to_string();
            prop_assert!(msg.contains("random.toml"), "error does not name the file: {}", msg);
        }
    }
}

#[test]
fn a_directory_and_a_missing_file_are_named() {
    for path in ["scenes", "scenes/no_such_scene.toml"] {
        let err = load_scene(Path::new(path), &[])
            .map(|_| ())
            .expect_err("not a scene");
        assert!(err.to_string().contains(path), "{err}");
    }
}
