//! The run folder belongs to one run (`run::folder`): each case below was once a way to lose or
//! mix a run's data and now ends in a clear refusal or a clean result.
//!
//! - a stale checkpoint, or one copied from another folder, cannot be resumed over a newer run;
//! - a second run into a folder in use is refused while the first runs, and the first's files
//!   stay whole;
//! - a new run into a folder holding anything is refused unless `--force` (and leaves no lock
//!   file behind), which removes only the previous run's listed files; the `running` summary
//!   replaces the old `completed` one; `--out` naming a file is refused as such;
//! - links planted in the folder are never written through;
//! - SIGINT and SIGTERM end the run after a step with a checkpoint, status `interrupted` and
//!   exit status 130 / 143, and the run resumes to the same bytes as a run never stopped;
//! - an output error in the middle of a run leaves status `failed` naming it;
//! - `--resume` refuses an edited scene file (unless told) and a checkpoint that would cut a
//!   log mid-row;
//! - a weakly compressible run compressed beyond 10 % says so.

use crate::common::run::{DAM_BREAK_2D as SCENE, SPH as BIN, coarse_run, kill_when, lines, wait_until};
use crate::common::scratch;
use sph::output::read_summary;
use sph::solver::checkpoint::Checkpoint;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::Duration;

/// `sph run` of the coarse 2D dam break (wcsph, one thread) with `extra` arguments.
fn run(scene: &Path, end: &str, extra: &[&str]) -> Command {
    let mut c = coarse_run(scene, "wcsph", end);
    c.args(extra).stdout(Stdio::piped()).stderr(Stdio::piped());
    c
}

fn out<'a>(args: &[&'a Path]) -> Vec<&'a std::ffi::OsStr> {
    args.iter().map(|p| p.as_os_str()).collect()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn ok(o: Output) -> Output {
    assert!(o.status.success(), "{}", stderr(&o));
    o
}

fn refused(o: Output, says: &str) -> String {
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains(says), "{err:?} should say {says:?}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn a_stale_or_foreign_checkpoint_never_overwrites_a_newer_run() {
    let dir = scratch("stale");
    let mix = dir.join("mix");
    ok(
        run(Path::new(SCENE), "0.03", &["--checkpoint-every", "1", "--out"])
            .args(out(&[&mix]))
            .output()
            .unwrap(),
    );
    let first = read(&mix.join("forces.csv"));
    // A second run into the same folder is refused and leaves it as it was.
    let again = run(
        Path::new(SCENE),
        "0.06",
        &["--set", "fluid.gravity=[0.0,-20.0]", "--out"],
    )
    .args(out(&[&mix]))
    .output()
    .unwrap();
    refused(again, "--force");
    assert_eq!(read(&mix.join("forces.csv")), first);
    // Forced, it replaces the first run's files, its checkpoint included.
    ok(run(
        Path::new(SCENE),
        "0.06",
        &["--set", "fluid.gravity=[0.0,-20.0]", "--force", "--out"],
    )
    .args(out(&[&mix]))
    .output()
    .unwrap());
    assert!(
        !mix.join("checkpoint.bin").exists(),
        "the first run's checkpoint is gone"
    );
    let second = read(&mix.join("forces.csv"));
    let resumed = Command::new(BIN)
        .args(["run", "--resume"])
        .arg(&mix)
        .output()
        .unwrap();
    refused(resumed, "checkpoint.bin");
    assert_eq!(read(&mix.join("forces.csv")), second, "the newer run is intact");

    // A checkpoint copied from another run's folder is refused.
    let (c, d) = (dir.join("c"), dir.join("d"));
    for folder in [&c, &d] {
        ok(
            run(Path::new(SCENE), "0.03", &["--checkpoint-every", "2", "--out"])
                .args(out(&[folder]))
                .output()
                .unwrap(),
        );
    }
    let kept = read(&d.join("forces.csv"));
    std::fs::copy(c.join("checkpoint.bin"), d.join("checkpoint.bin")).unwrap();
    let resumed = Command::new(BIN)
        .args(["run", "--resume"])
        .arg(&d)
        .output()
        .unwrap();
    refused(resumed, "another run");
    assert_eq!(read(&d.join("forces.csv")), kept);
    std::fs::remove_dir_all(&dir).ok();
}

/// Waits until `path` exists (a run writes `summary.json` as it starts).
fn wait_for(path: &Path) {
    wait_until(Duration::from_secs(120), &path.display().to_string(), || {
        path.exists()
    });
}

#[test]
fn a_second_run_into_a_folder_in_use_is_refused() {
    let dir = scratch("busy");
    let folder = dir.join("run");
    let first = run(Path::new(SCENE), "0.3", &["--out"])
        .args(out(&[&folder]))
        .spawn()
        .unwrap();
    wait_for(&folder.join("summary.json"));
    let second = run(Path::new(SCENE), "0.3", &["--force", "--out"])
        .args(out(&[&folder]))
        .output()
        .unwrap();
    refused(second, "in use by another sph run");
    ok(first.wait_with_output().unwrap());
    let summary = read_summary(&folder.join("summary.json")).unwrap();
    assert_eq!(summary.status, "completed");
    let csv = sph::output::CsvFile::read(&folder.join("forces.csv")).expect("whole rows");
    assert!(csv.len() > 10);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_new_run_never_overwrites_or_leaves_behind_what_is_not_its_own() {
    let dir = scratch("leftovers");
    let folder = dir.join("run");
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::write(folder.join("notes.txt"), "mine").unwrap();
    std::fs::write(folder.join("summary.json"), "my own summary").unwrap();
    refused(
        run(Path::new(SCENE), "0.05", &["--out"])
            .args(out(&[&folder]))
            .output()
            .unwrap(),
        "files not written by sph",
    );
    // Refused, the folder is left as it was: not even the lock file stays.
    assert!(
        !folder.join(".sph.lock").exists(),
        "the refused run left its lock file"
    );
    // `--out` naming a file is refused by what it is, and the file is left alone.
    let file = dir.join("results.txt");
    std::fs::write(&file, "not a folder").unwrap();
    refused(
        run(Path::new(SCENE), "0.05", &["--out"])
            .args(out(&[&file]))
            .output()
            .unwrap(),
        "is a file, not a folder",
    );
    assert_eq!(read(&file), b"not a folder");
    // Forced, it still will not overwrite the user's summary.json.
    refused(
        run(Path::new(SCENE), "0.05", &["--force", "--out"])
            .args(out(&[&folder]))
            .output()
            .unwrap(),
        "was not written by this run",
    );
    assert_eq!(read(&folder.join("summary.json")), b"my own summary");
    std::fs::remove_file(folder.join("summary.json")).unwrap();

    // A long run, then a shorter forced one: none of the long run's frames or checkpoint stay.
    ok(run(
        Path::new(SCENE),
        "0.2",
        &["--checkpoint-every", "10", "--force", "--out"],
    )
    .args(out(&[&folder]))
    .output()
    .unwrap());
    let long = std::fs::read_dir(folder.join("frames")).unwrap().count();
    ok(run(Path::new(SCENE), "0.05", &["--force", "--out"])
        .args(out(&[&folder]))
        .output()
        .unwrap());
    let series = sph::output::PvdSeries::read(&folder.join("particles.pvd")).unwrap();
    let frames = std::fs::read_dir(folder.join("frames")).unwrap().count();
    assert_eq!(frames, series.entries().len(), "only this run's frames");
    assert!(frames < long);
    assert!(!folder.join("checkpoint.bin").exists());
    assert_eq!(read(&folder.join("notes.txt")), b"mine");

    // A forced run killed at once leaves `running`, not the previous run's `completed`.
    let child = run(Path::new(SCENE), "0.3", &["--force", "--out"])
        .args(out(&[&folder]))
        .spawn()
        .unwrap();
    kill_when(child, Duration::from_secs(60), "running summary", || {
        read_summary(&folder.join("summary.json")).is_ok_and(|s| s.status == "running")
    });
    assert_eq!(
        read_summary(&folder.join("summary.json")).unwrap().status,
        "running"
    );
    assert_eq!(read(&folder.join("notes.txt")), b"mine");
    std::fs::remove_dir_all(&dir).ok();
}

#[cfg(unix)]
#[test]
fn links_planted_in_the_folder_are_never_written_through() {
    use std::os::unix::fs::symlink;
    let dir = scratch("links");
    let folder = dir.join("run");
    let outside = dir.join("outside");
    std::fs::create_dir_all(&outside).unwrap();
    ok(
        run(Path::new(SCENE), "0.05", &["--checkpoint-every", "5", "--out"])
            .args(out(&[&folder]))
            .output()
            .unwrap(),
    );
    // Every name the run writes, pointed at a file outside.
    let names = [
        "forces.csv",
        "steps.csv",
        "probes.csv",
        "summary.json",
        "particles.pvd",
        "checkpoint.bin",
    ];
    for name in names {
        let target = outside.join(name);
        std::fs::write(&target, "outside").unwrap();
        std::fs::remove_file(folder.join(name)).unwrap();
        symlink(&target, folder.join(name)).unwrap();
    }
    std::fs::remove_dir_all(folder.join("frames")).unwrap();
    symlink(&outside, folder.join("frames")).unwrap();
    // Resuming through the links is refused.
    let resumed = Command::new(BIN)
        .args(["run", "--resume"])
        .arg(&folder)
        .output()
        .unwrap();
    assert!(!resumed.status.success());
    // A forced run removes the links, not their targets, and will not write into the linked
    // frames folder.
    let forced = run(Path::new(SCENE), "0.05", &["--force", "--out"])
        .args(out(&[&folder]))
        .output()
        .unwrap();
    refused(forced, "not a directory");
    for name in names {
        assert_eq!(
            read(&outside.join(name)),
            b"outside",
            "{name} was written through"
        );
    }
    let inside: Vec<_> = std::fs::read_dir(&outside).unwrap().collect();
    assert_eq!(inside.len(), names.len(), "nothing new in the linked folder");
    std::fs::remove_dir_all(&dir).ok();
}

/// Sends `signal` to the run once it has taken `steps` steps, waits for it to end.
#[cfg(unix)]
fn interrupt(folder: &Path, end: &str, signal: &str, steps: usize) -> Output {
    let child = run(Path::new(SCENE), end, &["--out"])
        .args(out(&[folder]))
        .spawn()
        .unwrap();
    wait_until(Duration::from_secs(120), "progress", || {
        lines(&folder.join("steps.csv")) > steps
    });
    let sent = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    child.wait_with_output().unwrap()
}

#[cfg(unix)]
#[test]
fn sigint_and_sigterm_end_the_run_after_a_step_with_a_checkpoint() {
    let dir = scratch("signals");
    let straight = dir.join("straight");
    ok(run(Path::new(SCENE), "0.2", &["--out"])
        .args(out(&[&straight]))
        .output()
        .unwrap());
    for (signal, status) in [("-INT", 130), ("-TERM", 143)] {
        let folder = dir.join(signal);
        let ended = interrupt(&folder, "0.2", signal, 30);
        assert_eq!(ended.status.code(), Some(status), "{}", stderr(&ended));
        assert!(stderr(&ended).contains("interrupted"), "{}", stderr(&ended));
        let summary = read_summary(&folder.join("summary.json")).unwrap();
        assert!(summary.status.starts_with("interrupted"), "{}", summary.status);
        let state = Checkpoint::<2>::read(&folder.join("checkpoint.bin")).expect("checkpoint");
        assert_eq!(
            state.header.clock.step, summary.steps,
            "checkpointed at the last step"
        );
        ok(Command::new(BIN)
            .args(["run", "--threads", "1", "--resume"])
            .arg(&folder)
            .output()
            .unwrap());
        for file in ["forces.csv", "steps.csv", "probes.csv", "particles.pvd"] {
            assert!(
                read(&straight.join(file)) == read(&folder.join(file)),
                "{file} differs after {signal} and resume"
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn an_output_error_during_the_run_leaves_status_failed() {
    let dir = scratch("failed");
    let folder = dir.join("run");
    let child = run(Path::new(SCENE), "0.6", &["--out"])
        .args(out(&[&folder]))
        .spawn()
        .unwrap();
    // The first frame creates frames/.
    wait_for(&folder.join("frames/frame_00000.vtu"));
    // A file of the user's where the run's 25th frame goes.
    std::fs::write(folder.join("frames/frame_00025.vtu"), "mine").unwrap();
    let ended = child.wait_with_output().unwrap();
    refused(ended, "frame_00025.vtu");
    let summary = read_summary(&folder.join("summary.json")).unwrap();
    assert!(
        summary.status.starts_with("failed:") && summary.status.contains("frame_00025.vtu"),
        "{}",
        summary.status
    );
    assert!(
        summary.steps > 0 && summary.simulated_time > 0.4,
        "statistics kept"
    );
    assert_eq!(read(&folder.join("frames/frame_00025.vtu")), b"mine");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn resume_refuses_an_edited_scene_and_a_checkpoint_that_cuts_mid_row() {
    let dir = scratch("edited");
    let scene = dir.join("scene.toml");
    std::fs::copy(SCENE, &scene).unwrap();
    let folder = dir.join("run");
    ok(run(&scene, "0.03", &["--checkpoint-every", "2", "--out"])
        .args(out(&[&folder]))
        .output()
        .unwrap());
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(
        &scene,
        text.replace("gravity = [0.0, -9.81]", "gravity = [0.0, -30.0]"),
    )
    .unwrap();
    assert_ne!(std::fs::read_to_string(&scene).unwrap(), text, "the edit applies");
    let resumed = Command::new(BIN)
        .args(["run", "--resume"])
        .arg(&folder)
        .args(["--end-time", "0.05"])
        .output()
        .unwrap();
    refused(resumed, "--accept-edited-scene");
    std::fs::write(&scene, &text).unwrap();

    // A checkpoint with a valid checksum that would cut forces.csv inside its header.
    let path = folder.join("checkpoint.bin");
    let mut checkpoint = Checkpoint::<2>::read(&path).unwrap();
    checkpoint.header.metadata["forces_len"] = 5.into();
    checkpoint.write(&path).unwrap();
    let forces = read(&folder.join("forces.csv"));
    let resumed = Command::new(BIN)
        .args(["run", "--resume"])
        .arg(&folder)
        .output()
        .unwrap();
    refused(resumed, "not the end of a row");
    assert_eq!(read(&folder.join("forces.csv")), forces);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_weakly_compressible_run_compressed_beyond_ten_percent_warns() {
    let dir = scratch("mach");
    let folder = dir.join("run");
    let o = ok(run(
        Path::new(SCENE),
        "0.15",
        &["--set", "fluid.sound_speed=5", "--out"],
    )
    .args(out(&[&folder]))
    .output()
    .unwrap());
    let summary = read_summary(&folder.join("summary.json")).unwrap();
    assert!(summary.max_compression > 0.10, "{}", summary.max_compression);
    assert_eq!(summary.warnings.len(), 1, "{:?}", summary.warnings);
    assert!(
        summary.warnings[0].contains("sound_speed"),
        "{}",
        summary.warnings[0]
    );
    assert!(
        stderr(&o).contains("warning: the fluid was compressed"),
        "{}",
        stderr(&o)
    );
    // At the shipped sound speed the same run is within the limit and says nothing.
    let calm = dir.join("calm");
    ok(run(Path::new(SCENE), "0.15", &["--out"])
        .args(out(&[&calm]))
        .output()
        .unwrap());
    let summary = read_summary(&calm.join("summary.json")).unwrap();
    assert!(summary.warnings.is_empty(), "{:?}", summary.warnings);
    std::fs::remove_dir_all(&dir).ok();
}

/// A write past the file-size limit (`ulimit -f`) fails the run with status `failed` naming
/// the file, instead of SIGXFSZ ending the process with nothing recorded.
#[cfg(unix)]
#[test]
fn a_file_size_limit_leaves_status_failed() {
    let dir = scratch("fsize");
    let folder = dir.join("run");
    let o = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -f 64 && exec '{BIN}' run '{SCENE}' --set solver.kind=wcsph --set particles.spacing=0.01 --threads 1 --end-time 0.3 --out '{}'",
            folder.display()
        ))
        .output()
        .unwrap();
    let err = refused(o, "I/O error");
    let summary = read_summary(&folder.join("summary.json")).unwrap();
    assert!(
        summary.status.starts_with("failed: I/O error"),
        "{}\n{err}",
        summary.status
    );
    std::fs::remove_dir_all(&dir).ok();
}
