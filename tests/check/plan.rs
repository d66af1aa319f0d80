//! `sph plan SCENE` (issue 7): on every shipped scene it prints the plan, or, for the scenes whose
//! fixed step is refused on purpose (`scenes/hard/large_dt_*.toml`), the one-line validation
//! error and a non-zero exit; and the plan shows exactly the effects the scene asks for.

use crate::common::shipped_scenes;
use crate::common::tolerance::PRINTED_4E;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `sph plan` on `scene` with `--set` overrides.
fn plan(scene: &Path, sets: &[&str]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_sph"));
    cmd.arg("plan").arg(scene);
    for s in sets {
        cmd.arg("--set").arg(s);
    }
    cmd.output().expect("sph runs")
}

/// A shipped scene by its path under the crate.
fn shipped(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// The printed plan's stage lines (`  N. name  equation  description`).
fn stage_names(stdout: &str) -> Vec<String> {
    stdout
        .lines()
        .filter_map(|l| {
            let (number, rest) = l.trim_start().split_once(". ")?;
            number.parse::<u32>().ok()?;
            rest.split_whitespace().next().map(String::from)
        })
        .collect()
}

#[test]
fn plan_runs_on_every_shipped_scene_and_refuses_the_large_steps_in_one_line() {
    let scenes = shipped_scenes();
    assert!(scenes.len() >= 25, "found {} scenes", scenes.len());
    let mut refused = Vec::new();
    for scene in &scenes {
        let out = plan(scene, &[]);
        let (stdout, stderr) = (
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr),
        );
        let name = scene.file_name().expect("file").to_string_lossy().into_owned();
        if name.starts_with("large_dt_") {
            // Their fixed step is the largest accepted, h / C; ten times cfl h / C is refused.
            let out = plan(scene, &["solver.dt=0.004"]);
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert!(!out.status.success(), "{name}: accepted");
            let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
            assert_eq!(lines.len(), 1, "{name}: {stderr}");
            assert!(
                lines[0].contains("solver.dt") && lines[0].contains("h / C"),
                "{name}: {stderr}"
            );
            refused.push(name.clone());
        }
        assert!(out.status.success(), "{name}: {stderr}");
        let names = stage_names(&stdout);
        for expected in ["sort_by_cell", "density", "forces", "time_step"] {
            // With the `density_diffusion` effect the continuity equation's rate takes the
            // summation's place.
            assert!(
                names
                    .iter()
                    .any(|n| n == expected || (expected == "density" && n == "density_rate")),
                "{name}: no {expected} in {names:?}"
            );
        }
        // Every stage line names an equation or source, and every stage its fields.
        assert!(
            stdout.contains("(18)") && stdout.contains("(15)"),
            "{name}: {stdout}"
        );
        let fields = stdout.lines().filter(|l| l.starts_with("      reads ")).count();
        assert_eq!(fields, names.len(), "{name}: {stdout}");
    }
    assert_eq!(refused, ["large_dt_2d.toml", "large_dt_3d.toml"]);
}

#[test]
fn wcsph_without_viscosity_has_no_viscosity_line() {
    // `hydrostatic_2d` without its viscosity: the effect and its key removed (a key given without
    // its effect is refused, and `--set` cannot remove a key), written to a temporary file.
    let scene = shipped("scenes/hydrostatic_2d.toml");
    let text = std::fs::read_to_string(&scene).expect("scene");
    let inviscid: String = text
        .lines()
        .filter(|l| !l.starts_with("viscosity ="))
        .map(|l| {
            l.replace(
                r#"effects = ["gravity", "viscosity"]"#,
                r#"effects = ["gravity"]"#,
            ) + "\n"
        })
        .collect();
    let dir = std::env::temp_dir().join(format!("sph_plan_test_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("inviscid.toml");
    std::fs::write(&path, inviscid).expect("write scene");
    let out = plan(&path, &[]);
    let _ = std::fs::remove_dir_all(&dir);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(!stdout.contains("(17)"), "{stdout}");
    assert!(!stdout.contains("viscosity mu"), "{stdout}");
    assert!(
        !stdout.contains("wall_velocity"),
        "no viscosity, no no-slip walls: {stdout}"
    );
    let forces = stdout
        .lines()
        .find(|l| l.contains(". forces "))
        .expect("forces line");
    assert!(!forces.contains("viscosity"), "{forces}");
    assert!(stdout.contains("(15): (16), (6)"), "{stdout}");
    assert!(stage_names(&stdout).contains(&"equation_of_state".to_string()));
    // The shipped scene, with viscosity, has it.
    let viscous = plan(&scene, &[]);
    assert!(String::from_utf8_lossy(&viscous.stdout).contains("(15): (16), (17), (6)"));
}

/// The stage's reads line (the line after its stage line).
fn reads_of(stdout: &str, stage: &str) -> String {
    let lines: Vec<&str> = stdout.lines().collect();
    let at = lines
        .iter()
        .position(|l| l.contains(&format!(". {stage} ")))
        .unwrap_or_else(|| panic!("no {stage} stage: {stdout}"));
    lines[at + 1].to_string()
}

#[test]
fn no_slip_walls_show_with_viscosity_and_solids() {
    // [A12] eqs. (22)-(23): the wall_velocity stage between the wall pressure and the forces,
    // writing the field that (17) in the forces stage and its reaction on the solids read.
    let out = plan(&shipped("scenes/poiseuille_2d.toml"), &[]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let names = stage_names(&stdout);
    let at = |n: &str| names.iter().position(|x| x == n);
    let wall = at("wall_velocity").unwrap_or_else(|| panic!("no wall_velocity: {names:?}"));
    assert!(
        at("wall_pressure") < Some(wall) && Some(wall) < at("forces"),
        "{names:?}"
    );
    assert!(stdout.contains("[A12] (22)-(23)"), "{stdout}");
    assert!(
        reads_of(&stdout, "wall_velocity").contains("writes wall_velocity"),
        "{stdout}"
    );
    for reader in ["forces", "solid_forces"] {
        let reads = reads_of(&stdout, reader);
        let read = reads.split(" -> ").next().unwrap_or_default();
        assert!(read.contains("wall_velocity"), "{reader}: {reads}");
    }
}

#[test]
fn corrected_scene_shows_the_correction_and_no_equation_of_state() {
    let out = plan(&shipped("scenes/dam_break_2d.toml"), &[]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    let names = stage_names(&stdout);
    assert!(!names.contains(&"equation_of_state".to_string()), "{names:?}");
    assert_eq!(
        names.last().map(String::as_str),
        Some("correct_positions"),
        "{names:?}"
    );
    assert!(
        stdout.contains("(23)-(24)") && stdout.contains("(24), note 6"),
        "{stdout}"
    );
    for sub in [
        "- density",
        "- correction_pressure",
        "- correct_positions",
        "- keep_out",
    ] {
        assert!(stdout.contains(sub), "no {sub}: {stdout}");
    }
    assert!(stdout.contains("settle"), "{stdout}");
    // And the wcsph variant of the same scene has (19) and no correction.
    let wcsph = plan(&shipped("scenes/dam_break_2d.toml"), &["solver.kind=wcsph"]);
    let names = stage_names(&String::from_utf8_lossy(&wcsph.stdout));
    assert!(names.contains(&"equation_of_state".to_string()));
    assert!(!names.contains(&"correct_positions".to_string()));
}

#[test]
fn moving_walls_show_move_solids() {
    let out = plan(&shipped("scenes/hard/sloshing_2d.toml"), &[]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    let names = stage_names(&stdout);
    assert_eq!(
        names.first().map(String::as_str),
        Some("move_solids"),
        "{names:?}"
    );
    assert!(stdout.contains("(moving)"), "{stdout}");
    // A corrected run places them again before each correction.
    let corrected = plan(
        &shipped("scenes/hard/sloshing_2d.toml"),
        &["solver.kind=corrected"],
    );
    let names = stage_names(&String::from_utf8_lossy(&corrected.stdout));
    assert_eq!(
        names.iter().filter(|n| *n == "move_solids").count(),
        2,
        "{names:?}"
    );
    // Fixed walls: no such stage.
    let fixed = plan(&shipped("scenes/hydrostatic_2d.toml"), &[]);
    assert!(!stage_names(&String::from_utf8_lossy(&fixed.stdout)).contains(&"move_solids".to_string()));
}

#[test]
fn rotating_frame_shows_in_the_forces_stage_only_when_asked_for() {
    let out = plan(&shipped("scenes/rotating_tank_2d.toml"), &[]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("rotating_frame Omega = (0, 7, 0) rad/s about the axis through (0, 0) m"),
        "{stdout}"
    );
    let forces = stdout
        .lines()
        .find(|l| l.contains(". forces "))
        .expect("forces line");
    assert!(forces.contains("[B67] 3.2"), "{forces}");
    assert!(forces.contains("Coriolis and centrifugal"), "{forces}");
    // A scene without the effect has no such term.
    let plain = plan(&shipped("scenes/hydrostatic_2d.toml"), &[]);
    let plain = String::from_utf8_lossy(&plain.stdout);
    assert!(!plain.contains("[B67]") && !plain.contains("Coriolis"), "{plain}");
}

#[test]
fn surface_tension_shows_its_two_stages_only_when_asked_for() {
    // The printed constant of each model is the one the run calibrates.
    let printed = |stdout: &str, key: &str| -> f64 {
        stdout
            .split(key)
            .nth(1)
            .and_then(|r| r.split_whitespace().next())
            .and_then(|g| g.parse().ok())
            .unwrap_or_else(|| panic!("{key} printed in {stdout}"))
    };
    let akinci = "fluid.surface_tension_model=\"akinci\"";
    let out = plan(&shipped("scenes/droplet_2d.toml"), &[akinci]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        stdout.contains("surface_tension sigma = 0.072 N/m, model akinci"),
        "{stdout}"
    );
    let scene = sph::scene::load_scene(&shipped("scenes/droplet_2d.toml"), &[akinci.into()]).expect("valid");
    let sim = sph::run::simulation_from_scene::<2>(&scene).expect("builds");
    let (gamma, run_gamma) = (
        printed(&stdout, "gamma = "),
        f64::from(sim.surface_tension_gamma()),
    );
    assert!(
        (gamma / run_gamma - 1.0).abs() < PRINTED_4E,
        "plan {gamma} vs run {run_gamma}"
    );
    let line = |stdout: &str, name: &str| {
        stdout
            .lines()
            .find(|l| l.contains(&format!(". {name} ")))
            .unwrap_or_else(|| panic!("{name} line in {stdout}"))
            .to_string()
    };
    assert!(
        line(&stdout, "surface_normals").contains("[AAT13] (3)"),
        "{stdout}"
    );
    assert!(
        line(&stdout, "surface_tension").contains("[AAT13] (1)-(5)"),
        "{stdout}"
    );
    // The shipped scene uses the default model, the surface stress.
    let out = plan(&shipped("scenes/droplet_2d.toml"), &[]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        stdout.contains("surface_tension sigma = 0.072 N/m, model surface_stress"),
        "{stdout}"
    );
    let scene = sph::scene::load_scene(&shipped("scenes/droplet_2d.toml"), &[]).expect("valid");
    let sim = sph::run::simulation_from_scene::<2>(&scene).expect("builds");
    let (stress, run_stress) = (
        printed(&stdout, "sigma' = "),
        f64::from(sim.surface_stress_sigma()),
    );
    assert!(
        (stress / run_stress - 1.0).abs() < PRINTED_4E,
        "plan {stress} vs run {run_stress}"
    );
    assert_eq!(sim.surface_tension_gamma(), 0.0);
    let names = stage_names(&stdout);
    let forces = names.iter().position(|n| n == "forces").expect("a force stage");
    assert_eq!(names[forces + 1], "surface_normals", "{stdout}");
    assert_eq!(names[forces + 2], "surface_tension", "{stdout}");
    assert!(
        line(&stdout, "surface_normals").contains("[AAT13] (3), m/rho0"),
        "{stdout}"
    );
    assert!(
        line(&stdout, "surface_tension").contains("[LNSZZ94], [M00a]"),
        "{stdout}"
    );
    // The normals are a field of their own, written by one stage and read by the other.
    assert!(stdout.contains("normal"), "{stdout}");
    // A scene without the effect has neither stage.
    let plain = plan(&shipped("scenes/hydrostatic_2d.toml"), &[]);
    let plain = String::from_utf8_lossy(&plain.stdout);
    assert!(
        !plain.contains("surface_normals") && !plain.contains("[AAT13]"),
        "{plain}"
    );
}

/// The line after stage `name`'s line that starts with `prefix` (trimmed), before the next stage.
fn stage_detail(stdout: &str, name: &str, prefix: &str) -> Option<String> {
    let mut lines = stdout.lines().skip_while(|l| !l.contains(&format!(". {name} ")));
    lines.next()?;
    lines
        .take_while(|l| {
            l.trim_start()
                .split_once(". ")
                .is_none_or(|(n, _)| n.parse::<u32>().is_err())
        })
        .map(str::trim)
        .find(|l| l.starts_with(prefix))
        .map(String::from)
}

#[test]
fn multiphase_shows_the_variants_and_their_rest_density_reads() {
    for (scene, sets) in [
        ("scenes/two_layer_2d.toml", vec![]),
        ("scenes/two_layer_2d.toml", vec!["solver.kind=corrected"]),
        ("scenes/buoyant_blob_2d.toml", vec![]),
    ] {
        let out = plan(&shipped(scene), &sets);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(stdout.contains("multiphase rest densities"), "{stdout}");
        let density = stage_detail(&stdout, "density", "multiphase:").expect("density variant");
        assert!(density.contains("[HA06]"), "{density}");
        let forces = stage_detail(&stdout, "forces", "multiphase:").expect("forces variant");
        assert!(forces.contains("volume form"), "{forces}");
        let reads = stage_detail(&stdout, "time_step", "reads").expect("time_step reads");
        assert!(reads.contains("rest_density"), "{reads}");
        if sets.is_empty() {
            let eos = stage_detail(&stdout, "equation_of_state", "reads").expect("eos reads");
            assert!(eos.contains("rest_density"), "{eos}");
        } else {
            let correction = stage_detail(&stdout, "correct_positions", "reads").expect("correction reads");
            assert!(correction.contains("rest_density"), "{correction}");
            assert!(stdout.contains("- correction_pressure"), "{stdout}");
        }
    }
    // Without the effect: no variant, no rest_density.
    let plain = plan(&shipped("scenes/hydrostatic_2d.toml"), &[]);
    let plain = String::from_utf8_lossy(&plain.stdout);
    assert!(
        !plain.contains("multiphase") && !plain.contains("rest_density"),
        "{plain}"
    );
}

/// A periodic scene (`[periodic]`, `sph::periodic`): `sph plan` ends with `wrap_positions` and
/// `sph check` names the periodic axis with its period; the walled scene has neither.
#[test]
fn plan_and_check_show_the_periodic_axes() {
    let scene = shipped("tests/scenes/poiseuille_periodic_2d.toml");
    let out = plan(&scene, &[]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let names = stage_names(&String::from_utf8_lossy(&out.stdout));
    assert_eq!(
        names.last().map(String::as_str),
        Some("wrap_positions"),
        "{names:?}"
    );
    let walled = stage_names(&String::from_utf8_lossy(
        &plan(&shipped("scenes/poiseuille_2d.toml"), &[]).stdout,
    ));
    assert!(!walled.iter().any(|n| n == "wrap_positions"), "{walled:?}");
    let check = Command::new(env!("CARGO_BIN_EXE_sph"))
        .arg("check")
        .arg(&scene)
        .output()
        .expect("sph runs");
    let stdout = String::from_utf8_lossy(&check.stdout);
    assert!(check.status.success(), "{stdout}");
    assert!(stdout.contains("periodic         x (period 0.3 m)"), "{stdout}");
}
