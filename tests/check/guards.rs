//! Guards against input that cannot run: values `sph check` must refuse because the run could
//! never finish (progress) or because they overflow the solver's f32 arithmetic (magnitudes), a
//! time step that stalls at run time, a scene file too large to read, and a closed output pipe.
//!
//! Each case runs the built `sph` binary on a small shipped 2D scene with `--set` overrides and
//! asserts a clean refusal: a non-zero exit code other than 101 (a panic), no "panicked" on
//! stderr, the problem reported at the key at fault, and an end within a few seconds (a child
//! that runs longer is killed and the case fails).

use crate::common::run::SPH;
use crate::common::scratch as temp_dir;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use sph::solver::StepError;

/// The small corrected 2D dam break (2,500 fluid particles).
fn dam_break() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/dam_break_2d.toml")
}

/// What a finished child left: exit code (`None` if a signal ended it), stderr, seconds taken.
struct Outcome {
    code: Option<i32>,
    stderr: String,
    seconds: f64,
}

/// Runs `command` with stdout discarded, killing it after `limit`; panics if it had to be killed
/// (a hang is the failure these tests look for).
fn run_bounded(mut command: Command, limit: Duration) -> Outcome {
    let start = Instant::now();
    let mut child = command
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn sph");
    let mut stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        std::io::Read::read_to_string(&mut stderr, &mut text).ok();
        text
    });
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > limit {
            child.kill().ok();
            child.wait().ok();
            panic!("{command:?} still running after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Outcome {
        code: status.code(),
        stderr: reader.join().unwrap(),
        seconds: start.elapsed().as_secs_f64(),
    }
}

fn sph(args: &[&str]) -> Command {
    let mut command = Command::new(SPH);
    command.args(args);
    command
}

/// `args` end promptly with a clean refusal whose problem is reported at `key`; returns stderr.
fn assert_refused(args: &[&str], key: &str) -> String {
    let out = run_bounded(sph(args), Duration::from_secs(30));
    let code = out
        .code
        .unwrap_or_else(|| panic!("{args:?} ended by a signal: {}", out.stderr));
    assert!(
        code != 0 && code != 101,
        "{args:?}: exit code {code}\n{}",
        out.stderr
    );
    assert!(!out.stderr.contains("panicked"), "{args:?}: {}", out.stderr);
    // Problems render as `origin: LOCATION: KEY: reason`.
    assert!(
        out.stderr.contains(&format!(": {key}: ")),
        "{args:?}: no problem at {key}:\n{}",
        out.stderr
    );
    out.stderr
}

/// `sph check` with `--set` overrides on the 2D dam break.
fn check_args<'a>(scene: &'a str, sets: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["check", scene];
    for set in sets {
        args.extend(["--set", set]);
    }
    args
}

/// Values that make a run that cannot finish, and the key each problem is reported at.
const NEVER_FINISH: [(&[&str], &str); 9] = [
    // 6e11 frame times.
    (&["output.interval=1e-12"], "output.interval"),
    // |g| T overflows; the step would not change t = 1e30 s.
    (&["solver.end_time=1e30"], "solver.end_time"),
    // The step no longer changes the time at the end time.
    (&["solver.end_time=1e20"], "solver.end_time"),
    (&["solver.cfl=1e-30"], "solver.cfl"),
    // About 1e10 steps of the flow-speed CFL limit.
    (&["solver.cfl=1e-8"], "solver.cfl"),
    // A viscous limit of exactly 0 s.
    (
        &["fluid.artificial_viscosity=1e308"],
        "fluid.artificial_viscosity",
    ),
    // A viscous limit of 1.4e-16 s: 4e15 steps.
    (&["fluid.artificial_viscosity=1e12"], "fluid.artificial_viscosity"),
    (&["fluid.sound_speed=1e20"], "fluid.sound_speed"),
    (&["solver.dt=1e-300"], "solver.dt"),
];

#[test]
fn check_refuses_values_that_cannot_finish() {
    let scene = dam_break();
    let scene = scene.to_str().unwrap();
    for (sets, key) in NEVER_FINISH {
        assert_refused(&check_args(scene, sets), key);
    }
    // The weakly compressible solver: its step follows the sound speed.
    for (sets, key) in [
        (&["solver.kind=wcsph", "solver.cfl=1e-9"][..], "solver.cfl"),
        (
            &["solver.kind=wcsph", "fluid.sound_speed=1e13"],
            "fluid.sound_speed",
        ),
        (&["solver.kind=wcsph", "solver.dt=1e-16"], "solver.dt"),
    ] {
        assert_refused(&check_args(scene, sets), key);
    }
}

#[test]
fn run_refuses_values_that_cannot_finish() {
    let scene = dam_break();
    let scene = scene.to_str().unwrap();
    let out = temp_dir("never_finish");
    for (n, (sets, key)) in NEVER_FINISH.iter().enumerate() {
        let dir = out.join(n.to_string());
        let mut args = vec!["run", scene, "--out", dir.to_str().unwrap()];
        for set in *sets {
            args.extend(["--set", set]);
        }
        assert_refused(&args, key);
    }
    // `--end-time` is `--set solver.end_time`.
    let dir = out.join("end_time");
    assert_refused(
        &["run", scene, "--out", dir.to_str().unwrap(), "--end-time", "1e30"],
        "solver.end_time",
    );
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn reasonable_values_still_pass() {
    let scene = dam_break();
    let scene = scene.to_str().unwrap();
    for sets in [
        &[][..],
        &["output.interval=1e-6"],
        &["solver.end_time=10.0"],
        &["solver.cfl=1e-4"],
        &["fluid.viscosity=0.0"],
        &["fluid.gravity=[0.0,0.0]"],
        &["solver.kind=wcsph", "solver.dt=1e-6"],
    ] {
        let out = run_bounded(sph(&check_args(scene, sets)), Duration::from_secs(30));
        assert_eq!(out.code, Some(0), "{sets:?}: {}", out.stderr);
    }
}

/// Values (alone finite and positive where required) that overflow or underflow in use, and
/// the key each problem is reported at.
const OVERFLOW: [(&str, &str); 17] = [
    ("fluid.rho0=1e308", "fluid.rho0"),
    ("fluid.rho0=1e-300", "fluid.rho0"),
    // rho0 C^2 = 1.2e31 Pa: each value alone fits.
    ("fluid.rho0=1e28", "fluid.rho0"),
    ("fluid.sound_speed=5e-324", "fluid.sound_speed"),
    ("fluid.sound_speed=1e200", "fluid.sound_speed"),
    // C^2 / h = 1e34 m/s^2.
    ("fluid.sound_speed=1e16", "fluid.sound_speed"),
    ("fluid.viscosity=1e300", "fluid.viscosity"),
    ("fluid.viscosity=1e-320", "fluid.viscosity"),
    ("fluid.artificial_viscosity=1e-310", "fluid.artificial_viscosity"),
    ("fluid.gravity=[0.0,-1e300]", "fluid.gravity[1]"),
    ("fluid.gravity=[1e-310,-9.81]", "fluid.gravity[0]"),
    ("fluid_box.0.velocity=[1e300,0.0]", "fluid_box[0].velocity[0]"),
    ("particles.spacing=1e-200", "particles.spacing"),
    ("solver.end_time=1e300", "solver.end_time"),
    ("solver.dt=1e-200", "solver.dt"),
    ("output.interval=1e-310", "output.interval"),
    ("domain.max=[1e300,1.2]", "domain.max[0]"),
];

#[test]
fn check_refuses_values_that_overflow_in_use() {
    let scene = dam_break();
    let scene = scene.to_str().unwrap();
    for (set, key) in OVERFLOW {
        let stderr = assert_refused(&check_args(scene, &[set]), key);
        // A scale is not formed from a value already refused (it would read `= inf`).
        assert!(!stderr.contains("inf"), "{set}: {stderr}");
    }
}

/// A step of exactly 0 s at run time (what `fluid.artificial_viscosity = 1e308` gives when
/// validation is bypassed: 59,692 steps of 0 s in 15 s, measured) stops the run with a typed
/// error, and so does a fixed step below the f64 resolution of the end time.
#[test]
fn a_stalled_step_stops_the_run() {
    let valid = sph::scene::load_scene(&dam_break(), &["solver.end_time=0.01".into()]).unwrap();
    let mut zero = valid.clone();
    zero.pair_terms = zero
        .pair_terms
        .with(sph::model::pair_terms::PairTerm::ArtificialViscosity, 1e308);
    let mut tiny = valid.clone();
    tiny.dt = Some(1e-300);
    for (scene, what) in [(zero, "zero step"), (tiny, "tiny fixed step")] {
        let mut sim = sph::run::simulation_from_scene::<2>(&scene).unwrap();
        match sim.step(scene.end_time) {
            Err(e @ StepError::Stalled { .. }) => {
                let text = e.to_string();
                assert!(text.contains("does not advance"), "{what}: {text}");
            }
            other => panic!("{what}: expected StepError::Stalled, got {other:?}"),
        }
    }
    // The valid scene steps on.
    let mut sim = sph::run::simulation_from_scene::<2>(&valid).unwrap();
    let report = sim.step(valid.end_time).unwrap();
    assert!(report.dt > 0.0);
}

#[test]
fn a_scene_file_above_the_cap_is_refused_before_reading() {
    let dir = temp_dir("large");
    // Sparse: 17 MiB long, no blocks written.
    let big = dir.join("big.toml");
    let file = std::fs::File::create(&big).unwrap();
    file.set_len(sph::scene::MAX_SCENE_BYTES + 1024 * 1024).unwrap();
    drop(file);
    let mut paths = vec![big];
    // A character device reports a length of 0 and never ends.
    let zero = PathBuf::from("/dev/zero");
    if zero.exists() {
        paths.push(zero);
    }
    for path in paths {
        // Under a 2 GiB address-space limit, so that a reader without a cap fails in the child
        // rather than exhausting the machine.
        let mut command = Command::new("sh");
        command.args([
            "-c",
            "ulimit -v 2097152; exec \"$0\" check \"$1\"",
            SPH,
            path.to_str().unwrap(),
        ]);
        let out = run_bounded(command, Duration::from_secs(30));
        assert_eq!(out.code, Some(1), "{}: {}", path.display(), out.stderr);
        assert!(!out.stderr.contains("panicked"), "{}", out.stderr);
        assert!(
            out.stderr.contains("too large") && out.stderr.contains("16 MiB"),
            "{}: {}",
            path.display(),
            out.stderr
        );
        assert!(out.seconds < 10.0, "{}: {} s", path.display(), out.seconds);
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `sph check SCENE | head -1`: the reader closes the pipe after one line, and the program ends
/// without a panic message (the panic showed in 4 of 30 tries of the shell pipeline, measured).
#[test]
fn a_closed_pipe_ends_the_program_quietly() {
    let scene = dam_break();
    for _ in 0..20 {
        let mut child = Command::new(SPH)
            .args(["check", scene.to_str().unwrap()])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut stdout = BufReader::new(child.stdout.take().unwrap());
        let mut line = String::new();
        stdout.read_line(&mut line).unwrap();
        assert!(line.contains("valid"), "{line}");
        drop(stdout);
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert_ne!(out.status.code(), Some(101), "{stderr}");
    }
}
