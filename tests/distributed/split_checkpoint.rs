//! Checkpoints of split runs (`run::split_checkpoint`): a run interrupted on 2 ranks resumes on
//! 2 ranks bit for bit, and on 3 ranks to the same end with every particle.

use crate::common::scratch;
use sph::backend::partition::SharedCommunicator;
use sph::distributed::{LocalWorld, Method, Rebalance};
use sph::output::Summary;
use sph::run::{Ranks, Restart, RunOptions, run_scene};
use sph::scene::{Scene, load_scene, locate_references};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

fn scene() -> Scene {
    let sets = [
        "particles.spacing=0.01".to_string(),
        "solver.end_time=0.08".to_string(),
    ];
    let mut scene = load_scene(Path::new("scenes/dam_break_2d.toml"), &sets).expect("scene");
    locate_references(&mut scene, None);
    scene
}

/// `scene` on `n` ranks (threads) into `out`, checkpointing every 5 steps; `stop_after`: rank 0
/// raises the stop flag once that many steps are done (every rank then stops after the same
/// step); `resume`: continue the run in `out`. Rank 0's result.
fn run(
    scene: &Scene,
    n: usize,
    out: &Path,
    stop_after: Option<u64>,
    resume: bool,
) -> Result<Summary, String> {
    run_every(scene, n, out, stop_after, resume, 5)
}

/// [`run`], checkpointing every `every` steps.
fn run_every(
    scene: &Scene,
    n: usize,
    out: &Path,
    stop_after: Option<u64>,
    resume: bool,
    every: u64,
) -> Result<Summary, String> {
    let results = LocalWorld::run(n, |rank| {
        let stop = Arc::new(AtomicUsize::new(0));
        let comm: SharedCommunicator = Arc::new(Mutex::new(Box::new(rank)));
        let options = RunOptions {
            out_dir: Some(out.to_path_buf()),
            force: false,
            backend: sph::backend::BackendKind::Cpu,
            threads: 1,
            scene_name: scene.name.clone().unwrap_or_default(),
            restart: Restart {
                every: Some(every),
                resume,
                ..Restart::default()
            },
            stop: Some(stop.clone()),
            ranks: Some(Ranks {
                comm,
                method: Method::Bisection,
                rebalance: Rebalance::Above(0.1),
                device: 0,
            }),
        };
        run_scene(scene, &options, &mut |p| {
            if stop_after.is_some_and(|k| p.steps >= k) {
                stop.store(2, Ordering::SeqCst);
            }
        })
        .map_err(|e| e.to_string())
    });
    results.into_iter().next().expect("rank 0").expect("no panic")
}

fn bytes(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Interrupted after 13 steps (checkpointed then, also every 5 steps before) and resumed on
/// the same 2 ranks, the run writes the same `steps.csv`, `forces.csv` and `probes.csv` byte
/// for byte as the run that was not interrupted, and the same last frame's pieces.
#[test]
fn a_split_run_resumes_bit_for_bit_on_as_many_ranks() {
    let scene = scene();
    let whole = scratch("split_ckpt_straight");
    let straight = run(&scene, 2, &whole, None, false).expect("uninterrupted");
    let out = scratch("split_ckpt_resumed");
    let stopped = run(&scene, 2, &out, Some(12), false);
    assert!(
        stopped.as_ref().is_err_and(|e| e.contains("interrupted")),
        "{stopped:?}"
    );
    // The flag raised after step 12 is read after step 13: the last checkpoint is the
    // interruption's, at step 13; the pieces of step 10 are gone.
    let pieces: Vec<String> = std::fs::read_dir(out.join("checkpoints"))
        .expect("pieces")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(pieces, ["step_000000013_r1.bin"]);
    let resumed = run(&scene, 2, &out, None, true).expect("resumed");
    assert_eq!(resumed.steps, straight.steps);
    for name in ["steps.csv", "forces.csv", "probes.csv"] {
        assert!(bytes(&whole, name) == bytes(&out, name), "{name} differs");
    }
    let last = format!("frames/frame_{:05}_r1.vtu", straight.output_frames - 1);
    assert!(bytes(&whole, &last) == bytes(&out, &last), "{last} differs");
}

/// The run interrupted on 2 ranks resumes on 3: it ends at the same time with every particle
/// and the same fluid mass.
#[test]
fn a_split_run_resumes_on_another_number_of_ranks() {
    let scene = scene();
    let out = scratch("split_ckpt_three");
    let stopped = run(&scene, 2, &out, Some(12), false);
    assert!(stopped.is_err(), "{stopped:?}");
    let resumed = run(&scene, 3, &out, None, true).expect("resumed on 3 ranks");
    let straight = run(&scene, 2, &scratch("split_ckpt_three_straight"), None, false).expect("straight");
    assert_eq!(resumed.status, "completed");
    assert!((resumed.simulated_time - straight.simulated_time).abs() < 1e-12);
    assert_eq!(resumed.particles, straight.particles);
    assert_eq!(resumed.extra["fluid_mass"], straight.extra["fluid_mass"]);
    assert_eq!(resumed.extra["ranks"], 3);
}

/// The open channel (particles created at the inflow and removed at the outflow, with ids
/// above the scene's) interrupted on 2 ranks after 500 steps, once creation has begun, and
/// resumed on 2: `steps.csv` (with the created and removed counts) byte for byte as the run
/// that was not interrupted; resumed on 3: the same steps, created and removed particles and
/// fluid mass.
#[test]
fn a_split_run_with_open_boundaries_resumes() {
    let sets = ["solver.end_time=0.5".to_string()];
    let mut scene = load_scene(Path::new("scenes/open_channel_2d.toml"), &sets).expect("scene");
    locate_references(&mut scene, None);
    let whole = scratch("split_open_straight");
    let straight = run_every(&scene, 2, &whole, None, false, 200).expect("straight");
    for n in [2, 3] {
        let out = scratch(&format!("split_open_resumed_{n}"));
        let stopped = run_every(&scene, 2, &out, Some(500), false, 200);
        assert!(stopped.is_err(), "{stopped:?}");
        let resumed = run_every(&scene, n, &out, None, true, 200).expect("resumed");
        assert_eq!(resumed.status, "completed");
        assert_eq!(resumed.steps, straight.steps);
        assert_eq!(resumed.extra["fluid_mass"], straight.extra["fluid_mass"]);
        for key in ["created_particles", "outflow_particles"] {
            assert_eq!(resumed.extra[key], straight.extra[key], "{key}");
        }
        if n == 2 {
            assert!(
                bytes(&whole, "steps.csv") == bytes(&out, "steps.csv"),
                "steps.csv differs"
            );
        }
    }
    assert!(
        straight.extra["created_particles"]
            .as_u64()
            .is_some_and(|c| c > 0),
        "{:?}",
        straight.extra
    );
}
