//! The backend a [`Simulation`] runs its stages on: choosing it, syncing with it, its memory
//! and per-stage timing.

use super::stage::Stage;
use super::{Simulation, StepError};
use crate::backend::cpu::CpuBackend;
use crate::backend::{Backend, BackendError, BackendKind};
use crate::fields::Fields;
use crate::model::params::StepParams;

impl<const D: usize> Simulation<D> {
    /// Backend name.
    pub fn backend_name(&self) -> &'static str {
        self.backend.name()
    }

    /// Which backend runs the stages.
    pub fn backend_kind(&self) -> BackendKind {
        self.backend.kind()
    }

    /// The device the backend runs on (`None` for the host's CPUs).
    pub fn backend_device(&self) -> Option<String> {
        self.backend.device()
    }

    /// Memory per run the backend's side holds [B]: host fields, grid and scratch for the CPU;
    /// device buffers for a device-resident backend.
    pub fn backend_bytes(&self) -> usize {
        if self.backend.holds_state() {
            self.backend.heap_bytes()
        } else {
            self.heap_bytes()
        }
    }

    /// Runs the stages on `kind` from now on (the CPU backend is the default). The CUDA backend
    /// takes a copy of the current fields into device memory.
    ///
    /// # Errors
    /// [`BackendError`] when the backend cannot run here (no `--features cuda`, no driver, no
    /// NVRTC, no GPU) or the upload fails.
    pub fn use_backend(&mut self, kind: BackendKind) -> Result<(), BackendError> {
        self.use_backend_on(kind, 0)
    }

    /// [`Simulation::use_backend`] on GPU `device` (counted modulo the GPUs this process sees;
    /// a split run's rank takes its local rank, so the ranks of one machine spread over its
    /// GPUs). The CPU backend ignores it.
    ///
    /// # Errors
    /// As [`Simulation::use_backend`].
    pub fn use_backend_on(&mut self, kind: BackendKind, device: usize) -> Result<(), BackendError> {
        self.use_backend_from(|fields, params| match kind {
            BackendKind::Cpu => Ok(Box::new(CpuBackend::new())),
            BackendKind::Cuda => crate::backend::cuda::create(fields, params, device),
        })
    }

    /// Runs the stages from now on on the backend `make` builds from the current fields and
    /// parameters: [`Simulation::use_backend`] for a backend outside [`BackendKind`], such as
    /// the CUDA backend on the host shim (`backend::cuda::shim::Shim::backend`).
    ///
    /// # Errors
    /// What `make` returns, or [`BackendError::Device`] when the old backend's fields cannot be
    /// copied back first.
    pub fn use_backend_from(
        &mut self,
        make: impl FnOnce(&Fields<D>, &StepParams<D>) -> Result<Box<dyn Backend<D> + Send>, BackendError>,
    ) -> Result<(), BackendError> {
        self.sync_fields()?;
        // The velocity solves' records go along (a resumed run switches after the restore).
        let records = self.backend.velocity_solve_records(&self.fields.id)?;
        self.backend = make(&self.fields, &self.step_params())?;
        self.backend
            .restore_velocity_solve_records(&self.fields.id, &records)?;
        self.grid_fresh = false;
        self.density_fresh = false;
        Ok(())
    }

    /// Waits until the backend has finished every stage launched so far (for timings).
    ///
    /// # Errors
    /// [`BackendError`] when a stage failed on the device.
    pub fn synchronize(&mut self) -> Result<(), BackendError> {
        self.backend.synchronize();
        self.backend.take_error().map_or(Ok(()), Err)
    }

    /// Turns per-stage timing on (from zero) or off. While on, each stage waits for the backend
    /// to finish (`Backend::synchronize`) so its time is its own; the step gets slightly slower.
    pub fn time_stages(&mut self, on: bool) {
        self.stage_seconds = on.then(Vec::new);
    }

    /// Wall seconds spent in each stage of the plan since timing was turned on, by stage name
    /// in plan order (the correction loop counts as `correct_positions`, the velocity solves
    /// after it as `velocity_solve`).
    pub fn stage_seconds(&self) -> &[(&'static str, f64)] {
        self.stage_seconds.as_deref().unwrap_or(&[])
    }

    /// Times `count` sweeps (one density pass, the equation of state and one force pass, the
    /// unit of the paper's Fig. 5, plus the surface-tension stages when the scene has them) on
    /// the current state after one untimed warm-up sweep, and
    /// returns the seconds per sweep. The fields keep the last sweep's density, pressure and
    /// acceleration; positions and velocities are unchanged.
    ///
    /// # Errors
    /// [`StepError::Grid`] or [`StepError::Backend`] when a stage fails.
    pub fn time_sweeps(&mut self, count: usize) -> Result<f64, StepError> {
        let step = self.clock.step;
        let params = self.step_params();
        // The plan's own force and surface-tension stages, in plan order, so the sweep is the
        // one a step runs.
        let stages: Vec<Stage> = self
            .plan
            .iter()
            .filter(|s| {
                matches!(
                    s,
                    Stage::Forces(_) | Stage::SurfaceNormals(_) | Stage::SurfaceTension(_)
                )
            })
            .copied()
            .collect();
        let (bk, f) = (&mut self.backend, &mut self.fields);
        bk.sort_by_cell(f, &params)
            .map_err(|source| StepError::Grid { step, source })?;
        let sweep = |bk: &mut Box<dyn Backend<D> + Send>, f: &mut Fields<D>| {
            bk.density(f, &params);
            bk.equation_of_state(f, &params);
            for stage in &stages {
                match *stage {
                    Stage::Forces(terms) => bk.forces(f, &params, terms),
                    Stage::SurfaceNormals(model) => {
                        let params = StepParams {
                            surface_tension_model: model,
                            ..params
                        };
                        bk.surface_normals(f, &params);
                    }
                    Stage::SurfaceTension(model) => {
                        let params = StepParams {
                            surface_tension_model: model,
                            ..params
                        };
                        bk.surface_tension(f, &params);
                    }
                    _ => {}
                }
            }
        };
        sweep(bk, f);
        bk.synchronize();
        let start = std::time::Instant::now();
        for _ in 0..count {
            sweep(bk, f);
        }
        bk.synchronize();
        let seconds = start.elapsed().as_secs_f64() / count.max(1) as f64;
        self.grid_fresh = true;
        self.density_fresh = true;
        self.fields_stale = self.backend.holds_state();
        if let Some(source) = self.backend.take_error() {
            return Err(StepError::Backend { step, source });
        }
        Ok(seconds)
    }

    /// Builds the backend's state again from `fields` (after the host changed them: particles
    /// removed or created), on the same backend and device (`Backend::reload`).
    ///
    /// # Errors
    /// [`BackendError::Device`] when the device cannot take the fields.
    pub(super) fn reload_backend(&mut self) -> Result<(), BackendError> {
        let params = self.step_params();
        self.backend.reload(&self.fields, &params)?;
        self.fields_stale = false;
        self.grid_fresh = false;
        self.density_fresh = false;
        Ok(())
    }

    /// Brings `fields` up to date with the backend's state (a copy from the device for CUDA;
    /// nothing for the CPU). Call before reading `fields` after steps.
    ///
    /// # Errors
    /// [`BackendError::Device`] when the copy fails.
    pub fn sync_fields(&mut self) -> Result<(), BackendError> {
        if self.fields_stale {
            self.backend.download(&mut self.fields)?;
            self.fields_stale = false;
        }
        Ok(())
    }

    /// Bytes held by the particle fields, the grid and the scratch buffers.
    pub fn heap_bytes(&self) -> usize {
        self.fields.heap_bytes() + self.backend.heap_bytes()
    }
}
