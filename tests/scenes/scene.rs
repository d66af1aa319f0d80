//! Integration tests of the scene loader: parsing, validation with key paths
//! and line numbers, overrides, particle generation and fuzzing.

use crate::common::tolerance::{F32_ROUNDING, F64_FEW_OPERATIONS};
use sph::scene as sc;

use crate::common::scene::{
    GARBAGE, Tank2d, check_result, edit, line, line_of, only_problem_at, parse, parse_set, problem_at,
    problem_with, problems, with_key,
};
use proptest::prelude::*;
use sc::{Effect, Location, SceneError, SolidShape, SolverKind};
use sph::backend::SurfaceTensionModel;
use std::sync::LazyLock;

/// The shared 2D tank as a dam break: named, with viscosity, a gravity ramp, dx = 0.01 m and a
/// 0.25 m wide column.
static VALID_2D: LazyLock<String> = LazyLock::new(|| {
    Tank2d {
        head: "name = \"dam_break_2d\"\n",
        effects: r#"["gravity", "viscosity"]"#,
        spacing: 0.01,
        fluid: "viscosity = 1.0e-3\ngravity_ramp = 0.1\n",
        width: 0.25,
        ..Tank2d::default()
    }
    .text()
});

const VALID_3D: &str = r#"dimension = 3
effects = ["gravity"]

[domain]
min = [-0.1, -0.1, -0.1]
max = [1.1, 1.1, 1.1]

[particles]
spacing = 0.05
smoothing_length = 0.1

[fluid]
rho0 = 1000.0
sound_speed = 20.0
gravity = [0.0, 0.0, -9.81]

[[fluid_box]]
min = [0.0, 0.0, 0.0]
max = [0.5, 1.0, 0.5]
velocity = [0.1, 0.0, 0.0]

[[solid]]
name = "box"
shape = "container"
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
open_top = false

[[solid]]
name = "obstacle"
shape = "box"
min = [0.7, 0.4, 0.0]
max = [0.8, 0.6, 0.2]

[solver]
kind = "wcsph"
dt = 1e-4
cfl = 0.3
end_time = 0.5

[output]
interval = 0.01
frames = false
"#;

#[test]
fn valid_2d_scene_parses_with_resolved_values() {
    let s = parse(&VALID_2D).unwrap();
    assert_eq!(s.name.as_deref(), Some("dam_break_2d"));
    assert_eq!(s.dimension, 2);
    assert!(s.has(Effect::Gravity) && s.has(Effect::Pair(sph::model::pair_terms::PairTerm::Viscosity)));
    assert_eq!(s.spacing, 0.01);
    assert!(
        (s.smoothing_length - 0.02).abs() < F64_FEW_OPERATIONS,
        "h = ratio * dx"
    );
    assert_eq!(s.wall_layers(), 2);
    assert_eq!(
        s.pair_terms.get(sph::model::pair_terms::PairTerm::Viscosity),
        Some(1.0e-3)
    );
    assert_eq!(s.gravity, Some(vec![0.0, -9.81]));
    assert_eq!(s.gravity_ramp, 0.1);
    assert_eq!(s.solver.kind, SolverKind::Wcsph);
    assert_eq!(s.dt, None);
    assert_eq!(s.cfl, 0.2);
    assert_eq!(s.end_time, 1.0);
    assert!(
        (s.output_interval - 0.02).abs() < F64_FEW_OPERATIONS,
        "default end_time / 50"
    );
    assert!(s.write_frames);
    assert_eq!(s.fluid_boxes.len(), 1);
    assert_eq!(s.fluid_boxes[0].velocity, vec![0.0, 0.0]);
    assert_eq!(s.solids.len(), 1);
    assert_eq!(s.solids[0].shape, SolidShape::Container);
    assert!(s.solids[0].open_top, "open_top defaults to true");
}

#[test]
fn valid_3d_scene_parses_with_smoothing_length() {
    let s = parse(VALID_3D).unwrap();
    assert_eq!(s.dimension, 3);
    assert!(s.has(Effect::Gravity) && !s.has(Effect::Pair(sph::model::pair_terms::PairTerm::Viscosity)));
    assert_eq!(s.smoothing_length, 0.1, "h given directly");
    assert_eq!(
        s.pair_terms.get(sph::model::pair_terms::PairTerm::Viscosity),
        None
    );
    assert_eq!(s.gravity_ramp, 0.0);
    assert_eq!(s.dt, Some(1e-4));
    assert_eq!(s.cfl, 0.3);
    assert_eq!(s.output_interval, 0.01);
    assert!(!s.write_frames);
    assert!(!s.solids[0].open_top);
    assert!(!s.solids[1].open_top);
    assert_eq!(s.fluid_boxes[0].velocity, vec![0.1, 0.0, 0.0]);
}

#[test]
fn negative_spacing_names_key_and_line() {
    let text = edit(&VALID_2D, "spacing = 0.01", "spacing = -0.01");
    problem_at(&text, "particles.spacing", "spacing = -0.01", "> 0");
}

#[test]
fn unknown_key_is_named_with_line_and_column() {
    let text = edit(&VALID_2D, "spacing = 0.01", "spacng = 0.01");
    let ps = problems(parse(&text));
    let p = with_key(&ps, "particles.spacng");
    assert_eq!(
        p.location,
        Location::Line {
            line: line_of(&text, "spacng", 0),
            column: 1
        }
    );
    assert!(p.reason.contains("unknown field `spacng`"), "{}", p.reason);
}

#[test]
fn missing_key_names_the_key() {
    let text = edit(&VALID_2D, "end_time = 1.0\n", "");
    problem_at(&text, "solver.end_time", "[solver]", "missing field");
}

#[test]
fn wrong_type_names_the_key() {
    let text = edit(&VALID_2D, "rho0 = 1000.0", "rho0 = \"heavy\"");
    problem_at(&text, "fluid.rho0", "rho0", "");
}

#[test]
fn fluid_outside_domain() {
    let text = edit(&VALID_2D, "max = [0.25, 0.5]", "max = [0.25, 1.5]");
    let p = problem_at(&text, "fluid_box[0]", "[[fluid_box]]", "outside the domain");
    assert!(p.reason.contains("axis y"), "{}", p.reason);
}

#[test]
fn solid_walls_outside_domain() {
    // The container walls (2 layers of 0.01 m) reach x = -0.02 < -0.01.
    let text = edit(&VALID_2D, "min = [-0.05, -0.05]", "min = [-0.01, -0.05]");
    problem_at(&text, "solid[0]", "[[solid]]", "outside the domain");
}

#[test]
fn fluid_overlapping_solid_box() {
    let text = format!(
        "{}\n[[solid]]\nname = \"gate\"\nshape = \"box\"\nmin = [0.2, 0.0]\nmax = [0.3, 0.3]\n",
        *VALID_2D
    );
    only_problem_at(&text, "fluid_box[0]", "[[fluid_box]]", "gate");
}

#[test]
fn fluid_overlapping_container_wall() {
    // The fluid starts at x = -0.01, inside the 0.02 m thick left wall.
    let text = edit(
        &VALID_2D,
        "min = [0.0, 0.0]\nmax = [0.25",
        "min = [-0.01, 0.0]\nmax = [0.25",
    );
    only_problem_at(
        &text,
        "fluid_box[0]",
        "[[fluid_box]]",
        "walls of container \"tank\"",
    );
}

#[test]
fn fluid_above_open_container_is_fine_but_not_into_a_lid() {
    // Fluid sticking out of the open top does not touch any wall.
    let text = edit(&VALID_2D, "max = [0.25, 0.5]", "max = [0.25, 0.9]");
    parse(&text).unwrap();
    let closed = edit(
        &text,
        "max = [1.6, 0.8]\n",
        "max = [1.6, 0.8]\nopen_top = false\n",
    );
    let ps = problems(parse(&closed));
    assert!(with_key(&ps, "fluid_box[0]").reason.contains("walls"));
}

#[test]
fn both_smoothing_keys_given() {
    let text = edit(
        &VALID_2D,
        "smoothing_ratio = 2.0",
        "smoothing_ratio = 2.0\nsmoothing_length = 0.02",
    );
    problem_at(
        &text,
        "particles.smoothing_length",
        "smoothing_length",
        "exactly one",
    );
}

#[test]
fn smoothing_ratio_out_of_range() {
    let text = edit(&VALID_2D, "smoothing_ratio = 2.0", "smoothing_ratio = 0.5");
    problem_at(&text, "particles.smoothing_ratio", "smoothing_ratio", "");
}

#[test]
fn viscosity_without_effect() {
    let text = edit(
        &VALID_2D,
        "effects = [\"gravity\", \"viscosity\"]",
        "effects = [\"gravity\"]",
    );
    only_problem_at(&text, "fluid.viscosity", "viscosity = 1.0e-3", "not enabled");
}

/// `fluid.artificial_viscosity_wall_factor`: 1 by default, read when given, negative an error
/// at the key, and the key without the `artificial_viscosity` effect an error saying so.
#[test]
fn artificial_viscosity_wall_factor_qualifies_the_artificial_viscosity() {
    let on = edit(
        &VALID_2D,
        "effects = [\"gravity\", \"viscosity\"]",
        "effects = [\"gravity\", \"viscosity\", \"artificial_viscosity\"]",
    );
    let on = edit(
        &on,
        "viscosity = 1.0e-3",
        "viscosity = 1.0e-3\nartificial_viscosity = 0.05",
    );
    assert_eq!(parse(&on).expect("valid").artificial_viscosity_wall_factor, 1.0);
    let given = edit(
        &on,
        "artificial_viscosity = 0.05",
        "artificial_viscosity = 0.05\nartificial_viscosity_wall_factor = 0.0",
    );
    assert_eq!(
        parse(&given).expect("valid").artificial_viscosity_wall_factor,
        0.0
    );
    let negative = edit(&given, "wall_factor = 0.0", "wall_factor = -0.5");
    problem_at(
        &negative,
        "fluid.artificial_viscosity_wall_factor",
        "wall_factor = -0.5",
        "",
    );
    let without = edit(
        &VALID_2D,
        "viscosity = 1.0e-3",
        "viscosity = 1.0e-3\nartificial_viscosity_wall_factor = 0.5",
    );
    only_problem_at(
        &without,
        "fluid.artificial_viscosity_wall_factor",
        "artificial_viscosity_wall_factor",
        "not enabled",
    );
}

/// `density_diffusion`: the effect needs `fluid.density_diffusion` (δ ≥ 0), the key needs the
/// effect, and the corrected solver (density set by positions) refuses it at the key, saying why.
#[test]
fn density_diffusion_is_an_effect_with_its_fluid_key_for_wcsph_only() {
    let on = edit(
        &VALID_2D,
        "effects = [\"gravity\", \"viscosity\"]",
        "effects = [\"gravity\", \"viscosity\", \"density_diffusion\"]",
    );
    let with_key_text = edit(
        &on,
        "viscosity = 1.0e-3",
        "viscosity = 1.0e-3\ndensity_diffusion = 0.1",
    );
    let scene = parse(&with_key_text).expect("valid with its key");
    assert!(scene.has(Effect::DensityDiffusion));
    assert_eq!(scene.density_diffusion, Some(0.1));
    // The memory estimate counts the rate (4 B per particle), and under SSP-RK3 the step-start
    // density too (4 B more).
    let bytes = |text: &str| sc::solver_particle_bytes(&parse(text).expect("valid")).per_particle;
    let rk3 = |text: &str| edit(text, "kind = \"wcsph\"", "kind = \"wcsph\"\nintegrator = \"rk3\"");
    assert_eq!(bytes(&with_key_text) - bytes(&VALID_2D), 4);
    assert_eq!(bytes(&rk3(&with_key_text)) - bytes(&rk3(&VALID_2D)), 8);

    let ps = problems(parse(&on));
    let p = with_key(&ps, "fluid.density_diffusion");
    assert!(p.reason.contains("required because effect"), "{}", p.reason);

    let negative = edit(
        &with_key_text,
        "density_diffusion = 0.1",
        "density_diffusion = -0.1",
    );
    with_key(&problems(parse(&negative)), "fluid.density_diffusion");

    let without = edit(
        &VALID_2D,
        "viscosity = 1.0e-3",
        "viscosity = 1.0e-3\ndensity_diffusion = 0.1",
    );
    let ps = problems(parse(&without));
    assert!(
        with_key(&ps, "fluid.density_diffusion")
            .reason
            .contains("not enabled")
    );

    let corrected = edit(&with_key_text, "kind = \"wcsph\"", "kind = \"corrected\"");
    let ps = problems(parse(&corrected));
    let p = with_key(&ps, "fluid.density_diffusion");
    assert!(
        p.reason.contains("wcsph") && p.reason.contains("sets density by positions"),
        "{}",
        p.reason
    );
}

/// Every pair term of `kernels/pair_terms.table` is read from the scene by its name: its
/// effect needs its `[fluid]` key, a negative coefficient is refused, and the resolved scene
/// carries it.
#[test]
fn every_pair_term_is_an_effect_with_its_fluid_key() {
    use sph::model::pair_terms::PairTerm;
    for term in PairTerm::ALL {
        let name = term.name();
        let effects = format!("effects = [\"gravity\", \"{name}\"]");
        let base = edit(&VALID_2D, "effects = [\"gravity\", \"viscosity\"]", &effects);
        let base = edit(&base, "viscosity = 1.0e-3", &format!("{name} = 0.25"));
        let scene = parse(&base).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(scene.has(Effect::Pair(term)), "{name}");
        assert_eq!(scene.pair_terms.get(term), Some(0.25), "{name}");
        assert_eq!(scene.pair_terms.terms().iter().collect::<Vec<_>>(), vec![term]);

        let missing = edit(&base, &format!("{name} = 0.25\n"), "");
        let ps = problems(parse(&missing));
        let p = with_key(&ps, &format!("fluid.{name}"));
        assert!(p.reason.contains("required because effect"), "{}", p.reason);

        let negative = edit(&base, &format!("{name} = 0.25"), &format!("{name} = -1.0"));
        let ps = problems(parse(&negative));
        with_key(&ps, &format!("fluid.{name}"));
    }
    let unknown = edit(&VALID_2D, "\"viscosity\"]", "\"viscosty\"]");
    let ps = problems(parse(&unknown));
    assert!(
        ps.iter()
            .any(|p| p.reason.contains("viscosty") && p.reason.contains("artificial_viscosity")),
        "an unknown effect lists the known ones: {ps:#?}"
    );
}

#[test]
fn gravity_effect_without_gravity() {
    let text = edit(&VALID_2D, "gravity = [0.0, -9.81]\n", "");
    // Missing key: located at its table.
    problem_at(&text, "fluid.gravity", "[fluid]", "required");
}

#[test]
fn duplicate_effect() {
    let text = edit(
        &VALID_2D,
        "effects = [\"gravity\", \"viscosity\"]",
        "effects = [\"gravity\", \"viscosity\", \"gravity\"]",
    );
    let ps = problems(parse(&text));
    assert_eq!(line(with_key(&ps, "effects[2]")), 3);
}

#[test]
fn wrong_array_length() {
    let text = edit(&VALID_2D, "gravity = [0.0, -9.81]", "gravity = [0.0, -9.81, 0.0]");
    problem_at(&text, "fluid.gravity", "gravity = [", "expected 2 entries");
}

#[test]
fn non_finite_and_inverted_box() {
    let text = edit(&VALID_2D, "max = [1.6, 0.8]", "max = [nan, -0.5]");
    problem_at(&text, "solid[0].max[0]", "max = [nan", "finite");
}

#[test]
fn duplicate_solid_name() {
    let text = format!(
        "{}\n[[solid]]\nname = \"tank\"\nshape = \"box\"\nmin = [1.0, 0.0]\nmax = [1.1, 0.1]\n",
        *VALID_2D
    );
    let ps = problems(parse(&text));
    let p = with_key(&ps, "solid[1].name");
    assert_eq!(line(p), line_of(&text, "name = \"tank\"", 1));
    assert!(p.reason.contains("duplicate"), "{}", p.reason);
}

#[test]
fn open_top_on_a_box_and_bad_name() {
    let text = format!(
        "{}\n[[solid]]\nname = \"bad name\"\nshape = \"box\"\nmin = [1.0, 0.0]\nmax = [1.1, 0.1]\nopen_top = true\n",
        *VALID_2D
    );
    let ps = problems(parse(&text));
    assert_eq!(
        line(with_key(&ps, "solid[1].open_top")),
        line_of(&text, "open_top", 0)
    );
    assert_eq!(
        line(with_key(&ps, "solid[1].name")),
        line_of(&text, "bad name", 0)
    );
}

#[test]
fn thin_box_is_an_error() {
    let text = edit(&VALID_2D, "max = [0.25, 0.5]", "max = [0.004, 0.5]");
    let ps = problems(parse(&text));
    let p = with_key(&ps, "fluid_box[0].max");
    assert!(
        p.reason.contains("thinner than the particle spacing"),
        "{}",
        p.reason
    );
}

const HUGE: &str = r#"dimension = 3
[domain]
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
[particles]
spacing = 1e-6
smoothing_ratio = 2.0
[fluid]
rho0 = 1000.0
sound_speed = 10.0
[[fluid_box]]
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
[solver]
kind = "wcsph"
end_time = 1.0
"#;

#[test]
fn too_many_particles() {
    let ps = problems(parse(HUGE));
    let p = with_key(&ps, "particles.spacing");
    assert_eq!(line(p), line_of(HUGE, "spacing", 0));
    assert!(p.reason.contains("1000000000000000000 particles"), "{}", p.reason);
    assert!(p.reason.contains("u32"), "{}", p.reason);
    assert!(p.reason.contains("bytes"), "{}", p.reason);
}

#[test]
fn too_much_memory() {
    // 1500^3 = 3.4e9 particles fit u32 but need ~0.5 TB.
    let text = edit(HUGE, "spacing = 1e-6", "spacing = 0.000666666666666666666");
    let p = problem_with(&text, "particles.spacing", "3375000000 particles");
    assert!(p.reason.contains("bytes available"), "{}", p.reason);
    // The corrected solver needs more than twice the memory of wcsph on a scene half fluid
    // (tests/check/memory_estimate.rs checks both against measured peaks).
    let bytes = |kind| sc::run_bytes(2000, 1000, sc::particle_bytes(3, kind)).expect("fits");
    assert!(
        bytes(sc::SolverKind::Corrected) - sc::BASE_BYTES
            > 2 * (bytes(sc::SolverKind::Wcsph) - sc::BASE_BYTES)
    );
}

#[test]
fn multiple_errors_are_all_reported() {
    let text = edit(&VALID_2D, "spacing = 0.01", "spacing = -0.01");
    let text = edit(&text, "rho0 = 1000.0", "rho0 = 0.0");
    let text = edit(&text, "end_time = 1.0", "end_time = -1.0");
    let text = edit(&text, "max = [1.65, 1.0]", "max = [1.65]");
    let ps = problems(parse(&text));
    for (key, needle) in [
        ("particles.spacing", "spacing = -0.01"),
        ("fluid.rho0", "rho0 = 0.0"),
        ("solver.end_time", "end_time = -1.0"),
        ("domain.max", "max = [1.65]"),
    ] {
        assert_eq!(line(with_key(&ps, key)), line_of(&text, needle, 0), "{key}");
    }
    let err = parse(&text).unwrap_err().to_string();
    assert_eq!(err.lines().count(), ps.len());
    assert!(
        err.lines().any(|l| l
            == format!(
                "test.toml:{}:1: fluid.rho0: must be > 0, got 0",
                line_of(&text, "rho0", 0)
            )),
        "{err}"
    );
}

#[test]
fn toml_syntax_error_has_line() {
    let text = edit(&VALID_2D, "rho0 = 1000.0", "rho0 = 1000.0.0");
    let ps = problems(parse(&text));
    assert_eq!(line(&ps[0]), line_of(&text, "rho0", 0));
    assert!(!ps[0].reason.is_empty());
}

#[test]
fn override_adds_key() {
    let s = parse_set(&VALID_2D, &["solver.dt=1e-4", "output.interval=0.05"]).unwrap();
    assert_eq!(s.dt, Some(1e-4));
    assert_eq!(s.output_interval, 0.05);
}

#[test]
fn override_bare_string_and_arrays() {
    let s = parse_set(
        &VALID_2D,
        &[
            "solver.kind=wcsph",
            "fluid_box.0.max=[0.5, 0.25]",
            "fluid.gravity = [0.0, -1.0]",
            "name=other",
        ],
    )
    .unwrap();
    assert_eq!(s.solver.kind, SolverKind::Wcsph);
    assert_eq!(s.fluid_boxes[0].region.max, vec![0.5, 0.25]);
    assert_eq!(s.gravity, Some(vec![0.0, -1.0]));
    assert_eq!(s.name.as_deref(), Some("other"));
    let s = parse_set(&VALID_2D, &["fluid.gravity.1=-3.0", "solver.end_time=2"]).unwrap();
    assert_eq!(s.gravity, Some(vec![0.0, -3.0]));
    assert_eq!(s.end_time, 2.0);
}

#[test]
fn override_errors_name_the_override() {
    let cases: [(&str, &str); 6] = [
        ("solver.dt", "no '='"),
        ("=3", "empty KEY"),
        ("fluid.rho0.0=1", "not a table or array"),
        ("fluid_box.3.max=[1.0, 1.0]", "out of range"),
        ("solver.0=1", "not an array"),
        ("solver..dt=1", "empty segment"),
    ];
    for (set, reason) in cases {
        let ps = problems(parse_set(&VALID_2D, &[set]));
        assert_eq!(ps.len(), 1, "{set}: {ps:#?}");
        assert!(matches!(ps[0].location, Location::Override(_)), "{set}: {ps:?}");
        assert!(ps[0].reason.contains(reason), "{set}: {}", ps[0].reason);
        assert!(ps[0].reason.contains(set), "{set}: {}", ps[0].reason);
    }
    let mut doc: toml::Table = VALID_2D.parse().unwrap();
    assert!(
        sc::apply_overrides(&mut doc, &["x".to_string(), "y.1=2".to_string()])
            .is_err_and(|e| e.problems().len() == 2)
    );
}

#[test]
fn overridden_values_report_the_override_location() {
    let ps = problems(parse_set(&VALID_2D, &["particles.spacing=-1"]));
    let p = with_key(&ps, "particles.spacing");
    assert_eq!(p.location, Location::Override("particles.spacing".into()));
    let err = parse_set(&VALID_2D, &["particles.spacing=-1"])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("test.toml: --set particles.spacing: particles.spacing: must be > 0"),
        "{err}"
    );

    // An unknown key introduced by an override.
    let ps = problems(parse_set(&VALID_2D, &["solver.dtt=1e-4"]));
    let p = with_key(&ps, "solver.dtt");
    assert_eq!(p.location, Location::Override("solver.dtt".into()));

    // Wrong type through an override.
    let ps = problems(parse_set(&VALID_2D, &["solver.end_time=soon"]));
    assert_eq!(
        with_key(&ps, "solver.end_time").location,
        Location::Override("solver.end_time".into())
    );

    // Problems in other keys still point into the file.
    let text = edit(&VALID_2D, "rho0 = 1000.0", "rho0 = -1.0");
    let ps = problems(parse_set(&text, &["solver.dt=1e-4"]));
    assert_eq!(line(with_key(&ps, "fluid.rho0")), line_of(&text, "rho0", 0));
}

#[test]
fn load_scene_file_errors() {
    let dir = std::env::temp_dir().join(format!("sph_scene_test_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    assert!(matches!(
        sc::load_scene(&dir.join("missing.toml"), &[]),
        Err(SceneError::Io { .. })
    ));
    assert!(matches!(sc::load_scene(&dir, &[]), Err(SceneError::Io { .. })));

    let bad = dir.join("bad_utf8.toml");
    std::fs::write(&bad, b"dimension = 2\nname = \"\xff\xfe\"\n").unwrap();
    let ps = problems(sc::load_scene(&bad, &[]));
    assert_eq!(ps[0].location, Location::Line { line: 2, column: 9 });
    assert!(ps[0].reason.contains("UTF-8"));

    let good = dir.join("good.toml");
    std::fs::write(&good, &*VALID_2D).unwrap();
    let s = sc::load_scene(&good, &["solver.end_time=3".to_string()]).unwrap();
    assert_eq!(s.end_time, 3.0);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Checks that `count_particles` agrees with `generate`.
fn check_counts<const D: usize>(text: &str) -> (sc::Scene, sc::Layout<D>) {
    let scene = parse(text).unwrap();
    let counts = sc::count_particles(&scene).unwrap();
    let layout = sc::generate::<D>(&scene).unwrap();
    assert_eq!(counts.fluid as usize, layout.fluid_position.len());
    assert_eq!(layout.fluid_velocity.len(), layout.fluid_position.len());
    assert_eq!(counts.solid.len(), layout.solids.len());
    for ((name, n), s) in counts.solid.iter().zip(&layout.solids) {
        assert_eq!(name, &s.name);
        assert_eq!(*n as usize, s.position.len(), "solid {name}");
    }
    let total = layout.fluid_position.len() + layout.solids.iter().map(|s| s.position.len()).sum::<usize>();
    assert_eq!(counts.total as usize, total);
    (scene, layout)
}

#[test]
fn counts_agree_with_generation() {
    let (_, l) = check_counts::<2>(&VALID_2D);
    assert_eq!(l.fluid_position.len(), 25 * 50);
    assert_eq!(l.solids[0].position.len(), 164 * 82 - 160 * 80);
    let closed = edit(
        &VALID_2D,
        "max = [1.6, 0.8]\n",
        "max = [1.6, 0.8]\nopen_top = false\n",
    );
    let (_, l) = check_counts::<2>(&closed);
    assert_eq!(l.solids[0].position.len(), 164 * 84 - 160 * 80);
    let (_, l) = check_counts::<3>(VALID_3D);
    assert_eq!(l.fluid_position.len(), 10 * 20 * 10);
    assert_eq!(l.solids[0].position.len(), 24 * 24 * 24 - 20 * 20 * 20);
    assert_eq!(l.solids[1].position.len(), 2 * 4 * 4);
    assert!(
        l.fluid_velocity
            .iter()
            .all(|v| v.x == 0.1f32 && v.y == 0.0 && v.z == 0.0)
    );
    let open = edit(VALID_3D, "open_top = false\n", "");
    let (_, l) = check_counts::<3>(&open);
    assert_eq!(l.solids[0].position.len(), 24 * 24 * 22 - 20 * 20 * 20);
    // Non-aligned extents and h/dx = 2.5 (L = 3).
    let odd = edit(&VALID_2D, "smoothing_ratio = 2.0", "smoothing_ratio = 2.5");
    let odd = edit(&odd, "max = [0.25, 0.5]", "max = [0.247, 0.5033]");
    let (scene, _) = check_counts::<2>(&odd);
    assert_eq!(scene.wall_layers(), 3);
}

#[test]
fn generate_rejects_wrong_dimension() {
    let scene = parse(&VALID_2D).unwrap();
    assert!(matches!(
        sc::generate::<3>(&scene),
        Err(SceneError::Dimension {
            scene: 2,
            requested: 3
        })
    ));
}

/// Every wall particle of container `solid` lies in the band of `L dx`
/// around the inside box and outside the inside box; returns the number of
/// distinct floor layers.
fn check_container_band<const D: usize>(scene: &sc::Scene, layout: &sc::Layout<D>, solid: usize) -> usize {
    let s = &scene.solids[solid];
    let band = scene.wall_layers() as f64 * scene.spacing;
    let eps = 1e-5;
    let mut floor_levels: Vec<i64> = Vec::new();
    for p in &layout.solids[solid].position {
        let mut outside = false;
        for k in 0..D {
            let (lo, hi, x) = (s.region.min[k], s.region.max[k], f64::from(p[k]));
            let top = if s.open_top && k == D - 1 { hi } else { hi + band };
            assert!(x > lo - band - eps && x < top + eps, "axis {k}: {x} outside band");
            outside |= x < lo || x > hi;
        }
        assert!(outside, "wall point {p:?} inside the container");
        let z = f64::from(p[D - 1]);
        if z < s.region.min[D - 1] {
            let level = ((s.region.min[D - 1] - z) / scene.spacing).round() as i64;
            if !floor_levels.contains(&level) {
                floor_levels.push(level);
            }
        }
    }
    floor_levels.len()
}

fn min_fluid_solid_distance<const D: usize>(layout: &sc::Layout<D>) -> f32 {
    let mut best = f32::INFINITY;
    for f in &layout.fluid_position {
        for s in layout.solids.iter().flat_map(|s| &s.position) {
            best = best.min((f - s).norm());
        }
    }
    best
}

#[test]
fn container_walls_have_l_layers_and_fluid_keeps_distance() {
    let (scene, layout) = check_counts::<2>(&VALID_2D);
    assert_eq!(check_container_band(&scene, &layout, 0), 2);
    let d = min_fluid_solid_distance(&layout);
    assert!(d >= 0.5 * scene.spacing as f32 - F32_ROUNDING as f32, "{d}");

    let (scene, layout) = check_counts::<3>(VALID_3D);
    assert_eq!(check_container_band(&scene, &layout, 0), 2);
    let d = min_fluid_solid_distance(&layout);
    assert!(d >= 0.5 * scene.spacing as f32 - F32_ROUNDING as f32, "{d}");

    let thick = edit(&VALID_2D, "smoothing_ratio = 2.0", "smoothing_ratio = 3.5");
    let (scene, layout) = check_counts::<2>(&thick);
    assert_eq!(scene.wall_layers(), 4);
    assert_eq!(check_container_band(&scene, &layout, 0), 4);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        check_result(sc::parse_scene(&String::from_utf8_lossy(&bytes), "fuzz", &[]));
    }

    #[test]
    fn deleting_a_range_never_panics(which in 0usize..2, a in 0usize..2000, len in 0usize..40) {
        let text = if which == 0 { VALID_2D.as_str() } else { VALID_3D };
        let mut bytes = text.as_bytes().to_vec();
        let a = a % bytes.len();
        let b = (a + len).min(bytes.len());
        bytes.drain(a..b);
        check_result(sc::parse_scene(&String::from_utf8_lossy(&bytes), "fuzz", &[]));
    }

    #[test]
    fn duplicating_a_line_never_panics(which in 0usize..2, n in 0usize..100) {
        let text = if which == 0 { VALID_2D.as_str() } else { VALID_3D };
        let mut lines: Vec<&str> = text.lines().collect();
        let n = n % lines.len();
        lines.insert(n, lines[n]);
        check_result(sc::parse_scene(&lines.join("\n"), "fuzz", &[]));
    }

    #[test]
    fn replacing_a_number_never_panics(which in 0usize..2, n in 0usize..100, g in 0usize..GARBAGE.len()) {
        let text = if which == 0 { VALID_2D.as_str() } else { VALID_3D };
        let numbers: Vec<(usize, usize)> = number_spans(text);
        let (a, b) = numbers[n % numbers.len()];
        let mutated = format!("{}{}{}", &text[..a], GARBAGE[g], &text[b..]);
        check_result(sc::parse_scene(&mutated, "fuzz", &[]));
    }

    #[test]
    fn truncating_never_panics(which in 0usize..2, n in 0usize..2000) {
        let text = if which == 0 { VALID_2D.as_str() } else { VALID_3D };
        let n = n % (text.len() + 1);
        check_result(sc::parse_scene(&text[..n], "fuzz", &[]));
    }

    #[test]
    fn random_overrides_never_panic(key in "[a-z_.0-9]{0,20}", value in "[ -~]{0,20}") {
        check_result(parse_set(&VALID_2D, &[&format!("{key}={value}")]));
    }
}

/// Byte ranges of the numeric literals in `text`.
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts = bytes[i].is_ascii_digit()
            || (bytes[i] == b'-' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit));
        let in_word = i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_');
        if starts && !in_word {
            let mut j = i + 1;
            while j < bytes.len() && (bytes[j].is_ascii_alphanumeric() || b".-+".contains(&bytes[j])) {
                j += 1;
            }
            out.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

#[test]
fn missing_top_level_key_has_unknown_location() {
    let start = VALID_2D.find("[domain]").unwrap();
    let end = VALID_2D.find("[particles]").unwrap();
    let text = format!("{}{}", &VALID_2D[..start], &VALID_2D[end..]);
    let ps = problems(parse(&text));
    let p = with_key(&ps, "domain");
    assert_eq!(p.location, Location::Unknown);
    let shown = parse(&text).unwrap_err().to_string();
    assert_eq!(shown, "test.toml: domain: missing field `domain`");
}

/// `VALID_2D` with a motion table on its tank (the line right after the tank's `max`).
fn with_motion(motion: &str) -> String {
    edit(
        &VALID_2D,
        "max = [1.6, 0.8]\n",
        &format!("max = [1.6, 0.8]\nmotion = {motion}\n"),
    )
}

#[test]
fn solid_motion_resolves_to_a_sway() {
    let text = with_motion("{ amplitude = [0.02, 0.0], period = 1.5, ramp = 0.5 }");
    let scene = parse(&text).expect("valid motion");
    let sway = scene.solids[0]
        .motion
        .as_ref()
        .expect("the tank moves")
        .sway()
        .expect("a sway");
    assert_eq!(sway.amplitude, vec![0.02, 0.0]);
    assert_eq!((sway.period, sway.ramp), (1.5, 0.5));
    let no_ramp = parse(&with_motion("{ amplitude = [0.02, 0.01], period = 2.0 }")).expect("valid");
    assert_eq!(
        no_ramp.solids[0]
            .motion
            .as_ref()
            .and_then(|m| m.sway())
            .map(|s| s.ramp),
        Some(0.0)
    );
    assert_eq!(
        parse(&VALID_2D).expect("valid").solids[0].motion,
        None,
        "fixed by default"
    );
}

#[test]
fn bad_solid_motion_names_the_key_and_line() {
    let cases = [
        (
            "{ amplitude = [0.02, 0.0], period = 0.0 }",
            "solid[0].motion.period",
            "must be > 0",
        ),
        (
            "{ amplitude = [0.02, 0.0], period = -1.0 }",
            "solid[0].motion.period",
            "must be > 0",
        ),
        (
            "{ amplitude = [0.0, 0.0], period = 1.0 }",
            "solid[0].motion.amplitude",
            "all entries are 0",
        ),
        (
            "{ amplitude = [0.02], period = 1.0 }",
            "solid[0].motion.amplitude",
            "expected 2 entries",
        ),
        (
            "{ amplitude = [0.02, nan], period = 1.0 }",
            "solid[0].motion.amplitude[1]",
            "finite",
        ),
        (
            "{ amplitude = [0.02, 0.0], period = 1.0, ramp = -0.1 }",
            "solid[0].motion.ramp",
            "must be >= 0",
        ),
        (
            "{ amplitude = [0.02, 0.0], period = inf }",
            "solid[0].motion.period",
            "finite",
        ),
    ];
    for (motion, key, why) in cases {
        let p = problem_at(&with_motion(motion), key, "motion = ", why);
        assert!(
            !p.render("test.toml").contains('\n'),
            "one line: {}",
            p.render("test.toml")
        );
    }
}

#[test]
fn unknown_or_missing_motion_key_is_named() {
    let text = with_motion("{ amplitude = [0.02, 0.0], frequency = 1.0 }");
    let ps = problems(parse(&text));
    assert_eq!(ps.len(), 1, "{ps:#?}");
    assert!(ps[0].key.starts_with("solid[0].motion"), "{ps:#?}");
    assert_eq!(line(&ps[0]), line_of(&text, "motion = ", 0));
    assert!(ps[0].reason.contains("frequency"), "{}", ps[0].reason);
}

#[test]
fn moving_solid_must_stay_inside_the_domain() {
    // The walls reach x = -0.02 and 1.62; swaying by 0.02 m keeps them inside [-0.05, 1.65],
    // by 0.04 m they would reach -0.06 and 1.66.
    assert!(parse(&with_motion("{ amplitude = [0.02, 0.0], period = 1.0 }")).is_ok());
    let text = with_motion("{ amplitude = [-0.04, 0.0], period = 1.0 }");
    let p = only_problem_at(&text, "solid[0].motion.amplitude", "motion = ", "sweeps");
    assert!(p.reason.contains("axis x"), "{}", p.reason);
    // Vertically the lid-less tank's walls reach 0.8; the domain ends at 1.0.
    let text = with_motion("{ amplitude = [0.0, 0.3], period = 1.0 }");
    let p = with_key(&problems(parse(&text)), "solid[0].motion.amplitude").clone();
    assert!(p.reason.contains("axis y"), "{}", p.reason);
}

/// `VALID_2D` with `lines` added to `[fluid]` (after `gravity_ramp`).
fn fluid_lines_2d(lines: &str) -> String {
    edit(
        &VALID_2D,
        "gravity_ramp = 0.1\n",
        &format!("gravity_ramp = 0.1\n{lines}"),
    )
}

/// [`fluid_lines_2d`] with `effect` added to the effects.
fn effect_2d(effect: &str, lines: &str) -> String {
    edit(
        &fluid_lines_2d(lines),
        "effects = [\"gravity\", \"viscosity\"]",
        &format!("effects = [\"gravity\", \"viscosity\", \"{effect}\"]"),
    )
}

/// `VALID_2D` with the `rotating_frame` effect and `lines` added to `[fluid]`.
fn rotating_2d(lines: &str) -> String {
    effect_2d("rotating_frame", lines)
}

/// `VALID_3D` with the `rotating_frame` effect and `lines` added to `[fluid]`.
fn rotating_3d(lines: &str) -> String {
    let text = edit(
        VALID_3D,
        "effects = [\"gravity\"]",
        "effects = [\"gravity\", \"rotating_frame\"]",
    );
    edit(
        &text,
        "gravity = [0.0, 0.0, -9.81]\n",
        &format!("gravity = [0.0, 0.0, -9.81]\n{lines}"),
    )
}

#[test]
fn rotating_frame_resolves_to_three_components_in_2d_and_3d() {
    // 2D, a number: about the out-of-plane axis; the centre defaults to the origin.
    let s = parse(&rotating_2d("angular_velocity = 2.5\n")).expect("valid");
    assert!(s.has(Effect::RotatingFrame));
    assert_eq!(s.angular_velocity, Some([0.0, 0.0, 2.5]));
    assert_eq!(s.rotation_centre, vec![0.0, 0.0]);
    // 2D, two entries: an axis in the plane (the slice model).
    let s = parse(&rotating_2d(
        "angular_velocity = [0.0, 7.0]\nrotation_centre = [0.5, 0.0]\n",
    ))
    .expect("valid");
    assert_eq!(s.angular_velocity, Some([0.0, 7.0, 0.0]));
    assert_eq!(s.rotation_centre, vec![0.5, 0.0]);
    // 3D.
    let s = parse(&rotating_3d("angular_velocity = [0.0, 0.0, 3.0]\n")).expect("valid");
    assert_eq!(s.angular_velocity, Some([0.0, 0.0, 3.0]));
    assert_eq!(s.rotation_centre, vec![0.0, 0.0, 0.0]);
    // Off: no angular velocity.
    assert_eq!(parse(&VALID_2D).expect("valid").angular_velocity, None);
}

#[test]
fn rotating_frame_bad_input_names_the_key() {
    // The effect without its key.
    problem_with(&rotating_2d(""), "fluid.angular_velocity", "required");
    // The keys without the effect.
    let text = fluid_lines_2d("angular_velocity = 1.0\nrotation_centre = [0.0, 0.0]\n");
    let ps = problems(parse(&text));
    assert_eq!(ps.len(), 2, "{ps:#?}");
    let p = with_key(&ps, "fluid.angular_velocity");
    assert!(p.reason.contains("not enabled"), "{}", p.reason);
    assert_eq!(line(p), line_of(&text, "angular_velocity", 0));
    assert!(
        with_key(&ps, "fluid.rotation_centre")
            .reason
            .contains("not enabled")
    );
    // Wrong lengths.
    problem_with(
        &rotating_2d("angular_velocity = [0.0, 1.0, 2.0]\n"),
        "fluid.angular_velocity",
        "expected 2 entries",
    );
    problem_with(
        &rotating_2d("angular_velocity = 1.0\nrotation_centre = [0.0]\n"),
        "fluid.rotation_centre",
        "expected 2 entries",
    );
    // A number is for 2D only.
    problem_with(
        &rotating_3d("angular_velocity = 3.0\n"),
        "fluid.angular_velocity",
        "2D only",
    );
    // Not a number or an array.
    problem_with(
        &rotating_2d("angular_velocity = \"fast\"\n"),
        "fluid.angular_velocity",
        "a number",
    );
    // Integers are numbers.
    let s = parse(&rotating_2d("angular_velocity = [0, 7]\n")).expect("valid");
    assert_eq!(s.angular_velocity, Some([0.0, 7.0, 0.0]));
    let s = parse(&rotating_2d("angular_velocity = 2\n")).expect("valid");
    assert_eq!(s.angular_velocity, Some([0.0, 0.0, 2.0]));
    // Non-finite.
    let ps = problems(parse(&rotating_2d("angular_velocity = [0.0, nan]\n")));
    with_key(&ps, "fluid.angular_velocity[1]");
}

/// `VALID_2D` with the `surface_tension` effect and `lines` added to `[fluid]`.
fn surface_tension_2d(lines: &str) -> String {
    effect_2d("surface_tension", lines)
}

#[test]
fn surface_tension_resolves_with_its_effect_only() {
    let s = parse(&surface_tension_2d("surface_tension = 0.072\n")).expect("valid");
    assert!(s.has(Effect::SurfaceTension));
    assert_eq!(s.surface_tension, Some(0.072));
    assert_eq!(
        s.surface_tension_model,
        SurfaceTensionModel::SurfaceStress,
        "the default"
    );
    let s = parse(&surface_tension_2d(
        "surface_tension = 0.072\nsurface_tension_model = \"akinci\"\n",
    ))
    .expect("valid");
    assert_eq!(s.surface_tension_model, SurfaceTensionModel::Akinci);
    assert_eq!(parse(&VALID_2D).expect("valid").surface_tension, None);
}

#[test]
fn surface_tension_model_bad_input_names_the_key() {
    // An unknown model.
    let ps = problems(parse(&surface_tension_2d(
        "surface_tension = 0.072\nsurface_tension_model = \"csf\"\n",
    )));
    let p = with_key(&ps, "fluid.surface_tension_model");
    assert!(
        p.reason.contains("surface_stress") && p.reason.contains("akinci"),
        "{}",
        p.reason
    );
    // The model without the effect, on its line.
    let text = fluid_lines_2d("surface_tension_model = \"akinci\"\n");
    only_problem_at(
        &text,
        "fluid.surface_tension_model",
        "surface_tension_model",
        "not enabled",
    );
}

#[test]
fn surface_tension_bad_input_names_the_key() {
    // The effect without its key.
    problem_with(&surface_tension_2d(""), "fluid.surface_tension", "required");
    // The key without the effect, on its line.
    let text = fluid_lines_2d("surface_tension = 0.072\n");
    only_problem_at(&text, "fluid.surface_tension", "surface_tension", "not enabled");
    // Zero, negative, non-finite.
    for bad in ["0.0", "-0.072", "nan", "inf"] {
        let ps = problems(parse(&surface_tension_2d(&format!("surface_tension = {bad}\n"))));
        let p = with_key(&ps, "fluid.surface_tension");
        assert!(
            p.reason.contains("> 0") || p.reason.contains("finite"),
            "{bad}: {}",
            p.reason
        );
    }
    // Not a number.
    let ps = problems(parse(&surface_tension_2d("surface_tension = \"strong\"\n")));
    with_key(&ps, "fluid.surface_tension");
}

/// `VALID_2D` with `effects` replaced and `lines` added to its `[[fluid_box]]`.
fn phased_2d(effects: &str, lines: &str) -> String {
    edit(
        &edit(
            &VALID_2D,
            "effects = [\"gravity\", \"viscosity\"]",
            &format!("effects = {effects}"),
        ),
        "max = [0.25, 0.5]\n",
        &format!("max = [0.25, 0.5]\n{lines}"),
    )
}

#[test]
fn multiphase_box_density_resolves_and_defaults_to_the_fluid() {
    let s = parse(&phased_2d(
        r#"["gravity", "viscosity", "multiphase"]"#,
        "rho0 = 800.0\n",
    ))
    .expect("valid");
    assert!(s.has(Effect::Multiphase));
    assert_eq!(s.fluid_boxes[0].rho0, Some(800.0));
    // The effect without any box of another density is allowed: one phase, the multiphase
    // variants of the stages (tests/physics/multiphase.rs: equal to the plain run to rounding).
    let s = parse(&phased_2d(r#"["gravity", "viscosity", "multiphase"]"#, "")).expect("valid");
    assert_eq!(s.fluid_boxes[0].rho0, None);
    assert_eq!(parse(&VALID_2D).expect("valid").fluid_boxes[0].rho0, None);
}

#[test]
fn multiphase_bad_input_names_the_key() {
    // The key without the effect.
    let text = phased_2d(r#"["gravity", "viscosity"]"#, "rho0 = 800.0\n");
    let p = only_problem_at(&text, "fluid_box[0].rho0", "rho0 = 800.0", "not enabled");
    assert!(p.reason.contains("multiphase"), "{}", p.reason);
    // Not positive, not finite, not a number.
    for bad in ["0.0", "-800.0", "nan", "inf"] {
        let ps = problems(parse(&phased_2d(
            r#"["gravity", "viscosity", "multiphase"]"#,
            &format!("rho0 = {bad}\n"),
        )));
        let p = with_key(&ps, "fluid_box[0].rho0");
        assert!(
            p.reason.contains("> 0") || p.reason.contains("finite"),
            "{bad}: {}",
            p.reason
        );
    }
    let ps = problems(parse(&phased_2d(
        r#"["gravity", "viscosity", "multiphase"]"#,
        "rho0 = \"oil\"\n",
    )));
    assert!(ps.iter().any(|p| p.key.contains("rho0")), "{ps:#?}");
}
