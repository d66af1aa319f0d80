//! `sph run --checkpoint-every N` and `sph run --resume RUN_DIR`: a run killed with SIGKILL
//! leaves only complete files (checkpoint, frames, series, CSV logs), and resuming it ends with
//! the same probes, forces, frames and statistics, bit for bit, as a run that was never stopped.

use sph::output::{PvdSeries, read_summary, read_vtu};
use sph::solver::checkpoint::Checkpoint;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_sph");
const SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/dam_break_2d.toml");

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sph_restart_test_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn command(out: &Path) -> Command {
    let mut c = Command::new(BIN);
    c.args([
        "run",
        SCENE,
        "--set",
        "solver.kind=wcsph",
        "--set",
        "particles.spacing=0.01",
        "--end-time",
        "0.4",
        "--threads",
        "1",
        "--checkpoint-every",
        "25",
        "--out",
    ])
    .arg(out)
    .stdout(Stdio::null())
    .stderr(Stdio::null());
    c
}

/// Every line of a CSV file has as many fields as its header.
fn assert_complete_csv(path: &Path) {
    let text = std::fs::read_to_string(path).expect("csv");
    assert!(text.ends_with('\n'), "{}: ends mid-line", path.display());
    let mut lines = text.lines();
    let fields = lines.next().expect("header").split(',').count();
    for (k, line) in lines.enumerate() {
        assert_eq!(
            line.split(',').count(),
            fields,
            "{} line {}: {line:?}",
            path.display(),
            k + 2
        );
    }
}

#[test]
fn a_killed_run_leaves_complete_files_and_resumes_bit_identically() {
    let straight = scratch("straight");
    assert!(command(&straight).status().expect("runs").success());

    let killed = scratch("killed");
    let mut child = command(&killed).spawn().expect("starts");
    let checkpoint = killed.join("checkpoint.bin");
    let started = Instant::now();
    while !checkpoint.exists() {
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "no checkpoint after 60 s"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().expect("SIGKILL");
    let status = child.wait().expect("reaped");
    assert!(!status.success(), "the run was still going when killed");
    assert!(!killed.join("summary.json").exists(), "killed before the end");

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
    assert_eq!(a.max_density_error.to_bits(), b.max_density_error.to_bits());
    assert_eq!(a.mean_density_error.to_bits(), b.mean_density_error.to_bits());
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
