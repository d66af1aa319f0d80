//! A whole run: scene → simulation (dimension chosen once) → steps → output files.
//!
//! Output directory layout: `summary.json`, `forces.csv` (one row per solid per step),
//! `steps.csv` (one row per step: time, dt, the criterion that limited it, extremes; columns
//! in [`crate::output::csv`]),
//! `particles.pvd` and `frames/frame_NNNNN.vtu` (every particle with its stable `id`, or only the
//! fluid with `[output] fluid_only = true`; arrays stored as `[output] encoding` says); with
//! `[output] surface = true` also `surface.pvd` and `surface/surface_NNNNN.vtp` (the free surface
//! of eq. (25) at each frame time, [`crate::output::surface_series`]). The `.pvd` is rewritten
//! after every frame and every file is written to a temporary name and renamed, so a run that
//! stops (error or kill) leaves every frame written so far readable; on a step error
//! `summary.json` records it.

use crate::backend::{BackendKind, cuda};
use crate::boundary::keep_out::KeepOutBox;
use crate::error::Error;
use crate::math::{Real, Vector};
use crate::output::surface_series::{SurfaceOutputError, SurfaceSeries};
use crate::output::vtu::Frame;
use crate::output::{
    CsvTable, CsvValue, Encoding, ForceLog, OutputError, PvdSeries, Summary, write_summary, write_vtu,
};
use crate::probe::{ProbeLog, compare, write_figures};
use crate::scene::{Effect, Scene, SceneError, SolidShape, SolverKind, generate};
use crate::solver::checkpoint::{Checkpoint, CheckpointError};
use crate::solver::{Correction, Integrator};
use crate::solver::{SimConfig, Simulation, SurfaceTension};
use crate::surface::{SurfaceParams, reconstruct};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A simulation of either dimension, chosen once at load time.
pub enum AnySimulation {
    /// A 2D simulation.
    D2(Simulation<2>),
    /// A 3D simulation.
    D3(Simulation<3>),
}

/// Builds the `D`-dimensional simulation of a validated scene.
pub fn simulation_from_scene<const D: usize>(scene: &Scene) -> Result<Simulation<D>, Error> {
    let layout = generate::<D>(scene)?;
    let config = sim_config::<D>(scene);
    let solids: Vec<(String, Vec<Vector<D>>)> =
        layout.solids.into_iter().map(|s| (s.name, s.position)).collect();
    let motions = scene.solids.iter().map(|s| s.motion.clone()).collect();
    let mut sim = Simulation::new(config, &layout.fluid_position, &layout.fluid_velocity, &solids)?
        .with_solid_motion(motions)?;
    if scene.has(Effect::Multiphase) {
        sim = sim.with_phases(&crate::scene::fluid_rest_density(scene)?)?;
    }
    sim.set_keep_out(keep_out_boxes::<D>(scene, &solids))?;
    Ok(sim)
}

/// The solids' volumes for the no-penetration guard (`boundary::keep_out`): a `box` solid is its
/// region, a `container` the slabs of its walls (`wall_layers` spacings thick).
fn keep_out_boxes<const D: usize>(scene: &Scene, solids: &[(String, Vec<Vector<D>>)]) -> Vec<KeepOutBox<D>> {
    let vector = |v: &[f64]| Vector::<D>::from_iterator(v.iter().map(|&c| c as Real));
    let thickness = (scene.wall_layers() as f64 * scene.spacing) as Real;
    let mut boxes = Vec::new();
    for s in &scene.solids {
        let Some(index) = solids.iter().position(|(name, _)| *name == s.name) else {
            continue;
        };
        let (min, max) = (vector(&s.region.min), vector(&s.region.max));
        match s.shape {
            SolidShape::Box => boxes.push(KeepOutBox::fixed(min, max, index as u32)),
            SolidShape::Container => boxes.extend(KeepOutBox::container(
                min,
                max,
                thickness,
                s.open_top,
                index as u32,
            )),
        }
    }
    boxes
}

/// The solver settings of a validated scene (`scene.dimension` must be `D`).
pub fn sim_config<const D: usize>(scene: &Scene) -> SimConfig<D> {
    let vector = |v: &[f64]| Vector::<D>::from_iterator(v.iter().map(|&c| c as f32));
    SimConfig::<D> {
        spacing: scene.spacing,
        h: scene.smoothing_length,
        rho0: scene.rho0,
        sound_speed: scene.sound_speed,
        viscosity: if scene.has(Effect::Viscosity) {
            scene.viscosity
        } else {
            None
        },
        artificial_viscosity: if scene.has(Effect::ArtificialViscosity) {
            scene.artificial_viscosity
        } else {
            None
        },
        gravity: if scene.has(Effect::Gravity) {
            scene.gravity.as_deref().map(vector)
        } else {
            None
        },
        gravity_ramp: scene.gravity_ramp,
        angular_velocity: if scene.has(Effect::RotatingFrame) {
            scene.angular_velocity
        } else {
            None
        },
        rotation_centre: vector(&scene.rotation_centre),
        surface_tension: if scene.has(Effect::SurfaceTension) {
            scene.surface_tension.map(|sigma| SurfaceTension {
                sigma,
                model: scene.surface_tension_model,
            })
        } else {
            None
        },
        dt: scene.dt,
        cfl: scene.cfl,
        domain_min: vector(&scene.domain.min),
        domain_max: vector(&scene.domain.max),
        integrator: integrator(scene),
        correction: correction(scene),
    }
}

/// What the stage plan of a validated scene depends on (`solver::plan`): its effects, its
/// solids and whether any moves, its integrator and solver.
pub fn plan_inputs(scene: &Scene) -> crate::solver::plan::PlanInputs {
    crate::solver::plan::PlanInputs {
        viscosity: scene.has(Effect::Viscosity),
        artificial_viscosity: scene.has(Effect::ArtificialViscosity),
        rotating_frame: scene.has(Effect::RotatingFrame),
        surface_tension: scene
            .has(Effect::SurfaceTension)
            .then_some(scene.surface_tension_model),
        solids: !scene.solids.is_empty(),
        moving_solids: scene.solids.iter().any(|s| s.motion.is_some()),
        integrator: integrator(scene),
        corrected: correction(scene).is_some(),
    }
}

/// The scene's integrator.
pub fn integrator(scene: &Scene) -> Integrator {
    match scene.solver.integrator {
        crate::scene::Integrator::SymplecticEuler => Integrator::SymplecticEuler,
        crate::scene::Integrator::Rk3 => Integrator::Rk3,
    }
}

/// The scene's position-correction settings; `None` for `wcsph`.
pub fn correction(scene: &Scene) -> Option<Correction> {
    let s = &scene.solver;
    match s.kind {
        SolverKind::Wcsph => None,
        SolverKind::Corrected => Some(Correction {
            delta: s.delta,
            max_iterations: s.max_iterations,
            strict: s.strict,
            relaxation: s.relaxation,
        }),
    }
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
    /// Backend to use.
    pub backend: BackendKind,
    /// Worker threads in use (reported in the summary).
    pub threads: usize,
    /// Scene name for the summary.
    pub scene_name: String,
    /// Checkpoints and restart.
    pub restart: Restart,
}

/// Checkpoints of a run (`sph run --checkpoint-every N`, `sph run --resume DIR`).
#[derive(Clone, Debug, Default)]
pub struct Restart {
    /// Write `checkpoint.bin` in the output directory every this many steps and at the end.
    pub every: Option<u64>,
    /// Continue from `checkpoint.bin` in the output directory.
    pub resume: bool,
    /// The scene file and its overrides, kept in the checkpoint for `--resume`.
    pub scene: Option<(PathBuf, Vec<String>)>,
}

/// The run driver's state kept in a checkpoint beside the simulation's.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct RunState {
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
    /// Wall seconds spent before the checkpoint.
    pub wall_seconds: f64,
}

/// The name of the checkpoint file in a run's output directory.
pub const CHECKPOINT_FILE: &str = "checkpoint.bin";

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

/// Output files of one run.
struct Writers {
    dir: PathBuf,
    pvd: PvdSeries,
    /// Storage of the frames' and surfaces' arrays (`[output] encoding`).
    encoding: Encoding,
    /// Frames hold only the fluid particles (`[output] fluid_only`).
    fluid_only: bool,
    forces: Option<ForceLog>,
    /// `steps.csv`: one row per step, the step and the criterion that limited it.
    steps: CsvTable,
    /// The free-surface series and its parameters, when the scene asks for it.
    surface: Option<(SurfaceSeries, SurfaceParams)>,
}

/// The surface series of a scene with `[output] surface = true`, continuing `entries`.
fn surface_series<const D: usize>(
    dir: &Path,
    scene: &Scene,
    entries: &[(f64, String)],
) -> Result<Option<(SurfaceSeries, SurfaceParams)>, OutputError> {
    if !scene.write_surface {
        return Ok(None);
    }
    let params = SurfaceParams::with_radius::<D>(scene.spacing, scene.surface_radius);
    Ok(Some((
        SurfaceSeries::resume(dir, entries, scene.output_encoding)?,
        params,
    )))
}

/// Columns of `steps.csv`.
const STEP_COLUMNS: [&str; 8] = [
    "step",
    "t_s",
    "dt_s",
    "limit",
    "max_speed_m_per_s",
    "max_compression",
    "max_surface_deficit",
    "correction_iterations",
];

impl Writers {
    /// The writers as they were at a checkpoint: frames listed up to then, `forces.csv` cut back.
    fn resume<const D: usize>(
        dir: &Path,
        with_forces: bool,
        scene: &Scene,
        state: &RunState,
    ) -> Result<Self, OutputError> {
        std::fs::create_dir_all(dir.join("frames")).map_err(|e| OutputError::io(&dir.join("frames"), e))?;
        let forces = match (with_forces, state.forces_len) {
            (true, Some(len)) => Some(ForceLog::resume(&dir.join("forces.csv"), D, len)?),
            (true, None) => Some(ForceLog::create(&dir.join("forces.csv"), D)?),
            (false, _) => None,
        };
        let mut pvd = PvdSeries::new();
        for (t, name) in &state.frames {
            pvd.push(*t, name.clone());
        }
        let steps_path = dir.join("steps.csv");
        let steps = match state.steps_len {
            Some(len) => CsvTable::resume(&steps_path, &STEP_COLUMNS, len)?,
            None => CsvTable::create(&steps_path, &STEP_COLUMNS)?,
        };
        Ok(Self {
            dir: dir.to_path_buf(),
            pvd,
            encoding: scene.output_encoding,
            fluid_only: scene.fluid_only,
            forces,
            steps,
            surface: surface_series::<D>(dir, scene, &state.surfaces)?,
        })
    }

    fn create<const D: usize>(dir: &Path, with_forces: bool, scene: &Scene) -> Result<Self, OutputError> {
        std::fs::create_dir_all(dir.join("frames")).map_err(|e| OutputError::io(&dir.join("frames"), e))?;
        let forces = if with_forces {
            Some(ForceLog::create(&dir.join("forces.csv"), D)?)
        } else {
            None
        };
        Ok(Self {
            dir: dir.to_path_buf(),
            pvd: PvdSeries::new(),
            encoding: scene.output_encoding,
            fluid_only: scene.fluid_only,
            forces,
            steps: CsvTable::create(&dir.join("steps.csv"), &STEP_COLUMNS)?,
            surface: surface_series::<D>(dir, scene, &[])?,
        })
    }

    fn frame<const D: usize>(&mut self, sim: &Simulation<D>, write_frame: bool) -> Result<(), Error> {
        if let Some(f) = self.forces.as_mut() {
            f.flush()?;
        }
        self.steps.flush()?;
        let f = &sim.fields;
        let time = sim.clock().time;
        if let Some((series, params)) = self.surface.as_mut() {
            let fluid: Vec<Vector<D>> = (0..f.len())
                .filter(|&i| f.kind[i] == 0)
                .map(|i| f.position[i])
                .collect();
            let mesh = reconstruct(&fluid, params).map_err(SurfaceOutputError::from)?;
            series
                .push(series.entries().len(), time, &mesh)
                .map_err(SurfaceOutputError::from)?;
        }
        if !write_frame {
            return Ok(());
        }
        let name = format!("frames/frame_{:05}.vtu", self.pvd.len());
        let frame = Frame {
            time,
            position: &f.position,
            velocity: &f.velocity,
            density: &f.density,
            pressure: &f.pressure,
            kind: &f.kind,
            id: &f.id,
        };
        let path = self.dir.join(&name);
        if self.fluid_only {
            write_vtu(&path, &frame.fluid().frame(), self.encoding)?;
        } else {
            write_vtu(&path, &frame, self.encoding)?;
        }
        self.pvd.push(time, name);
        Ok(self.pvd.write(&self.dir.join("particles.pvd"))?)
    }
}

fn drive<const D: usize>(
    mut sim: Simulation<D>,
    scene: &Scene,
    options: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Summary, Error> {
    let end = scene.end_time;
    let restart = &options.restart;
    let with_forces = !sim.solid_names().is_empty();
    // On --resume: the state and the output bookkeeping of the checkpoint.
    let resumed: Option<RunState> = match (&options.out_dir, restart.resume) {
        (Some(dir), true) => {
            let checkpoint = Checkpoint::<D>::read(&dir.join(CHECKPOINT_FILE))?;
            let state: RunState =
                serde_json::from_value(checkpoint.header.metadata.clone()).map_err(|e| {
                    CheckpointError::Malformed {
                        path: dir.join(CHECKPOINT_FILE),
                        reason: format!("run state: {e}"),
                    }
                })?;
            sim.restore(checkpoint)?;
            Some(state)
        }
        _ => None,
    };
    let mut writers = match (&options.out_dir, &resumed) {
        (Some(dir), Some(state)) => Some(Writers::resume::<D>(dir, with_forces, scene, state)?),
        (Some(dir), None) => Some(Writers::create::<D>(dir, with_forces, scene)?),
        (None, _) => None,
    };
    sim.use_backend(options.backend)?;
    let solver = scene.solver.kind.name();
    let mut summary = Summary {
        scene: options.scene_name.clone(),
        scene_file: options.restart.scene.as_ref().map(|(file, _)| file.clone()),
        scene_overrides: options
            .restart
            .scene
            .as_ref()
            .map(|(_, sets)| sets.clone())
            .unwrap_or_default(),
        dimension: D,
        solver: solver.into(),
        backend: sim.backend_name().into(),
        threads: options.threads,
        particles: sim.fields.len() as u64,
        fluid_particles: sim.fluid_count() as u64,
        status: "running".into(),
        ..Summary::default()
    };
    let probe_dir = writers.as_ref().map(|w| w.dir.as_path());
    let probe_interval = scene.output_interval / 10.0;
    let (mut probes, mut next_frame, mut limits, wall_before) = match resumed {
        Some(state) => (
            ProbeLog::resume(scene, probe_dir, probe_interval, state.probes)?,
            state.next_frame,
            state.limits,
            state.wall_seconds,
        ),
        None => {
            let mut probes = ProbeLog::create(scene, probe_dir, probe_interval)?;
            if let Some(w) = writers.as_mut() {
                w.frame(&sim, scene.write_frames)?;
            }
            probes.record(0.0, 0.0, &sim.fields, sim.solid_forces(), true)?;
            (
                probes,
                scene.output_interval,
                std::collections::BTreeMap::new(),
                0.0,
            )
        }
    };
    let start = Instant::now();
    let mut failure = None;
    while sim.clock().time < end {
        let iterations_before = sim.stats().correction.iterations;
        let dt = match sim.step(end) {
            Ok(report) => {
                let name = serde_json::to_value(report.limit)
                    .ok()
                    .and_then(|v| v.as_str().map(String::from))
                    .unwrap_or_default();
                if let Some(w) = writers.as_mut() {
                    let e = &report.extremes;
                    let clock = sim.clock();
                    w.steps.push_row(&[
                        CsvValue::Int(clock.step as i64),
                        CsvValue::Float(clock.time),
                        CsvValue::Float(report.dt),
                        CsvValue::Text(&name),
                        CsvValue::Float(e.max_speed),
                        CsvValue::Float(e.max_compression),
                        CsvValue::Float(e.max_surface_deficit),
                        CsvValue::Int((sim.stats().correction.iterations - iterations_before) as i64),
                    ])?;
                }
                *limits.entry(name).or_default() += 1;
                report.dt
            }
            Err(e) => {
                failure = Some(e);
                break;
            }
        };
        let clock = sim.clock();
        let last = clock.time >= end;
        let frame_due = writers.is_some()
            && (scene.write_frames || scene.write_surface)
            && (clock.time >= next_frame - 1e-12 * end || last);
        if frame_due || probes.wants_fields(clock.time, last) {
            sim.sync_fields()?;
        }
        probes.record(clock.time, dt, &sim.fields, sim.solid_forces(), last)?;
        if let Some(w) = writers.as_mut() {
            if let Some(log) = w.forces.as_mut() {
                for (name, force) in sim.solid_names().iter().zip(sim.solid_forces()) {
                    log.push(clock.time, name, *force)?;
                }
            }
            if clock.time >= next_frame - 1e-12 * end || clock.time >= end {
                w.frame(&sim, scene.write_frames)?;
                while next_frame <= clock.time + 1e-12 * end {
                    next_frame += scene.output_interval;
                }
            }
        }
        if let (Some(w), Some(every)) = (writers.as_mut(), restart.every)
            && (clock.step % every.max(1) == 0 || clock.time >= end)
        {
            let state = RunState {
                scene: restart.scene.clone(),
                next_frame,
                frames: w.pvd.entries().to_vec(),
                surfaces: w
                    .surface
                    .as_ref()
                    .map_or_else(Vec::new, |s| s.0.entries().to_vec()),
                limits: limits.clone(),
                probes: probes.state()?,
                forces_len: match w.forces.as_mut() {
                    Some(f) => Some(f.len_on_disk()?),
                    None => None,
                },
                steps_len: Some(w.steps.len_on_disk()?),
                wall_seconds: wall_before + start.elapsed().as_secs_f64(),
            };
            let metadata = serde_json::to_value(&state).map_err(|e| CheckpointError::Malformed {
                path: w.dir.join(CHECKPOINT_FILE),
                reason: format!("run state: {e}"),
            })?;
            sim.checkpoint(metadata)?.write(&w.dir.join(CHECKPOINT_FILE))?;
        }
        let wall = start.elapsed().as_secs_f64();
        progress(&Progress {
            time: clock.time,
            end_time: end,
            steps: clock.step,
            particle_steps_per_second: clock.step as f64 * sim.fields.len() as f64 / wall.max(1e-9),
            unconverged_stages: sim.stats().correction.unconverged_stages,
        });
    }
    let wall = wall_before + start.elapsed().as_secs_f64();
    sim.sync_fields()?;
    let clock = sim.clock();
    let stats = sim.stats();
    let steps = clock.step.max(1) as f64;
    summary.steps = clock.step;
    summary.simulated_time = clock.time;
    summary.wall_seconds = wall;
    summary.particle_steps_per_second = clock.step as f64 * sim.fields.len() as f64 / wall.max(1e-9);
    summary.max_compression = stats.max_compression;
    summary.mean_compression = stats.sum_mean_compression / steps;
    summary.max_surface_deficit = stats.max_surface_deficit;
    summary.mean_surface_deficit = stats.sum_mean_surface_deficit / steps;
    summary.output_frames = writers.as_ref().map_or(0, |w| w.pvd.len() as u64);
    summary.status = match &failure {
        None => "completed".into(),
        Some(e) => format!("failed: {e}"),
    };
    let extra = &mut summary.extra;
    extra.insert("fluid_mass".into(), sim.fluid_mass().into());
    extra.insert("memory_bytes".into(), (sim.heap_bytes() as u64).into());
    extra.insert(
        "memory_bytes_per_particle".into(),
        (sim.heap_bytes() as f64 / sim.fields.len().max(1) as f64).into(),
    );
    extra.insert("smoothing_length".into(), scene.smoothing_length.into());
    extra.insert("spacing".into(), scene.spacing.into());
    extra.insert(
        "time_step_limits".into(),
        serde_json::Value::Object(limits.into_iter().map(|(k, v)| (k, v.into())).collect()),
    );
    extra.insert(
        "plan".into(),
        sim.plan().iter().map(|s| s.name()).collect::<Vec<_>>().into(),
    );
    extra.insert("integrator".into(), scene.solver.integrator.name().into());
    // How often the no-penetration guard, not the particle boundary, held the fluid.
    extra.insert("keep_out_pushes".into(), stats.keep_out_pushes.into());
    if let Some(c) = sim.config().correction {
        let cs = stats.correction;
        extra.insert("delta".into(), c.delta.into());
        extra.insert("correction_iterations_mean".into(), cs.mean_iterations().into());
        extra.insert("correction_iterations_max".into(), cs.max_iterations.into());
        extra.insert("corrected_stages".into(), cs.stages.into());
        extra.insert("unconverged_stages".into(), cs.unconverged_stages.into());
        extra.insert("velocity_solves".into(), cs.velocity_solves.into());
        extra.insert(
            "velocity_iterations_mean".into(),
            cs.mean_velocity_iterations().into(),
        );
        extra.insert(
            "operator_applications_per_stage".into(),
            cs.mean_operator_applications().into(),
        );
        extra.insert(
            "velocity_solves_given_up".into(),
            cs.velocity_solves_given_up.into(),
        );
        extra.insert(
            "max_compression_after_correction".into(),
            cs.max_compression_after.into(),
        );
    }
    let comparisons = compare(scene, &probes)?;
    let mut probe_errors = serde_json::Map::new();
    for c in &comparisons {
        let value = match (&c.error, &c.peak) {
            (Some(e), _) => serde_json::json!({"error_max": e.max, "error_mean": e.mean, "points": e.count}),
            (None, Some(peak)) => {
                let (sim, reference) = (peak.simulated, peak.reference);
                serde_json::json!({
                    "peak_time_s": sim.0,
                    "peak_N": sim.1,
                    "reference_peak_time_s": reference.0,
                    "reference_peak_N": reference.1,
                    "peak_error": (sim.1 - reference.1) / reference.1,
                    "peak_time_error_s": sim.0 - reference.0,
                    "onset_time_s": peak.onset.map(|o| o.0),
                    "reference_onset_time_s": peak.onset.map(|o| o.1),
                    "rise_time_error_s": peak.rise_time_error(),
                })
            }
            (None, None) => serde_json::Value::Null,
        };
        probe_errors.insert(c.name.clone(), value);
    }
    // A probe whose reference file is not available was sampled but not compared.
    for skipped in crate::scene::skipped_references(scene) {
        let value = serde_json::json!({
            "status": "skipped",
            "reference_file": skipped.file.display().to_string(),
            "reason": skipped.reason.to_string(),
        });
        probe_errors.insert(skipped.probe, value);
    }
    if !probe_errors.is_empty() {
        extra.insert("probe_errors".into(), probe_errors.into());
    }
    if let Some(w) = writers.as_ref() {
        write_figures(&w.dir, solver, &comparisons)?;
    }
    if let Some(w) = writers.as_mut() {
        write_summary(&w.dir.join("summary.json"), &summary)?;
    }
    match failure {
        None => Ok(summary),
        Some(e) => Err(e.into()),
    }
}
