//! The `sph` binary as a child process: a plain run of a scene, the coarse 2D dam break that
//! the run-folder, restart and kill tests run, and waiting on a running child (for a file, a row
//! count, a status) before killing or signalling it.

use std::path::Path;
use std::process::{Child, Command, ExitStatus};
use std::time::{Duration, Instant};

/// The `sph` binary under test.
pub const SPH: &str = env!("CARGO_BIN_EXE_sph");

/// The shipped 2D dam break (`scenes/dam_break_2d.toml`).
pub const DAM_BREAK_2D: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/dam_break_2d.toml");

/// `sph run SCENE` with `solver`, at the coarse spacing of 0.01 m (2,500 fluid particles on the
/// shipped dam break, a second or so of work), on one thread (bitwise reproducible), to `end`
/// seconds. The caller adds `--out`, checkpoints and where stdout and stderr go.
pub fn coarse_run(scene: &Path, solver: &str, end: &str) -> Command {
    let mut c = Command::new(SPH);
    c.arg("run")
        .arg(scene)
        .args(["--set", &format!("solver.kind={solver}")])
        .args(["--set", "particles.spacing=0.01"])
        .args(["--threads", "1", "--end-time", end]);
    c
}

/// `sph run SCENE --out OUT` on one thread; panics with its stderr unless it succeeds.
pub fn run_scene(scene: &Path, out: &Path) {
    let run = Command::new(SPH)
        .arg("run")
        .arg(scene)
        .args(["--threads", "1", "--out"])
        .arg(out)
        .output()
        .expect("sph run starts");
    assert!(
        run.status.success(),
        "sph run failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
}

/// Polls `done` every millisecond until it holds; panics, saying `what` was awaited, after
/// `limit`.
pub fn wait_until(limit: Duration, what: &str, mut done: impl FnMut() -> bool) {
    let start = Instant::now();
    while !done() {
        assert!(start.elapsed() < limit, "no {what} after {limit:?}");
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// Waits ([`wait_until`]) until `ready` holds or `child` has ended by itself, then kills it
/// (SIGKILL) if it still runs and reaps it.
pub fn kill_when(
    mut child: Child,
    limit: Duration,
    what: &str,
    mut ready: impl FnMut() -> bool,
) -> ExitStatus {
    wait_until(limit, what, || {
        ready() || child.try_wait().expect("child status").is_some()
    });
    let _ = child.kill();
    child.wait().expect("reaped")
}

/// The number of lines of the text file at `path` (0 while it is missing): a run's progress
/// through `steps.csv`, one header line and one row per step.
pub fn lines(path: &Path) -> usize {
    std::fs::read_to_string(path).map_or(0, |s| s.lines().count())
}
