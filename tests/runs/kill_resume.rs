//! Kill and resume at random points: a run killed with SIGKILL after a random number of steps,
//! with checkpoints every random number of steps, then resumed with `sph run --resume`, ends
//! with the same bytes as a run never stopped: `forces.csv`, `steps.csv`, `probes.csv`,
//! `particles.pvd`, every frame, and every statistic of `summary.json` (all but the wall time,
//! the throughput derived from it, the run's identifier and the process's heap and peak
//! resident set). Both solvers, 10 kill points
//! each (proptest; CI fixes the seed).

use crate::common::fresh_path as scratch;
use crate::common::run::{DAM_BREAK_2D as SCENE, SPH as BIN, coarse_run, kill_when, lines};
use proptest::prelude::*;
use sph::output::{PvdSeries, Summary, read_summary};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::time::Duration;

const END: &str = "0.15";

/// The coarse dam break with `solver` to `END`, a frame every 0.01 s and a checkpoint every
/// `every` steps, quiet.
fn command(solver: &str, out: &Path, every: u64) -> Command {
    let mut c = coarse_run(Path::new(SCENE), solver, END);
    c.args(["--set", "output.interval=0.01"])
        .args(["--checkpoint-every", &every.to_string(), "--out"])
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    c
}

/// The uninterrupted run of `solver` (once per test process) and its step count.
fn straight(solver: &'static str) -> &'static (PathBuf, usize) {
    static RUNS: [OnceLock<(PathBuf, usize)>; 2] = [OnceLock::new(), OnceLock::new()];
    RUNS[usize::from(solver == "corrected")].get_or_init(|| {
        let out = scratch(&format!("straight_{solver}"));
        assert!(command(solver, &out, 1_000_000).status().unwrap().success());
        let steps = read_summary(&out.join("summary.json")).unwrap().steps as usize;
        (out, steps)
    })
}

/// The summary without what belongs to the process rather than the simulation: wall time,
/// throughput, the run's identifier and the heap the process holds at the end (a resumed
/// process has allocated only what its own steps needed).
fn statistics(mut s: Summary) -> String {
    s.wall_seconds = 0.0;
    s.particle_steps_per_second = 0.0;
    s.run_id.clear();
    s.extra.remove("memory_bytes");
    s.extra.remove("memory_bytes_per_particle");
    s.extra.remove("peak_resident_bytes");
    // Both summaries went through JSON, so comparing their JSON compares every bit.
    serde_json::to_string(&s).unwrap()
}

fn kill_and_resume(solver: &'static str, every: u64, kill_fraction: f64, case: &str) {
    let (reference, steps) = straight(solver);
    let out = scratch(&format!("{solver}_{case}"));
    let kill_after = 1 + (kill_fraction * (*steps as f64 - 2.0)) as usize;
    let child = command(solver, &out, every).spawn().unwrap();
    kill_when(child, Duration::from_secs(300), "progress", || {
        lines(&out.join("steps.csv")) > kill_after
    });
    // Killed before its first checkpoint: nothing to resume, the run starts afresh.
    let resume = if out.join("checkpoint.bin").exists() {
        Command::new(BIN)
            .args(["run", "--threads", "1", "--resume"])
            .arg(&out)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .output()
            .unwrap()
    } else {
        command(solver, &out, every).arg("--force").output().unwrap()
    };
    assert!(
        resume.status.success(),
        "{}",
        String::from_utf8_lossy(&resume.stderr)
    );
    for file in ["forces.csv", "steps.csv", "probes.csv", "particles.pvd"] {
        let (a, b) = (
            std::fs::read(reference.join(file)).unwrap(),
            std::fs::read(out.join(file)).unwrap(),
        );
        assert!(
            a == b,
            "{solver}, every {every}, killed after {kill_after}: {file} differs"
        );
    }
    let series = PvdSeries::read(&reference.join("particles.pvd")).unwrap();
    for (_, frame) in series.entries() {
        assert!(
            std::fs::read(reference.join(frame)).unwrap() == std::fs::read(out.join(frame)).unwrap(),
            "{solver}: {frame} differs"
        );
    }
    let (a, b) = (
        read_summary(&reference.join("summary.json")).unwrap(),
        read_summary(&out.join("summary.json")).unwrap(),
    );
    assert_eq!(statistics(a), statistics(b), "{solver}: summary.json differs");
    std::fs::remove_dir_all(&out).ok();
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 10, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn wcsph_resumes_bit_identically_after_a_kill(every in 3u64..40, at in 0.0f64..1.0) {
        kill_and_resume("wcsph", every, at, &format!("{every}_{at}"));
    }

    #[test]
    fn corrected_resumes_bit_identically_after_a_kill(every in 1u64..12, at in 0.0f64..1.0) {
        kill_and_resume("corrected", every, at, &format!("{every}_{at}"));
    }
}
