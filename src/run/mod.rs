//! A whole run: scene → simulation (dimension chosen once) → steps → output files.
//!
//! Output directory layout: `summary.json`, `forces.csv` (one row per solid per step),
//! `bodies.csv` (one row per floating solid per step, `output::bodies`),
//! `steps.csv` (one row per step: time, dt, the criterion that limited it, extremes; columns
//! in [`crate::output::csv`]),
//! `particles.pvd` and `frames/frame_NNNNN.vtu` (every particle with its stable `id`, or only the
//! fluid with `[output] fluid_only = true`; arrays stored as `[output] encoding` says); with
//! `[output] surface = true` also `surface.pvd` and `surface/surface_NNNNN.vtp` (the free surface
//! of eq. (25) at each frame time, [`crate::output::surface_series`]). The `.pvd` is rewritten
//! after every frame and every file is written to a temporary name and renamed, so a run that
//! stops (error or kill) leaves every frame written so far readable; on a step error
//! `summary.json` records it.
//!
//! The folder belongs to one run at a time ([`folder`]): a lock, a manifest of the run's files,
//! and `summary.json` written at the start with status `running` and replaced on every way out
//! by `completed`, `failed: …` or `interrupted …`. A checkpoint carries the run's identity and
//! `--resume` continues only the run that wrote it, from the scene file it started from.

use crate::backend::{BackendKind, cuda};
use crate::error::Error;
use crate::output::Summary;
use crate::probe::ProbeLog;
use crate::scene::{Scene, SceneError};
use crate::solver::Simulation;
use crate::solver::checkpoint::{Checkpoint, CheckpointError};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

pub mod folder;
pub mod out_of_memory;
pub mod ranks;
mod record;
mod report;
mod setup;
mod split_checkpoint;
mod step_row;
mod writers;

pub use folder::{RunFolder, RunFolderError, RunIdentity};
pub use ranks::Ranks;
use record::{record_probes, record_step, write_frame};
pub use setup::{correction, integrator, plan_inputs, sim_config, simulation_from_scene};
pub use step_row::StepRow;
use writers::Writers;
pub use writers::{CHECKPOINT_FILE, STEP_COLUMNS};

/// A simulation of either dimension, chosen once at load time.
pub enum AnySimulation {
    /// A 2D simulation.
    D2(Simulation<2>),
    /// A 3D simulation.
    D3(Simulation<3>),
}

impl AnySimulation {
    /// Builds the simulation of a validated scene in the scene's dimension.
    pub fn from_scene(scene: &Scene) -> Result<Self, Error> {
        match scene.dimension {
            2 => Ok(Self::D2(simulation_from_scene::<2>(scene)?)),
            3 => Ok(Self::D3(simulation_from_scene::<3>(scene)?)),
            d => Err(SceneError::Dimension {
                scene: d,
                requested: 3,
            }
            .into()),
        }
    }
}

/// How to run a scene.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Output directory; `None` writes nothing (tests, benchmarks).
    pub out_dir: Option<PathBuf>,
    /// Replace the files of another run in `out_dir` (only those its manifest lists).
    pub force: bool,
    /// Backend to use.
    pub backend: BackendKind,
    /// Worker threads in use (reported in the summary).
    pub threads: usize,
    /// Scene name for the summary.
    pub scene_name: String,
    /// Checkpoints and restart.
    pub restart: Restart,
    /// Set to a signal number (non-zero) to end the run after its current step with a
    /// checkpoint and status `interrupted` ([`Error::Interrupted`]).
    pub stop: Option<Arc<AtomicUsize>>,
    /// The run is split across ranks (`mpirun -np N sph run`, [`ranks`]); `None`: one process.
    pub ranks: Option<Ranks>,
}

/// Checkpoints of a run (`sph run --checkpoint-every N`, `sph run --resume DIR`).
#[derive(Clone, Debug, Default)]
pub struct Restart {
    /// Write `checkpoint.bin` in the output directory every this many steps and at the end.
    pub every: Option<u64>,
    /// Continue from `checkpoint.bin` in the output directory.
    pub resume: bool,
    /// Resume although the scene file changed since the run started.
    pub accept_edited_scene: bool,
    /// The scene file and its overrides, kept in the checkpoint for `--resume`.
    pub scene: Option<(PathBuf, Vec<String>)>,
}

/// The run driver's state kept in a checkpoint beside the simulation's.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct RunState {
    /// The run that wrote the checkpoint; `--resume` refuses a checkpoint of another run.
    #[serde(default)]
    pub identity: Option<RunIdentity>,
    /// The scene file (absolute) and its overrides.
    pub scene: Option<(PathBuf, Vec<String>)>,
    /// Time of the next output frame [s].
    pub next_frame: f64,
    /// Frames written so far: `(t [s], file)`.
    pub frames: Vec<(f64, String)>,
    /// Surface meshes written so far: `(t [s], vtp file)`.
    #[serde(default)]
    pub surfaces: Vec<(f64, String)>,
    /// Steps per time-step limit so far.
    pub limits: std::collections::BTreeMap<String, u64>,
    /// The probes' record so far.
    pub probes: crate::probe::ProbeState,
    /// Length of `forces.csv` [bytes].
    pub forces_len: Option<u64>,
    /// Length of `steps.csv` [bytes].
    #[serde(default)]
    pub steps_len: Option<u64>,
    /// Length of `bodies.csv` [bytes], when a solid floats.
    #[serde(default)]
    pub bodies_len: Option<u64>,
    /// Wall seconds spent before the checkpoint.
    pub wall_seconds: f64,
    /// The pieces of a split run's checkpoint (`split_checkpoint`); `None` for a whole run's.
    #[serde(default)]
    pub ranks: Option<split_checkpoint::RankPieces>,
}

/// Progress of a run, reported after every step.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Simulated time [s].
    pub time: f64,
    /// End time [s].
    pub end_time: f64,
    /// Steps taken.
    pub steps: u64,
    /// Particle updates per wall-clock second so far.
    pub particle_steps_per_second: f64,
    /// Integrator stages whose position correction hit the iteration cap so far.
    pub unconverged_stages: u64,
    /// Fluid particles removed so far for having left the domain.
    pub removed_particles: u64,
}

/// What a failed run of the scene at `path` into `out` left, for the error's context: the
/// folder untouched (`error` is [`crate::Error::Folder`]: refused before anything was
/// written), results so far, or nothing written. The CLI and the Python module say the same.
pub fn failure_context(path: &Path, out: &Path, error: &Error) -> String {
    if matches!(error, Error::Folder(_)) {
        format!("running scene {} (the folder was left as it was)", path.display())
    } else if out.exists() {
        format!(
            "running scene {} (results so far in {})",
            path.display(),
            out.display()
        )
    } else {
        format!("running scene {} (nothing written)", path.display())
    }
}

/// Runs `scene` to its end time. Returns the summary (also written to `summary.json`).
pub fn run_scene(
    scene: &Scene,
    options: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Summary, Error> {
    // A missing or malformed reference file must stop the run before it computes, not after.
    crate::probe::check_references(scene)?;
    if options.backend == BackendKind::Cuda {
        cuda::probe()?;
    }
    match AnySimulation::from_scene(scene)? {
        AnySimulation::D2(sim) => drive(sim, scene, options, progress),
        AnySimulation::D3(sim) => drive(sim, scene, options, progress),
    }
}

/// The FNV-1a hash of the run's scene file now (empty when the run names none).
fn scene_hash(options: &RunOptions) -> Result<String, Error> {
    match &options.restart.scene {
        Some((file, _)) => {
            let bytes = std::fs::read(file).map_err(|e| crate::output::OutputError::io(file, e))?;
            Ok(folder::hex(&bytes))
        }
        None => Ok(String::new()),
    }
}

/// The checkpoint to resume from, checked against the folder's run and the scene file, and
/// applied to `sim`.
fn resumed_state<const D: usize>(
    sim: &mut Simulation<D>,
    folder: &RunFolder,
    options: &RunOptions,
) -> Result<RunState, Error> {
    let (checkpoint, state) = checked_checkpoint::<D>(folder, options)?;
    sim.restore(checkpoint)?;
    Ok(state)
}

/// The folder's checkpoint and its run state, checked against the folder's run and the scene
/// file.
fn checked_checkpoint<const D: usize>(
    folder: &RunFolder,
    options: &RunOptions,
) -> Result<(Checkpoint<D>, RunState), Error> {
    let path = folder.dir().join(CHECKPOINT_FILE);
    let bad = |reason: String| CheckpointError::Malformed {
        path: path.clone(),
        reason,
    };
    if !folder.owns(CHECKPOINT_FILE) {
        return Err(bad(format!(
            "not written by the run this folder holds (not in {})",
            folder::MANIFEST_FILE
        ))
        .into());
    }
    let checkpoint = Checkpoint::<D>::read(&path)?;
    let state: RunState = serde_json::from_value(checkpoint.header.metadata.clone())
        .map_err(|e| bad(format!("run state: {e}")))?;
    let held = folder.identity();
    match &state.identity {
        Some(id) if id.run_id == held.run_id => {}
        Some(id) => {
            return Err(bad(format!(
                "written by run {}, but the folder holds run {} (a checkpoint from another run or folder)",
                id.run_id, held.run_id
            ))
            .into());
        }
        None => return Err(bad("it names no run".into()).into()),
    }
    let now = scene_hash(options)?;
    if now != held.scene_hash && !options.restart.accept_edited_scene {
        let file = options.restart.scene.as_ref().map(|s| s.0.display().to_string());
        return Err(bad(format!(
            "the scene file {} changed since the run started (hash {} now, {} then); resuming would mix two scenes: give --accept-edited-scene to continue anyway",
            file.unwrap_or_default(),
            now,
            held.scene_hash
        ))
        .into());
    }
    Ok((checkpoint, state))
}

/// Where the time loop ended.
enum Ending {
    /// At the end time.
    Completed,
    /// A step or a write failed.
    Failed(Error),
    /// A signal asked to stop (its number), after a step, or inside the step given, which was
    /// abandoned (`solver::interrupt`).
    Interrupted(usize, Option<u64>),
}

/// What the time loop carries from step to step.
struct Loop {
    writers: Option<Writers>,
    probes: Option<ProbeLog>,
    next_frame: f64,
    limits: std::collections::BTreeMap<String, u64>,
    wall_before: f64,
    start: Instant,
    /// Largest particle speed over the steps [m/s].
    max_speed: f64,
    /// Frames written so far (every rank of a split run counts them, to name its pieces).
    frames_written: usize,
}

fn drive<const D: usize>(
    mut sim: Simulation<D>,
    scene: &Scene,
    options: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Summary, Error> {
    let restart = &options.restart;
    let with_forces = !sim.solid_names().is_empty();
    let root = options.ranks.as_ref().is_none_or(Ranks::is_root);
    // The folder first: a refused folder is left exactly as it was. Split across ranks, rank 0
    // opens it, and the others go on only if it did.
    let folder = if root { open_folder(options) } else { Ok(None) };
    if let Some(ranks) = &options.ranks {
        let opened = ranks.root_says(f64::from(u8::from(folder.is_ok())))?;
        if opened == 0.0 && !root {
            return Err(crate::backend::BackendError::Ranks(
                crate::distributed::DistributedError::RootStopped {
                    reason: "it could not open the run folder",
                },
            )
            .into());
        }
    }
    let folder = folder?;
    let resumed = match (&folder, &options.ranks) {
        (_, Some(ranks)) if restart.resume => Some(split_checkpoint::resume(
            &mut sim,
            folder.as_ref(),
            options,
            ranks,
        )?),
        (Some(f), None) if restart.resume => Some(resumed_state(&mut sim, f, options)?),
        _ => None,
    };
    let mut summary = report::initial(&sim, scene, options, folder.as_ref().map(|f| f.identity()));
    let mut state = Loop {
        writers: None,
        probes: None,
        next_frame: scene.output_interval,
        limits: Default::default(),
        wall_before: 0.0,
        start: Instant::now(),
        max_speed: 0.0,
        frames_written: 0,
    };
    let ending = match start(
        &mut sim,
        scene,
        options,
        folder,
        resumed,
        with_forces,
        &mut summary,
        &mut state,
    )
    .and_then(|()| steps(&mut sim, scene, options, &mut state, progress))
    {
        Ok(ending) => ending,
        Err(e) => Ending::Failed(e),
    };
    report::finish(&mut sim, scene, options, &mut summary, &mut state, ending)
}

/// The run folder of a new run, or of the run `--resume` continues.
fn open_folder(options: &RunOptions) -> Result<Option<RunFolder>, Error> {
    Ok(match &options.out_dir {
        Some(dir) if options.restart.resume => Some(RunFolder::resume(dir)?),
        Some(dir) => {
            let identity = RunIdentity {
                scene_hash: scene_hash(options)?,
                ..RunIdentity::new(None)
            };
            Some(RunFolder::fresh(dir, identity, options.force)?)
        }
        None => None,
    })
}

/// Opens the output files, writes the `running` summary and, on a new run, the first frame.
#[allow(clippy::too_many_arguments)]
fn start<const D: usize>(
    sim: &mut Simulation<D>,
    scene: &Scene,
    options: &RunOptions,
    folder: Option<RunFolder>,
    resumed: Option<RunState>,
    with_forces: bool,
    summary: &mut Summary,
    state: &mut Loop,
) -> Result<(), Error> {
    state.writers = match (folder, &resumed) {
        (Some(folder), Some(r)) => Some(Writers::resume::<D>(folder, with_forces, scene, r)?),
        (Some(folder), None) => Some(Writers::create::<D>(folder, with_forces, scene)?),
        (None, _) => None,
    };
    let device = options.ranks.as_ref().map_or(0, |r| r.device);
    sim.use_backend_on(options.backend, device)?;
    if let Some(ranks) = &options.ranks {
        let pieces = resumed.as_ref().and_then(|r| r.ranks.as_ref());
        split_checkpoint::split(sim, ranks, pieces)?;
        summary.extra.insert("ranks".into(), ranks.size().into());
    }
    summary.backend = sim.backend_name().into();
    if let Some(w) = state.writers.as_mut() {
        w.summary(summary)?;
    }
    let probe_interval = ProbeLog::interval_for(scene);
    let probe_file = match state.writers.as_mut() {
        Some(w) if !scene.probes.is_empty() => Some(w.folder.claim("probes.csv")?),
        _ => None,
    };
    let probe_dir = probe_file.as_deref().and_then(|p| p.parent());
    match resumed {
        Some(r) => {
            state.probes = Some(ProbeLog::resume(scene, probe_dir, probe_interval, r.probes)?);
            state.frames_written = r.frames.len();
            state.next_frame = r.next_frame;
            state.limits = r.limits;
            state.wall_before = r.wall_seconds;
        }
        None => {
            state.probes = Some(ProbeLog::create(scene, probe_dir, probe_interval)?);
            write_frame(sim, scene, options, state)?;
            record_probes(sim, options, state, 0.0, 0.0, true)?;
        }
    }
    state.start = Instant::now();
    Ok(())
}

/// The checkpoint of the run's state now.
fn write_checkpoint<const D: usize>(
    sim: &mut Simulation<D>,
    options: &RunOptions,
    state: &mut Loop,
) -> Result<(), Error> {
    if let Some(ranks) = &options.ranks {
        return split_checkpoint::write(sim, options, state, ranks);
    }
    let Some(run_state) = run_state(options, state)? else {
        return Ok(());
    };
    let w = state.writers.as_mut().expect("run_state needs the writers");
    w.checkpoint(sim, &run_state)
}

/// The run driver's state now, for a checkpoint (`None` without output files).
fn run_state(options: &RunOptions, state: &mut Loop) -> Result<Option<RunState>, Error> {
    let (Some(w), Some(probes)) = (state.writers.as_mut(), state.probes.as_mut()) else {
        return Ok(None);
    };
    let run_state = RunState {
        identity: Some(w.folder.identity().clone()),
        scene: options.restart.scene.clone(),
        next_frame: state.next_frame,
        frames: w.frames().to_vec(),
        surfaces: w.surfaces(),
        limits: state.limits.clone(),
        probes: probes.state()?,
        forces_len: match w.forces.as_mut() {
            Some(f) => Some(f.len_on_disk()?),
            None => None,
        },
        steps_len: Some(w.steps.len_on_disk()?),
        bodies_len: match w.bodies.as_mut() {
            Some(b) => Some(b.len_on_disk()?),
            None => None,
        },
        wall_seconds: state.wall_before + state.start.elapsed().as_secs_f64(),
        ranks: None,
    };
    Ok(Some(run_state))
}

/// Steps to the end time (or a failure, or a stop signal).
fn steps<const D: usize>(
    sim: &mut Simulation<D>,
    scene: &Scene,
    options: &RunOptions,
    state: &mut Loop,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Ending, Error> {
    let end = scene.end_time;
    let every = options.restart.every;
    // A stop request ends a step that runs on past a grace time (`solver::interrupt`): twice
    // the longest step so far, at least `STOP_GRACE`. Not across ranks: they agree on a stop
    // after a step.
    if let (Some(flag), None) = (&options.stop, &options.ranks) {
        sim.interrupt_long_steps(flag.clone(), crate::solver::interrupt::STOP_GRACE);
    }
    let mut longest = std::time::Duration::ZERO;
    while sim.clock().time < end {
        let iterations_before = sim.stats().correction.iterations;
        let started = Instant::now();
        let report = match sim.step(end) {
            Ok(report) => report,
            Err(crate::solver::StepError::Interrupted { signal, step, .. }) => {
                return Ok(Ending::Interrupted(signal, Some(step)));
            }
            Err(e) => return Ok(Ending::Failed(e.into())),
        };
        longest = longest.max(started.elapsed());
        sim.set_interrupt_grace(2 * longest);
        let row = StepRow::of(sim, &report, iterations_before);
        record_step(sim, scene, options, state, &row)?;
        let clock = sim.clock();
        let last = clock.time >= end;
        let mut signal = options.stop.as_ref().map_or(0, |s| s.load(Ordering::SeqCst));
        if let Some(ranks) = &options.ranks {
            // A signal on any rank stops every rank after the same step.
            signal = ranks.largest(signal as f64)? as usize;
        }
        if every.is_some_and(|n| clock.step % n.max(1) == 0 || last) || signal != 0 {
            write_checkpoint(sim, options, state)?;
        }
        if signal != 0 {
            return Ok(Ending::Interrupted(signal, None));
        }
        let wall = state.start.elapsed().as_secs_f64();
        if !options.ranks.as_ref().is_none_or(Ranks::is_root) {
            continue;
        }
        progress(&Progress {
            time: clock.time,
            end_time: end,
            steps: clock.step,
            particle_steps_per_second: clock.step as f64 * sim.fields.len() as f64 / wall.max(1e-9),
            unconverged_stages: sim.stats().correction.unconverged_stages,
            removed_particles: sim.stats().removed_particles,
        });
    }
    Ok(Ending::Completed)
}
