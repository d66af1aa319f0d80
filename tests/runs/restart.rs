//! `sph run --checkpoint-every N` and `sph run --resume RUN_DIR`: a run killed with SIGKILL
//! leaves only complete files (checkpoint, frames, series, CSV logs), and resuming it ends with
//! the same probes, forces, frames and statistics, bit for bit, as a run that was never stopped.
//! And the state guards: a run that loses a particle or meets a non-finite value stops naming the
//! step, the time, the particle and the quantity, and keeps its last good frame and checkpoint.

use crate::common::fresh_path as scratch;
use crate::common::run::{DAM_BREAK_2D as SCENE, SPH as BIN, coarse_run, kill_when};
use crate::common::scene::unwalled_2d;
use crate::common::tolerance::F64_SUM;
use sph::output::{PvdSeries, read_summary, read_vtu};
use sph::solver::checkpoint::Checkpoint;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

/// The coarse dam break (wcsph) to 0.4 s with a checkpoint every 25 steps, quiet.
fn command(out: &Path) -> Command {
    let mut c = coarse_run(Path::new(SCENE), "wcsph", "0.4");
    c.args(["--checkpoint-every", "25", "--out"])
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    c
}

/// A CSV file ends with a whole line and reads back (every row as long as its header).
fn assert_complete_csv(path: &Path) {
    let text = std::fs::read_to_string(path).expect("csv");
    assert!(text.ends_with('\n'), "{}: ends mid-line", path.display());
    if let Err(e) = sph::output::CsvFile::read(path) {
        panic!("{e}");
    }
}

#[test]
fn a_killed_run_leaves_complete_files_and_resumes_bit_identically() {
    let straight = scratch("straight");
    assert!(command(&straight).status().expect("runs").success());

    let killed = scratch("killed");
    let child = command(&killed).spawn().expect("starts");
    let checkpoint = killed.join("checkpoint.bin");
    let status = kill_when(child, Duration::from_secs(60), "checkpoint", || {
        checkpoint.exists()
    });
    assert!(!status.success(), "the run was still going when killed");
    let running = read_summary(&killed.join("summary.json")).expect("written at the start");
    assert_eq!(running.status, "running", "killed before the end");

    // Everything left is complete.
    let state = Checkpoint::<2>::read(&checkpoint).expect("the checkpoint is whole");
    assert!(state.header.clock.step >= 25 && state.header.clock.step % 25 == 0);
    let series = PvdSeries::read(&killed.join("particles.pvd")).expect("the series is whole");
    for (_, file) in series.entries() {
        read_vtu(&killed.join(file)).unwrap_or_else(|e| panic!("frame {file}: {e}"));
    }
    assert_complete_csv(&killed.join("forces.csv"));
    assert_complete_csv(&killed.join("probes.csv"));
    assert_complete_csv(&killed.join("steps.csv"));

    let resumed = Command::new(BIN)
        .args(["run", "--threads", "1", "--resume"])
        .arg(&killed)
        .stdout(Stdio::null())
        .status()
        .expect("resumes");
    assert!(resumed.success());

    let a = read_summary(&straight.join("summary.json")).expect("straight summary");
    let b = read_summary(&killed.join("summary.json")).expect("resumed summary");
    assert_eq!(a.status, "completed");
    assert_eq!((a.steps, a.simulated_time), (b.steps, b.simulated_time));
    assert_eq!(a.max_compression.to_bits(), b.max_compression.to_bits());
    assert_eq!(a.mean_compression.to_bits(), b.mean_compression.to_bits());
    assert_eq!(a.max_surface_deficit.to_bits(), b.max_surface_deficit.to_bits());
    assert_eq!(a.mean_surface_deficit.to_bits(), b.mean_surface_deficit.to_bits());
    assert_eq!(a.extra.get("probe_errors"), b.extra.get("probe_errors"));
    assert_eq!(a.extra.get("time_step_limits"), b.extra.get("time_step_limits"));
    for file in ["probes.csv", "forces.csv", "steps.csv", "particles.pvd"] {
        let (x, y) = (
            std::fs::read(straight.join(file)).expect("straight"),
            std::fs::read(killed.join(file)).expect("resumed"),
        );
        assert!(x == y, "{file} differs after the restart");
    }
    let series = PvdSeries::read(&straight.join("particles.pvd")).expect("series");
    let (_, last) = series.entries().last().expect("frames");
    assert_eq!(
        std::fs::read(straight.join(last)).expect("frame"),
        std::fs::read(killed.join(last)).expect("frame"),
        "the last frame differs"
    );
    std::fs::remove_dir_all(&straight).ok();
    std::fs::remove_dir_all(&killed).ok();
}

#[test]
fn resume_refuses_a_folder_without_a_checkpoint_and_extra_arguments() {
    let empty = scratch("empty");
    std::fs::create_dir_all(&empty).expect("dir");
    let out = Command::new(BIN)
        .args(["run", "--resume"])
        .arg(&empty)
        .output()
        .expect("runs");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("checkpoint.bin"), "{err}");
    let out = Command::new(BIN)
        .args(["run", SCENE, "--resume"])
        .arg(&empty)
        .output()
        .expect("runs");
    assert!(!out.status.success());
    let out = Command::new(BIN)
        .args(["run", SCENE, "--checkpoint-every", "0"])
        .output()
        .expect("runs");
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--checkpoint-every"));
    std::fs::remove_dir_all(&empty).ok();
}

/// The guards of `sph run`: a block thrown at 5 m/s out of a domain with no
/// walls stops the run with a one-line error naming the step, the time, the particle and its
/// position; `summary.json` says `failed` with the same message; every frame listed and the last
/// checkpoint are whole, and the checkpoint holds a state from before the failing step, from
/// which the run resumes (and stops again at the same step).
#[test]
fn a_particle_leaving_the_domain_stops_the_run_and_keeps_the_last_good_files() {
    let dir = scratch("escape");
    std::fs::create_dir_all(&dir).expect("dir");
    let scene = dir.join("escape.toml");
    std::fs::write(
        &scene,
        unwalled_2d(
            "escape",
            "min = [0.4, 0.4]\nmax = [0.6, 0.6]\nvelocity = [5.0, 0.0]",
            "end_time = 0.5\non_escape = \"stop\"",
            0.02,
        ),
    )
    .expect("scene");
    let out = dir.join("run");
    let run = Command::new(BIN)
        .args(["run"])
        .arg(&scene)
        .args(["--threads", "1", "--checkpoint-every", "20", "--out"])
        .arg(&out)
        .output()
        .expect("runs");
    assert!(!run.status.success(), "the run must fail");
    let err = String::from_utf8_lossy(&run.stderr);
    let line = err
        .lines()
        .find(|l| l.contains("left the domain"))
        .unwrap_or_else(|| panic!("{err}"));
    for part in ["step ", "t = ", "fluid particle ", " m"] {
        assert!(line.contains(part), "{line:?} lacks {part:?}");
    }
    let summary = read_summary(&out.join("summary.json")).expect("summary");
    assert!(
        summary.status.starts_with("failed:") && summary.status.contains("left the domain"),
        "{}",
        summary.status
    );
    let series = PvdSeries::read(&out.join("particles.pvd")).expect("the series is whole");
    assert!(series.entries().len() >= 3, "frames before the escape");
    for (_, file) in series.entries() {
        read_vtu(&out.join(file)).unwrap_or_else(|e| panic!("frame {file}: {e}"));
    }
    let state = Checkpoint::<2>::read(&out.join("checkpoint.bin")).expect("the checkpoint is whole");
    assert!(state.header.clock.step > 0 && state.header.clock.step < summary.steps + 1);
    // The block's front reaches x = 1 after about (1 - 0.6) / 5 = 0.08 s.
    assert!(
        summary.simulated_time > 0.05 && summary.simulated_time < 0.12,
        "{}",
        summary.simulated_time
    );
    let resumed = Command::new(BIN)
        .args(["run", "--threads", "1", "--resume"])
        .arg(&out)
        .output()
        .expect("resumes");
    assert!(!resumed.status.success());
    let again = String::from_utf8_lossy(&resumed.stderr);
    assert!(
        again.contains(line.trim_start_matches("error: ")),
        "{again}\nvs\n{line}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The per-step guard on non-finite values: a NaN planted in one particle's velocity stops the
/// next step with an error naming the step, the time, that particle's id and the quantity.
#[test]
fn a_non_finite_velocity_stops_the_step_naming_the_particle_and_quantity() {
    use sph::run::AnySimulation;
    use sph::solver::StepError;
    let scene = sph::scene::load_scene(Path::new(SCENE), &["particles.spacing=0.02".into()]).expect("scene");
    let AnySimulation::D2(mut sim) = AnySimulation::from_scene(&scene).expect("builds") else {
        panic!("a 2D scene");
    };
    for _ in 0..3 {
        sim.step(1.0).expect("a good step");
    }
    let i = 17;
    let id = sim.fields.id[i];
    sim.fields.velocity[i][1] = f32::NAN;
    match sim.step(1.0) {
        Err(
            e @ StepError::NonFinite {
                step: 3,
                particle,
                quantity,
                ..
            },
        ) => {
            assert_eq!((particle, quantity), (id, "velocity"));
            let text = e.to_string();
            assert!(
                text.contains(&format!("particle {id}")) && text.contains("velocity"),
                "{text}"
            );
        }
        other => panic!("expected NonFinite at step 3, got {other:?}"),
    }
}

/// A droplet thrown out of the domain (the default `solver.on_escape = "remove"`) is removed at
/// the next step's start, counted per step in `steps.csv` and in `summary.json` with a warning,
/// and the run goes on to its end; a run resumed from a checkpoint taken after the removal ends
/// with the same bytes as one never stopped.
#[test]
fn a_droplet_leaving_the_domain_is_removed_and_the_run_goes_on() {
    let dir = scratch("droplet");
    std::fs::create_dir_all(&dir).expect("dir");
    let scene = dir.join("droplet.toml");
    std::fs::write(
        &scene,
        unwalled_2d(
            "droplet",
            "min = [0.3, 0.1]\nmax = [0.7, 0.3]\n\n[[fluid_box]]\nmin = [0.4, 0.6]\nmax = [0.5, 0.7]\nvelocity = [5.0, 0.0]",
            "end_time = 0.3",
            0.05,
        ),
    )
    .expect("scene");
    let run = |out: &Path, extra: &[&str]| {
        Command::new(BIN)
            .args(["run"])
            .arg(&scene)
            .args(["--threads", "1", "--out"])
            .arg(out)
            .args(extra)
            .output()
            .expect("runs")
    };
    let straight = dir.join("straight");
    let done = run(&straight, &[]);
    assert!(done.status.success(), "{}", String::from_utf8_lossy(&done.stderr));
    assert!(String::from_utf8_lossy(&done.stderr).contains("left the domain and are removed"));
    let summary = read_summary(&straight.join("summary.json")).expect("summary");
    assert_eq!(summary.status, "completed");
    assert!((summary.simulated_time - 0.3).abs() < F64_SUM);
    // The droplet is 5 x 5 particles; the pool stays.
    assert_eq!(summary.extra["removed_particles"], 25);
    assert!(
        summary
            .warnings
            .iter()
            .any(|w| w.contains("25 fluid particles left the domain"))
    );
    let steps = sph::output::CsvFile::read(&straight.join("steps.csv")).expect("steps.csv");
    let removed: f64 = steps
        .numbers(steps.column("removed_particles").expect("column"))
        .expect("numbers")
        .iter()
        .sum();
    assert_eq!(removed, 25.0);
    let series = PvdSeries::read(&straight.join("particles.pvd")).expect("series");
    let (_, last) = series.entries().last().expect("frames");
    let frame = read_vtu(&straight.join(last)).expect("frame");
    assert_eq!(frame.points.len() as u64, summary.particles - 25);

    // Killed once a checkpoint holds fewer particles than the scene, then resumed: the same
    // bytes.
    let resumed = dir.join("resumed");
    let child = Command::new(BIN)
        .args(["run"])
        .arg(&scene)
        .args(["--threads", "1", "--checkpoint-every", "5", "--out"])
        .arg(&resumed)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("starts");
    kill_when(child, Duration::from_secs(120), "removal", || {
        Checkpoint::<2>::read(&resumed.join("checkpoint.bin"))
            .is_ok_and(|c| (c.fields.len() as u64) < summary.particles)
    });
    let again = Command::new(BIN)
        .args(["run", "--threads", "1", "--resume"])
        .arg(&resumed)
        .output()
        .expect("resumes");
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    for file in ["steps.csv", "particles.pvd", last.as_str()] {
        assert!(
            std::fs::read(straight.join(file)).expect("straight")
                == std::fs::read(resumed.join(file)).expect("resumed"),
            "{file} differs after resuming past the removal"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
