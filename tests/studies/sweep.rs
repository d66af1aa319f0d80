//! `sph sweep`: splitting value lists, the variants of several swept keys, validation of every
//! variant before anything runs, and a whole sweep of a tiny dam break over
//! `solver.kind=wcsph,corrected` (its `sweep.csv`, `sweep.png` and `fronts.png`).

use sph::run::RunOptions;
use sph::sweep::{Sweep, SweepError, comparisons_from_csv, run_sweep, split_values, variant_dir};
use std::path::{Path, PathBuf};

/// A made-up surge-front record in the format of Martin & Moyce's digitisations (the sweep's
/// machinery is tested here, not the physics): `Z = 1 + T²/2` at a few normalised times.
const SURGE_FRONT: &str = "series,n2_height_over_width,a_column_width_in,T_n_t_sqrt_g_over_a,Z_front_over_a
MM1952_n2-1_jaxsph,1,,0.20,1.02
MM1952_n2-1_jaxsph,1,,0.43,1.09
MM1952_n2-1_trixiparticles,1,,0.62,1.19
MM1952_n2-1_trixiparticles,1,,0.90,1.41
";

/// A 2D dam break of 10 x 10 particles: a column a = 1 cm (dx = 1 mm) in a 5 cm tank, run to
/// t = 20 ms, i.e. T = t sqrt(g/a) = 0.63, which reaches two of the reference points.
fn tiny_scene() -> String {
    String::from(
        r#"name = "tiny_dam_break"
dimension = 2
effects = ["gravity", "viscosity"]

[domain]
min = [-0.005, -0.005]
max = [0.055, 0.03]

[particles]
spacing = 0.001
smoothing_ratio = 2.0

[fluid]
rho0 = 1000.0
sound_speed = 5.0
viscosity = 1.0e-3
gravity = [0.0, -9.81]

[[fluid_box]]
min = [0.0, 0.0]
max = [0.01, 0.01]

[[solid]]
name = "tank"
shape = "container"
min = [0.0, 0.0]
max = [0.05, 0.02]
open_top = true

[solver]
kind = "corrected"
cfl = 0.2
end_time = 0.02

[output]
frames = false

[[probe]]
name = "front"
kind = "front"
axis = "x"

[probe.reference]
file = "front.csv"
series = ["MM1952_n2-1_jaxsph", "MM1952_n2-1_trixiparticles"]
length = 0.01
time_range = [0.0, 3.0]
"#,
    )
}

/// A fresh directory holding the tiny scene; returns (directory, scene path).
fn scene_dir(name: &str) -> (PathBuf, PathBuf) {
    let dir = std::env::temp_dir().join(format!("sph_sweep_test_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let scene = dir.join("tiny.toml");
    std::fs::write(&scene, tiny_scene()).expect("scene written");
    std::fs::write(dir.join("front.csv"), SURGE_FRONT).expect("reference written");
    (dir, scene)
}

fn strings(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

fn options() -> RunOptions {
    RunOptions {
        out_dir: None,
        force: false,
        stop: None,
        ranks: None,
        backend: Default::default(),
        threads: rayon::current_num_threads(),
        scene_name: "tiny_dam_break".into(),
        restart: Default::default(),
    }
}

/// `sweep.csv` as (header, rows), through the program's CSV reader.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let table = sph::output::CsvFile::read(path).expect("sweep.csv");
    let rows = (0..table.len())
        .map(|r| {
            (0..table.header().len())
                .map(|k| table.text(r, k).to_string())
                .collect()
        })
        .collect();
    (table.header().to_vec(), rows)
}

fn is_png(path: &Path) -> bool {
    let bytes = std::fs::read(path).unwrap_or_default();
    bytes.starts_with(&[0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a])
}

#[test]
fn values_split_on_commas_outside_brackets_and_quotes() {
    assert_eq!(
        split_values("1e-2,1e-3,1e-4,1e-5"),
        ["1e-2", "1e-3", "1e-4", "1e-5"]
    );
    assert_eq!(split_values("wcsph, corrected"), ["wcsph", "corrected"]);
    assert_eq!(split_values("corrected"), ["corrected"]);
    assert_eq!(split_values("[0,-9.81]"), ["[0,-9.81]"]);
    assert_eq!(
        split_values("[0,-9.81],[0, -19.62]"),
        ["[0,-9.81]", "[0, -19.62]"]
    );
    assert_eq!(
        split_values(r#"["gravity"],["gravity","viscosity"]"#),
        [r#"["gravity"]"#, r#"["gravity","viscosity"]"#]
    );
    assert_eq!(split_values(r#""a,b",c"#), [r#""a,b""#, "c"]);
    assert_eq!(split_values(r#"'a,b'"#), ["'a,b'"]);
    assert_eq!(split_values(r#""a\",b""#), [r#""a\",b""#]);
    assert_eq!(
        split_values("{ a = 1, b = [2, 3] },{ a = 4 }"),
        ["{ a = 1, b = [2, 3] }", "{ a = 4 }"]
    );
}

#[test]
fn swept_keys_give_the_cartesian_product_first_key_slowest() {
    let sweep = Sweep::from_sets(&strings(&[
        "solver.kind=wcsph,corrected",
        "solver.cfl=0.1",
        "fluid.gravity=[0,-9.81],[0,-1],[0,-2]",
    ]))
    .expect("valid sets");
    assert_eq!(sweep.keys, ["solver.kind", "fluid.gravity"]);
    let names: Vec<&str> = sweep.variants.iter().map(|v| v.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "solver.kind=wcsph fluid.gravity=[0,-9.81]",
            "solver.kind=wcsph fluid.gravity=[0,-1]",
            "solver.kind=wcsph fluid.gravity=[0,-2]",
            "solver.kind=corrected fluid.gravity=[0,-9.81]",
            "solver.kind=corrected fluid.gravity=[0,-1]",
            "solver.kind=corrected fluid.gravity=[0,-2]",
        ]
    );
    let v = &sweep.variants[4];
    assert_eq!(v.values, ["corrected", "[0,-1]"]);
    assert_eq!(
        v.sets,
        ["solver.kind=corrected", "solver.cfl=0.1", "fluid.gravity=[0,-1]"]
    );
    assert_eq!(
        variant_dir(Path::new("out"), 4, 6, v),
        Path::new("out/5-solver.kind_corrected_fluid.gravity_0_-1")
    );
    assert_eq!(
        sweep.columns(&strings(&["front"]))[..3],
        ["variant", "solver.kind", "fluid.gravity"]
    );

    let twelve = Sweep::from_sets(&strings(&["a=1,2,3", "b=1,2,3,4"])).expect("valid");
    assert_eq!(twelve.variants.len(), 12);
    assert_eq!(
        variant_dir(Path::new("d"), 0, 12, &twelve.variants[0]),
        Path::new("d/01-a_1_b_1")
    );

    let single = Sweep::from_sets(&strings(&["solver.cfl=0.1"])).expect("valid");
    assert!(single.keys.is_empty());
    assert_eq!(single.variants.len(), 1);
    assert_eq!(single.variants[0].name, "base");
    assert_eq!(single.variants[0].sets, ["solver.cfl=0.1"]);
}

#[test]
fn malformed_sets_are_rejected() {
    let err = |sets: &[&str]| Sweep::from_sets(&strings(sets)).expect_err("invalid").to_string();
    assert!(err(&["solver.kind"]).contains("no '=' found"));
    assert!(err(&["solver.delta=1e-3,,1e-4"]).contains("empty value"));
    assert!(err(&["=1,2"]).contains("empty KEY"));
    let twice = err(&["solver.delta=1e-3,1e-4", "solver.delta=1e-5"]);
    assert!(
        twice.contains("solver.delta") && twice.contains("only once"),
        "{twice}"
    );
}

#[test]
fn an_invalid_value_names_key_and_value_before_anything_runs() {
    let (dir, scene) = scene_dir("invalid");
    let sweep = Sweep::from_sets(&strings(&["solver.delta=1e-3,abc,1e-5"])).expect("sets");
    let err = sweep.load(&scene).expect_err("abc is not a number");
    assert!(
        matches!(
            err,
            SweepError::InvalidVariant {
                index: 2,
                count: 3,
                ..
            }
        ),
        "{err:?}"
    );
    let shown = err.to_string();
    assert!(shown.contains("solver.delta=abc"), "{shown}");

    // Through the command line: the error names the key and value, and no variant has run.
    let out = dir.join("out");
    let result = sph::cli::run::<_, &std::ffi::OsStr>([
        "sph".as_ref(),
        "sweep".as_ref(),
        scene.as_os_str(),
        "--set".as_ref(),
        "solver.delta=1e-3,abc".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    let shown = format!("{:#}", result.expect_err("invalid variant"));
    assert!(shown.contains("solver.delta=abc"), "{shown}");
    assert!(shown.contains("expected f64"), "{shown}");
    assert!(!out.exists(), "nothing may run before every variant is valid");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sweep_over_solver_kind_writes_table_and_figures() {
    let (dir, scene) = scene_dir("kinds");
    let out = dir.join("out");
    let sweep = Sweep::from_sets(&strings(&["solver.kind=wcsph,corrected"])).expect("sets");
    let mut scenes = sweep.load(&scene).expect("variants load");
    for s in &mut scenes {
        assert!(sph::scene::locate_references(s, Some(&dir)).is_empty());
    }
    let mut started = Vec::new();
    let report = run_sweep(&sweep, &scenes, &out, &options(), &mut |e| {
        if let sph::sweep::SweepEvent::Started { index, count, .. } = e {
            started.push((index, count));
        }
    })
    .expect("sweep runs");
    assert_eq!(started, [(1, 2), (2, 2)]);
    assert!(report.skipped_figures.is_empty(), "{:?}", report.skipped_figures);

    let (header, rows) = read_csv(&out.join("sweep.csv"));
    assert_eq!(
        header,
        [
            "variant",
            "solver.kind",
            "wall_s",
            "wall_s_per_simulated_s",
            "particle_steps_per_s",
            "steps",
            "correction_iterations_mean",
            "correction_iterations_max",
            "velocity_iterations_mean",
            "operator_applications_per_stage",
            "unconverged_stages",
            "max_compression",
            "max_surface_deficit",
            "front_relative_error_max",
            "front_relative_error_mean",
            "status",
        ]
    );
    assert_eq!(rows.len(), 2);
    let col = |name: &str| header.iter().position(|h| h == name).expect(name);
    let number = |row: &[String], name: &str| -> f64 {
        let cell = &row[col(name)];
        let x: f64 = cell.parse().unwrap_or_else(|_| panic!("{name} = {cell:?}"));
        assert!(x.is_finite(), "{name} = {x}");
        x
    };
    for (row, kind) in rows.iter().zip(["wcsph", "corrected"]) {
        assert_eq!(row[col("variant")], format!("solver.kind={kind}"));
        assert_eq!(row[col("solver.kind")], kind);
        assert_eq!(row[col("status")], "completed");
        assert!(number(row, "wall_s") > 0.0);
        assert!(number(row, "particle_steps_per_s") > 0.0);
        assert!(number(row, "steps") >= 1.0);
        assert!(number(row, "max_compression") >= 0.0);
        // A dam-break column has a free surface: its particles there lack neighbours.
        assert!(number(row, "max_surface_deficit") > 0.05);
        let (max, mean) = (
            number(row, "front_relative_error_max"),
            number(row, "front_relative_error_mean"),
        );
        assert!(0.0 <= mean && mean <= max, "front error mean {mean}, max {max}");
    }
    assert_eq!(
        rows[0][col("correction_iterations_mean")],
        "",
        "wcsph has no correction"
    );
    assert!(number(&rows[1], "correction_iterations_mean") >= 1.0);
    assert!(number(&rows[1], "correction_iterations_max") >= 1.0);
    // Every stage applies the operators at least once (position sweeps + velocity iterations).
    assert!(
        number(&rows[1], "operator_applications_per_stage") >= number(&rows[1], "correction_iterations_mean")
    );
    assert_eq!(
        rows[0][col("operator_applications_per_stage")],
        "",
        "wcsph has no correction"
    );
    assert_eq!(number(&rows[1], "unconverged_stages"), 0.0);

    // The curves read back from each variant's probes.csv give the errors of its summary.
    for (r, s) in report.results.iter().zip(&scenes) {
        assert!(r.dir.join("summary.json").is_file());
        let comparisons = comparisons_from_csv(s, &r.dir.join("probes.csv")).expect("probes.csv");
        assert_eq!(comparisons.len(), 1);
        let error = comparisons[0].error.expect("reference points reached");
        assert_eq!(Some(error.mean), r.probe_error("front", "error_mean"));
        assert_eq!(Some(error.max), r.probe_error("front", "error_max"));
    }
    assert_eq!(report.results[0].dir, out.join("1-solver.kind_wcsph"));
    assert!(is_png(&out.join("sweep.png")), "sweep.png");
    assert!(is_png(&out.join("fronts.png")), "fronts.png");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_failed_variant_is_recorded_and_the_sweep_goes_on() {
    let (dir, scene) = scene_dir("failed");
    let out = dir.join("out");
    // One correction iteration cannot reach delta, and strict makes that a step error.
    sph::cli::run([
        "sph".as_ref(),
        "sweep".as_ref(),
        scene.as_os_str(),
        "--set".as_ref(),
        "solver.max_iterations=1,200".as_ref(),
        "--set".as_ref(),
        "solver.strict=true".as_ref(),
        "--end-time".as_ref(),
        "0.01".as_ref(),
        "--threads".as_ref(),
        "1".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ] as [&std::ffi::OsStr; 13])
    .expect("a failed variant does not fail the sweep");
    let (header, rows) = read_csv(&out.join("sweep.csv"));
    let status = header.iter().position(|h| h == "status").expect("status");
    assert_eq!(rows.len(), 2);
    assert!(rows[0][status].starts_with("failed: "), "{}", rows[0][status]);
    assert_eq!(rows[1][status], "completed");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn solvers_sweep_each_solver_over_its_own_key() {
    let sweep = Sweep::solvers(
        &strings(&["wcsph=20,35", "corrected=1e-2,1e-3,1e-4"]),
        &strings(&["solver.end_time=0.1"]),
    )
    .expect("solvers");
    assert_eq!(sweep.keys, ["solver.kind", "fluid.sound_speed", "solver.delta"]);
    let names: Vec<&str> = sweep.variants.iter().map(|v| v.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "solver.kind=wcsph fluid.sound_speed=20",
            "solver.kind=wcsph fluid.sound_speed=35",
            "solver.kind=corrected solver.delta=1e-2",
            "solver.kind=corrected solver.delta=1e-3",
            "solver.kind=corrected solver.delta=1e-4",
        ]
    );
    assert_eq!(sweep.variants[1].values, ["wcsph", "35", ""]);
    assert_eq!(sweep.variants[4].values, ["corrected", "", "1e-4"]);
    assert_eq!(
        sweep.variants[0].sets,
        ["solver.end_time=0.1", "solver.kind=wcsph", "fluid.sound_speed=20"]
    );
    for (given, sets, part) in [
        (vec!["sph=1,2"], vec![], "wcsph (sound speeds) or corrected"),
        (vec!["wcsph"], vec![], "expected KIND=V1,V2"),
        (vec!["wcsph=20", "wcsph=35"], vec![], "once"),
        (vec!["corrected=1e-3,"], vec![], "empty value"),
        (vec!["wcsph=20"], vec!["fluid.rho0=1000,998"], "one value"),
    ] {
        let err = Sweep::solvers(&strings(&given), &strings(&sets)).expect_err("refused");
        assert!(err.to_string().contains(part), "{given:?}: {err}");
    }
}

/// `sph sweep --solvers` on the tiny dam break: one row per solver setting, the cost per simulated
/// second in `sweep.csv`, and `pareto.png` beside the other figures.
#[test]
fn solvers_sweep_writes_the_pareto_figure() {
    let (dir, scene) = scene_dir("solvers");
    let out = dir.join("out");
    sph::cli::run([
        "sph".as_ref(),
        "sweep".as_ref(),
        scene.as_os_str(),
        "--solvers".as_ref(),
        "wcsph=5,10".as_ref(),
        "--solvers".as_ref(),
        "corrected=1e-3".as_ref(),
        "--end-time".as_ref(),
        "0.01".as_ref(),
        "--reference-dir".as_ref(),
        dir.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ] as [&std::ffi::OsStr; 13])
    .unwrap_or_else(|e| panic!("sph sweep --solvers: {e:#}"));
    let (header, rows) = read_csv(&out.join("sweep.csv"));
    let col = |name: &str| header.iter().position(|h| h == name).expect(name);
    assert_eq!(rows.len(), 3);
    let kinds: Vec<&str> = rows.iter().map(|r| r[col("solver.kind")].as_str()).collect();
    assert_eq!(kinds, ["wcsph", "wcsph", "corrected"]);
    for row in &rows {
        assert_eq!(row[col("status")], "completed");
        let wall: f64 = row[col("wall_s")].parse().expect("wall");
        let per: f64 = row[col("wall_s_per_simulated_s")].parse().expect("per second");
        assert!(
            (per - wall / 0.01).abs() <= 1e-6 * per,
            "{per} against {wall} / 0.01 s"
        );
    }
    // A stiffer wcsph takes more steps for the same simulated time.
    let steps: Vec<f64> = rows
        .iter()
        .map(|r| r[col("steps")].parse().expect("steps"))
        .collect();
    assert!(steps[1] > steps[0], "steps at C = 5 and 10 m/s: {steps:?}");
    assert_eq!(rows[0][col("solver.delta")], "");
    assert!(is_png(&out.join("pareto.png")), "pareto.png");
    let _ = std::fs::remove_dir_all(&dir);
}
