//! [`CudaBackend`]: every particle field in device memory, one kernel launch (or a short fixed
//! sequence) per `Backend` stage, under the CPU backend's names. Particle data crosses to the
//! host only in [`Backend::download`] (output frames, probes, checkpoints, error reports) and a
//! few scalars per stage (reductions the driver needs: the time step's extremes, the correction's
//! residual and largest displacement, forces on solids).
//!
//! This file holds the buffers, the construction, the transfers and the `Backend` methods, which
//! call one `launch_<stage>` per stage; the stages live in child modules named as the kernel files
//! they launch (`sort_by_cell`, `density`, `density_rate`, `wall_pressure`, `move_solids`, `forces`,
//! `solid_forces`, `surface_tension`, `state_extremes`, `integrate`, `correction`, `anderson`,
//! `warm_start`),
//! as those of the CPU backend.

use super::compile::{arch_for, compile_all};
use super::extremes::{DeviceExtremes, max_from_bits, max_from_bits_or_nan, sweep};
use super::grid::GridGeometry;
use super::launch::{Buffer, DeviceFault, Gpu, KERNEL_NAMES, Launch, Memory};
use crate::backend::partition::Partition;
use crate::backend::{
    Backend, BackendError, CorrectionError, ForceTerms, MomentSums, SolidForceSource, SolidLoad,
    StateExtremes, Sweep, WallModel,
};
use crate::boundary::keep_out::{KeepOutBox, KeepOutReport};
use crate::boundary::motion::{SolidKinematics, SolidReference};
use crate::boundary::rigid::motion_floats;
use crate::fields::{Field, Fields};
use crate::grid::GridError;
use crate::math::{Real, Vector};
use crate::model::pair_terms::PairTerms;
use crate::model::params::StepParams;
use crate::physics::damping_zone::DampingZone;
use crate::physics::multiphase::Phases;
use crate::solver::anderson::AndersonState;
use cudarc::driver::CudaContext;

/// Views a slice of `D`-vectors as its `n·D` floats (the layout the kernels use).
fn floats<const D: usize>(v: &[Vector<D>]) -> &[Real] {
    const { assert!(std::mem::size_of::<Vector<1>>() == std::mem::size_of::<Real>()) };
    // SAFETY: `Vector<D>` is nalgebra's `#[repr(C)]` matrix over a `[[Real; D]; 1]` array
    // storage: `D` contiguous floats with the alignment of `Real`, no padding.
    unsafe { std::slice::from_raw_parts(v.as_ptr().cast::<Real>(), v.len() * D) }
}

fn floats_mut<const D: usize>(v: &mut [Vector<D>]) -> &mut [Real] {
    // SAFETY: as in `floats`.
    unsafe { std::slice::from_raw_parts_mut(v.as_mut_ptr().cast::<Real>(), v.len() * D) }
}

/// The particle fields in device memory (mirror of `Fields`, struct of arrays, `D` floats per
/// vector).
struct DeviceFields<K: Memory> {
    position: K::Buf<f32>,
    velocity: K::Buf<f32>,
    acceleration: K::Buf<f32>,
    position_start: K::Buf<f32>,
    velocity_start: K::Buf<f32>,
    density: K::Buf<f32>,
    pressure: K::Buf<f32>,
    mass: K::Buf<f32>,
    kind: K::Buf<u32>,
    id: K::Buf<u32>,
    /// `Fields::wall_velocity` ([A12] no-slip walls): only where the host allocated it (viscosity
    /// with solids), or once the `wall_velocity` stage runs.
    wall_velocity: Option<K::Buf<f32>>,
    /// `Fields::rest_density` where the fields carry it (the `multiphase` effect); the stages
    /// run on `StepParams::phases` and [`multiphase_rest`] reports a plan of several phases
    /// on a backend built without it.
    rest_density: Option<K::Buf<f32>>,
    /// `Fields::acting_pressure` where the fields carry it (the `corrected` solver), written by
    /// `end_velocity_solve` and `record_acting_pressure`.
    acting_pressure: Option<K::Buf<f32>>,
}

/// The dense cell grid and the sort's buffers.
struct DeviceGrid<const D: usize, K: Memory> {
    geometry: GridGeometry<D>,
    cell_size: Real,
    /// Per particle: key at hashing time (unsorted order).
    key: K::Buf<u32>,
    /// Per particle: key of its cell at the last sort (sorted order).
    cell_key: K::Buf<u32>,
    /// Per cell (+1): particle count, then the scan's output.
    cell_count: K::Buf<u32>,
    cell_start: K::Buf<u32>,
    cell_fill: K::Buf<u32>,
    /// Per scan level: the chunk sums of the level below, and their exclusive scan.
    chunk_sums: Vec<(K::Buf<u32>, K::Buf<u32>)>,
    perm: K::Buf<u32>,
}

/// The CUDA backend of dimension `D` on the device `K`: a GPU ([`Gpu`]), or the host shim
/// (`shim::Shim`), which runs the same kernels in the same sequence on the CPU.
pub struct CudaBackend<const D: usize, K: Launch<D> = Gpu> {
    dev: K,
    n: usize,
    domain: (Vector<D>, Vector<D>),
    f: DeviceFields<K>,
    grid: Option<DeviceGrid<D, K>>,
    scratch_vec: K::Buf<f32>,
    scratch_u32: K::Buf<u32>,
    /// The correction's pressure `Δp` (eq. 19) and the sweep's displacements (`D` floats per
    /// particle). These and the three `*_solve_start` buffers below serve the `corrected`
    /// solver alone: they hold one element until its first stage
    /// (`ensure_correction_buffers`), so a `wcsph` run holds none of them.
    delta_p: K::Buf<f32>,
    /// The previous sweep's `Δp` (the momentum term), and the scratch of `sort_by_cell`'s
    /// gathers for every solver (so always `n` floats).
    delta_p_previous: K::Buf<f32>,
    has_previous: bool,
    displacement: K::Buf<f32>,
    /// Velocities (`D` floats per particle) and pressures at `begin_velocity_solve`, for
    /// `end_velocity_solve`. They live within one velocity solve, which no sort interrupts, so
    /// `sort_by_cell` does not gather them.
    velocity_solve_start: K::Buf<f32>,
    pressure_solve_start: K::Buf<f32>,
    /// Densities (18) at `begin_velocity_solve`, for the solve's base density
    /// (`velocity_solve_base`, kernels/sph.cuh).
    density_solve_start: K::Buf<f32>,
    /// The velocity solve's Anderson acceleration (`solver::anderson`): the host state, reset by
    /// `begin_velocity_solve`, and the window on the device (`anderson`), allocated at the first
    /// `mix_velocity_pressure`.
    anderson: AndersonState,
    anderson_buffers: Option<anderson::AndersonBuffers<K>>,
    reduce_i32: K::Buf<i32>,
    extremes: K::Buf<DeviceExtremes>,
    solid_out: K::Buf<f64>,
    /// The gradient moment's sums, 2 doubles (`gradient_moment`).
    moment_out: K::Buf<f64>,
    /// The guard's boxes as last uploaded (`kernels/keep_out.cu` layout) and on the device.
    keep_out_host: Vec<f32>,
    keep_out_boxes: K::Buf<f32>,
    /// The guard's per-solid counts and momentum changes, 4 doubles per solid.
    keep_out_out: K::Buf<f64>,
    /// Moving solids: `x0` by id (`D` floats per solid particle), uploaded at the first
    /// `move_solids`; `None` until then (and in scenes where nothing moves).
    solid_reference: Option<K::Buf<f32>>,
    /// Per solid the motion record of the last `move_solids` (`motion_floats(D)` floats,
    /// `SolidKinematics::kernel_floats`).
    solid_motion: K::Buf<f32>,
    /// Per solid the motion record given to `wall_pressure` (as `solid_motion`); zeros while
    /// nothing moves.
    wall_motion: K::Buf<f32>,
    /// Whether `wall_motion` holds the records of the last `wall_pressure` (else zeros).
    wall_motion_set: bool,
    /// Surface normals [AAT13] (`D` floats per particle), allocated by the first
    /// `surface_normals` (only scenes with the `surface_tension` effect run it). Recomputed after
    /// every sort before use, so the sort does not gather it.
    normal: Option<K::Buf<f32>>,
    /// `dρ/dt` of the continuity equation ([F19]), allocated by the first `density_rate`
    /// (only scenes with the `density_diffusion` effect run it).
    density_rate: Option<K::Buf<f32>>,
    /// The step-start density of SSP-RK3 with that effect, allocated by the first
    /// `store_density_start`; the backend's scratch, as `position_start`.
    density_start: Option<K::Buf<f32>>,
    /// The whole simulation or one rank's share (`backend::partition`): which particles the
    /// reductions count, and how they combine with the other ranks'.
    partition: Partition,
    /// The partition's mask on the device, in the current order: 1 for a particle the
    /// reductions count, 0 for a ghost (all ones for the whole simulation).
    owned: K::Buf<u32>,
    /// One more than the largest particle id uploaded: the ids the velocity solves' records
    /// must hold.
    id_bound: usize,
    /// Each stage's last velocity solve, its warm start (`warm_start`).
    solve_records: warm_start::VelocitySolveRecords<K>,
    error: Option<BackendError>,
}

/// Keeps the first failure in `error`; later stages are skipped until the driver takes it.
fn record<T>(error: &mut Option<BackendError>, during: &str, r: Result<T, DeviceFault>) -> Option<T> {
    match r {
        Ok(v) => Some(v),
        Err(e) => {
            if error.is_none() {
                *error = Some(device_error(during, e));
            }
            None
        }
    }
}

/// The rest densities the [`Phases::Multi`] variants read; `None`, with the error recorded,
/// where the backend holds none (its fields were uploaded before `Simulation::with_phases`).
fn multiphase_rest<'a, B>(rest_density: &'a Option<B>, error: &mut Option<BackendError>) -> Option<&'a B> {
    if rest_density.is_none() && error.is_none() {
        *error = Some(BackendError::Device {
            backend: "cuda",
            during: "running a multiphase stage".into(),
            reason: "the fields were uploaded without rest densities".into(),
        });
    }
    rest_density.as_ref()
}

fn device_error(during: &str, e: impl Into<DeviceFault>) -> BackendError {
    BackendError::Device {
        backend: "cuda",
        during: during.into(),
        reason: e.into().0,
    }
}

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    /// Uploads `fields` to `dev`; `params` gives the domain of the dense grid.
    ///
    /// # Errors
    /// [`BackendError::Device`] when an allocation or the upload fails.
    pub fn on_device(dev: K, fields: &Fields<D>, params: &StepParams<D>) -> Result<Self, BackendError> {
        let n = fields.len();
        let up = |during: &str, e: DeviceFault| device_error(during, e);
        let dn = (n * D).max(1);
        let vec_zeros = |d: &K| d.alloc_zeros::<f32>(dn).map_err(|e| up("allocating", e));
        let upload = |d: &K, v: &[f32]| d.upload(v).map_err(|e| up("uploading", e));
        let upload_u32 = |d: &K, v: &[u32]| d.upload(v).map_err(|e| up("uploading", e));
        let f = DeviceFields {
            position: upload(&dev, floats(&fields.position))?,
            velocity: upload(&dev, floats(&fields.velocity))?,
            acceleration: upload(&dev, floats(&fields.acceleration))?,
            // The step-start copies where the host holds them (a split run stages a rank's
            // particles through the host, `distributed::RankBackend`), zeros otherwise.
            position_start: if n > 0 && fields.position_start.len() == n {
                upload(&dev, floats(&fields.position_start))?
            } else {
                vec_zeros(&dev)?
            },
            velocity_start: if n > 0 && fields.velocity_start.len() == n {
                upload(&dev, floats(&fields.velocity_start))?
            } else {
                vec_zeros(&dev)?
            },
            density: upload(&dev, &fields.density)?,
            pressure: upload(&dev, &fields.pressure)?,
            mass: upload(&dev, &fields.mass)?,
            kind: upload_u32(&dev, &fields.kind)?,
            id: upload_u32(&dev, &fields.id)?,
            wall_velocity: if fields.wall_velocity.len() == n {
                Some(upload(&dev, floats(&fields.wall_velocity))?)
            } else {
                None
            },
            rest_density: if fields.rest_density.is_empty() {
                None
            } else {
                Some(upload(&dev, &fields.rest_density)?)
            },
            acting_pressure: if fields.acting_pressure.is_empty() {
                None
            } else {
                Some(upload(&dev, &fields.acting_pressure)?)
            },
        };
        let zeros_f32 = |len: usize| {
            dev.alloc_zeros::<f32>(len.max(1))
                .map_err(|e| up("allocating", e))
        };
        // Solid k has kind k + 1; the per-solid buffers hold one entry per kind above fluid.
        let solids = fields.kind.iter().copied().max().unwrap_or(0) as usize;
        let backend = Self {
            solid_reference: None,
            solid_motion: zeros_f32(motion_floats(D) * solids)?,
            wall_motion: zeros_f32(motion_floats(D) * solids)?,
            wall_motion_set: false,
            n,
            domain: (params.domain_min, params.domain_max),
            f,
            grid: None,
            scratch_vec: zeros_f32(n * D)?,
            scratch_u32: dev
                .alloc_zeros::<u32>(n.max(1))
                .map_err(|e| up("allocating", e))?,
            delta_p: zeros_f32(1)?,
            delta_p_previous: zeros_f32(n)?,
            has_previous: false,
            displacement: zeros_f32(1)?,
            velocity_solve_start: zeros_f32(1)?,
            pressure_solve_start: zeros_f32(1)?,
            density_solve_start: zeros_f32(1)?,
            anderson: AndersonState::default(),
            anderson_buffers: None,
            reduce_i32: dev.alloc_zeros::<i32>(2).map_err(|e| up("allocating", e))?,
            extremes: dev
                .upload(&[DeviceExtremes::initial()])
                .map_err(|e| up("allocating", e))?,
            solid_out: dev.alloc_zeros::<f64>(3).map_err(|e| up("allocating", e))?,
            moment_out: dev.alloc_zeros::<f64>(2).map_err(|e| up("allocating", e))?,
            keep_out_host: Vec::new(),
            keep_out_boxes: dev.alloc_zeros::<f32>(1).map_err(|e| up("allocating", e))?,
            keep_out_out: dev.alloc_zeros::<f64>(4).map_err(|e| up("allocating", e))?,
            // Recomputed after every sort before use (the sort does not gather it).
            normal: None,
            density_rate: if n > 0 && fields.density_rate.len() == n {
                Some(upload(&dev, &fields.density_rate)?)
            } else {
                None
            },
            density_start: if n > 0 && fields.density_start.len() == n {
                Some(upload(&dev, &fields.density_start)?)
            } else {
                None
            },
            partition: Partition::Whole,
            owned: upload_u32(&dev, &vec![1; n.max(1)])?,
            id_bound: fields.id.iter().map(|&k| k as usize + 1).max().unwrap_or(0),
            solve_records: warm_start::VelocitySolveRecords::default(),
            error: None,
            dev,
        };
        Ok(backend)
    }
}

/// Launches `$kernel` (a [`Launch`] method: the table's launch shape) with the arguments given,
/// recording a failure.
macro_rules! launch {
    ($self:ident, $during:expr, $kernel:ident($($arg:expr),* $(,)?)) => {{
        // SAFETY: every buffer passed holds the item count the kernel reads or writes (n
        // particles, times D for vectors; ncell + 1 for cell arrays); the argument list is the
        // table's, which the shim's C++ compile checks against the kernel.
        let r = unsafe { $self.dev.$kernel($($arg),*) };
        record(&mut $self.error, $during, r);
    }};
}

// The velocity solve's iteration, in its own file; a child module, as it reads the private
// buffers, declared after `launch!` so that it can use it.
#[path = "anderson.rs"]
mod anderson;
#[path = "correction.rs"]
mod correction;
#[path = "damping_zone.rs"]
mod damping_zone;
#[path = "density.rs"]
mod density;
#[path = "density_rate.rs"]
mod density_rate;
#[path = "download.rs"]
mod download;
#[path = "forces.rs"]
mod forces;
#[path = "gpu_start.rs"]
mod gpu_start;
#[path = "gradient_moment.rs"]
mod gradient_moment;
#[path = "heap.rs"]
mod heap;
#[path = "integrate.rs"]
mod integrate;
#[path = "move_solids.rs"]
mod move_solids;
#[path = "solid_forces.rs"]
mod solid_forces;
#[path = "sort_by_cell.rs"]
mod sort_by_cell;
#[path = "staging.rs"]
mod staging;
#[path = "state_extremes.rs"]
mod state_extremes;
#[path = "surface_tension.rs"]
mod surface_tension;
#[path = "wall_pressure.rs"]
mod wall_pressure;
#[path = "warm_start.rs"]
mod warm_start;
#[path = "wrap_positions.rs"]
mod wrap_positions;

impl<const D: usize, K: Launch<D> + Clone> Backend<D> for CudaBackend<D, K> {
    fn name(&self) -> &'static str {
        "cuda"
    }

    fn kind(&self) -> crate::backend::BackendKind {
        crate::backend::BackendKind::Cuda
    }

    fn reload(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> Result<(), BackendError> {
        // The device and its compiled kernels stay; every buffer is made again. A rank's share
        // stays one (its owned particles are set again after the next sort), and a failure
        // not yet reported stays reported.
        // The velocity solves' records are by id, which a reload keeps.
        let partition = std::mem::take(&mut self.partition);
        let error = self.error.take();
        let records = std::mem::take(&mut self.solve_records);
        *self = Self::on_device(self.dev.clone(), fields, params)?;
        self.partition = partition;
        self.error = error;
        self.solve_records = records;
        self.upload_owned()
    }

    fn heap_bytes(&self) -> usize {
        self.buffer_bytes()
    }

    fn holds_state(&self) -> bool {
        true
    }

    fn device(&self) -> Option<String> {
        Some(self.dev.name())
    }

    fn synchronize(&mut self) {
        let r = self.dev.synchronize();
        record(&mut self.error, "waiting for the GPU", r);
    }

    fn download(&mut self, fields: &mut Fields<D>) -> Result<(), BackendError> {
        self.download_fields(fields)
    }

    fn take_error(&mut self) -> Option<BackendError> {
        self.error
            .take()
            .or_else(|| self.partition.take_error().map(BackendError::Ranks))
    }

    fn download_some(&mut self, fields: &mut Fields<D>, which: &[Field]) -> Result<(), BackendError> {
        self.download_chosen(fields, which)
    }

    fn upload_some(&mut self, fields: &Fields<D>, which: &[Field]) -> Result<(), BackendError> {
        self.upload_chosen(fields, which)
    }

    fn partition(&self) -> &Partition {
        &self.partition
    }

    fn partition_mut(&mut self) -> Option<&mut Partition> {
        Some(&mut self.partition)
    }

    fn set_partition(&mut self, partition: Partition) -> Result<(), BackendError> {
        self.partition = partition;
        self.upload_owned()
    }

    fn mix_velocity_pressure(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>, k: f32) {
        self.mix_pressure(params, k);
    }

    fn velocity_from_pressure(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>, tau: f32) {
        self.pressure_to_velocity(params, tau);
    }

    fn sort_by_cell(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) -> Result<(), GridError> {
        self.launch_sort_by_cell(params.h, params.periodic)
    }

    fn density(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) {
        self.launch_density(params)
    }

    fn equation_of_state(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) {
        self.launch_equation_of_state(params)
    }

    fn density_rate(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) {
        self.launch_density_rate(params)
    }

    fn damping_zone(&mut self, _fields: &mut Fields<D>, zone: &DampingZone<D>, dt: f32) {
        self.launch_damping_zone(zone, dt)
    }

    fn wrap_positions(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) {
        self.launch_wrap_positions(params)
    }

    fn integrate_density(&mut self, _fields: &mut Fields<D>, dt: f32) {
        self.launch_integrate_density(dt)
    }

    fn store_density_start(&mut self, _fields: &mut Fields<D>) {
        self.launch_store_density_start()
    }

    fn rk_density_stage(&mut self, _fields: &mut Fields<D>, dt: f32, a: f32, b: f32) {
        self.launch_rk_density_stage(dt, a, b)
    }

    fn predicted_density(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>, tau: f32) {
        self.launch_predicted_density(params, tau)
    }

    fn move_solids(
        &mut self,
        _fields: &mut Fields<D>,
        reference: &SolidReference<D>,
        kinematics: &[SolidKinematics<D>],
    ) {
        self.launch_move_solids(reference, kinematics)
    }

    fn wall_pressure(
        &mut self,
        _fields: &mut Fields<D>,
        params: &StepParams<D>,
        model: WallModel,
        kinematics: &[SolidKinematics<D>],
    ) {
        self.launch_wall_pressure(params, model, kinematics)
    }

    fn wall_velocity(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) {
        self.launch_wall_velocity(params)
    }

    fn keep_out(
        &mut self,
        _fields: &mut Fields<D>,
        boxes: &[KeepOutBox<D>],
        solids: usize,
        margin: f32,
        from_step_start: bool,
    ) -> KeepOutReport {
        self.launch_keep_out(boxes, solids, margin, from_step_start)
    }

    fn forces(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>, terms: ForceTerms) {
        self.launch_forces(params, terms)
    }

    fn gradient_moment(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) -> MomentSums {
        self.launch_gradient_moment(params)
    }

    fn solid_forces(
        &mut self,
        _fields: &Fields<D>,
        params: &StepParams<D>,
        solids: usize,
        source: SolidForceSource,
    ) -> Vec<SolidLoad> {
        self.launch_solid_forces(params, solids, source)
    }

    fn surface_normals(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) {
        self.launch_surface_normals(params)
    }

    fn surface_tension(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) {
        self.launch_surface_tension(params)
    }

    fn state_extremes(&mut self, _fields: &Fields<D>, params: &StepParams<D>) -> StateExtremes {
        self.launch_state_extremes(params)
    }

    fn integrate(&mut self, _fields: &mut Fields<D>, dt: f32) {
        self.launch_integrate(dt)
    }

    fn store_step_start(&mut self, _fields: &mut Fields<D>) {
        self.launch_store_step_start()
    }

    fn rk_stage(&mut self, _fields: &mut Fields<D>, dt: f32, a: f32, b: f32) {
        self.launch_rk_stage(dt, a, b)
    }

    fn correction_error(&mut self, _fields: &Fields<D>, params: &StepParams<D>) -> CorrectionError {
        self.launch_correction_error(params)
    }

    fn begin_correction(&mut self, _fields: &mut Fields<D>) {
        self.launch_begin_correction()
    }

    fn correction_pressure(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>, k: f32) {
        self.launch_correction_pressure(params, k)
    }

    fn correct_positions(
        &mut self,
        _fields: &mut Fields<D>,
        params: &StepParams<D>,
        tau: f32,
        kick_tau: f32,
        max_step: f32,
    ) -> Sweep {
        self.launch_correct_positions(params, tau, kick_tau, max_step)
    }

    fn begin_velocity_solve(&mut self, _fields: &mut Fields<D>, _params: &StepParams<D>) {
        self.launch_begin_velocity_solve()
    }

    fn warm_start_velocity_solve(&mut self, _fields: &mut Fields<D>, slot: usize) {
        self.launch_warm_start_velocity_solve(slot)
    }

    fn record_velocity_solve(&mut self, _fields: &mut Fields<D>, slot: usize, keep: bool) {
        self.launch_record_velocity_solve(slot, keep)
    }

    fn velocity_solve_records(
        &mut self,
        ids: &[u32],
    ) -> Result<Vec<crate::backend::SolveRecord>, BackendError> {
        CudaBackend::velocity_solve_records(self, ids)
    }

    fn restore_velocity_solve_records(
        &mut self,
        ids: &[u32],
        records: &[crate::backend::SolveRecord],
    ) -> Result<(), BackendError> {
        CudaBackend::restore_velocity_solve_records(self, ids, records)
    }

    fn end_velocity_solve(&mut self, _fields: &mut Fields<D>, keep: bool) {
        self.launch_end_velocity_solve(keep)
    }

    fn record_acting_pressure(&mut self, _fields: &mut Fields<D>) {
        self.launch_record_acting_pressure()
    }
}
