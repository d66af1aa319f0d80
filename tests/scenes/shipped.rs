//! The shipped scenes: each is valid, `sph check` accepts it, the 3D ones run (short end time)
//! and the CLI writes the promised files; bad input is a clear error.

use crate::common::fresh_path as scratch;
use crate::common::tolerance::{F32_ROUNDING, F64_SUM};
use sph::output::{CsvFile, PvdSeries, read_summary, read_vtu};
use sph::run::{RunOptions, run_scene, simulation_from_scene};
use sph::scene::{count_particles, load_scene};
use std::path::Path;

const SHIPPED: [&str; 19] = [
    "scenes/dam_break_2d.toml",
    "scenes/dam_break_wall_2d.toml",
    "scenes/droplet_2d.toml",
    "scenes/hydrostatic_2d.toml",
    "scenes/poiseuille_2d.toml",
    "scenes/rotating_tank_2d.toml",
    "scenes/dam_break_column_3d.toml",
    "scenes/droplet_3d.toml",
    "scenes/yeh_petroff_3d.toml",
    "scenes/dam_break_obstacle_3d.toml",
    "scenes/wave_flume_2d.toml",
    "scenes/wave_flap_2d.toml",
    "scenes/floating_box_2d.toml",
    "scenes/floating_box_waves_2d.toml",
    "scenes/floating_box_3d.toml",
    "scenes/wave_flume_column_3d.toml",
    "scenes/wave_flume_focused_2d.toml",
    "scenes/wave_flume_irregular_2d.toml",
    "scenes/open_channel_2d.toml",
];

/// The columns of `steps.csv`, in order, as docs/output.md promises them. Spelled out here
/// rather than taken from the writer (`run::writers`, private), so that a change to the file's
/// layout shows as a failing test.
const STEP_COLUMNS: [&str; 11] = [
    "step",
    "t_s",
    "dt_s",
    "limit",
    "max_speed_m_per_s",
    "max_compression",
    "max_surface_deficit",
    "correction_iterations",
    "removed_particles",
    "created_particles",
    "outflow_particles",
];

#[test]
fn every_shipped_scene_is_valid_and_checks() {
    for path in SHIPPED {
        let scene = load_scene(Path::new(path), &[]).unwrap_or_else(|e| panic!("{path}: {e}"));
        assert!(count_particles(&scene).expect("counts").fluid > 0, "{path}");
        sph::cli::run(["sph", "check", path]).unwrap_or_else(|e| panic!("sph check {path}: {e:#}"));
    }
}

/// Section 4 of the paper as printed: about 112,588 fluid particles (ours: 111,888, dx = 10.8 mm).
#[test]
fn column_scene_has_the_papers_particle_count() {
    let scene = load_scene(Path::new("scenes/dam_break_column_3d.toml"), &[]).expect("valid");
    let fluid = count_particles(&scene).expect("counts").fluid as f64;
    assert!(
        (fluid - 112_588.0).abs() / 112_588.0 < 0.01,
        "{fluid} fluid particles"
    );
}

/// The 3D dam breaks run 30 ms of the collapse at twice their spacing (`--set
/// particles.spacing` alone, as a user coarsens them; CI runs each at its own spacing for 5 ms in
/// `tests/mpi/every_scene.sh`): the water starts to fall, no particle escapes, mass is constant,
/// the compression stays below 5 % (sound speed ~10x the flow speed gives ~1 %). The obstacle
/// scene (its STL obstacle read through the scene's relative path) runs at 5 cm.
#[test]
fn three_dimensional_scenes_run_a_short_time() {
    for (path, spacing) in [
        ("scenes/dam_break_column_3d.toml", "particles.spacing=0.0216"),
        ("scenes/yeh_petroff_3d.toml", "particles.spacing=0.0216"),
        ("scenes/dam_break_obstacle_3d.toml", "particles.spacing=0.05"),
    ] {
        let sets = vec!["solver.end_time=0.03".to_string(), spacing.to_string()];
        let scene = load_scene(Path::new(path), &sets).expect("valid");
        let mut sim = simulation_from_scene::<3>(&scene).expect("builds");
        let mass0 = sim.fluid_mass();
        let mut max_compression: f64 = 0.0;
        while sim.clock().time < scene.end_time {
            let r = sim.step(scene.end_time).unwrap_or_else(|e| panic!("{path}: {e}"));
            max_compression = max_compression.max(r.extremes.max_compression);
        }
        assert_eq!(sim.fluid_mass(), mass0, "{path}");
        assert!(max_compression < 0.05, "{path}: compression {max_compression}");
        let p = sim.fluid_momentum();
        assert!(p[2] < 0.0, "{path}: the column falls (momentum {p:?})");
        assert!(sim.solid_forces().iter().all(|f| f.iter().all(|c| c.is_finite())));
    }
}

/// The README's main command, through the library: the 2D dam break (shortened) writes
/// summary.json, a .pvd series with its .vtu frames, and forces.csv.
#[test]
fn run_writes_summary_frames_and_forces() {
    let out = scratch("dam");
    let mut scene = load_scene(
        Path::new("scenes/dam_break_2d.toml"),
        &["solver.end_time=0.05".into()],
    )
    .expect("valid");
    // A bare clone has no reference data: the front is sampled, its comparison skipped.
    let skipped = sph::scene::locate_references(&mut scene, None);
    assert_eq!(skipped.len(), 1, "{skipped:?}");
    let options = RunOptions {
        out_dir: Some(out.clone()),
        force: false,
        stop: None,
        ranks: None,
        backend: sph::backend::BackendKind::Cpu,
        threads: rayon::current_num_threads(),
        scene_name: "dam_break_2d".into(),
        restart: Default::default(),
    };
    let summary = run_scene(&scene, &options, &mut |_| {}).expect("runs");
    let written = read_summary(&out.join("summary.json")).expect("summary.json");
    assert_eq!(written.steps, summary.steps);
    assert_eq!(written.status, "completed");
    assert_eq!(written.fluid_particles, 2500);
    assert!((written.simulated_time - 0.05).abs() < F64_SUM);
    assert!(written.particle_steps_per_second > 0.0);
    let front = &written.extra["probe_errors"]["front"];
    assert_eq!(front["status"], "skipped", "{front}");
    assert_eq!(front["reference_file"], "martin_moyce_1952_surge_front.csv");
    assert!(
        front["reason"]
            .as_str()
            .is_some_and(|r| r.contains("SPH_REFERENCE_DIR")),
        "{front}"
    );
    let series = PvdSeries::read(&out.join("particles.pvd")).expect("pvd");
    assert_eq!(series.len(), 4, "frames at t = 0, 0.02, 0.04, 0.05");
    let (_, last) = series.entries().last().expect("frames").clone();
    let frame = read_vtu(&out.join(last)).expect("vtu");
    assert_eq!(frame.points.len() as u64, written.particles);
    for name in ["velocity", "density", "pressure", "kind"] {
        assert!(frame.point_array(name).is_some(), "{name} in frame");
    }
    // Every CSV file reads back through the program's reader, with unit-named columns; a 2D
    // run's forces are per metre of depth.
    let forces = CsvFile::read(&out.join("forces.csv")).expect("forces.csv");
    assert_eq!(forces.header(), ["t_s", "solid", "fx_N_per_m", "fy_N_per_m"]);
    assert_eq!(
        forces.len() as u64,
        summary.steps,
        "one row per step for the tank"
    );
    for r in 0..forces.len() {
        assert_eq!(forces.text(r, 1), "tank");
        for k in [0, 2, 3] {
            assert!(forces.number(r, k).expect("number").is_finite(), "row {r}");
        }
    }
    let probes = CsvFile::read(&out.join("probes.csv")).expect("probes.csv");
    assert_eq!(probes.header(), ["t_s", "front_m"]);
    let front = probes.numbers(1).expect("front_m");
    assert!(front.iter().all(|z| (0.24..0.5).contains(z)), "front {front:?}");
    // steps.csv: one row per step, times adding up, each naming the criterion that limited it.
    let steps = CsvFile::read(&out.join("steps.csv")).expect("steps.csv");
    assert_eq!(steps.header(), STEP_COLUMNS);
    assert_eq!(steps.len() as u64, summary.steps);
    let column = |name: &str| steps.column(name).expect(name);
    let (t_s, dt_s, limit) = (column("t_s"), column("dt_s"), column("limit"));
    let mut t = 0.0;
    for k in 0..steps.len() {
        assert_eq!(steps.text(k, column("step")), (k + 1).to_string());
        t += steps.number(k, dt_s).expect("dt");
        assert!(
            (steps.number(k, t_s).expect("t") - t).abs() < 1e-9,
            "row {k}: t is the sum of dt"
        );
        assert!(
            [
                "flow_speed",
                "force",
                "viscosity",
                "end_time",
                "sound_speed",
                "fixed"
            ]
            .contains(&steps.text(k, limit)),
            "row {k}: limit {}",
            steps.text(k, limit)
        );
        // Position sweeps of the step: zero where the velocity solve left the positions within δ.
        let sweeps = steps
            .number(k, column("correction_iterations"))
            .expect("iterations");
        assert!(sweeps >= 0.0 && sweeps.fract() == 0.0, "row {k}: {sweeps} sweeps");
    }
    assert_eq!(
        steps.text(steps.len() - 1, limit),
        "end_time",
        "the last step lands on the end time"
    );
    // The corrected solver works in every stage: position sweeps plus velocity iterations.
    let work = written.extra["operator_applications_per_stage"]
        .as_f64()
        .expect("work");
    assert!(work >= 1.0, "{work} operator applications per stage");
    // The summary's headline numbers are the largest of the per-step columns (written in
    // round-trip notation, so equal to the bit), and mean what they say: the compression the
    // corrected solver bounds by delta, and the free-surface deficit of a column of water.
    let largest = |name: &str| {
        steps
            .numbers(column(name))
            .expect(name)
            .into_iter()
            .fold(0.0, f64::max)
    };
    assert_eq!(
        largest("max_compression").to_bits(),
        written.max_compression.to_bits()
    );
    assert_eq!(
        largest("max_surface_deficit").to_bits(),
        written.max_surface_deficit.to_bits()
    );
    let delta = written.extra["delta"].as_f64().expect("delta");
    assert_eq!(written.extra["unconverged_stages"].as_u64(), Some(0));
    // Tolerance: the step-start density is summed afresh after the sort, in another order than
    // the correction's last sum; f32 rounding of ~30 terms of ~1000 kg/m^3 moves the
    // compression by well under 1e-6.
    assert!(
        written.max_compression <= delta + F32_ROUNDING,
        "max compression {:e} above delta {delta:e}",
        written.max_compression
    );
    assert!(written.mean_compression <= written.max_compression);
    // Measured 0.20 over the first 0.1 s: a surface particle lacks a fifth of its neighbours.
    assert!(
        written.max_surface_deficit > 0.1 && written.max_surface_deficit < 0.6,
        "max surface deficit {}",
        written.max_surface_deficit
    );
    assert!(written.mean_surface_deficit > 0.0 && written.mean_surface_deficit < written.max_surface_deficit);
    assert!(
        written.extra.get("max_compression").is_none(),
        "one place for each number"
    );
    std::fs::remove_dir_all(&out).expect("cleanup");
}

#[test]
fn cli_reports_bad_input_without_panicking() {
    let err = sph::cli::run(["sph", "check", "scenes/does_not_exist.toml"]).expect_err("missing file");
    assert!(format!("{err:#}").contains("does_not_exist.toml"), "{err:#}");
    let err = sph::cli::run(["sph", "check", "scenes"]).expect_err("a directory");
    assert!(format!("{err:#}").contains("scenes"), "{err:#}");
    let err = sph::cli::run([
        "sph",
        "check",
        "scenes/dam_break_2d.toml",
        "--set",
        "particles.spacing=-1",
    ])
    .expect_err("negative spacing");
    assert!(format!("{err:#}").contains("particles.spacing"), "{err:#}");
    // An output folder that cannot be created: its parent is a regular file.
    let out = scratch("blocked");
    std::fs::create_dir_all(&out).expect("dir");
    std::fs::write(out.join("file"), b"x").expect("file");
    let target = out.join("file").join("run");
    let err = sph::cli::run([
        "sph",
        "run",
        "scenes/dam_break_2d.toml",
        "--end-time",
        "0.001",
        "--out",
        target.to_str().expect("utf-8 path"),
    ])
    .expect_err("unwritable output");
    assert!(format!("{err:#}").contains("file"), "{err:#}");
    let err = sph::cli::run([
        "sph",
        "run",
        "scenes/dam_break_2d.toml",
        "--backend",
        "cuda",
        "--end-time",
        "0.001",
    ])
    .expect_err("no CUDA backend yet");
    assert!(format!("{err:#}").contains("cuda"), "{err:#}");
    std::fs::remove_dir_all(&out).expect("cleanup");
}

/// A reference file that is there but malformed stops `sph run` before it computes, naming the
/// probe and the file, and leaves no output folder; a missing one is reported in one line, the
/// run goes on and `summary.json` records the comparison as skipped; one whose values no figure
/// can hold completes the run with a warning.
#[test]
fn run_refuses_a_malformed_reference_and_skips_a_missing_one() {
    let dir = scratch("missing_reference");
    let data = dir.join("data");
    std::fs::create_dir_all(&data).expect("dir");
    std::fs::write(
        data.join("martin_moyce_1952_surge_front.csv"),
        "series,T\nx,not a number\n",
    )
    .expect("write");
    let out = dir.join("run");
    let run = |out: &Path, refs: &Path| {
        sph::cli::run([
            "sph",
            "run",
            "scenes/dam_break_2d.toml",
            "--end-time",
            "0.002",
            "--reference-dir",
            refs.to_str().expect("utf-8"),
            "--out",
            out.to_str().expect("utf-8"),
        ])
    };
    let err = run(&out, &data).expect_err("malformed reference");
    let text = format!("{err:#}");
    assert!(
        text.contains("martin_moyce_1952_surge_front.csv") && text.contains("front"),
        "{text}"
    );
    assert!(text.contains("nothing written"), "{text}");
    // The output folder is made before the first step: none means nothing was computed.
    assert!(!out.exists(), "no output folder for a run that never started");

    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).expect("dir");
    run(&out, &empty).unwrap_or_else(|e| panic!("a missing reference is not an error: {e:#}"));
    let summary = read_summary(&out.join("summary.json")).expect("summary.json");
    let front = &summary.extra["probe_errors"]["front"];
    assert_eq!(front["status"], "skipped", "{front}");
    let reason = front["reason"].as_str().expect("reason");
    assert!(reason.contains(&empty.display().to_string()), "{reason}");
    assert!(out.join("probes.csv").exists(), "the probe is still sampled");

    // Finite values no figure can hold (±1e308): the run still completes, the figure's
    // failure is a warning, and the numbers stay in summary.json.
    let extreme = dir.join("extreme");
    std::fs::create_dir_all(&extreme).expect("dir");
    let mut record =
        String::from("series,n2_height_over_width,a_column_width_in,T_n_t_sqrt_g_over_a,Z_front_over_a\n");
    for (k, series) in ["MM1952_n2-1_jaxsph", "MM1952_n2-1_trixiparticles"]
        .iter()
        .enumerate()
    {
        for (t, z) in [(0.0, 1e308), (0.01, -1e308), (1.5 + k as f64, 1e308)] {
            record += &format!("{series},1,,{t},{z}\n");
        }
    }
    std::fs::write(extreme.join("martin_moyce_1952_surge_front.csv"), record).expect("write");
    let out = dir.join("extreme_run");
    run(&out, &extreme).unwrap_or_else(|e| panic!("a figure cannot fail the run: {e:#}"));
    let summary = read_summary(&out.join("summary.json")).expect("summary.json");
    assert_eq!(summary.status, "completed");
    assert!(
        summary
            .warnings
            .iter()
            .any(|w| w.contains("figures were not drawn") && w.contains("1.000e308")),
        "{:?}",
        summary.warnings
    );
    assert!(
        summary.extra["probe_errors"].get("front").is_some(),
        "{:?}",
        summary.extra
    );
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

/// `sph compare` draws two runs' force probes against the Yeh & Petroff record and refuses a run
/// without that probe, naming it.
#[test]
fn compare_draws_runs_against_the_reference() {
    let out = scratch("compare");
    std::fs::create_dir_all(&out).expect("dir");
    // A made-up force record in the reference directory (the scene names the file).
    let mut record = String::from("time_s,force_x_N\n");
    for k in 0..=80 {
        let t = f64::from(k) * 0.01;
        record.push_str(&format!(
            "{t},{}\n",
            if (0.3..0.4).contains(&t) { 35.0 } else { 0.0 }
        ));
    }
    for file in [
        "yeh_petroff_column_force_pysph.csv",
        "yeh_petroff_column_force_anuga.csv",
    ] {
        std::fs::write(out.join(file), &record).expect("write");
    }
    let refs = out.to_str().expect("utf-8").to_string();
    for (name, peak) in [("a", 30.0), ("b", 40.0)] {
        let dir = out.join(name);
        std::fs::create_dir_all(&dir).expect("dir");
        let mut csv = String::from("t_s,column_force_pysph_N,column_force_anuga_N\n");
        for k in 0..=80 {
            let t = f64::from(k) * 0.01;
            let f = if (0.3..0.4).contains(&t) { peak } else { 0.0 };
            csv.push_str(&format!("{t},{f},{f}\n"));
        }
        std::fs::write(dir.join("probes.csv"), csv).expect("write");
    }
    let figure = out.join("force.png");
    let run = |label: &str, dir: &str| format!("{label}={}", out.join(dir).display());
    sph::cli::run([
        "sph",
        "compare",
        "scenes/yeh_petroff_3d.toml",
        "--run",
        &run("a = 30", "a"),
        "--run",
        &run("b", "b"),
        "--probe",
        "column_force_pysph",
        "--t-max",
        "0.8",
        "--reference-dir",
        &refs,
        "--out",
        figure.to_str().expect("utf-8"),
    ])
    .unwrap_or_else(|e| panic!("sph compare: {e:#}"));
    let png = std::fs::read(&figure).expect("figure written");
    assert_eq!(&png[1..4], b"PNG");
    let err = sph::cli::run([
        "sph",
        "compare",
        "scenes/yeh_petroff_3d.toml",
        "--run",
        &run("a", "a"),
        "--probe",
        "no_such_probe",
        "--out",
        figure.to_str().expect("utf-8"),
    ])
    .expect_err("unknown probe");
    assert!(format!("{err:#}").contains("no_such_probe"), "{err:#}");
    std::fs::remove_dir_all(&out).expect("cleanup");
}
