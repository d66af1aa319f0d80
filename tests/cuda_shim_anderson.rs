//! The velocity solve's iteration on the device (`kernels/anderson.cu`, with the correction's
//! `correction_pressure_fluid`, `correction_pressure_wall`, `correction_displacement` and their
//! multiphase variants), run on the CPU through the host shim (`backend::cuda::shim`) in the
//! order `CudaBackend` launches them (`backend::cuda::anderson`), against
//! `CpuBackend::mix_velocity_pressure` and `velocity_from_pressure`: several iterations of
//! `predicted_density` → mix → velocities from the same start, compared per particle `id` after
//! each, in 2D and 3D, and with two phases in 2D.
//!
//! Tolerances. The per-particle arithmetic matches the CPU's operation for operation; what
//! differs is the order of sums: the neighbour sums of the predicted density, the walls'
//! extrapolation and the displacement (about 1e-7 relative each, see tests/cuda_shim_dynamics.rs),
//! and the dot products of the least-squares problem (f64 on both sides, so ~1e-16, but the
//! coefficients `γ` come out of a Gram matrix whose conditioning grows as the iterates converge).
//! These differences feed the next iteration, so they are compared against the size of what the
//! solve changes: pressures within [`TOLERANCE`] of the largest `|P − P_start|`, velocities
//! within it of the largest `|u − u_start|` component. A control run of the same kernels with
//! the acceleration off (`held = 0` in `anderson_mix`: plain projected Jacobi) must miss the
//! CPU by far more, so the comparison sees the mixing.
#![cfg(feature = "cuda")]

use sph::backend::Backend;
use sph::backend::cpu::CpuBackend;
use sph::backend::cuda::grid::GridGeometry;
use sph::backend::cuda::shim;
use sph::backend::params::StepParams;
use sph::fields::{FLUID, Fields};
use sph::math::{Real, Vector};
use sph::physics::lattice::{correction_stiffness, lattice_spiky_scale};
use sph::solver::anderson::{AndersonState, WINDOW};

/// Relative tolerance against the solve's change of the field (module doc).
const TOLERANCE: f64 = 1.0e-4;
/// Iterations compared: past `WINDOW + 1`, so that the ring of differences wraps around.
const ITERATIONS: usize = WINDOW + 3;
/// Lattice spacing [m]; the support is `h = 2 dx`.
const DX: f32 = 0.01;
/// Rest density [kg/m³] (of the heavier phase with two).
const RHO0: f32 = 1000.0;
/// The lighter phase's rest density [kg/m³] (left half of the fluid, two phases only).
const RHO0_LIGHT: f32 = 800.0;
/// The solve's `τ` [s]: about 1 % of ρ0 from velocities of 1 m/s over dx = 1 cm.
const TAU: f32 = 1.0e-4;

/// A small deterministic generator (xorshift), so failures reproduce.
struct Rng(u64);
impl Rng {
    /// Uniform in `[0, 1)`.
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in `[-a, a)`.
    fn sym(&mut self, a: f32) -> f32 {
        a * (2.0 * self.next() - 1.0)
    }
}

/// A jittered fluid block (24 × 16 in 2D, 10 × 8 × 8 in 3D) on a floor (solid 1) beside a left
/// wall (solid 2), two layers each, at rest: random fluid velocities up to 1 m/s, densities (18)
/// spread over `(0.98 ± 0.03) ρ0` (both sides of `velocity_solve_base`), pressures up to 2 kPa
/// (a quarter of the fluid at zero). With `two_phases`, the left half of the fluid is the lighter
/// phase (its own rest density and mass). Step parameters of the `corrected` solver: the spiky
/// density kernel's scale and a gradient scale ≠ 1.
fn scene<const D: usize>(seed: u64, two_phases: bool) -> (Fields<D>, StepParams<D>) {
    let mut rng = Rng(seed);
    let n = if D == 2 { [24, 16, 1] } else { [10, 8, 8] };
    let lo = [-2, -2, 0];
    let mut f = Fields::<D>::default();
    let total: i32 = (0..D).map(|k| n[k] - lo[k]).product();
    let mut rest = Vec::new();
    for c in 0..total {
        let mut idx = [0i32; 3];
        let mut left = c;
        for k in 0..D {
            let extent = n[k] - lo[k];
            idx[k] = lo[k] + left % extent;
            left /= extent;
        }
        let kind = if idx[1] < 0 {
            1
        } else if idx[0] < 0 {
            2
        } else {
            FLUID
        };
        let rho0 = if two_phases && kind == FLUID && idx[0] < n[0] / 2 {
            RHO0_LIGHT
        } else {
            RHO0
        };
        let mut x = Vector::<D>::zeros();
        let mut u = Vector::<D>::zeros();
        for k in 0..D {
            x[k] = (idx[k] as f32 + 0.5) * DX;
            if kind == FLUID {
                x[k] += rng.sym(0.15 * DX);
                u[k] = rng.sym(1.0);
            }
        }
        let rho = rho0 * (0.98 + rng.sym(0.03));
        f.push(x, u, rho0 * DX.powi(D as i32), rho, kind);
        rest.push(rho0);
        let p = if kind == FLUID && rng.next() < 0.25 {
            0.0
        } else {
            2000.0 * rng.next()
        };
        *f.pressure.last_mut().expect("just pushed") = p;
    }
    if two_phases {
        f.rest_density = rest;
    }
    let mut domain_min = Vector::<D>::zeros();
    let mut domain_max = Vector::<D>::zeros();
    for k in 0..D {
        domain_min[k] = (lo[k] as f32 - 1.0) * DX;
        domain_max[k] = (n[k] as f32 + 6.0) * DX;
    }
    let mut p = StepParams {
        h: 2.0 * DX,
        rho0: RHO0,
        c2: 40.0 * 40.0,
        mu: 0.0,
        alpha: 0.0,
        c: 40.0,
        pressure_gradient_scale: 1.05,
        gravity: Vector::zeros(),
        domain_min,
        domain_max,
        angular_velocity: [0.0; 3],
        rotation_centre: Vector::zeros(),
        viscosity_scale: 1.0,
        surface_tension_gamma: 0.0,
        surface_tension_sigma: 0.0,
        spacing: DX,
        density_spiky_scale: 0.0,
        density_kernel: sph::physics::density::DensityKernel::ScaledSpiky,
        surface_tension_model: sph::backend::SurfaceTensionModel::SurfaceStress,
        rotating_frame: 0,
        phases: if two_phases {
            sph::physics::multiphase::Phases::Multi
        } else {
            sph::physics::multiphase::Phases::Single
        },
    };
    p.density_spiky_scale = lattice_spiky_scale(&p.smoothing(), f64::from(DX)) as Real;
    (f, p)
}

/// The correction's stiffness `ω K/τ²` [m²/s²] as the driver computes it (`ω = 0.5`).
fn stiffness<const D: usize>(p: &StepParams<D>) -> f32 {
    let kappa = 1.0 / f64::from(p.pressure_gradient_scale);
    let k = correction_stiffness(
        &p.smoothing(),
        f64::from(DX),
        f64::from(RHO0),
        kappa,
        p.density_weight(),
    );
    (0.5 * k / f64::from(TAU * TAU)) as f32
}

/// Key of the dense-grid cell of `x`, as `cell_of` and `cell_key` of `kernels/sph.cuh`.
fn cell_key<const D: usize>(g: &GridGeometry<D>, x: &Vector<D>) -> u32 {
    let mut cell = [0u32; D];
    for k in 0..D {
        let f = ((x[k] - g.origin[k]) * g.inv_cell).floor();
        let hi = g.dims[k] as i32 - 2;
        cell[k] = if f.is_nan() || f < 1.0 {
            1
        } else if f > hi as f32 {
            hi as u32
        } else {
            f as u32
        };
    }
    let mut key = cell[D - 1];
    for k in (0..D - 1).rev() {
        key = key * g.dims[k] + cell[k];
    }
    key
}

/// A pointer to `x` as the shim's type for this dimension (the same `#[repr(C)]` struct).
fn ptr<T, U>(x: &T) -> *const U {
    (x as *const T).cast()
}

/// Calls the 2D or the 3D launcher.
macro_rules! launch {
    ($d:expr, $two:ident, $three:ident, $($arg:expr),* $(,)?) => {
        // SAFETY: every buffer holds n items (D floats each for vectors, WINDOW n for the
        // window's slots), `cell_start` holds ncell + 1 entries, and the structs are the
        // launcher's own type for this dimension.
        unsafe {
            match $d {
                2 => shim::$two($($arg),*),
                3 => shim::$three($($arg),*),
                d => unreachable!("dimension {d}"),
            }
        }
    };
}

/// Calls a multiphase launcher (the shim exports them for 2D).
macro_rules! launch_2d {
    ($d:expr, $two:ident, $($arg:expr),* $(,)?) => {{
        assert_eq!($d, 2, "the multiphase launchers are 2D");
        // SAFETY: as in `launch!`.
        unsafe { shim::$two($($arg),*) }
    }};
}

/// What `CudaBackend` holds during a velocity solve, as host arrays the shim's kernels run on:
/// the fields sorted by (cell, id) with the dense grid, as `sort_by_cell` leaves them, the
/// solve's start (`begin_velocity_solve`), and the Anderson window
/// (`backend::cuda::anderson::AndersonBuffers`) with its host state.
struct ShimSolve<const D: usize> {
    g: GridGeometry<D>,
    cell_start: Vec<u32>,
    cell_key: Vec<u32>,
    pos: Vec<f32>,
    vel: Vec<f32>,
    density: Vec<f32>,
    pressure: Vec<f32>,
    mass: Vec<f32>,
    kind: Vec<u32>,
    id: Vec<u32>,
    /// `Fields::rest_density` in sorted order (read with `Phases::Multi`); empty with one phase.
    rest: Vec<f32>,
    velocity_start: Vec<f32>,
    pressure_start: Vec<f32>,
    density_start: Vec<f32>,
    delta_p: Vec<f32>,
    displacement: Vec<f32>,
    state: AndersonState,
    dp: Vec<f32>,
    df: Vec<f32>,
    previous: Vec<f32>,
    previous_f: Vec<f32>,
    f: Vec<f32>,
    /// `false` for the control run: `anderson_mix` with `held = 0` (plain projected Jacobi).
    accelerate: bool,
}

impl<const D: usize> ShimSolve<D> {
    fn new(f: &Fields<D>, p: &StepParams<D>, accelerate: bool) -> Self {
        let g = GridGeometry::new(&p.domain_min, &p.domain_max, p.h).expect("a small domain");
        let keys: Vec<u32> = f.position.iter().map(|x| cell_key(&g, x)).collect();
        let mut order: Vec<usize> = (0..f.len()).collect();
        order.sort_by_key(|&i| (keys[i], f.id[i]));
        let mut cell_start = vec![0u32; g.cell_count() + 1];
        for &k in &keys {
            cell_start[k as usize + 1] += 1;
        }
        for c in 0..g.cell_count() {
            cell_start[c + 1] += cell_start[c];
        }
        let vectors =
            |v: &[Vector<D>]| -> Vec<f32> { order.iter().flat_map(|&i| v[i].iter().copied()).collect() };
        let scalars = |v: &[f32]| -> Vec<f32> { order.iter().map(|&i| v[i]).collect() };
        let n = f.len();
        let (vel, pressure, density) = (vectors(&f.velocity), scalars(&f.pressure), scalars(&f.density));
        Self {
            g,
            cell_start,
            cell_key: order.iter().map(|&i| keys[i]).collect(),
            pos: vectors(&f.position),
            velocity_start: vel.clone(),
            pressure_start: pressure.clone(),
            density_start: density.clone(),
            vel,
            density,
            pressure,
            mass: scalars(&f.mass),
            kind: order.iter().map(|&i| f.kind[i]).collect(),
            id: order.iter().map(|&i| f.id[i]).collect(),
            rest: if f.rest_density.is_empty() {
                Vec::new()
            } else {
                scalars(&f.rest_density)
            },
            delta_p: vec![f32::NAN; n],
            displacement: vec![f32::NAN; n * D],
            state: AndersonState::default(),
            // Stale window contents (as device memory holds them): only filled slots are read.
            dp: vec![f32::NAN; WINDOW * n],
            df: vec![f32::NAN; WINDOW * n],
            previous: vec![f32::NAN; n],
            previous_f: vec![f32::NAN; n],
            f: vec![f32::NAN; n],
            accelerate,
        }
    }

    fn n(&self) -> u32 {
        self.kind.len() as u32
    }

    /// `predicted_density` (or its multiphase variant) from the start's densities.
    fn predicted_density(&mut self, p: &StepParams<D>) {
        let n = self.n();
        if p.phases == sph::physics::multiphase::Phases::Single {
            launch!(
                D,
                sph_shim_predicted_density_2,
                sph_shim_predicted_density_3,
                n,
                ptr(p),
                ptr(&self.g),
                self.cell_start.as_ptr(),
                self.cell_key.as_ptr(),
                self.pos.as_ptr(),
                self.vel.as_ptr(),
                self.mass.as_ptr(),
                self.kind.as_ptr(),
                self.density_start.as_ptr(),
                TAU,
                self.density.as_mut_ptr(),
            );
        } else {
            launch_2d!(
                D,
                sph_shim_predicted_density_multiphase_2,
                n,
                ptr(p),
                ptr(&self.g),
                self.cell_start.as_ptr(),
                self.cell_key.as_ptr(),
                self.pos.as_ptr(),
                self.vel.as_ptr(),
                self.mass.as_ptr(),
                self.rest.as_ptr(),
                self.kind.as_ptr(),
                self.density_start.as_ptr(),
                TAU,
                self.density.as_mut_ptr(),
            );
        }
    }

    /// `anderson_dots` of `a[offset..offset + n]` with the first `count` slots of `Δf`.
    fn dots(&self, a: *const f32, offset: usize, count: usize) -> [f64; WINDOW] {
        let mut out = [0.0f64; WINDOW];
        launch!(
            D,
            sph_shim_anderson_dots_2,
            sph_shim_anderson_dots_3,
            self.n(),
            count as u32,
            a,
            offset as u32,
            self.df.as_ptr(),
            out.as_mut_ptr(),
        );
        out
    }

    /// `CudaBackend::mix_velocity_pressure`'s sequence (`backend::cuda::anderson::mix_pressure`).
    fn mix(&mut self, p: &StepParams<D>, k: f32) {
        let n = self.n();
        let unused = vec![f32::NAN; n as usize];
        if p.phases == sph::physics::multiphase::Phases::Single {
            launch!(
                D,
                sph_shim_correction_pressure_fluid_2,
                sph_shim_correction_pressure_fluid_3,
                n,
                p.rho0,
                k,
                0.0,
                0,
                self.density.as_ptr(),
                self.pressure.as_ptr(),
                self.kind.as_ptr(),
                unused.as_ptr(),
                self.f.as_mut_ptr(),
            );
        } else {
            launch_2d!(
                D,
                sph_shim_correction_pressure_fluid_multiphase_2,
                n,
                self.rest.as_ptr(),
                k,
                0.0,
                0,
                self.density.as_ptr(),
                self.pressure.as_ptr(),
                self.kind.as_ptr(),
                unused.as_ptr(),
                self.f.as_mut_ptr(),
            );
        }
        if self.state.has_previous {
            let s = self.state.next;
            launch!(
                D,
                sph_shim_anderson_difference_2,
                sph_shim_anderson_difference_3,
                n,
                s as u32,
                self.pressure.as_ptr(),
                self.previous.as_ptr(),
                self.f.as_ptr(),
                self.previous_f.as_ptr(),
                self.dp.as_mut_ptr(),
                self.df.as_mut_ptr(),
            );
            let valid = (self.state.held + 1).min(WINDOW);
            let row = self.dots(self.df.as_ptr(), s * n as usize, valid);
            self.state.push(&row);
        }
        let held = self.state.held;
        let rhs = if held > 0 {
            self.dots(self.f.as_ptr(), 0, held)
        } else {
            [0.0; WINDOW]
        };
        let gamma = self.state.coefficients(&rhs).map(|g| g as Real);
        let held = if self.accelerate { held as u32 } else { 0 };
        launch!(
            D,
            sph_shim_anderson_mix_2,
            sph_shim_anderson_mix_3,
            n,
            held,
            gamma.as_ptr(),
            self.kind.as_ptr(),
            self.f.as_ptr(),
            self.dp.as_ptr(),
            self.df.as_ptr(),
            self.previous.as_mut_ptr(),
            self.previous_f.as_mut_ptr(),
            self.pressure.as_mut_ptr(),
        );
        self.state.has_previous = true;
    }

    /// `CudaBackend::velocity_from_pressure`'s sequence
    /// (`backend::cuda::anderson::pressure_to_velocity`).
    fn velocity_from_pressure(&mut self, p: &StepParams<D>) {
        let n = self.n();
        launch!(
            D,
            sph_shim_velocity_solve_increments_2,
            sph_shim_velocity_solve_increments_3,
            n,
            self.kind.as_ptr(),
            self.pressure.as_ptr(),
            self.pressure_start.as_ptr(),
            self.delta_p.as_mut_ptr(),
        );
        launch!(
            D,
            sph_shim_correction_pressure_wall_2,
            sph_shim_correction_pressure_wall_3,
            n,
            ptr(p),
            ptr(&self.g),
            self.cell_start.as_ptr(),
            self.cell_key.as_ptr(),
            self.pos.as_ptr(),
            self.density_start.as_ptr(),
            self.pressure_start.as_ptr(),
            self.kind.as_ptr(),
            self.delta_p.as_mut_ptr(),
        );
        launch!(
            D,
            sph_shim_velocity_solve_solid_pressure_2,
            sph_shim_velocity_solve_solid_pressure_3,
            n,
            self.kind.as_ptr(),
            self.pressure_start.as_ptr(),
            self.delta_p.as_ptr(),
            self.pressure.as_mut_ptr(),
        );
        let tau2 = TAU * TAU;
        // Its largest-|Δx| output is not read: the velocity solve does not scale.
        let mut largest = 0i32;
        if p.phases == sph::physics::multiphase::Phases::Single {
            launch!(
                D,
                sph_shim_correction_displacement_2,
                sph_shim_correction_displacement_3,
                n,
                ptr(p),
                ptr(&self.g),
                self.cell_start.as_ptr(),
                self.cell_key.as_ptr(),
                self.pos.as_ptr(),
                self.mass.as_ptr(),
                self.density_start.as_ptr(),
                self.delta_p.as_ptr(),
                self.kind.as_ptr(),
                tau2,
                self.displacement.as_mut_ptr(),
                &mut largest,
            );
        } else {
            launch_2d!(
                D,
                sph_shim_correction_displacement_multiphase_2,
                n,
                ptr(p),
                ptr(&self.g),
                self.cell_start.as_ptr(),
                self.cell_key.as_ptr(),
                self.pos.as_ptr(),
                self.mass.as_ptr(),
                self.density_start.as_ptr(),
                self.delta_p.as_ptr(),
                self.kind.as_ptr(),
                tau2,
                self.displacement.as_mut_ptr(),
                &mut largest,
            );
        }
        launch!(
            D,
            sph_shim_velocity_from_displacement_2,
            sph_shim_velocity_from_displacement_3,
            n,
            TAU,
            self.kind.as_ptr(),
            self.velocity_start.as_ptr(),
            self.displacement.as_ptr(),
            self.vel.as_mut_ptr(),
        );
    }
}

/// `out[id] = index`.
fn index_of_id(id: &[u32]) -> Vec<usize> {
    let mut out = vec![usize::MAX; id.len()];
    for (i, &k) in id.iter().enumerate() {
        out[k as usize] = i;
    }
    out
}

/// The largest differences of a shim run from the CPU after one iteration, relative to the
/// solve's change so far: (pressure, velocity, scales).
struct Misfit {
    pressure: f64,
    velocity: f64,
    /// Largest `|P − P_start|` [Pa] and `|u − u_start|` component [m/s] on the CPU.
    scales: (f64, f64),
}

fn misfit<const D: usize>(start: &Fields<D>, cf: &Fields<D>, s: &ShimSolve<D>) -> Misfit {
    let cpu_at = index_of_id(&cf.id);
    let dev_at = index_of_id(&s.id);
    let n = start.len();
    let (mut p_scale, mut u_scale) = (0.0f64, 0.0f64);
    for id in 0..n {
        let c = cpu_at[id];
        p_scale = p_scale.max(f64::from(cf.pressure[c] - start.pressure[id]).abs());
        for k in 0..D {
            u_scale = u_scale.max(f64::from(cf.velocity[c][k] - start.velocity[id][k]).abs());
        }
    }
    let (mut dp, mut du) = (0.0f64, 0.0f64);
    for id in 0..n {
        let (c, i) = (cpu_at[id], dev_at[id]);
        let diff = f64::from(s.pressure[i] - cf.pressure[c]).abs();
        dp = dp.max(if diff.is_nan() { f64::INFINITY } else { diff });
        for k in 0..D {
            let diff = f64::from(s.vel[i * D + k] - cf.velocity[c][k]).abs();
            du = du.max(if diff.is_nan() { f64::INFINITY } else { diff });
        }
    }
    Misfit {
        pressure: dp / p_scale,
        velocity: du / u_scale,
        scales: (p_scale, u_scale),
    }
}

/// [`ITERATIONS`] iterations of the velocity solve from the same start on the CPU backend and
/// through the shim (and the unaccelerated control), compared after each (module doc). Also
/// checks that the solve does something visible: the residual (largest `|ρ* − ρ0|/ρ0`) falls,
/// the window fills and wraps around, and the control misses by more than 100 × the tolerance.
fn check_iterations<const D: usize>(seed: u64, two_phases: bool) {
    let (start, p) = scene::<D>(seed, two_phases);
    let k = stiffness(&p);
    let mut cf = start.clone();
    let mut cpu = CpuBackend::<D>::new();
    cpu.sort_by_cell(&mut cf, p.h).expect("finite positions");
    cpu.begin_velocity_solve(&mut cf);
    let mut shim = ShimSolve::new(&start, &p, true);
    let mut control = ShimSolve::new(&start, &p, false);
    let label = format!("{D}D{}", if two_phases { ", two phases" } else { "" });
    let (mut first_residual, mut last_residual) = (None, 0.0f64);
    let mut control_worst = 0.0f64;
    for iteration in 0..ITERATIONS {
        cpu.predicted_density(&mut cf, &p, TAU);
        let residual = cpu.correction_error(&cf, &p).residual;
        first_residual.get_or_insert(residual);
        last_residual = residual;
        cpu.mix_velocity_pressure(&mut cf, &p, k);
        cpu.velocity_from_pressure(&mut cf, &p, TAU);
        for s in [&mut shim, &mut control] {
            s.predicted_density(&p);
            s.mix(&p, k);
            s.velocity_from_pressure(&p);
        }
        let m = misfit(&start, &cf, &shim);
        let c = misfit(&start, &cf, &control);
        eprintln!(
            "{label} iteration {iteration} (residual {residual:.2e}, held {}): pressure {:.2e}, \
             velocity {:.2e} of the change ({:.0} Pa, {:.3} m/s); control {:.2e}, {:.2e}",
            shim.state.held, m.pressure, m.velocity, m.scales.0, m.scales.1, c.pressure, c.velocity
        );
        assert!(
            m.pressure <= TOLERANCE,
            "{label} iteration {iteration}: pressures differ by {:.2e} of the change",
            m.pressure
        );
        assert!(
            m.velocity <= TOLERANCE,
            "{label} iteration {iteration}: velocities differ by {:.2e} of the change",
            m.velocity
        );
        control_worst = control_worst.max(c.pressure.max(c.velocity));
    }
    let first = first_residual.expect("iterations ran");
    assert!(
        last_residual < 0.5 * first,
        "{label}: the solve converges ({first:.2e} -> {last_residual:.2e})"
    );
    assert_eq!(shim.state.held, WINDOW, "{label}: the window fills");
    assert!(
        control_worst > 100.0 * TOLERANCE,
        "{label}: without the mixing the kernels miss the CPU by only {control_worst:.2e}"
    );
}

#[test]
fn velocity_solve_iterations_match_the_cpu_backend_2d() {
    check_iterations::<2>(0x3333_cccc_5678_1234, false);
}

#[test]
fn velocity_solve_iterations_match_the_cpu_backend_3d() {
    check_iterations::<3>(0x9999_4444_aaaa_bbbb, false);
}

#[test]
fn velocity_solve_iterations_match_the_cpu_backend_with_two_phases_2d() {
    check_iterations::<2>(0x5a5a_1234_c3c3_8765, true);
}
