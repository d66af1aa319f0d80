//! `sph check`'s memory estimate (`scene::run_bytes`: a base for the program, a figure per
//! particle and one per fluid particle by dimension and solver, and the frame writer's share)
//! against the peak resident set a run reaches (`summary.json` `extra.peak_resident_bytes`,
//! Linux): within 10 % on every shipped scene with both solvers, as the scene runs (frames
//! written), on 2 threads. The small scenes' peaks move with the machine's load by up to
//! 0.6 MiB (`scene::validate::memory::BASE_BYTES`), about 7 % of theirs; each error is
//! printed, so a failure shows the whole spread.

use crate::common::run::SPH as BIN;
use sph::output::read_summary;
use sph::scene::{count_particles, load_scene, run_bytes, scene_particle_bytes};
use std::path::Path;
use std::process::Command;

/// The estimate's relative error on `scene` (a path under `scenes/`, without `.toml`) run
/// with `solver`, or `None` where the scene refuses that solver (checked to be `sph check`'s
/// refusal too) or the peak is not known (not Linux).
fn error(scene: &str, solver: &str) -> Option<f64> {
    let out = std::env::temp_dir().join(format!(
        "sph_memory_{}_{}_{solver}",
        std::process::id(),
        scene.replace('/', "_")
    ));
    let _ = std::fs::remove_dir_all(&out);
    let path = format!("{}/scenes/{scene}.toml", env!("CARGO_MANIFEST_DIR"));
    let sets = [format!("solver.kind={solver}")];
    let loaded = match load_scene(Path::new(&path), &sets) {
        Ok(s) => s,
        Err(e) => {
            // A scene may be written for one solver (a fixed dt too large for the other).
            assert!(e.to_string().contains("solver."), "{scene} {solver}: {e}");
            return None;
        }
    };
    let run = Command::new(BIN)
        .args(["run", &path, "--end-time", "0.003", "--set", &sets[0]])
        .args(["--threads", "2", "--out"])
        .arg(&out)
        .output()
        .expect("runs");
    assert!(
        run.status.success(),
        "{scene} {solver}: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let summary = read_summary(&out.join("summary.json")).expect("summary");
    std::fs::remove_dir_all(&out).ok();
    let Some(peak) = summary.extra.get("peak_resident_bytes").and_then(|v| v.as_u64()) else {
        // Not Linux: the peak is not known, and this check cannot be made.
        assert!(sph::memory::peak_resident_bytes().is_none());
        return None;
    };
    let counts = count_particles(&loaded).expect("counts");
    let estimate = run_bytes(counts.total, counts.fluid, scene_particle_bytes(&loaded)).expect("fits");
    Some(estimate as f64 / peak as f64 - 1.0)
}

fn holds_on(scenes: &[String]) {
    let mut failures = Vec::new();
    let mut checked = 0;
    for scene in scenes {
        for solver in ["wcsph", "corrected"] {
            if let Some(e) = error(scene, solver) {
                checked += 1;
                eprintln!("MEM {scene} {solver}: {:+.1} %", 100.0 * e);
                if e.abs() > 0.10 {
                    failures.push(format!("{scene} {solver}: {:+.1} %", 100.0 * e));
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "estimate off by more than 10 %: {failures:?}"
    );
    assert!(
        cfg!(not(target_os = "linux")) || checked >= scenes.len(),
        "{checked} runs checked"
    );
}

/// The shipped scenes under `scenes/` (and `scenes/hard/` if `hard`), as `error` names them.
fn shipped(hard: bool) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let dir = if hard { root.join("hard") } else { root };
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .expect("scenes/")
        .filter_map(|e| {
            let name = e.ok()?.file_name().into_string().ok()?;
            let stem = name.strip_suffix(".toml")?;
            Some(if hard {
                format!("hard/{stem}")
            } else {
                stem.to_string()
            })
        })
        .collect();
    names.sort();
    assert!(names.len() >= 8, "{names:?}");
    names
}

#[test]
fn the_estimate_holds_on_every_shipped_scene() {
    holds_on(&shipped(false));
}

#[test]
fn the_estimate_holds_on_every_hard_case() {
    holds_on(&shipped(true));
}

/// Under `ulimit -v`, a scene whose estimate exceeds what the limit leaves is refused by
/// `sph check` and `sph run` before anything is allocated, naming the limit.
#[cfg(unix)]
#[test]
fn the_address_space_limit_is_honoured() {
    let scene = format!("{}/scenes/dam_break_column_3d.toml", env!("CARGO_MANIFEST_DIR"));
    for command in ["check", "run"] {
        let out = Command::new("sh")
            .arg("-c")
            .arg(format!(
                "ulimit -v 150000 && exec '{BIN}' {command} '{scene}' --set particles.spacing=0.006 {}",
                if command == "run" {
                    "--out /nonexistent/never-created"
                } else {
                    ""
                }
            ))
            .output()
            .expect("sh");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{command}: {err}");
        assert!(
            err.contains("(ulimit -v)") && err.contains("particles.spacing"),
            "{command}: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
}

/// A run whose memory runs out after it started ends with the allocation failure on stderr,
/// a non-zero exit and `summary.json` saying `failed: out of memory`, never `running`. The
/// failure is injected (`SPH_TEST_FAIL_ALLOCATIONS_ABOVE`: requests above 1 MB fail once the
/// run writes its folder), since glibc reuses freed memory and a lowered `RLIMIT_AS` does not
/// make a running process fail at a predictable point; the real limit is
/// `the_address_space_limit_is_honoured`'s.
#[test]
fn a_run_out_of_memory_leaves_status_failed() {
    let scene = format!("{}/scenes/dam_break_column_3d.toml", env!("CARGO_MANIFEST_DIR"));
    let out = std::env::temp_dir().join(format!("sph_memory_{}_oom", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let run = Command::new(BIN)
        .args(["run", &scene, "--end-time", "0.002", "--threads", "2", "--out"])
        .arg(&out)
        .env(sph::run::out_of_memory::FAIL_ALLOCATIONS_ABOVE_VAR, "1000000")
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "{err}");
    assert!(err.contains("memory allocation of"), "{err}");
    let summary = read_summary(&out.join("summary.json")).expect("summary");
    assert!(
        summary.status.starts_with("failed: out of memory"),
        "{}",
        summary.status
    );
    std::fs::remove_dir_all(&out).ok();
}

/// `sph run` also counts its worker threads' heaps against `ulimit -v`
/// (`memory::address_space_need`): a scene `sph check` accepts under the limit is refused by a
/// run on 2 threads, naming `--threads`, before its folder is made.
#[cfg(target_os = "linux")]
#[test]
fn a_run_counts_its_threads_against_the_address_space_limit() {
    let scene = format!("{}/scenes/dam_break_column_3d.toml", env!("CARGO_MANIFEST_DIR"));
    let out = std::env::temp_dir().join(format!("sph_memory_{}_threads", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let under_limit = |command: &str| {
        Command::new("sh")
            .arg("-c")
            .arg(format!(
                "ulimit -v 250000 && exec '{BIN}' {command} '{scene}' --set solver.kind=corrected"
            ))
            .output()
            .expect("sh")
    };
    let check = under_limit("check");
    assert!(
        check.status.success(),
        "{}",
        String::from_utf8_lossy(&check.stderr)
    );
    let run = under_limit(&format!("run --threads 2 --out '{}'", out.display()));
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{err}");
    assert!(err.contains("ulimit -v") && err.contains("--threads"), "{err}");
    assert!(!out.exists());
}
