//! A signal ends a run within a bounded time even inside a step that would run for minutes
//! (`solver::interrupt`), and a second signal ends the process at once: either way
//! `summary.json` ends with an `interrupted` status, never `running`.
//!
//! The long step: the corrected solver asked for δ = 1e-9, below what f32 densities can reach,
//! with 100,000 position sweeps allowed per stage: about 40 s a stage on one thread at the
//! coarse spacing, four stages in the first step.

use crate::common::fresh_path as scratch;
use crate::common::run::{DAM_BREAK_2D as SCENE, coarse_run, wait_until};
use sph::output::read_summary;
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Starts the long first step in `folder` and waits until the run has written its `running`
/// summary.
fn start_long_step(folder: &Path) -> Child {
    let child = coarse_run(Path::new(SCENE), "corrected", "0.1")
        .args([
            "--set",
            "solver.delta=1e-9",
            "--set",
            "solver.max_iterations=100000",
        ])
        .arg("--out")
        .arg(folder)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_until(Duration::from_secs(60), "running summary", || {
        read_summary(&folder.join("summary.json")).is_ok_and(|s| s.status == "running")
    });
    child
}

fn send(child: &Child, signal: &str) {
    let sent = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
}

/// Waits for `child` to end, at most `limit` (then kills it and fails).
fn ended_within(mut child: Child, limit: Duration) -> (Output, Duration) {
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            child.kill().ok();
            panic!("the run still ran {limit:?} after the signal");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    (child.wait_with_output().unwrap(), start.elapsed())
}

/// The first signal ends the step once it has run 5 s past it (`STOP_GRACE`: no step has
/// finished yet, so the grace is the least one): within 60 s, where the step alone would take
/// minutes; status 143, the summary says which step was abandoned, and no checkpoint claims it.
#[cfg(unix)]
#[test]
fn a_signal_ends_a_long_step_after_the_grace_time() {
    let folder = scratch("long_step_term");
    let child = start_long_step(&folder);
    send(&child, "-TERM");
    let (ended, took) = ended_within(child, Duration::from_secs(60));
    let stderr = String::from_utf8_lossy(&ended.stderr);
    assert_eq!(ended.status.code(), Some(143), "{stderr}");
    assert!(
        took >= sph::solver::interrupt::STOP_GRACE,
        "ended after {took:?}, before the grace time"
    );
    assert!(stderr.contains("inside step 1"), "{stderr}");
    let summary = read_summary(&folder.join("summary.json")).unwrap();
    assert_eq!(
        summary.status,
        "interrupted (signal 15) inside step 1, which was not written"
    );
    assert!(
        !folder.join("checkpoint.bin").exists(),
        "a checkpoint of a step that did not end"
    );
    std::fs::remove_dir_all(&folder).ok();
}

/// A second signal within the grace time ends the process at once with its status (130 for
/// SIGINT), after marking the summary `interrupted` in its own words.
#[cfg(unix)]
#[test]
fn a_second_signal_ends_the_run_at_once_with_a_final_status() {
    let folder = scratch("long_step_twice");
    let child = start_long_step(&folder);
    send(&child, "-TERM");
    std::thread::sleep(Duration::from_millis(300));
    send(&child, "-INT");
    let (ended, _) = ended_within(child, Duration::from_secs(60));
    assert_eq!(
        ended.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&ended.stderr)
    );
    // The second signal's own words, not the grace time's (which would name the step).
    let summary = read_summary(&folder.join("summary.json")).unwrap();
    assert_eq!(
        summary.status,
        "interrupted (signal 2): a second signal ended the process inside a step"
    );
    std::fs::remove_dir_all(&folder).ok();
}
