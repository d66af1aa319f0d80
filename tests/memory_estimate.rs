//! `sph check`'s memory estimate (`scene::run_bytes`: a base for the program plus a figure per
//! particle that depends on the dimension and the solver) against the peak resident set a run
//! reaches (`summary.json` `extra.peak_resident_bytes`, Linux): within 15 % on the large shipped
//! scenes, where the particles hold most of the memory. One figure per particle does not fit both
//! 3D scenes to 10 %: measured, the estimate is +5 to +9 % on the column and −5 to −9 % on Yeh &
//! Petroff, and the peak of one scene moves by about 3 % from run to run. On scenes of a few thousand particles
//! the program's own base dominates, and it varies between runs by about ±13 % (6.6–8.4 MiB
//! measured), so there the estimate is held to 25 %.

use sph::output::read_summary;
use sph::scene::{SolverKind, run_bytes};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_sph");

fn check(scene: &str, solver: &str, tolerance: f64) {
    let out = std::env::temp_dir().join(format!(
        "sph_memory_{}_{}_{solver}",
        std::process::id(),
        scene.replace('/', "_")
    ));
    let _ = std::fs::remove_dir_all(&out);
    let path = format!("{}/scenes/{scene}.toml", env!("CARGO_MANIFEST_DIR"));
    let run = Command::new(BIN)
        .args([
            "run",
            &path,
            "--end-time",
            "0.003",
            "--set",
            "output.frames=false",
        ])
        .args([
            "--set",
            &format!("solver.kind={solver}"),
            "--threads",
            "2",
            "--out",
        ])
        .arg(&out)
        .output()
        .expect("runs");
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let summary = read_summary(&out.join("summary.json")).expect("summary");
    let Some(peak) = summary.extra.get("peak_resident_bytes").and_then(|v| v.as_u64()) else {
        // Not Linux: the peak is not known, and this check cannot be made.
        assert!(sph::memory::peak_resident_bytes().is_none());
        return;
    };
    let kind = if solver == "corrected" {
        SolverKind::Corrected
    } else {
        SolverKind::Wcsph
    };
    let estimate = run_bytes(summary.particles, summary.dimension, kind).expect("fits") as f64;
    let error = estimate / peak as f64 - 1.0;
    assert!(
        error.abs() <= tolerance,
        "{scene} {solver}: estimate {estimate:.0} B, peak {peak} B ({:+.1} %)",
        100.0 * error
    );
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn the_estimate_holds_on_the_large_3d_scenes() {
    for scene in ["dam_break_column_3d", "yeh_petroff_3d"] {
        for solver in ["wcsph", "corrected"] {
            check(scene, solver, 0.15);
        }
    }
}

#[test]
fn the_estimate_holds_on_small_scenes_within_the_base_spread() {
    for scene in ["dam_break_2d", "hydrostatic_2d", "hard/rest_3d", "hard/jet_3d"] {
        for solver in ["wcsph", "corrected"] {
            check(scene, solver, 0.25);
        }
    }
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

/// A run that `sph check` accepts but whose address space runs out (`ulimit -v` leaves room for
/// the estimate, not for the worker threads' heaps) ends with the allocation failure on stderr
/// and, once it has written `summary.json`, with that summary saying `failed: out of memory`,
/// never `running`. Where the allocation fails depends on the limit and on when the threads
/// make their heaps (measured: not monotonic in the limit), so several limits are tried and at
/// least one must fail after the run has started.
#[cfg(unix)]
#[test]
fn a_run_out_of_memory_leaves_status_failed() {
    let scene = format!("{}/scenes/dam_break_column_3d.toml", env!("CARGO_MANIFEST_DIR"));
    let mut after_start = 0;
    for limit_kib in [112_000, 120_000, 128_000, 136_000, 144_000, 152_000, 160_000] {
        let out = std::env::temp_dir().join(format!("sph_memory_{}_oom_{limit_kib}", std::process::id()));
        let _ = std::fs::remove_dir_all(&out);
        let run = Command::new("sh")
            .arg("-c")
            .arg(format!(
                "ulimit -v {limit_kib} && exec '{BIN}' run '{scene}' --set solver.kind=corrected --end-time 0.002 --threads 2 --out '{}'",
                out.display()
            ))
            .output()
            .expect("sh");
        let err = String::from_utf8_lossy(&run.stderr);
        if run.status.success() || !err.contains("memory allocation of") {
            std::fs::remove_dir_all(&out).ok();
            continue;
        }
        if let Ok(summary) = read_summary(&out.join("summary.json")) {
            assert!(
                summary.status.starts_with("failed: out of memory"),
                "ulimit -v {limit_kib}: {}",
                summary.status
            );
            after_start += 1;
        }
        std::fs::remove_dir_all(&out).ok();
    }
    assert!(after_start > 0, "no limit made the run fail after it started");
}
