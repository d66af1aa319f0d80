//! [`CudaBackend`]: every particle field in device memory, one kernel launch (or a short fixed
//! sequence) per `Backend` stage, under the CPU backend's names. Particle data crosses to the
//! host only in [`Backend::download`] (output frames, probes, checkpoints, error reports) and a
//! few scalars per stage (reductions the driver needs: the time step's extremes, the correction's
//! residual and largest displacement, forces on solids).

use super::compile::{arch_for, compile_all};
use super::extremes::{DeviceExtremes, max_from_bits, sweep};
use super::grid::GridGeometry;
use super::launch::{Buffer, DeviceFault, FORCES, Gpu, KERNEL_NAMES, Launch, Memory};
use crate::backend::params::StepParams;
use crate::backend::{
    Backend, BackendError, CorrectionError, ForceTerms, SolidForceSource, StateExtremes, Sweep, WallModel,
};
use crate::boundary::keep_out::{KeepOutBox, KeepOutReport};
use crate::boundary::motion::{SolidKinematics, SolidReference};
use crate::fields::Fields;
use crate::grid::GridError;
use crate::math::{Real, Vector};
use crate::physics::correction;
use crate::physics::multiphase::Phases;
use crate::solver::anderson::AndersonState;
use cudarc::driver::CudaContext;

/// What a sweep reports when nothing ran (no grid yet, or an earlier failure).
const NO_SWEEP: Sweep = Sweep {
    largest: 0.0,
    scale: 1.0,
};

/// Items per thread at each level of the cell-count scan: a level of `m` items leaves `m/64`
/// chunk sums, scanned the same way, until at most `SCAN_TOP` remain for one thread.
const SCAN_CHUNK: u32 = 64;
/// Largest level the scan leaves to a single thread.
const SCAN_TOP: u32 = 1024;

/// Sizes of the scan's levels above the cell counts: `m/64`, `m/64²`, ... down to `SCAN_TOP`.
fn scan_levels(m: u32) -> Vec<u32> {
    let mut sizes = vec![m.div_ceil(SCAN_CHUNK)];
    while *sizes.last().expect("one level") > SCAN_TOP {
        let next = sizes.last().expect("one level").div_ceil(SCAN_CHUNK);
        sizes.push(next);
    }
    sizes
}

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
    /// The guard's boxes as last uploaded (`kernels/keep_out.cu` layout) and on the device.
    keep_out_host: Vec<f32>,
    keep_out_boxes: K::Buf<f32>,
    /// The guard's per-solid counts and momentum changes, 4 doubles per solid.
    keep_out_out: K::Buf<f64>,
    /// Moving solids: `x0` by id (`D` floats per solid particle), uploaded at the first
    /// `move_solids`; `None` until then (and in scenes where nothing moves).
    solid_reference: Option<K::Buf<f32>>,
    /// Per solid `[d, d']` (`2 D` floats) of the last `move_solids`.
    solid_motion: K::Buf<f32>,
    /// Per solid acceleration `d''` (`D` floats), uploaded by `wall_pressure`; zeros while
    /// nothing moves.
    wall_acc: K::Buf<f32>,
    /// Surface normals [AAT13] (`D` floats per particle), allocated by the first
    /// `surface_normals` (only scenes with the `surface_tension` effect run it). Recomputed after
    /// every sort before use, so the sort does not gather it.
    normal: Option<K::Buf<f32>>,
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

impl<const D: usize> CudaBackend<D, Gpu> {
    /// Compiles the kernels for the first GPU and uploads `fields`; `params` gives the domain of
    /// the dense grid. Call `cuda::probe` first (cudarc panics when a library is missing).
    ///
    /// # Errors
    /// [`BackendError::Unavailable`] when NVRTC rejects a kernel, [`BackendError::Device`] when
    /// the context, an allocation or the upload fails.
    pub fn new(fields: &Fields<D>, params: &StepParams<D>) -> Result<Self, BackendError> {
        let ctx = CudaContext::new(0).map_err(|e| device_error("opening GPU 0", e))?;
        let (major, minor) = ctx
            .compute_capability()
            .map_err(|e| device_error("reading the compute capability", e))?;
        let device_name = ctx.name().unwrap_or_else(|_| "unknown GPU".into());
        let arch = arch_for(major, minor);
        let modules = compile_all(D, arch).map_err(|e| BackendError::Unavailable {
            backend: "cuda",
            reason: e.to_string(),
        })?;
        let mut functions = vec![None; KERNEL_NAMES.len()];
        for (file, ptx) in modules {
            let module = ctx
                .load_module(ptx)
                .map_err(|e| device_error(&format!("loading kernels/{file}.cu"), e))?;
            for (slot, &name) in functions.iter_mut().zip(&KERNEL_NAMES) {
                if let Ok(function) = module.load_function(name) {
                    *slot = Some(function);
                }
            }
        }
        let functions = functions
            .into_iter()
            .zip(&KERNEL_NAMES)
            .map(|(f, name)| {
                f.ok_or_else(|| BackendError::Unavailable {
                    backend: "cuda",
                    reason: format!("no kernel named {name} in kernels/"),
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Self::on_device(Gpu::new(&ctx, functions, device_name), fields, params)
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
            position_start: vec_zeros(&dev)?,
            velocity_start: vec_zeros(&dev)?,
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
        };
        let zeros_f32 = |len: usize| {
            dev.alloc_zeros::<f32>(len.max(1))
                .map_err(|e| up("allocating", e))
        };
        // Solid k has kind k + 1; the per-solid buffers hold one entry per kind above fluid.
        let solids = fields.kind.iter().copied().max().unwrap_or(0) as usize;
        let backend = Self {
            solid_reference: None,
            solid_motion: zeros_f32(2 * D * solids)?,
            wall_acc: zeros_f32(D * solids)?,
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
            keep_out_host: Vec::new(),
            keep_out_boxes: dev.alloc_zeros::<f32>(1).map_err(|e| up("allocating", e))?,
            keep_out_out: dev.alloc_zeros::<f64>(4).map_err(|e| up("allocating", e))?,
            normal: None,
            error: None,
            dev,
        };
        Ok(backend)
    }

    /// Builds (or keeps) the dense grid for cells of size `h`.
    fn ensure_grid(&mut self, h: Real) -> Result<(), BackendError> {
        if self.grid.as_ref().is_some_and(|g| g.cell_size == h) {
            return Ok(());
        }
        let geometry =
            GridGeometry::new(&self.domain.0, &self.domain.1, h).map_err(|e| BackendError::Unavailable {
                backend: "cuda",
                reason: e.to_string(),
            })?;
        let cells = geometry.cell_count();
        let dev = &self.dev;
        let a = |len: usize| {
            dev.alloc_zeros::<u32>(len.max(1))
                .map_err(|e| device_error("allocating the grid", e))
        };
        self.grid = Some(DeviceGrid {
            geometry,
            cell_size: h,
            key: a(self.n)?,
            cell_key: a(self.n)?,
            cell_count: a(cells + 1)?,
            cell_start: a(cells + 1)?,
            cell_fill: a(cells)?,
            chunk_sums: scan_levels(cells as u32 + 1)
                .into_iter()
                .map(|m| Ok((a(m as usize)?, a(m as usize)?)))
                .collect::<Result<_, BackendError>>()?,
            perm: a(self.n)?,
        });
        Ok(())
    }

    /// Gathers one vector field by the sort's permutation.
    fn gather_vec(&mut self, which: VecField) {
        let n = self.n as u32;
        let grid = self.grid.as_ref().expect("sorted");
        let src = match which {
            VecField::Position => &mut self.f.position,
            VecField::Velocity => &mut self.f.velocity,
            VecField::Acceleration => &mut self.f.acceleration,
            VecField::PositionStart => &mut self.f.position_start,
            VecField::VelocityStart => &mut self.f.velocity_start,
            VecField::WallVelocity => match self.f.wall_velocity.as_mut() {
                Some(b) => b,
                None => return,
            },
        };
        // SAFETY: perm, src and scratch hold n entries (times D for vectors).
        let r = unsafe { self.dev.gather_vec(n, &grid.perm, src, &mut self.scratch_vec) };
        std::mem::swap(src, &mut self.scratch_vec);
        record(&mut self.error, "gathering a vector field", r);
    }

    fn gather_scalar(&mut self, which: ScalarField) {
        let n = self.n as u32;
        let grid = self.grid.as_ref().expect("sorted");
        let src = match which {
            ScalarField::Density => &mut self.f.density,
            ScalarField::Pressure => &mut self.f.pressure,
            ScalarField::Mass => &mut self.f.mass,
            ScalarField::RestDensity => match self.f.rest_density.as_mut() {
                Some(b) => b,
                None => return,
            },
        };
        // SAFETY: perm and src hold n entries; the scratch holds at least n floats.
        let r = unsafe {
            self.dev
                .gather_f32(n, &grid.perm, src, &mut self.delta_p_previous)
        };
        // delta_p_previous is dead after a sort (the momentum restarts), so it is the scratch.
        std::mem::swap(src, &mut self.delta_p_previous);
        record(&mut self.error, "gathering a scalar field", r);
    }

    fn gather_index(&mut self, which: IndexField) {
        let n = self.n as u32;
        let grid = self.grid.as_mut().expect("sorted");
        let r = match which {
            IndexField::Kind | IndexField::Id => {
                let src = if which == IndexField::Kind {
                    &mut self.f.kind
                } else {
                    &mut self.f.id
                };
                // SAFETY: perm, src and scratch hold n entries.
                let r = unsafe { self.dev.gather_u32(n, &grid.perm, src, &mut self.scratch_u32) };
                std::mem::swap(src, &mut self.scratch_u32);
                r
            }
            // SAFETY: perm, key and cell_key hold n entries.
            IndexField::CellKey => unsafe {
                self.dev.gather_u32(n, &grid.perm, &grid.key, &mut grid.cell_key)
            },
        };
        record(&mut self.error, "gathering an index field", r);
    }

    /// Copies particle `i`'s fields to name the first non-finite quantity, as the CPU does.
    fn non_finite_quantity(&mut self, i: usize) -> &'static str {
        let dev = &self.dev;
        let vec_at =
            |b: &K::Buf<f32>| -> Vec<f32> { dev.download_range(b, i * D..(i + 1) * D).unwrap_or_default() };
        let scalar_at = |b: &K::Buf<f32>| -> Vec<f32> { dev.download_range(b, i..i + 1).unwrap_or_default() };
        let bad = |v: Vec<f32>| v.iter().any(|c| !c.is_finite());
        if bad(vec_at(&self.f.position)) {
            "position"
        } else if bad(vec_at(&self.f.velocity)) {
            "velocity"
        } else if bad(vec_at(&self.f.acceleration)) {
            "acceleration"
        } else if bad(scalar_at(&self.f.density)) {
            "density"
        } else {
            "pressure"
        }
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

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    /// Sizes the `corrected` solver's buffers (`delta_p`, `displacement`, the `*_solve_start`
    /// copies) to the particle count at its first stage; later calls find them sized. Particles
    /// are never added, so `n` is fixed.
    fn ensure_correction_buffers(&mut self) {
        if self.delta_p.len() >= self.n || self.error.is_some() {
            return;
        }
        let (n, dn) = (self.n.max(1), (self.n * D).max(1));
        let dev = &self.dev;
        let r = (|| -> Result<(), DeviceFault> {
            self.delta_p = dev.alloc_zeros::<f32>(n)?;
            self.displacement = dev.alloc_zeros::<f32>(dn)?;
            self.velocity_solve_start = dev.alloc_zeros::<f32>(dn)?;
            self.pressure_solve_start = dev.alloc_zeros::<f32>(n)?;
            self.density_solve_start = dev.alloc_zeros::<f32>(n)?;
            Ok(())
        })();
        record(&mut self.error, "allocating the correction's buffers", r);
    }

    /// Launches eq. (23) without moving anything (`correction_displacement`, or its [HA06]
    /// variant): `Δx = τ² a^press(δp)` of every fluid particle into `displacement`, with the
    /// densities (18) in the `density` field or, for the velocity solve (`solve_start`), those
    /// `begin_velocity_solve` remembered; the bits of the largest |Δx| go to `reduce_i32[0]`
    /// through atomicMax, which the caller clears first when it reads them. `None` without a
    /// grid or after a failure.
    fn launch_displacements(&mut self, params: &StepParams<D>, tau: f32, solve_start: bool) -> Option<()> {
        let g = self.grid.as_ref()?;
        if self.error.is_some() {
            return None;
        }
        let n = self.n as u32;
        let tau2 = tau * tau;
        let density = if solve_start {
            &self.density_solve_start
        } else {
            &self.f.density
        };
        launch!(
            self,
            "computing displacements",
            correction_displacement(
                params.phases as usize,
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.mass,
                density,
                &self.delta_p,
                &self.f.kind,
                tau2,
                &mut self.displacement,
                &mut self.reduce_i32
            )
        );
        Some(())
    }

    /// `correct_positions`' displacements (as `CpuBackend::correction_displacements`): eq. (23)
    /// into `displacement`, and the one scale that keeps the largest within `max_step` [m].
    /// `None` without a grid or after a failure.
    fn correction_displacements(&mut self, params: &StepParams<D>, tau: f32, max_step: f32) -> Option<Sweep> {
        self.grid.as_ref()?;
        if self.error.is_some() {
            return None;
        }
        let r = self.dev.zero(&mut self.reduce_i32);
        record(&mut self.error, "clearing the largest displacement", r)?;
        self.launch_displacements(params, tau, false)?;
        let out = self.dev.download(&self.reduce_i32);
        let out = record(&mut self.error, "copying the largest displacement", out)?;
        Some(sweep(out[0], max_step))
    }
}

impl<const D: usize, K: Launch<D>> Backend<D> for CudaBackend<D, K> {
    fn name(&self) -> &'static str {
        "cuda"
    }

    fn kind(&self) -> crate::backend::BackendKind {
        crate::backend::BackendKind::Cuda
    }

    fn heap_bytes(&self) -> usize {
        // Every device buffer, counted from its length (the driver's own context is not).
        let f = &self.f;
        let mut bytes = [
            &f.position,
            &f.velocity,
            &f.acceleration,
            &f.position_start,
            &f.velocity_start,
            &f.density,
            &f.pressure,
            &f.mass,
            &self.scratch_vec,
            &self.delta_p,
            &self.delta_p_previous,
            &self.displacement,
            &self.velocity_solve_start,
            &self.pressure_solve_start,
            &self.density_solve_start,
            &self.solid_motion,
            &self.wall_acc,
        ]
        .iter()
        .map(|b| b.num_bytes())
        .sum::<usize>()
            + f.kind.num_bytes()
            + f.id.num_bytes()
            + self.scratch_u32.num_bytes()
            + self.reduce_i32.num_bytes()
            + self.extremes.num_bytes()
            + self.solid_out.num_bytes()
            + self.keep_out_boxes.num_bytes()
            + self.keep_out_out.num_bytes()
            + self.solid_reference.as_ref().map_or(0, |b| b.num_bytes())
            + self.f.wall_velocity.as_ref().map_or(0, |b| b.num_bytes())
            + self.normal.as_ref().map_or(0, |b| b.num_bytes())
            + self.f.rest_density.as_ref().map_or(0, |b| b.num_bytes())
            + self.anderson_buffers.as_ref().map_or(0, |b| b.num_bytes());
        if let Some(g) = &self.grid {
            bytes += [
                &g.key,
                &g.cell_key,
                &g.cell_count,
                &g.cell_start,
                &g.cell_fill,
                &g.perm,
            ]
            .iter()
            .map(|b| b.num_bytes())
            .sum::<usize>();
            bytes += g
                .chunk_sums
                .iter()
                .map(|(a, b)| a.num_bytes() + b.num_bytes())
                .sum::<usize>();
        }
        bytes
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
        let n = self.n;
        let s = &self.dev;
        let e = |x: DeviceFault| device_error("copying the fields to the host", x);
        fields.position.resize(n, Vector::zeros());
        fields.velocity.resize(n, Vector::zeros());
        fields.acceleration.resize(n, Vector::zeros());
        s.download_into(&self.f.position, floats_mut(&mut fields.position))
            .map_err(e)?;
        s.download_into(&self.f.velocity, floats_mut(&mut fields.velocity))
            .map_err(e)?;
        s.download_into(&self.f.acceleration, floats_mut(&mut fields.acceleration))
            .map_err(e)?;
        fields.density = s.download(&self.f.density).map_err(e)?;
        fields.pressure = s.download(&self.f.pressure).map_err(e)?;
        fields.mass = s.download(&self.f.mass).map_err(e)?;
        fields.kind = s.download(&self.f.kind).map_err(e)?;
        fields.id = s.download(&self.f.id).map_err(e)?;
        for v in [&mut fields.density, &mut fields.pressure, &mut fields.mass] {
            v.truncate(n);
        }
        fields.kind.truncate(n);
        fields.id.truncate(n);
        match &self.f.wall_velocity {
            Some(b) => {
                fields.wall_velocity.resize(n, Vector::zeros());
                s.download_into(b, floats_mut(&mut fields.wall_velocity))
                    .map_err(e)?;
            }
            None => fields.wall_velocity.clear(),
        }
        if let Some(rest) = &self.f.rest_density {
            fields.rest_density = s.download(rest).map_err(e)?;
            fields.rest_density.truncate(n);
        }
        // The step-start copies are the backend's scratch of SSP-RK3; the host keeps none.
        fields.position_start.clear();
        fields.velocity_start.clear();
        match &self.normal {
            Some(normal) => {
                fields.normal.resize(n, Vector::zeros());
                s.download_into(normal, floats_mut(&mut fields.normal))
                    .map_err(e)?;
            }
            None => fields.normal.clear(),
        }
        Ok(())
    }

    fn take_error(&mut self) -> Option<BackendError> {
        self.error.take()
    }

    fn sort_by_cell(&mut self, _fields: &mut Fields<D>, h: f32) -> Result<(), GridError> {
        if self.error.is_some() {
            return Ok(());
        }
        if let Err(e) = self.ensure_grid(h) {
            self.error = Some(e);
            return Ok(());
        }
        let n = self.n;
        let n32 = n as u32;
        {
            let grid = self.grid.as_mut().expect("built above");
            let r = self.dev.zero(&mut grid.cell_count);
            let r2 = self.dev.zero(&mut grid.cell_fill);
            let r = r.and(r2);
            if let Err(e) = r {
                self.error = Some(device_error("clearing the cell counts", e));
                return Ok(());
            }
        }
        let grid = self.grid.as_mut().expect("built above");
        let geometry = grid.geometry;
        let cells = geometry.cell_count();
        let m = (cells + 1) as u32;
        let chunk = SCAN_CHUNK;
        let ncell = cells as u32;
        let dev = &self.dev;
        let mut results = Vec::with_capacity(6);
        // SAFETY (all launches below): buffers sized n, ncell + 1 and chunks as the kernels of
        // kernels/sort_by_cell.cu expect.
        unsafe {
            results.push(dev.cell_hash(
                n32,
                &geometry,
                &self.f.position,
                &mut grid.key,
                &mut grid.cell_count,
            ));
            // The exclusive scan of the counts, level by level (see `scan_levels`).
            let levels = &mut grid.chunk_sums;
            let sizes = scan_levels(m);
            results.push(dev.scan_chunks(m, chunk, &grid.cell_count, &mut grid.cell_start, &mut levels[0].0));
            for l in 1..sizes.len() {
                let (below, above) = levels.split_at_mut(l);
                let (sums, scanned) = (&below[l - 1].0, &mut below[l - 1].1);
                results.push(dev.scan_chunks(sizes[l - 1], chunk, sums, scanned, &mut above[0].0));
            }
            let top = sizes.len() - 1;
            results.push(dev.scan_chunk_sums(sizes[top], &mut levels[top].0));
            for l in (1..sizes.len()).rev() {
                // Level l's scanned sums complete the scan of level l - 1's sums.
                let (below, above) = levels.split_at_mut(l);
                let add = if l == top { &above[0].0 } else { &above[0].1 };
                results.push(dev.scan_add(sizes[l - 1], chunk, &mut below[l - 1].1, add));
            }
            let add = if top == 0 { &levels[0].0 } else { &levels[0].1 };
            results.push(dev.scan_add(m, chunk, &mut grid.cell_start, add));
            results.push(dev.scatter(
                n32,
                &grid.key,
                &grid.cell_start,
                &mut grid.cell_fill,
                &mut grid.perm,
            ));
            results.push(dev.order_cells(ncell, &grid.cell_start, &self.f.id, &mut grid.perm));
        }
        for r in results {
            record(&mut self.error, "sorting by cell", r);
        }
        for v in [
            VecField::Position,
            VecField::Velocity,
            VecField::Acceleration,
            VecField::PositionStart,
            VecField::VelocityStart,
            VecField::WallVelocity,
        ] {
            self.gather_vec(v);
        }
        for sf in [
            ScalarField::Density,
            ScalarField::Pressure,
            ScalarField::Mass,
            ScalarField::RestDensity,
        ] {
            self.gather_scalar(sf);
        }
        for i in [IndexField::Kind, IndexField::Id, IndexField::CellKey] {
            self.gather_index(i);
        }
        self.has_previous = false;
        Ok(())
    }

    fn density(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) {
        let Some(g) = self.grid.as_ref() else { return };
        let n = self.n as u32;
        // [HA06] number density with several phases (kernels/density.cu).
        launch!(
            self,
            "computing the density",
            density(
                params.phases as usize,
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.mass,
                &self.f.kind,
                &mut self.f.density
            )
        );
    }

    fn equation_of_state(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) {
        let n = self.n as u32;
        if params.phases == Phases::Multi {
            let Some(rest) = multiphase_rest(&self.f.rest_density, &mut self.error) else {
                return;
            };
            launch!(
                self,
                "applying the equation of state",
                equation_of_state_multiphase(
                    n,
                    params,
                    &self.f.density,
                    rest,
                    &self.f.kind,
                    &mut self.f.pressure
                )
            );
            return;
        }
        launch!(
            self,
            "applying the equation of state",
            equation_of_state(n, params, &self.f.density, &self.f.kind, &mut self.f.pressure)
        );
    }

    fn move_solids(
        &mut self,
        _fields: &mut Fields<D>,
        reference: &SolidReference<D>,
        kinematics: &[SolidKinematics<D>],
    ) {
        if self.error.is_some() {
            return;
        }
        if self.solid_reference.is_none() {
            let r = self.dev.upload(floats(&reference.position));
            self.solid_reference = record(&mut self.error, "uploading the solids' reference positions", r);
        }
        let motion: Vec<Vector<D>> = kinematics
            .iter()
            .flat_map(|k| [k.displacement, k.velocity])
            .collect();
        if motion.len() * D > self.solid_motion.len() {
            self.error = Some(device_error(
                "moving solids",
                format!("{} solids, buffers for fewer", kinematics.len()),
            ));
            return;
        }
        let r = self.dev.write(floats(&motion), &mut self.solid_motion);
        record(&mut self.error, "uploading the solids' motion", r);
        let Some(x0) = self.solid_reference.as_ref() else {
            return;
        };
        let n = self.n as u32;
        let first_id = reference.first_id;
        launch!(
            self,
            "moving solids",
            move_solids(
                n,
                &self.f.kind,
                &self.f.id,
                first_id,
                x0,
                &self.solid_motion,
                &mut self.f.position,
                &mut self.f.velocity
            )
        );
    }

    fn wall_pressure(
        &mut self,
        _fields: &mut Fields<D>,
        params: &StepParams<D>,
        model: WallModel,
        wall_acceleration: &[Vector<D>],
    ) {
        // Moving walls: their accelerations go up with each call (a few floats); while nothing
        // moves the buffer keeps its zeros and nothing is copied.
        if !wall_acceleration.is_empty() && self.error.is_none() {
            if wall_acceleration.len() * D > self.wall_acc.len() {
                self.error = Some(device_error(
                    "extrapolating the wall pressure",
                    format!("{} wall accelerations, buffer for fewer", wall_acceleration.len()),
                ));
                return;
            }
            let r = self.dev.write(floats(wall_acceleration), &mut self.wall_acc);
            record(&mut self.error, "uploading the walls' accelerations", r);
        }
        let Some(g) = self.grid.as_ref() else { return };
        let n = self.n as u32;
        let summed = i32::from(model == WallModel::ExtrapolatedOrSummed);
        launch!(
            self,
            "extrapolating the wall pressure",
            wall_pressure(
                params.phases as usize,
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.mass,
                &self.f.kind,
                &self.wall_acc,
                summed,
                &mut self.f.pressure,
                &mut self.f.density
            )
        );
    }

    fn wall_velocity(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) {
        if self.error.is_some() {
            return;
        }
        if self.f.wall_velocity.is_none() {
            let r = self.dev.alloc_zeros::<f32>((self.n * D).max(1));
            self.f.wall_velocity = record(&mut self.error, "allocating the wall velocity", r);
        }
        let (Some(g), Some(out)) = (self.grid.as_ref(), self.f.wall_velocity.as_mut()) else {
            return;
        };
        let n = self.n as u32;
        // SAFETY: as in `launch!`; wall_velocity holds n D floats.
        let r = unsafe {
            self.dev.wall_velocity(
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.velocity,
                &self.f.kind,
                out,
            )
        };
        record(&mut self.error, "extrapolating the wall velocity", r);
    }

    fn forces(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>, terms: ForceTerms) {
        let Some(g) = self.grid.as_ref() else { return };
        let n = self.n as u32;
        // One entry per term set, then the same with the [HA06] pressure force.
        let entry = terms.index() + FORCES.len() / 2 * params.phases as usize;
        launch!(
            self,
            "computing the forces",
            forces(
                entry,
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.velocity,
                &self.f.mass,
                &self.f.density,
                &self.f.pressure,
                &self.f.kind,
                // Without no-slip walls a solid carries its own velocity in (17).
                self.f.wall_velocity.as_ref().unwrap_or(&self.f.velocity),
                &mut self.f.acceleration
            )
        );
    }

    fn surface_normals(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) {
        if self.error.is_some() {
            return;
        }
        let Some(g) = self.grid.as_ref() else { return };
        if self.normal.is_none() {
            let r = self.dev.alloc_zeros::<f32>((self.n * D).max(1));
            match record(&mut self.error, "allocating the surface normals", r) {
                Some(b) => self.normal = Some(b),
                None => return,
            }
        }
        let n = self.n as u32;
        let Some(normal) = self.normal.as_mut() else {
            return;
        };
        let has_rest = u32::from(params.phases == Phases::Multi);
        let rest = match params.phases {
            // The kernel reads no rest density then; any f32 buffer stands in.
            Phases::Single => &self.f.density,
            Phases::Multi => match multiphase_rest(&self.f.rest_density, &mut self.error) {
                Some(rest) => rest,
                None => return,
            },
        };
        launch!(
            self,
            "computing the surface normals",
            surface_normals(
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.mass,
                &self.f.density,
                rest,
                has_rest,
                &self.f.kind,
                normal
            )
        );
    }

    fn surface_tension(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>) {
        if self.error.is_some() {
            return;
        }
        let (Some(g), Some(normal)) = (self.grid.as_ref(), self.normal.as_ref()) else {
            return;
        };
        let n = self.n as u32;
        let has_rest = u32::from(params.phases == Phases::Multi);
        let rest = match params.phases {
            // The kernel reads no rest density then; any f32 buffer stands in.
            Phases::Single => &self.f.density,
            Phases::Multi => match multiphase_rest(&self.f.rest_density, &mut self.error) {
                Some(rest) => rest,
                None => return,
            },
        };
        launch!(
            self,
            "computing the surface tension",
            surface_tension(
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.mass,
                &self.f.density,
                rest,
                has_rest,
                &self.f.kind,
                normal,
                &mut self.f.acceleration
            )
        );
    }

    fn solid_forces(
        &mut self,
        _fields: &Fields<D>,
        params: &StepParams<D>,
        solids: usize,
        source: SolidForceSource,
    ) -> Vec<[f64; 3]> {
        let zero = vec![[0.0; 3]; solids];
        if self.error.is_some() || solids == 0 {
            return zero;
        }
        let Some(g) = self.grid.as_ref() else { return zero };
        if self.solid_out.len() < 3 * solids {
            let r = self.dev.alloc_zeros::<f64>(3 * solids);
            match record(&mut self.error, "allocating the solid forces", r) {
                Some(b) => self.solid_out = b,
                None => return zero,
            }
        }
        let r = self.dev.zero(&mut self.solid_out);
        if record(&mut self.error, "clearing the solid forces", r).is_none() {
            return zero;
        }
        let p = source.params(params);
        let pressure = match source {
            SolidForceSource::Forces => &self.f.pressure,
            SolidForceSource::Correction => &self.delta_p,
        };
        let n = self.n as u32;
        // About 8 particles per thread (grid-stride loop in kernels/solid_forces.cu).
        // SAFETY: as in `launch!`; solid_out holds 3 doubles per solid.
        let r = unsafe {
            self.dev.solid_forces(
                params.phases as usize,
                n,
                &p,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.velocity,
                &self.f.mass,
                &self.f.density,
                pressure,
                &self.f.kind,
                self.f.wall_velocity.as_ref().unwrap_or(&self.f.velocity),
                &mut self.solid_out,
            )
        };
        if record(&mut self.error, "summing the forces on solids", r).is_none() {
            return zero;
        }
        let out = self.dev.download(&self.solid_out);
        match record(&mut self.error, "copying the solid forces", out) {
            Some(v) => (0..solids)
                .map(|k| [v[3 * k], v[3 * k + 1], v[3 * k + 2]])
                .collect(),
            None => zero,
        }
    }

    fn state_extremes(&mut self, _fields: &Fields<D>, params: &StepParams<D>) -> StateExtremes {
        let fallback = StateExtremes::default();
        if self.error.is_some() {
            return fallback;
        }
        let r = self.dev.write(&[DeviceExtremes::initial()], &mut self.extremes);
        if record(&mut self.error, "resetting the extremes", r).is_none() {
            return fallback;
        }
        let n = self.n as u32;
        // About 64 particles per thread (grid-stride loop), so one set of atomics per 64.
        if params.phases == Phases::Multi {
            let Some(rest) = multiphase_rest(&self.f.rest_density, &mut self.error) else {
                return fallback;
            };
            launch!(
                self,
                "reducing the extremes",
                state_extremes_multiphase(
                    n,
                    params,
                    &self.f.position,
                    &self.f.velocity,
                    &self.f.acceleration,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    rest,
                    &mut self.extremes
                )
            );
        } else {
            launch!(
                self,
                "reducing the extremes",
                state_extremes(
                    n,
                    params,
                    &self.f.position,
                    &self.f.velocity,
                    &self.f.acceleration,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    &mut self.extremes
                )
            );
        }
        let out = self.dev.download(&self.extremes);
        let Some(out) = record(&mut self.error, "copying the extremes", out) else {
            return fallback;
        };
        let mut e = out[0].finish(params.rho0);
        if let Some(i) = out[0].first_non_finite() {
            e.non_finite = Some((i, self.non_finite_quantity(i)));
        }
        e
    }

    fn integrate(&mut self, _fields: &mut Fields<D>, dt: f32) {
        let n = self.n as u32;
        launch!(
            self,
            "integrating",
            integrate(
                n,
                dt,
                &self.f.kind,
                &self.f.acceleration,
                &mut self.f.velocity,
                &mut self.f.position
            )
        );
    }

    fn store_step_start(&mut self, _fields: &mut Fields<D>) {
        let n = self.n as u32;
        launch!(
            self,
            "storing the step start",
            store_step_start(
                n,
                &self.f.position,
                &self.f.velocity,
                &mut self.f.position_start,
                &mut self.f.velocity_start
            )
        );
    }

    fn rk_stage(&mut self, _fields: &mut Fields<D>, dt: f32, a: f32, b: f32) {
        let n = self.n as u32;
        launch!(
            self,
            "taking a Runge-Kutta stage",
            rk_stage(
                n,
                dt,
                a,
                b,
                &self.f.kind,
                &self.f.acceleration,
                &self.f.position_start,
                &self.f.velocity_start,
                &mut self.f.position,
                &mut self.f.velocity
            )
        );
    }

    fn correction_error(&mut self, _fields: &Fields<D>, params: &StepParams<D>) -> CorrectionError {
        let failed = CorrectionError {
            compression: f64::NAN,
            residual: f64::NAN,
        };
        if self.error.is_some() {
            return failed;
        }
        let r = self.dev.zero(&mut self.reduce_i32);
        if record(&mut self.error, "clearing the residual", r).is_none() {
            return failed;
        }
        let n = self.n as u32;
        if params.phases == Phases::Multi {
            let Some(rest) = multiphase_rest(&self.f.rest_density, &mut self.error) else {
                return failed;
            };
            launch!(
                self,
                "reducing the density error",
                correction_error_multiphase(
                    n,
                    rest,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    &mut self.reduce_i32
                )
            );
        } else {
            launch!(
                self,
                "reducing the density error",
                correction_error(
                    n,
                    params.rho0,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    &mut self.reduce_i32
                )
            );
        }
        let out = self.dev.download(&self.reduce_i32);
        match record(&mut self.error, "copying the residual", out) {
            Some(v) => CorrectionError {
                compression: max_from_bits(v[0]),
                residual: max_from_bits(v[1]),
            },
            None => failed,
        }
    }

    fn begin_correction(&mut self, _fields: &mut Fields<D>) {
        self.has_previous = false;
        self.ensure_correction_buffers();
    }

    fn correction_pressure(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>, k: f32) {
        let Some(g) = self.grid.as_ref() else { return };
        let n = self.n as u32;
        let beta = correction::MOMENTUM;
        let has_previous = i32::from(self.has_previous);
        if params.phases == Phases::Multi {
            let Some(rest) = multiphase_rest(&self.f.rest_density, &mut self.error) else {
                return;
            };
            launch!(
                self,
                "computing pressure increments",
                correction_pressure_fluid_multiphase(
                    n,
                    rest,
                    k,
                    beta,
                    has_previous,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    &self.delta_p_previous,
                    &mut self.delta_p
                )
            );
        } else {
            launch!(
                self,
                "computing pressure increments",
                correction_pressure_fluid(
                    n,
                    params.rho0,
                    k,
                    beta,
                    has_previous,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    &self.delta_p_previous,
                    &mut self.delta_p
                )
            );
        }
        launch!(
            self,
            "extrapolating pressure increments to walls",
            correction_pressure_wall(
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.density,
                &self.f.pressure,
                &self.f.kind,
                &mut self.delta_p
            )
        );
        launch!(
            self,
            "adding pressure increments",
            correction_pressure_apply(n, &self.delta_p, &mut self.f.pressure, &mut self.delta_p_previous)
        );
        self.has_previous = true;
    }

    fn correct_positions(
        &mut self,
        _fields: &mut Fields<D>,
        params: &StepParams<D>,
        tau: f32,
        kick_tau: f32,
        max_step: f32,
    ) -> Sweep {
        let Some(sweep) = self.correction_displacements(params, tau, max_step) else {
            return NO_SWEEP;
        };
        let n = self.n as u32;
        let scale = sweep.scale as Real;
        launch!(
            self,
            "moving particles",
            apply_displacement(
                n,
                scale,
                kick_tau,
                &self.f.kind,
                &self.displacement,
                &mut self.f.position,
                &mut self.f.velocity
            )
        );
        sweep
    }

    fn begin_velocity_solve(&mut self, _fields: &mut Fields<D>) {
        self.has_previous = false;
        self.anderson.reset();
        self.ensure_correction_buffers();
        if self.error.is_some() {
            return;
        }
        let r = self
            .dev
            .copy(&self.f.velocity, &mut self.velocity_solve_start)
            .and_then(|()| self.dev.copy(&self.f.pressure, &mut self.pressure_solve_start))
            .and_then(|()| self.dev.copy(&self.f.density, &mut self.density_solve_start));
        record(
            &mut self.error,
            "remembering the velocities, pressures and densities",
            r,
        );
    }

    fn predicted_density(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>, tau: f32) {
        let Some(g) = self.grid.as_ref() else { return };
        let n = self.n as u32;
        if params.phases == Phases::Multi {
            let Some(rest) = multiphase_rest(&self.f.rest_density, &mut self.error) else {
                return;
            };
            // [HA06] each particle's own mass and rest density (kernels/density.cu).
            launch!(
                self,
                "predicting the density",
                predicted_density_multiphase(
                    n,
                    params,
                    &g.geometry,
                    &g.cell_start,
                    &g.cell_key,
                    &self.f.position,
                    &self.f.velocity,
                    &self.f.mass,
                    rest,
                    &self.f.kind,
                    &self.density_solve_start,
                    tau,
                    &mut self.f.density
                )
            );
            return;
        }
        launch!(
            self,
            "predicting the density",
            predicted_density(
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.velocity,
                &self.f.mass,
                &self.f.kind,
                &self.density_solve_start,
                tau,
                &mut self.f.density
            )
        );
    }

    fn mix_velocity_pressure(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>, k: f32) {
        self.mix_pressure(params, k);
    }

    fn velocity_from_pressure(&mut self, _fields: &mut Fields<D>, params: &StepParams<D>, tau: f32) {
        self.pressure_to_velocity(params, tau);
    }

    fn end_velocity_solve(&mut self, _fields: &mut Fields<D>, keep: bool) {
        if self.error.is_some() {
            return;
        }
        // The saved buffers hold at least one entry; `copy` moves the fields' lengths back.
        if keep {
            let n = self.n as u32;
            launch!(
                self,
                "keeping the released pressure",
                keep_pressure_decreases(n, &self.pressure_solve_start, &mut self.f.pressure)
            );
        } else {
            let r = self
                .dev
                .copy(&self.velocity_solve_start, &mut self.f.velocity)
                .and_then(|()| self.dev.copy(&self.pressure_solve_start, &mut self.f.pressure));
            record(&mut self.error, "restoring the velocities and pressures", r);
        }
        // Positions did not move: the sum (18) is still the one remembered at the start.
        let r = self.dev.copy(&self.density_solve_start, &mut self.f.density);
        record(&mut self.error, "restoring the densities", r);
    }

    fn keep_out(
        &mut self,
        _fields: &mut Fields<D>,
        boxes: &[KeepOutBox<D>],
        solids: usize,
        margin: f32,
        from_step_start: bool,
    ) -> KeepOutReport {
        let mut report = KeepOutReport::none(solids);
        if boxes.is_empty() || solids == 0 || self.error.is_some() {
            return report;
        }
        // Upload the boxes only when they changed (moving solids): min, max, velocity, solid.
        let host: Vec<f32> = boxes.iter().flat_map(KeepOutBox::kernel_floats).collect();
        if host != self.keep_out_host {
            let r = self.dev.upload(&host);
            match record(&mut self.error, "uploading the solid volumes", r) {
                Some(b) => self.keep_out_boxes = b,
                None => return report,
            }
            self.keep_out_host = host;
        }
        if self.keep_out_out.len() < 4 * solids {
            let r = self.dev.alloc_zeros::<f64>(4 * solids);
            match record(&mut self.error, "allocating the guard's sums", r) {
                Some(b) => self.keep_out_out = b,
                None => return report,
            }
        }
        let r = self.dev.zero(&mut self.keep_out_out);
        if record(&mut self.error, "clearing the guard's sums", r).is_none() {
            return report;
        }
        let (n, count) = (self.n as u32, boxes.len() as u32);
        let has_from = u32::from(from_step_start);
        launch!(
            self,
            "keeping fluid out of solids",
            keep_out(
                n,
                count,
                &self.keep_out_boxes,
                margin,
                &self.f.kind,
                &self.f.mass,
                &self.f.position_start,
                has_from,
                &mut self.f.position,
                &mut self.f.velocity,
                &mut self.keep_out_out
            )
        );
        let out = self.dev.download(&self.keep_out_out);
        if let Some(v) = record(&mut self.error, "copying the guard's sums", out) {
            for (s, slot) in report.impulse.iter_mut().enumerate() {
                report.pushes += v[4 * s] as u64;
                slot.copy_from_slice(&v[4 * s + 1..4 * s + 4]);
            }
        }
        report
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum VecField {
    Position,
    Velocity,
    Acceleration,
    PositionStart,
    VelocityStart,
    WallVelocity,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum ScalarField {
    Density,
    Pressure,
    Mass,
    RestDensity,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum IndexField {
    Kind,
    Id,
    CellKey,
}
