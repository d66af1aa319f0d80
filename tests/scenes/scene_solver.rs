//! Integration tests of the scene keys for the solver choice (`[solver]` kind, integrator and
//! position-correction settings) and for `[[probe]]` tables: defaults, one problem per bad
//! value naming its key and line, `--set` overrides, and reference-path resolution.

use sph::model::GradientMoment;
use sph::solver::escape::EscapePolicy;
use std::path::{Path, PathBuf};

use sph::scene as sc;

use crate::common::scene::{
    GARBAGE, Tank2d, check_result, edit, line, line_of, only_problem_at, parse, parse_set, problem_at,
    problem_with, problems, with_key,
};
use proptest::prelude::*;
use sc::{Integrator, Location, ProbeKind, SolverKind, SolverSettings};
use std::sync::LazyLock;

/// The shared 2D tank with the `wcsph` solver and no probes.
static WCSPH: LazyLock<String> = LazyLock::new(|| Tank2d::default().text());

/// The same scene with the `corrected` solver, every solver key and two probes.
static CORRECTED: LazyLock<String> = LazyLock::new(|| {
    Tank2d {
        solver: "kind = \"corrected\"\nintegrator = \"symplectic_euler\"\ndelta = 1e-3\nmax_iterations = 50\nstrict = true\nrelaxation = 0.8\nwarm_start = true\nend_time = 1.0\n",
        tail: r#"
[[probe]]
name = "surge"
kind = "front"
axis = "x"
origin = 0.01

[probe.reference]
file = "data/martin_moyce.csv"
series = ["n2_a2.25", "n2_a1.125"]
length = 0.25
time_range = [0.5, 2.5]

[[probe]]
name = "height"
kind = "front"
axis = "y"
"#,
        ..Tank2d::default()
    }
    .text()
});

/// Edits `text`, expects exactly one problem, with `key`, on the line containing `needle`,
/// whose reason contains `reason`.
fn expect_one(text: &str, from: &str, to: &str, key: &str, needle: &str, reason: &str) {
    only_problem_at(&edit(text, from, to), key, needle, reason);
}

#[test]
fn wcsph_defaults() {
    let s = parse(&WCSPH).unwrap();
    assert_eq!(s.solver, SolverSettings::defaults(SolverKind::Wcsph));
    assert_eq!(
        s.solver,
        SolverSettings {
            kind: SolverKind::Wcsph,
            integrator: Integrator::SymplecticEuler,
            delta: 1e-4,
            max_iterations: 200,
            strict: false,
            relaxation: 0.5,
            warm_start: false,
            on_escape: EscapePolicy::Remove,
            gradient_moment: SolverSettings::default_gradient_moment(SolverKind::Wcsph),
        }
    );
    assert_eq!(s.cfl, 0.2);
    assert_eq!(s.dt, None);
    assert!(s.probes.is_empty());
}

#[test]
fn corrected_defaults() {
    let s = parse(&edit(&WCSPH, "kind = \"wcsph\"", "kind = \"corrected\"")).unwrap();
    assert_eq!(
        s.solver,
        SolverSettings {
            kind: SolverKind::Corrected,
            integrator: Integrator::Rk3,
            delta: 1e-4,
            max_iterations: 200,
            strict: false,
            relaxation: 0.5,
            warm_start: false,
            on_escape: EscapePolicy::Remove,
            gradient_moment: SolverSettings::default_gradient_moment(SolverKind::Corrected),
        }
    );
    assert_eq!(s.solver, SolverSettings::defaults(SolverKind::Corrected));
    assert_eq!(SolverKind::Corrected.name(), "corrected");
    assert_eq!(Integrator::Rk3.name(), "rk3");
    assert_eq!(Integrator::SymplecticEuler.name(), "symplectic_euler");
    assert_eq!(ProbeKind::Front.name(), "front");
}

#[test]
fn corrected_with_every_key_and_probes() {
    let s = parse(&CORRECTED).unwrap();
    assert_eq!(
        s.solver,
        SolverSettings {
            kind: SolverKind::Corrected,
            integrator: Integrator::SymplecticEuler,
            delta: 1e-3,
            max_iterations: 50,
            strict: true,
            relaxation: 0.8,
            warm_start: true,
            on_escape: EscapePolicy::Remove,
            gradient_moment: SolverSettings::default_gradient_moment(SolverKind::Corrected),
        }
    );
    assert_eq!(s.probes.len(), 2);
    let p = &s.probes[0];
    assert_eq!(p.name, "surge");
    assert_eq!(p.kind, ProbeKind::Front);
    assert_eq!(p.axis, 0);
    assert_eq!(p.origin, 0.01);
    let r = p.reference.as_ref().unwrap();
    assert_eq!(
        r.file,
        PathBuf::from("data/martin_moyce.csv"),
        "parse_scene keeps it relative"
    );
    assert_eq!(r.series, vec!["n2_a2.25".to_string(), "n2_a1.125".to_string()]);
    assert_eq!(r.length, Some(0.25));
    assert_eq!(r.time_range, (0.5, 2.5));
    let q = &s.probes[1];
    assert_eq!((q.name.as_str(), q.axis, q.origin), ("height", 1, 0.0));
    assert_eq!(q.reference, None);
}

#[test]
fn probe_and_reference_defaults() {
    let text = format!(
        "{}\n[[probe]]\nname = \"front\"\nkind = \"front\"\n\n[probe.reference]\nfile = \"ref.csv\"\nlength = 0.1\n",
        *WCSPH
    );
    let s = parse(&text).unwrap();
    let p = &s.probes[0];
    assert_eq!((p.axis, p.origin), (0, 0.0), "axis x, origin 0");
    let r = p.reference.as_ref().unwrap();
    assert!(r.series.is_empty(), "all series");
    assert_eq!(r.time_range, (1.0, 3.0));
    assert_eq!(r.time_range, sc::ProbeReference::DEFAULT_TIME_RANGE);
}

#[test]
fn wcsph_accepts_rk3_and_corrected_accepts_symplectic_euler() {
    let s = parse(&edit(
        &WCSPH,
        "kind = \"wcsph\"",
        "kind = \"wcsph\"\nintegrator = \"rk3\"",
    ))
    .unwrap();
    assert_eq!(s.solver.integrator, Integrator::Rk3);
    assert_eq!(s.solver.kind, SolverKind::Wcsph);
    let s = parse(&CORRECTED).unwrap();
    assert_eq!(s.solver.integrator, Integrator::SymplecticEuler);
}

#[test]
fn bad_solver_values_name_the_key() {
    let cases: [(&str, &str, &str, &str); 11] = [
        (
            "delta = 1e-3",
            "delta = 0.0",
            "solver.delta",
            "must be in (0, 0.1]",
        ),
        ("delta = 1e-3", "delta = 0.5", "solver.delta", "got 0.5"),
        (
            "delta = 1e-3",
            "delta = -1e-3",
            "solver.delta",
            "must be in (0, 0.1]",
        ),
        ("delta = 1e-3", "delta = nan", "solver.delta", "finite"),
        ("delta = 1e-3", "delta = inf", "solver.delta", "finite"),
        (
            "max_iterations = 50",
            "max_iterations = 0",
            "solver.max_iterations",
            "[1, 100000]",
        ),
        (
            "max_iterations = 50",
            "max_iterations = -3",
            "solver.max_iterations",
            "got -3",
        ),
        (
            "max_iterations = 50",
            "max_iterations = 100001",
            "solver.max_iterations",
            "[1, 100000]",
        ),
        (
            "relaxation = 0.8",
            "relaxation = 1.5",
            "solver.relaxation",
            "must be in (0, 1]",
        ),
        (
            "relaxation = 0.8",
            "relaxation = 0.0",
            "solver.relaxation",
            "must be in (0, 1]",
        ),
        (
            "relaxation = 0.8",
            "relaxation = nan",
            "solver.relaxation",
            "finite",
        ),
    ];
    for (from, to, key, reason) in cases {
        expect_one(&CORRECTED, from, to, key, to, reason);
    }
    // The limits themselves are fine.
    for (from, to) in [
        ("delta = 1e-3", "delta = 0.1"),
        ("max_iterations = 50", "max_iterations = 1"),
        ("max_iterations = 50", "max_iterations = 100000"),
        ("relaxation = 0.8", "relaxation = 1.0"),
    ] {
        parse(&edit(&CORRECTED, from, to)).unwrap_or_else(|e| panic!("{to}: {e}"));
    }
}

#[test]
fn bad_solver_types_and_names_name_the_key() {
    let cases: [(&str, &str, &str); 5] = [
        (
            "integrator = \"symplectic_euler\"",
            "integrator = \"rk4\"",
            "solver.integrator",
        ),
        (
            "integrator = \"symplectic_euler\"",
            "integrator = 3",
            "solver.integrator",
        ),
        ("kind = \"corrected\"", "kind = \"iisph\"", "solver.kind"),
        (
            "max_iterations = 50",
            "max_iterations = 2.5",
            "solver.max_iterations",
        ),
        ("strict = true", "strict = \"yes\"", "solver.strict"),
    ];
    for (from, to, key) in cases {
        problem_at(&edit(&CORRECTED, from, to), key, to, "");
    }
    let ps = problems(parse(&edit(
        &CORRECTED,
        "integrator = \"symplectic_euler\"",
        "integrator = \"rk4\"",
    )));
    assert!(
        ps[0].reason.contains("rk3"),
        "lists the variants: {}",
        ps[0].reason
    );
    assert!(ps[0].reason.contains("symplectic_euler"), "{}", ps[0].reason);
}

#[test]
fn corrected_only_keys_are_rejected_with_wcsph() {
    for key in [
        "delta = 1e-3",
        "max_iterations = 10",
        "strict = false",
        "relaxation = 0.5",
    ] {
        let text = edit(&WCSPH, "end_time = 1.0", &format!("{key}\nend_time = 1.0"));
        let name = key.split(' ').next().unwrap();
        let reason = "only with solver.kind = \"corrected\"";
        only_problem_at(&text, &format!("solver.{name}"), key, reason);
    }
    // All four at once: four problems.
    let text = edit(
        &WCSPH,
        "end_time = 1.0",
        "delta = 1e-3\nmax_iterations = 10\nstrict = true\nrelaxation = 0.5\nend_time = 1.0",
    );
    assert_eq!(problems(parse(&text)).len(), 4);
    let shown = parse(&edit(&WCSPH, "end_time = 1.0", "delta = 1e-3\nend_time = 1.0"))
        .unwrap_err()
        .to_string();
    let want = format!(
        "test.toml:{}:1: solver.delta: only with solver.kind = \"corrected\"",
        line_of(&WCSPH, "end_time", 0)
    );
    assert!(shown.starts_with(&want), "{shown}");
}

#[test]
fn duplicate_and_bad_probe_names() {
    let text = edit(&CORRECTED, "name = \"height\"", "name = \"surge\"");
    let ps = problems(parse(&text));
    assert_eq!(ps.len(), 1, "{ps:#?}");
    let p = with_key(&ps, "probe[1].name");
    assert_eq!(line(p), line_of(&text, "name = \"surge\"", 1));
    assert!(
        p.reason.contains("duplicate probe name \"surge\""),
        "{}",
        p.reason
    );
    assert!(p.reason.contains("probe[0]"), "{}", p.reason);

    // A probe may share a solid's name.
    parse(&edit(&CORRECTED, "name = \"height\"", "name = \"tank\"")).unwrap();

    for (to, reason) in [("name = \"\"", "empty"), ("name = \"a b\"", "may only contain")] {
        expect_one(&CORRECTED, "name = \"height\"", to, "probe[1].name", to, reason);
    }
}

#[test]
fn bad_probe_axis() {
    for (to, reason) in [
        ("axis = \"z\"", "dimension = 2"),
        ("axis = \"w\"", "\"x\" or \"y\""),
        ("axis = \"X\"", "got \"X\""),
    ] {
        expect_one(&CORRECTED, "axis = \"y\"", to, "probe[1].axis", to, reason);
    }
    // Wrong type is a deserialization problem at the key.
    let text = edit(&CORRECTED, "axis = \"y\"", "axis = 1");
    problem_at(&text, "probe[1].axis", "axis = 1", "");
}

#[test]
fn probe_axis_z_in_3d() {
    let text = format!(
        "{}\n[[probe]]\nname = \"depth\"\nkind = \"front\"\naxis = \"z\"\norigin = -0.5\n",
        edit(&WCSPH, "dimension = 2", "dimension = 3")
            .replace("[-0.05, -0.05]", "[-0.05, -0.05, -0.05]")
            .replace("[1.65, 1.0]", "[1.65, 1.0, 1.0]")
            .replace("[0.0, -9.81]", "[0.0, 0.0, -9.81]")
            .replace("min = [0.0, 0.0]", "min = [0.0, 0.0, 0.0]")
            .replace("[0.26, 0.5]", "[0.26, 0.5, 0.5]")
            .replace("[1.6, 0.8]", "[1.6, 0.8, 0.8]")
    );
    let s = parse(&text).unwrap();
    assert_eq!((s.probes[0].axis, s.probes[0].origin), (2, -0.5));
}

#[test]
fn bad_probe_values() {
    let cases: [(&str, &str, &str, &str); 9] = [
        (
            "length = 0.25",
            "length = 0.0",
            "probe[0].reference.length",
            "> 0",
        ),
        (
            "length = 0.25",
            "length = -0.25",
            "probe[0].reference.length",
            "> 0",
        ),
        (
            "length = 0.25",
            "length = nan",
            "probe[0].reference.length",
            "finite",
        ),
        (
            "time_range = [0.5, 2.5]",
            "time_range = [2.5, 0.5]",
            "probe[0].reference.time_range",
            "T0 < T1",
        ),
        (
            "time_range = [0.5, 2.5]",
            "time_range = [1.0, 1.0]",
            "probe[0].reference.time_range",
            "T0 < T1",
        ),
        (
            "time_range = [0.5, 2.5]",
            "time_range = [1.0]",
            "probe[0].reference.time_range",
            "2 entries",
        ),
        (
            "time_range = [0.5, 2.5]",
            "time_range = [0.5, inf]",
            "probe[0].reference.time_range[1]",
            "finite",
        ),
        ("origin = 0.01", "origin = nan", "probe[0].origin", "finite"),
        (
            "file = \"data/martin_moyce.csv\"",
            "file = \"\"",
            "probe[0].reference.file",
            "empty",
        ),
    ];
    for (from, to, key, reason) in cases {
        expect_one(&CORRECTED, from, to, key, to, reason);
    }
    expect_one(
        &CORRECTED,
        "series = [\"n2_a2.25\", \"n2_a1.125\"]",
        "series = [\"n2_a2.25\", \"n2_a2.25\"]",
        "probe[0].reference.series[1]",
        "series = [",
        "duplicate series",
    );
    // An empty series list means all series.
    let s = parse(&edit(
        &CORRECTED,
        "series = [\"n2_a2.25\", \"n2_a1.125\"]",
        "series = []",
    ))
    .unwrap();
    assert!(s.probes[0].reference.as_ref().unwrap().series.is_empty());
}

#[test]
fn unknown_probe_keys_and_kinds() {
    let cases: [(&str, &str, &str); 5] = [
        ("axis = \"x\"", "axes = \"x\"", "probe[0].axes"),
        ("length = 0.25", "lenght = 0.25", "probe[0].reference.lenght"),
        (
            "kind = \"front\"\naxis = \"y\"",
            "kind = \"height\"\naxis = \"y\"",
            "probe[1].kind",
        ),
        (
            "name = \"height\"\nkind = \"front\"\n",
            "kind = \"front\"\n",
            "probe[1].name",
        ),
        ("length = 0.25\n", "\n", "probe[0].reference.length"),
    ];
    for (from, to, key) in cases {
        let text = edit(&CORRECTED, from, to);
        let ps = problems(parse(&text));
        assert_eq!(ps.len(), 1, "{to}: {ps:#?}");
        let p = with_key(&ps, key);
        assert!(
            matches!(p.location, Location::Line { .. }),
            "{to}: a location in the file: {p:?}"
        );
    }
    let text = edit(&CORRECTED, "axis = \"x\"", "axes = \"x\"");
    let ps = problems(parse(&text));
    assert_eq!(line(&ps[0]), line_of(&text, "axes", 0));
    let text = edit(
        &CORRECTED,
        "kind = \"front\"\naxis = \"y\"",
        "kind = \"height\"\naxis = \"y\"",
    );
    let ps = problems(parse(&text));
    assert_eq!(line(&ps[0]), line_of(&text, "kind = \"height\"", 0));
}

#[test]
fn probe_reference_needs_gravity() {
    let text =
        edit(&CORRECTED, "effects = [\"gravity\"]", "effects = []").replace("gravity = [0.0, -9.81]\n", "");
    only_problem_at(&text, "probe[0].reference", "[probe.reference]", "gravity");
}

#[test]
fn many_problems_are_reported_together() {
    let text = edit(&CORRECTED, "delta = 1e-3", "delta = 0.0");
    let text = edit(&text, "relaxation = 0.8", "relaxation = 2.0");
    let text = edit(&text, "axis = \"y\"", "axis = \"z\"");
    let text = edit(&text, "length = 0.25", "length = -1.0");
    let text = edit(&text, "spacing = 0.02", "spacing = -0.02");
    let ps = problems(parse(&text));
    for key in [
        "solver.delta",
        "solver.relaxation",
        "probe[1].axis",
        "probe[0].reference.length",
        "particles.spacing",
    ] {
        with_key(&ps, key);
    }
}

#[test]
fn overrides_set_the_new_solver_keys() {
    let s = parse_set(&WCSPH, &["solver.kind=corrected", "solver.delta=1e-3"]).unwrap();
    assert_eq!(s.solver.kind, SolverKind::Corrected);
    assert_eq!(s.solver.delta, 1e-3);
    assert_eq!(s.solver.integrator, Integrator::Rk3, "default for corrected");
    let s = parse_set(
        &WCSPH,
        &[
            "solver.kind=\"corrected\"",
            "solver.strict=true",
            "solver.integrator=symplectic_euler",
            "solver.max_iterations=25",
            "solver.relaxation=0.25",
        ],
    )
    .unwrap();
    assert_eq!(
        s.solver,
        SolverSettings {
            kind: SolverKind::Corrected,
            integrator: Integrator::SymplecticEuler,
            delta: 1e-4,
            max_iterations: 25,
            strict: true,
            relaxation: 0.25,
            warm_start: false,
            on_escape: EscapePolicy::Remove,
            gradient_moment: SolverSettings::default_gradient_moment(SolverKind::Corrected),
        }
    );
    // The gradient moment: measured for corrected, the lattice's for wcsph, either on request.
    assert_eq!(s.solver.gradient_moment, GradientMoment::Measured);
    assert_eq!(
        parse_set(&WCSPH, &[]).unwrap().solver.gradient_moment,
        GradientMoment::Lattice
    );
    for (kind, moment, want) in [
        ("corrected", "lattice", GradientMoment::Lattice),
        ("wcsph", "measured", GradientMoment::Measured),
    ] {
        let set = [
            format!("solver.kind={kind}"),
            format!("solver.gradient_moment={moment}"),
        ];
        let set: Vec<&str> = set.iter().map(String::as_str).collect();
        assert_eq!(parse_set(&WCSPH, &set).unwrap().solver.gradient_moment, want);
    }
    let ps = problems(parse_set(&WCSPH, &["solver.gradient_moment=exact"]));
    assert_eq!(ps.len(), 1, "{ps:#?}");
    assert!(
        ps[0].reason.contains("lattice") && ps[0].reason.contains("measured"),
        "an unknown gradient moment names the accepted ones: {ps:#?}"
    );
    let s = parse_set(&WCSPH, &["solver.integrator=rk3"]).unwrap();
    assert_eq!(s.solver.integrator, Integrator::Rk3);
    assert_eq!(s.solver.kind, SolverKind::Wcsph);
    // Back to wcsph from the corrected scene requires dropping its corrected-only keys.
    let ps = problems(parse_set(&CORRECTED, &["solver.kind=wcsph"]));
    assert_eq!(ps.len(), 5, "{ps:#?}");
    assert_eq!(
        with_key(&ps, "solver.delta").location,
        Location::Line {
            line: line_of(&CORRECTED, "delta = 1e-3", 0),
            column: 1
        }
    );
}

#[test]
fn override_errors_name_the_override() {
    let ps = problems(parse_set(&WCSPH, &["solver.delta=1e-3"]));
    assert_eq!(ps.len(), 1, "{ps:#?}");
    let p = with_key(&ps, "solver.delta");
    assert_eq!(p.location, Location::Override("solver.delta".into()));
    assert!(
        p.reason.contains("only with solver.kind = \"corrected\""),
        "{}",
        p.reason
    );
    let shown = parse_set(&WCSPH, &["solver.delta=1e-3"]).unwrap_err().to_string();
    assert!(
        shown.starts_with("test.toml: --set solver.delta: solver.delta: only with solver.kind"),
        "{shown}"
    );

    let cases: [(&str, &str); 6] = [
        ("solver.delta=0", "solver.delta"),
        ("solver.delta=nan", "solver.delta"),
        ("solver.max_iterations=0", "solver.max_iterations"),
        ("solver.relaxation=1.5", "solver.relaxation"),
        ("solver.integrator=rk4", "solver.integrator"),
        ("solver.strict=maybe", "solver.strict"),
    ];
    for (set, key) in cases {
        let ps = problems(parse_set(&CORRECTED, &[set]));
        assert_eq!(ps.len(), 1, "{set}: {ps:#?}");
        assert_eq!(
            with_key(&ps, key).location,
            Location::Override(key.into()),
            "{set}"
        );
    }
}

#[test]
fn overrides_reach_probes() {
    let s = parse_set(
        &CORRECTED,
        &[
            "probe.0.origin=0.5",
            "probe.0.reference.time_range=[2.0, 4.0]",
            "probe.1.axis=x",
        ],
    )
    .unwrap();
    assert_eq!(s.probes[0].origin, 0.5);
    assert_eq!(s.probes[0].reference.as_ref().unwrap().time_range, (2.0, 4.0));
    assert_eq!(s.probes[1].axis, 0);

    let ps = problems(parse_set(
        &CORRECTED,
        &["probe.0.reference.time_range=[4.0, 2.0]"],
    ));
    assert_eq!(
        with_key(&ps, "probe[0].reference.time_range").location,
        Location::Override("probe.0.reference.time_range".into())
    );

    // A whole probe list from the command line.
    let s = parse_set(
        &WCSPH,
        &[r#"probe=[{ name = "f", kind = "front", reference = { file = "r.csv", length = 0.1 } }]"#],
    )
    .unwrap();
    assert_eq!(s.probes.len(), 1);
    assert_eq!(
        s.probes[0].reference.as_ref().unwrap().file,
        PathBuf::from("r.csv")
    );
}

#[test]
fn reference_files_are_looked_up_in_the_reference_directory() {
    let dir = std::env::temp_dir().join(format!("sph_scene_solver_test_{}", std::process::id()));
    let scenes = dir.join("scenes");
    let data = dir.join("data");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::create_dir_all(&data).unwrap();
    let path = scenes.join("corrected.toml");
    std::fs::write(&path, &*CORRECTED).unwrap();

    // load_scene keeps the file as the scene names it, not yet looked up.
    let mut s = sc::load_scene(&path, &[]).unwrap();
    let r = s.probes[0].reference.as_ref().unwrap();
    assert_eq!(r.file, Path::new("data/martin_moyce.csv"));
    assert_eq!(r.location, sc::ReferenceLocation::Unlocated);

    // Not beside the scene: in the reference directory, and only there.
    std::fs::write(scenes.join("data_martin_moyce.csv"), "x\n").unwrap();
    let skipped = sc::locate_references(&mut s, Some(&dir));
    assert_eq!(skipped.len(), 1);
    assert_eq!(
        skipped[0].reason,
        sc::MissingReason::NotFound(dir.join("data/martin_moyce.csv"))
    );
    // A folder where the file should be is named as such, not as missing.
    std::fs::create_dir_all(data.join("martin_moyce.csv")).unwrap();
    let skipped = sc::locate_references(&mut s, Some(&dir));
    assert_eq!(
        skipped[0].reason,
        sc::MissingReason::NotRegular(dir.join("data/martin_moyce.csv"), "a directory")
    );
    assert!(
        skipped[0]
            .to_string()
            .contains("is a directory, not a regular file"),
        "{}",
        skipped[0]
    );
    std::fs::remove_dir(data.join("martin_moyce.csv")).unwrap();
    std::fs::write(data.join("martin_moyce.csv"), "x\n").unwrap();
    assert!(sc::locate_references(&mut s, Some(&dir)).is_empty());
    assert_eq!(
        s.probes[0].reference.as_ref().unwrap().location,
        sc::ReferenceLocation::Found(dir.join("data/martin_moyce.csv"))
    );
    // Without a directory a relative file is skipped, and the skip is listed.
    let skipped = sc::locate_references(&mut s, None);
    assert_eq!(skipped[0].reason, sc::MissingReason::NoDirectory);
    assert_eq!(sc::skipped_references(&s), skipped);

    // An absolute path is used as it is, with or without a directory.
    let abs = dir.join("elsewhere.csv");
    std::fs::write(&abs, "x\n").unwrap();
    let set = format!("probe.0.reference.file={}", abs.display());
    let mut s = sc::load_scene(&path, &[set]).unwrap();
    assert!(sc::locate_references(&mut s, None).is_empty());
    assert_eq!(
        s.probes[0].reference.as_ref().unwrap().location,
        sc::ReferenceLocation::Found(abs)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn replacing_a_value_never_panics(n in 0usize..200, g in 0usize..GARBAGE.len()) {
        // Replace the value of the n-th `key = value` line.
        let lines: Vec<&str> = CORRECTED.lines().collect();
        let assignments: Vec<usize> = (0..lines.len()).filter(|&i| lines[i].contains(" = ")).collect();
        let i = assignments[n % assignments.len()];
        let key = lines[i].split(" = ").next().unwrap_or_default();
        let mut mutated: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
        mutated[i] = format!("{key} = {}", GARBAGE[g]);
        check_result(parse(&mutated.join("\n")));
    }

    #[test]
    fn truncating_never_panics(n in 0usize..2000) {
        let n = n % (CORRECTED.len() + 1);
        check_result(parse(&CORRECTED[..n]));
    }

    #[test]
    fn random_solver_overrides_never_panic(
        key in prop::sample::select(vec!["kind", "integrator", "delta", "max_iterations", "strict", "relaxation"]),
        value in "[ -~]{0,12}",
    ) {
        check_result(parse_set(&WCSPH, &[&format!("solver.{key}={value}")]));
        check_result(parse_set(&CORRECTED, &[&format!("solver.{key}={value}")]));
    }
}

/// `CORRECTED` plus a force probe on the tank (`extra` is appended inside it).
fn with_force_probe(extra: &str) -> String {
    format!(
        "{}\n[[probe]]\nname = \"wall_force\"\nkind = \"force\"\n{extra}",
        *CORRECTED
    )
}

#[test]
fn force_probe_names_an_existing_solid_and_defaults_its_time_range() {
    let text =
        with_force_probe("solid = \"tank\"\naxis = \"x\"\n\n[probe.reference]\nfile = \"force.csv\"\n");
    let scene = parse(&text).expect("valid");
    let p = &scene.probes[2];
    assert_eq!(p.kind, sc::ProbeKind::Force);
    assert_eq!(p.solid, Some(0));
    let r = p.reference.as_ref().expect("reference");
    assert_eq!(r.time_range, (0.0, 1.0), "default: the whole run");
}

#[test]
fn bad_force_probes_name_the_key() {
    let cases = [
        ("axis = \"x\"\n", "probe[2].solid", "required"),
        ("solid = \"lid\"\n", "probe[2].solid", "no solid named"),
        (
            "solid = \"tank\"\norigin = 0.1\n",
            "probe[2].origin",
            "only with kind",
        ),
        (
            "solid = \"tank\"\n\n[probe.reference]\nfile = \"f.csv\"\nlength = 0.2\n",
            "probe[2].reference.length",
            "only for a front",
        ),
    ];
    for (extra, key, reason) in cases {
        problem_with(&with_force_probe(extra), key, reason);
    }
    let front_with_solid = edit(
        &CORRECTED,
        "name = \"height\"\n",
        "name = \"height\"\nsolid = \"tank\"\n",
    );
    problem_with(&front_with_solid, "probe[1].solid", "only with kind");
    let front_without_length = edit(&CORRECTED, "length = 0.25\n", "");
    problem_with(&front_without_length, "probe[0].reference.length", "required");
}
