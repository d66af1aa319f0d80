//! The output files of one run, each claimed in the run's folder ([`RunFolder::claim`])
//! before it is first written: the frames and their series, the surface series, `forces.csv`,
//! `steps.csv`, `summary.json` and `checkpoint.bin`.

use super::RunState;
use super::folder::RunFolder;
use crate::error::Error;
use crate::fields::Fields;
use crate::math::Vector;
use crate::output::bodies::BodyLog;
use crate::output::pvtu::{piece_name, write_pvtu};
use crate::output::surface_series::{SurfaceOutputError, SurfaceSeries};
use crate::output::vtu::Frame;
use crate::output::{
    CsvTable, Encoding, ForceLog, OutputError, PvdSeries, Summary, write_summary, write_vtu,
};
use crate::scene::Scene;
use crate::solver::Simulation;
use crate::solver::checkpoint::CheckpointError;
use crate::surface::{SurfaceParams, reconstruct};
use std::path::Path;

/// The name of the checkpoint file in a run's output directory.
pub const CHECKPOINT_FILE: &str = "checkpoint.bin";

/// Columns of `steps.csv`.
pub const STEP_COLUMNS: [&str; 11] = [
    "step",
    "t_s",
    "dt_s",
    "limit",
    "max_speed_m_per_s",
    "max_compression",
    "max_surface_deficit",
    "correction_iterations",
    "removed_particles",
    "created_particles",
    "outflow_particles",
];

/// Output files of one run.
pub(super) struct Writers {
    pub(super) folder: RunFolder,
    pvd: PvdSeries,
    /// Storage of the frames' and surfaces' arrays (`[output] encoding`).
    encoding: Encoding,
    /// Frames hold only the fluid particles (`[output] fluid_only`).
    fluid_only: bool,
    pub(super) forces: Option<ForceLog>,
    /// `bodies.csv`, when a solid floats (`output::bodies`).
    pub(super) bodies: Option<BodyLog>,
    /// `steps.csv`: one row per step, the step and the criterion that limited it.
    pub(super) steps: CsvTable,
    /// The free-surface series and its parameters, when the scene asks for it.
    surface: Option<(SurfaceSeries, SurfaceParams)>,
}

/// Whether a solid of `scene` floats (it then writes `bodies.csv`).
fn floats(scene: &Scene) -> bool {
    scene.solids.iter().any(|s| s.floating.is_some())
}

/// The surface series of a scene with `[output] surface = true`, continuing `entries`.
fn surface_series<const D: usize>(
    folder: &mut RunFolder,
    scene: &Scene,
    entries: &[(f64, String)],
) -> Result<Option<(SurfaceSeries, SurfaceParams)>, Error> {
    if !scene.write_surface {
        return Ok(None);
    }
    folder.claim(crate::output::surface_series::SURFACE_PVD)?;
    let params = SurfaceParams::with_radius::<D>(scene.spacing, scene.surface_radius);
    Ok(Some((
        SurfaceSeries::resume(folder.dir(), entries, scene.output_encoding)?,
        params,
    )))
}

impl Writers {
    /// New files for a new run.
    pub(super) fn create<const D: usize>(
        mut folder: RunFolder,
        with_forces: bool,
        scene: &Scene,
    ) -> Result<Self, Error> {
        let forces = if with_forces {
            Some(ForceLog::create(&folder.claim("forces.csv")?, D)?)
        } else {
            None
        };
        let steps = CsvTable::create(&folder.claim("steps.csv")?, &STEP_COLUMNS)?;
        let bodies = if floats(scene) {
            Some(BodyLog::create(&folder.claim("bodies.csv")?, D)?)
        } else {
            None
        };
        let surface = surface_series::<D>(&mut folder, scene, &[])?;
        Ok(Self {
            folder,
            pvd: PvdSeries::new(),
            encoding: scene.output_encoding,
            fluid_only: scene.fluid_only,
            forces,
            bodies,
            steps,
            surface,
        })
    }

    /// The writers as they were at a checkpoint: the frames it lists (each must exist; later
    /// ones are removed), the CSV logs cut back to their lengths then.
    pub(super) fn resume<const D: usize>(
        mut folder: RunFolder,
        with_forces: bool,
        scene: &Scene,
        state: &RunState,
    ) -> Result<Self, Error> {
        let checkpoint = folder.dir().join(CHECKPOINT_FILE);
        let missing = |name: &str| {
            OutputError::malformed(
                &checkpoint,
                format!("it lists {name}, which is not in the folder (or not this run's)"),
            )
        };
        for (_, name) in state.frames.iter().chain(&state.surfaces) {
            if !folder.owns(name) || !folder.dir().join(name).is_file() {
                return Err(missing(name).into());
            }
        }
        let mut kept: std::collections::BTreeSet<String> = state
            .frames
            .iter()
            .chain(&state.surfaces)
            .map(|(_, n)| n.clone())
            .collect();
        // A parallel frame keeps its pieces (`output::pvtu`).
        for (_, name) in &state.frames {
            if let Some(stem) = name.strip_suffix(".pvtu") {
                let folder_of = |piece: &str| match stem.rsplit_once('/') {
                    Some((parent, _)) => format!("{parent}/{piece}"),
                    None => piece.to_string(),
                };
                for piece in crate::output::pvtu::read_pvtu_pieces(&folder.dir().join(name))? {
                    kept.insert(folder_of(&piece));
                }
            }
        }
        for prefix in ["frames/", "surface/"] {
            for name in folder.listed(prefix) {
                if !kept.contains(&name) {
                    folder.discard(&name)?;
                }
            }
        }
        let forces = match (with_forces, state.forces_len) {
            (true, Some(len)) => Some(ForceLog::resume(&folder.claim("forces.csv")?, D, len)?),
            (true, None) => return Err(missing("no forces.csv length").into()),
            (false, _) => None,
        };
        let mut pvd = PvdSeries::new();
        for (t, name) in &state.frames {
            pvd.push(*t, name.clone());
        }
        let steps = match state.steps_len {
            Some(len) => CsvTable::resume(&folder.claim("steps.csv")?, &STEP_COLUMNS, len)?,
            None => return Err(missing("no steps.csv length").into()),
        };
        let bodies = match (floats(scene), state.bodies_len) {
            (true, Some(len)) => Some(BodyLog::resume(&folder.claim("bodies.csv")?, D, len)?),
            (true, None) => return Err(missing("no bodies.csv length").into()),
            (false, _) => None,
        };
        let surface = surface_series::<D>(&mut folder, scene, &state.surfaces)?;
        Ok(Self {
            folder,
            pvd,
            encoding: scene.output_encoding,
            fluid_only: scene.fluid_only,
            forces,
            bodies,
            steps,
            surface,
        })
    }

    /// The run folder.
    pub(super) fn dir(&self) -> &Path {
        self.folder.dir()
    }

    /// The frames written so far: `(t [s], file)`.
    pub(super) fn frames(&self) -> &[(f64, String)] {
        self.pvd.entries()
    }

    /// The surface meshes written so far: `(t [s], file)`.
    pub(super) fn surfaces(&self) -> Vec<(f64, String)> {
        self.surface
            .as_ref()
            .map_or_else(Vec::new, |s| s.0.entries().to_vec())
    }

    /// Writes `summary.json`.
    /// Writes `summary.json`; while the status is `running`, a `failed: out of memory` copy is
    /// kept ready ([`super::out_of_memory`]).
    pub(super) fn summary(&mut self, summary: &Summary) -> Result<(), Error> {
        let path = self.folder.claim("summary.json")?;
        if summary.status == "running" {
            super::out_of_memory::prepare(&path, summary);
        } else {
            super::out_of_memory::clear();
        }
        Ok(write_summary(&path, summary)?)
    }

    /// Writes `checkpoint.bin` with the run driver's `state`.
    pub(super) fn checkpoint<const D: usize>(
        &mut self,
        sim: &mut Simulation<D>,
        state: &RunState,
    ) -> Result<(), Error> {
        let path = self.folder.claim(CHECKPOINT_FILE)?;
        let metadata = serde_json::to_value(state).map_err(|e| CheckpointError::Malformed {
            path: path.clone(),
            reason: format!("run state: {e}"),
        })?;
        sim.checkpoint(metadata)?.write(&path)?;
        Ok(())
    }

    /// Flushes the logs and writes the frame (when `write_frame`) and surface of `sim`'s state.
    pub(super) fn frame<const D: usize>(
        &mut self,
        sim: &Simulation<D>,
        write_frame: bool,
    ) -> Result<(), Error> {
        self.surface_and_logs(sim.clock().time, &sim.fields)?;
        if !write_frame {
            return Ok(());
        }
        let f = &sim.fields;
        let time = sim.clock().time;
        let name = format!("frames/frame_{:05}.vtu", self.pvd.len());
        let path = self.folder.claim(&name)?;
        write_frame_file(&path, time, f, self.fluid_only, self.encoding)?;
        self.pvd.push(time, name);
        Ok(self.pvd.write(&self.folder.claim("particles.pvd")?)?)
    }

    /// The pieces of the next frame of a run split over `ranks` ranks, claimed in the folder
    /// before any rank writes one (paths, in rank order).
    pub(super) fn claim_pieces(&mut self, ranks: usize) -> Result<Vec<std::path::PathBuf>, Error> {
        let stem = format!("frame_{:05}", self.pvd.len());
        (0..ranks)
            .map(|r| Ok(self.folder.claim(&format!("frames/{}", piece_name(&stem, r)))?))
            .collect()
    }

    /// Flushes the logs and, once every rank wrote its piece of the frame at `time` [s]
    /// ([`Writers::claim_pieces`], [`write_frame_file`]), writes the `.pvtu` header and adds it
    /// to the series (when `write_frame`); the surface from `all`, every rank's particles.
    pub(super) fn parallel_frame<const D: usize>(
        &mut self,
        time: f64,
        ranks: usize,
        all: Option<&Fields<D>>,
        write_frame: bool,
    ) -> Result<(), Error> {
        if let Some(all) = all {
            self.surface_and_logs(time, all)?;
        } else {
            self.surface_and_logs::<D>(time, &Fields::default())?;
        }
        if !write_frame {
            return Ok(());
        }
        let stem = format!("frame_{:05}", self.pvd.len());
        let name = format!("frames/{stem}.pvtu");
        let pieces: Vec<String> = (0..ranks).map(|r| piece_name(&stem, r)).collect();
        write_pvtu(&self.folder.claim(&name)?, &pieces)?;
        self.pvd.push(time, name);
        Ok(self.pvd.write(&self.folder.claim("particles.pvd")?)?)
    }

    /// Flushes the logs and writes the surface of the fluid of `f` at `time` [s].
    fn surface_and_logs<const D: usize>(&mut self, time: f64, f: &Fields<D>) -> Result<(), Error> {
        if let Some(f) = self.forces.as_mut() {
            f.flush()?;
        }
        if let Some(b) = self.bodies.as_mut() {
            b.flush()?;
        }
        self.steps.flush()?;
        if let Some((series, params)) = self.surface.as_mut() {
            let index = series.entries().len();
            self.folder
                .claim(&crate::output::surface_series::surface_file(index))?;
            let fluid: Vec<Vector<D>> = (0..f.len())
                .filter(|&i| f.kind[i] == 0)
                .map(|i| f.position[i])
                .collect();
            let mesh = reconstruct(&fluid, params).map_err(SurfaceOutputError::from)?;
            series
                .push(index, time, &mesh)
                .map_err(SurfaceOutputError::from)?;
        }
        Ok(())
    }
}

/// Writes the particles `f` at `time` [s] to the `.vtu` file `path` (only the fluid with
/// `fluid_only`): a whole frame, or one rank's piece of a parallel one.
pub(super) fn write_frame_file<const D: usize>(
    path: &Path,
    time: f64,
    f: &Fields<D>,
    fluid_only: bool,
    encoding: Encoding,
) -> Result<(), OutputError> {
    let frame = Frame {
        time,
        position: &f.position,
        velocity: &f.velocity,
        density: &f.density,
        pressure: &f.pressure,
        kind: &f.kind,
        id: &f.id,
    };
    if fluid_only {
        write_vtu(path, &frame.fluid().frame(), encoding)
    } else {
        write_vtu(path, &frame, encoding)
    }
}
