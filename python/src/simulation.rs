//! `Simulation`: a scene's simulation stepped from Python, with the records `sph run` writes
//! (the rows of `forces.csv`, `probes.csv` and `steps.csv`) kept in memory.
//!
//! Each step is the library's `Simulation::step(end)`, followed by what `sph run` records after
//! it (`run::record_step`): the forces on the named solids and the probes, fed the same values
//! in the same order, so the records equal the command line's files.
//!
//! Fields are NumPy arrays that borrow the simulation's host memory: no copy, read-only, each a
//! snapshot of the state when `fields()` was called, valid for as long as it lives. The arrays
//! of one `fields()` (and of every further call before the next step) share a `Generation`,
//! which owns nothing while they show the simulation's current memory. Before anything writes
//! into the host fields (a step, which may reorder, remove or add particles and swap buffers
//! with scratch ones), a generation with arrays alive takes the field vectors out of the
//! simulation (`detach_views`): a `Vec`'s heap buffer stays where it is when the `Vec` moves, so
//! the arrays keep reading valid memory with the values they were taken with, and the
//! simulation goes on with copies. Holding arrays across a step thus costs one copy of the
//! fields in that step; arrays dropped before it cost nothing. On the CUDA backend the fields
//! are first downloaded to the host copy, which the arrays then borrow.

use crate::errors::{from_lib, to_py};
use crate::scene::PyScene;
use numpy::ndarray::{ArrayView1, ArrayView2};
use numpy::{Element, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use sph::backend::BackendKind;
use sph::probe::{ProbeLog, column_name};
use sph::run::{AnySimulation, StepRow};
use sph::scene::Scene;
use sph::solver::Simulation;
use std::any::Any;
use std::sync::{Arc, Mutex, Weak};

/// Calls `$body` with `$s` bound to the simulation of either dimension.
macro_rules! each_dim {
    ($sim:expr, $s:ident => $body:expr) => {
        match $sim {
            AnySimulation::D2($s) => $body,
            AnySimulation::D3($s) => $body,
        }
    };
}

/// The simulation and its records.
struct State {
    sim: AnySimulation,
    probes: ProbeLog,
    /// `(t [s], solid index, force)` per solid per step, as `forces.csv`.
    forces: Vec<(f64, usize, [f64; 3])>,
    steps: Vec<StepRow>,
}

// SAFETY: a `Simulation` is not `Send` because its backend is a `Box<dyn Backend>` without that
// bound; the backends hold plain host buffers (CPU) or a CUDA context, which cudarc binds to
// the calling thread on every call. The state is reached only through PyO3's borrow flag
// (`&mut` through `PyRefMut`, exclusive) and moved to one worker of the pool at a time while
// the caller waits, so no two threads touch it at once.
unsafe impl Send for State {}
// SAFETY: shared access (`PyRef`) only reads plain values (clock, counts, names); every method
// that steps or syncs takes the exclusive borrow.
unsafe impl Sync for State {}

/// The field vectors a generation of arrays took out of the simulation (`take_fields`).
type Held = Box<dyn Any + Send>;

/// The memory behind the arrays of one generation of `fields()`: nothing while they show the
/// simulation's current fields, the vectors they point into once the simulation moved on.
#[derive(Default)]
struct Generation {
    held: Mutex<Option<Held>>,
}

/// The NumPy base of every array of one generation: keeps the generation, hence the memory the
/// arrays read, alive for as long as any of them lives.
#[pyclass(name = "FieldMemory", module = "sph._sph", frozen)]
struct FieldGuard {
    _generation: Arc<Generation>,
}

/// A scene's simulation, stepped from Python.
#[pyclass(name = "Simulation", module = "sph._sph", subclass)]
pub struct PySimulation {
    state: State,
    scene: Scene,
    pool: rayon::ThreadPool,
    /// The generation of the arrays showing the current fields, while any is alive.
    views: Weak<Generation>,
}

impl PySimulation {
    /// Hands the field vectors to the arrays of the current generation if any is alive, the
    /// simulation keeping copies; after this, nothing outside the simulation points into its
    /// fields. Called before anything that writes into them.
    fn detach_views(&mut self) {
        if let Some(generation) = self.views.upgrade() {
            let held = each_dim!(&mut self.state.sim, s => take_fields(&mut s.fields));
            *generation.held.lock().unwrap_or_else(|e| e.into_inner()) = Some(held);
        }
        self.views = Weak::new();
    }
}

impl Drop for PySimulation {
    /// Arrays outliving the simulation keep its fields' memory.
    fn drop(&mut self) {
        if let Some(generation) = self.views.upgrade() {
            let held = each_dim!(&mut self.state.sim, s => {
                let fields = std::mem::take(&mut s.fields);
                Box::new(fields) as Held
            });
            *generation.held.lock().unwrap_or_else(|e| e.into_inner()) = Some(held);
        }
    }
}

/// The vectors `fields()` hands out, moved out of `f` (their heap buffers stay where they are)
/// and replaced there by copies.
fn take_fields<const D: usize>(f: &mut sph::fields::Fields<D>) -> Held {
    fn take<T: Clone>(v: &mut Vec<T>) -> Vec<T> {
        let copy = v.clone();
        std::mem::replace(v, copy)
    }
    Box::new((
        take(&mut f.position),
        take(&mut f.velocity),
        take(&mut f.density),
        take(&mut f.pressure),
        take(&mut f.mass),
        take(&mut f.rest_density),
        take(&mut f.kind),
        take(&mut f.id),
    ))
}

/// The backend named `name` (`cpu` or `cuda`).
pub fn backend_kind(name: &str) -> PyResult<BackendKind> {
    match name {
        "cpu" => Ok(BackendKind::Cpu),
        "cuda" => Ok(BackendKind::Cuda),
        other => Err(pyo3::exceptions::PyValueError::new_err(format!(
            "backend {other:?}: expected \"cpu\" or \"cuda\""
        ))),
    }
}

/// A pool of `threads` workers (default: all cores), as `sph run --threads`.
pub fn pool(threads: Option<usize>) -> PyResult<rayon::ThreadPool> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        if n == 0 {
            return Err(pyo3::exceptions::PyValueError::new_err(
                "threads must be at least 1",
            ));
        }
        builder = builder.num_threads(n);
    }
    builder
        .build()
        .map_err(|e| to_py(anyhow::Error::new(e).context("starting the worker threads")))
}

/// The simulation of `scene` on `backend`, as `run::run_scene` builds it, with its probes'
/// record at time 0 (as `sph run` takes it).
fn build(scene: &Scene, backend: BackendKind) -> Result<State, sph::Error> {
    sph::probe::check_references(scene)?;
    if backend == BackendKind::Cuda {
        sph::backend::cuda::probe()?;
    }
    let mut sim = AnySimulation::from_scene(scene)?;
    let mut probes = ProbeLog::create(scene, None, ProbeLog::interval_for(scene))?;
    each_dim!(&mut sim, s => {
        s.use_backend(backend)?;
        probes.record_loads(0.0, 0.0, &s.fields, s.solid_forces(), s.solid_moments(), true)?;
    });
    Ok(State {
        sim,
        probes,
        forces: Vec::new(),
        steps: Vec::new(),
    })
}

/// One step towards `until` [s], and the records `sph run` takes after it (`run::record_step`);
/// `end` is the scene's end time (the last step records the probes whatever their interval).
fn step<const D: usize>(
    sim: &mut Simulation<D>,
    probes: &mut ProbeLog,
    forces: &mut Vec<(f64, usize, [f64; 3])>,
    until: f64,
    end: f64,
) -> Result<StepRow, sph::Error> {
    let iterations_before = sim.stats().correction.iterations;
    let report = sim.step(until)?;
    let clock = sim.clock();
    let last = clock.time >= end;
    if probes.wants_fields(clock.time, last) {
        sim.sync_fields()?;
    }
    probes.record_loads(
        clock.time,
        report.dt,
        &sim.fields,
        sim.solid_forces(),
        sim.solid_moments(),
        last,
    )?;
    for (k, force) in sim.solid_forces().iter().enumerate() {
        forces.push((clock.time, k, *force));
    }
    Ok(StepRow::of(sim, &report, iterations_before))
}

/// Where each field's host memory is, read under the borrow and used after it.
struct FieldMemory {
    n: usize,
    dim: usize,
    vectors: [(&'static str, *const f32); 2],
    reals: Vec<(&'static str, *const f32)>,
    indices: [(&'static str, *const u32); 2],
}

impl FieldMemory {
    fn of<const D: usize>(f: &sph::fields::Fields<D>) -> Self {
        // A `Vector<D>` is nalgebra's `SVector<f32, D>`, `#[repr(C)]` around `[f32; D]`, so a
        // slice of them is `n·D` contiguous `f32` in row-major (N, D) order.
        let n = f.len();
        let mut reals = vec![
            ("density", f.density.as_ptr()),
            ("pressure", f.pressure.as_ptr()),
            ("mass", f.mass.as_ptr()),
        ];
        // Allocated only for several fluid phases (`Fields::is_allocated`).
        if n > 0 && f.rest_density.len() == n {
            reals.push(("rest_density", f.rest_density.as_ptr()));
        }
        Self {
            n,
            dim: D,
            vectors: [
                ("position", f.position.as_ptr().cast()),
                ("velocity", f.velocity.as_ptr().cast()),
            ],
            reals,
            indices: [("kind", f.kind.as_ptr()), ("id", f.id.as_ptr())],
        }
    }
}

/// A read-only 1-D array over `n` values at `ptr`, kept alive by `owner`.
///
/// # Safety
/// `ptr` must point to `n` initialised values that stay where they are while `owner` lives.
unsafe fn borrowed_1d<'py, T: Element>(
    owner: &Bound<'py, PyAny>,
    ptr: *const T,
    n: usize,
) -> PyResult<Bound<'py, PyAny>> {
    // SAFETY: the caller's contract; `owner` is the array's base, so it outlives the array.
    let array = unsafe {
        let view = ArrayView1::from_shape_ptr(n, ptr);
        PyArray1::borrow_from_array(&view, owner.clone().into_any())
    };
    array.getattr("flags")?.setattr("writeable", false)?;
    Ok(array.into_any())
}

/// A read-only (n, dim) array at `ptr`, kept alive by `owner`.
///
/// # Safety
/// `ptr` must point to `n·dim` initialised values that stay where they are while `owner`
/// lives.
unsafe fn borrowed_2d<'py>(
    owner: &Bound<'py, PyAny>,
    ptr: *const f32,
    n: usize,
    dim: usize,
) -> PyResult<Bound<'py, PyAny>> {
    // SAFETY: the caller's contract; `owner` is the array's base, so it outlives the array.
    let array = unsafe {
        let view = ArrayView2::from_shape_ptr((n, dim), ptr);
        PyArray2::borrow_from_array(&view, owner.clone().into_any())
    };
    array.getattr("flags")?.setattr("writeable", false)?;
    Ok(array.into_any())
}

#[pymethods]
impl PySimulation {
    /// The simulation of `scene` with `threads` workers on `backend` (`"cpu"` or `"cuda"`).
    #[new]
    #[pyo3(signature = (scene, threads=None, backend="cpu"))]
    fn new(py: Python<'_>, scene: &PyScene, threads: Option<usize>, backend: &str) -> PyResult<Self> {
        let kind = backend_kind(backend)?;
        let pool = pool(threads)?;
        let scene = scene.scene.clone();
        let state = py
            .detach(|| pool.install(|| build(&scene, kind)))
            .map_err(from_lib)?;
        Ok(Self {
            state,
            scene,
            pool,
            views: Weak::new(),
        })
    }

    /// Takes one step towards `until` [s] (default: the scene's end time; the step is shortened
    /// to end there) and returns its row of `steps.csv` as a dict. The GIL is released while the
    /// step runs; a pending Ctrl-C raises `KeyboardInterrupt` after it.
    #[pyo3(signature = (until=None))]
    fn step<'py>(&mut self, py: Python<'py>, until: Option<f64>) -> PyResult<Bound<'py, PyDict>> {
        let end = self.scene.end_time;
        let until = until.unwrap_or(end);
        self.detach_views();
        let State {
            sim,
            probes,
            forces,
            steps,
        } = &mut self.state;
        let pool = &self.pool;
        let row = py
            .detach(|| pool.install(|| each_dim!(sim, s => step(s, probes, forces, until, end))))
            .map_err(from_lib)?;
        steps.push(row.clone());
        py.check_signals()?;
        step_dict(py, &row)
    }

    /// Simulated time [s].
    #[getter]
    fn time(&self) -> f64 {
        each_dim!(&self.state.sim, s => s.clock().time)
    }

    /// Steps taken.
    #[getter]
    fn steps_taken(&self) -> u64 {
        each_dim!(&self.state.sim, s => s.clock().step)
    }

    /// The scene's end time [s].
    #[getter]
    fn end_time(&self) -> f64 {
        self.scene.end_time
    }

    /// 2 or 3.
    #[getter]
    fn dimension(&self) -> usize {
        self.scene.dimension
    }

    /// Particles now (fluid and solid).
    #[getter]
    fn particle_count(&self) -> usize {
        each_dim!(&self.state.sim, s => s.fields.len())
    }

    /// The backend's name.
    #[getter]
    fn backend(&self) -> &'static str {
        each_dim!(&self.state.sim, s => s.backend_name())
    }

    /// Worker threads.
    #[getter]
    fn threads(&self) -> usize {
        self.pool.current_num_threads()
    }

    /// The named solids, in scene order.
    #[getter]
    fn solids(&self) -> Vec<String> {
        each_dim!(&self.state.sim, s => s.solid_names().to_vec())
    }

    /// The particle fields as read-only NumPy arrays over the simulation's memory, no copy:
    /// `position` and `velocity` (N, D) float32 [m, m/s], `density` [kg/m^3], `pressure` [Pa],
    /// `mass` [kg] (N,) float32, `rest_density` (N,) float32 with several fluid phases (else
    /// absent), `kind` (N,) uint32 (0 fluid, k+1 solid k) and `id` (N,) uint32 (stable ids, as
    /// in the frames). A snapshot of the state now, valid for as long as the arrays live;
    /// holding them across a step costs one copy of the fields in that step.
    fn fields<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let py = slf.py();
        let (memory, generation) = {
            let mut this = slf.borrow_mut();
            let this = &mut *this;
            // Between steps the host fields are in sync once arrays exist (they were taken after
            // a sync, and only a step makes them stale), so this writes into no array's memory.
            let memory = each_dim!(&mut this.state.sim, s => {
                s.sync_fields().map_err(from_lib)?;
                FieldMemory::of(&s.fields)
            });
            let generation = match this.views.upgrade() {
                Some(generation) => generation,
                None => {
                    let generation = Arc::new(Generation::default());
                    this.views = Arc::downgrade(&generation);
                    generation
                }
            };
            (memory, generation)
        };
        let guard = Bound::new(
            py,
            FieldGuard {
                _generation: generation,
            },
        )?
        .into_any();
        let dict = PyDict::new(py);
        let n = memory.n;
        // SAFETY: each pointer is the start of a field of `n` entries (`n·dim` for vectors) of
        // the simulation `slf` holds, read under its borrow just now. `guard`, every array's
        // base, holds the generation the simulation points to, so before the simulation next
        // writes into its fields or is dropped (`detach_views`, `drop`) it moves these vectors
        // into the generation, where their heap buffers stay put until the last array is gone.
        unsafe {
            for (name, ptr) in memory.vectors {
                dict.set_item(name, borrowed_2d(&guard, ptr, n, memory.dim)?)?;
            }
            for (name, ptr) in memory.reals {
                dict.set_item(name, borrowed_1d(&guard, ptr, n)?)?;
            }
            for (name, ptr) in memory.indices {
                dict.set_item(name, borrowed_1d(&guard, ptr, n)?)?;
            }
        }
        Ok(dict)
    }

    /// The forces on the named solids after every step, as `forces.csv`'s columns: `t_s`,
    /// `solid`, then `fx`, `fy` (and `fz` in 3D) in N (N per metre of depth in 2D).
    fn forces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dim = self.scene.dimension;
        let names = each_dim!(&self.state.sim, s => s.solid_names().to_vec());
        let columns = sph::output::ForceLog::columns(dim);
        let rows = &self.state.forces;
        let dict = PyDict::new(py);
        let times: Vec<f64> = rows.iter().map(|r| r.0).collect();
        dict.set_item(&columns[0], PyArray1::from_vec(py, times))?;
        let solids: Vec<&str> = rows.iter().map(|r| names[r.1].as_str()).collect();
        dict.set_item(&columns[1], PyList::new(py, solids)?)?;
        for (k, column) in columns[2..].iter().enumerate() {
            let values: Vec<f64> = rows.iter().map(|r| r.2[k]).collect();
            dict.set_item(column, PyArray1::from_vec(py, values))?;
        }
        Ok(dict)
    }

    /// The probes' samples, as `probes.csv`'s columns: `t_s`, then one column per probe named
    /// as there (`<probe>_<unit>`).
    fn probes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let log = &self.state.probes;
        let dict = PyDict::new(py);
        if log.probes().is_empty() {
            return Ok(dict);
        }
        let times: Vec<f64> = log.samples(0).iter().map(|s| s.0).collect();
        dict.set_item("t_s", PyArray1::from_vec(py, times))?;
        for (k, probe) in log.probes().iter().enumerate() {
            let values: Vec<f64> = log.samples(k).iter().map(|s| s.1).collect();
            dict.set_item(
                column_name(probe, self.scene.dimension),
                PyArray1::from_vec(py, values),
            )?;
        }
        Ok(dict)
    }

    /// One entry per step taken, as `steps.csv`'s columns (`sph::run::STEP_COLUMNS`).
    fn steps<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let rows = &self.state.steps;
        let dict = PyDict::new(py);
        let c = sph::run::STEP_COLUMNS;
        let int = |f: fn(&StepRow) -> u64| PyArray1::from_vec(py, rows.iter().map(f).collect());
        let real = |f: fn(&StepRow) -> f64| PyArray1::from_vec(py, rows.iter().map(f).collect());
        dict.set_item(c[0], int(|r| r.step))?;
        dict.set_item(c[1], real(|r| r.time))?;
        dict.set_item(c[2], real(|r| r.dt))?;
        let limits: Vec<&str> = rows.iter().map(|r| r.limit.as_str()).collect();
        dict.set_item(c[3], PyList::new(py, limits)?)?;
        dict.set_item(c[4], real(|r| r.max_speed))?;
        dict.set_item(c[5], real(|r| r.max_compression))?;
        dict.set_item(c[6], real(|r| r.max_surface_deficit))?;
        dict.set_item(c[7], int(|r| r.correction_iterations))?;
        dict.set_item(c[8], int(|r| r.removed))?;
        dict.set_item(c[9], int(|r| r.created))?;
        dict.set_item(c[10], int(|r| r.outflow))?;
        Ok(dict)
    }

    fn __repr__(&self) -> String {
        format!(
            "Simulation({}D, {} particles, t = {} s of {} s, {} steps, {} backend)",
            self.scene.dimension,
            self.particle_count(),
            self.time(),
            self.scene.end_time,
            self.steps_taken(),
            self.backend()
        )
    }
}

/// A step's row as a dict keyed by `steps.csv`'s columns.
fn step_dict<'py>(py: Python<'py>, r: &StepRow) -> PyResult<Bound<'py, PyDict>> {
    let c = sph::run::STEP_COLUMNS;
    let dict = PyDict::new(py);
    dict.set_item(c[0], r.step)?;
    dict.set_item(c[1], r.time)?;
    dict.set_item(c[2], r.dt)?;
    dict.set_item(c[3], &r.limit)?;
    dict.set_item(c[4], r.max_speed)?;
    dict.set_item(c[5], r.max_compression)?;
    dict.set_item(c[6], r.max_surface_deficit)?;
    dict.set_item(c[7], r.correction_iterations)?;
    dict.set_item(c[8], r.removed)?;
    dict.set_item(c[9], r.created)?;
    dict.set_item(c[10], r.outflow)?;
    Ok(dict)
}
