//! The force, integration and correction kernels of `kernels/` (`forces.cu`, `solid_forces.cu`,
//! `state_extremes.cu`, `integrate.cu`, `correction.cu`, `keep_out.cu`, `move_solids.cu`) and the
//! velocity solve's (`predicted_density` of `density.cu`, `keep_pressure_decreases` of
//! `correction.cu`; its iteration, `kernels/anderson.cu`, is in `tests/cuda_shim_anderson.rs`),
//! run on the CPU through the host shim (`backend::cuda::shim`), against the rayon stage each mirrors, per particle `id`, in 2D and
//! 3D. These run everywhere, GPU or not.
//!
//! Tolerances. A kernel evaluates every pair term with the same f32 operations as its CPU twin,
//! so the terms are bitwise equal; only the order of the neighbour sums differs (the dense grid
//! orders particles by (cell, id), the CPU's sparse grid by its own keys). Two orders of an f32
//! sum of N terms t_j differ by at most 2 (N - 1) u Σ|t_j| (u = 2^-24); a support of radius
//! h = 2 dx holds about 13 neighbours in 2D and 34 in 3D, so [`SUM_ORDER`] = 1e-5 of Σ|t_j| bounds
//! every case with room (N up to ~80) while a missing or wrong term, which moves the result by
//! one whole term, fails it. Per-particle arithmetic without sums is compared bitwise.
#![cfg(feature = "cuda")]

use sph::backend::cpu::CpuBackend;
use sph::backend::cuda::extremes::{self, DeviceExtremes};
use sph::backend::cuda::grid::GridGeometry;
use sph::backend::cuda::shim;
use sph::backend::params::StepParams;
use sph::backend::{Backend, ForceTerms, SolidForceSource};
use sph::boundary::keep_out::KeepOutBox;
use sph::boundary::motion::{SolidKinematics, SolidReference};
use sph::boundary::solid_force::force_on_solid;
use sph::fields::{FLUID, Fields};
use sph::math::Vector;
use sph::physics::artificial_viscosity::artificial_viscous_acceleration;
use sph::physics::correction::MOMENTUM;
use sph::physics::density::{
    DensityWeight, SURFACE_DENSITY_RATIO, density_kernel_gradient, velocity_solve_base,
};
use sph::physics::pressure::pressure_acceleration;
use sph::physics::rotating_frame::rotating_frame_acceleration;
use sph::physics::viscosity::viscous_acceleration;

/// Relative tolerance of a neighbour sum, against the sum of its terms' magnitudes (module doc).
const SUM_ORDER: f64 = 1.0e-5;

/// Lattice spacing [m]; the support is `h = 2 dx`.
const DX: f32 = 0.01;
/// Rest density [kg/m³].
const RHO0: f32 = 1000.0;
/// Number of named solids in the scene (floor = 1, left wall = 2).
const SOLIDS: usize = 2;

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

/// Fluid lattice size per axis.
fn fluid_counts<const D: usize>() -> [i32; 3] {
    if D == 2 { [24, 16, 1] } else { [10, 8, 8] }
}

/// A jittered fluid block on a floor (solid 1, two layers) beside a left wall (solid 2, two
/// layers), each wall moving rigidly: random fluid velocities, densities within 1 % of ρ0, pressures up to 2 kPa (a quarter of
/// the fluid at zero, for the residual's two branches). Strong viscosity and artificial viscosity,
/// gravity and a gradient scale ≠ 1, so that every term is visible above the tolerance.
fn scene<const D: usize>(seed: u64) -> (Fields<D>, StepParams<D>) {
    let mut rng = Rng(seed);
    let n = fluid_counts::<D>();
    let lo = [-2, -2, 0];
    let mut f = Fields::<D>::default();
    let mass = RHO0 * DX.powi(D as i32);
    let total: i32 = (0..D).map(|k| n[k] - lo[k]).product();
    for c in 0..total {
        let mut idx = [0i32; 3];
        let mut rest = c;
        for k in 0..D {
            let extent = n[k] - lo[k];
            idx[k] = lo[k] + rest % extent;
            rest /= extent;
        }
        let kind = if idx[1] < 0 {
            1
        } else if idx[0] < 0 {
            2
        } else {
            FLUID
        };
        let mut x = Vector::<D>::zeros();
        let mut u = Vector::<D>::zeros();
        for k in 0..D {
            x[k] = (idx[k] as f32 + 0.5) * DX;
            if kind == FLUID {
                x[k] += rng.sym(0.15 * DX);
                u[k] = rng.sym(1.0);
            } else {
                // Moving walls: one rigid velocity per solid, so the viscous terms of the forces
                // and of the force on solids see the wall's velocity (`boundary::motion`).
                u[k] = [0.4, -0.25, 0.1][k] * if kind == 1 { 1.0 } else { -0.7 };
            }
        }
        let rho = RHO0 * (1.0 + rng.sym(0.01));
        f.push(x, u, mass, rho, kind);
        let p = if kind == FLUID && rng.next() < 0.25 {
            0.0
        } else {
            2000.0 * rng.next()
        };
        *f.pressure.last_mut().expect("just pushed") = p;
    }
    // No-slip walls ([A12] eqs. 22-23): each solid particle's viscous velocity, random (the
    // wall_velocity stage's own output is checked in tests/cuda_shim.rs), so (17) on both sides
    // must read it rather than the wall's velocity.
    f.wall_velocity = (0..f.len())
        .map(|_| Vector::from_fn(|_, _| rng.sym(1.0)))
        .collect();
    let mut gravity = Vector::<D>::zeros();
    gravity[1] = -9.81;
    let mut domain_min = Vector::<D>::zeros();
    let mut domain_max = Vector::<D>::zeros();
    for k in 0..D {
        domain_min[k] = (lo[k] as f32 - 1.0) * DX;
        domain_max[k] = (n[k] as f32 + 6.0) * DX;
    }
    let p = StepParams {
        h: 2.0 * DX,
        rho0: RHO0,
        c2: 40.0 * 40.0,
        mu: 1.0,
        alpha: 0.3,
        c: 40.0,
        pressure_gradient_scale: 1.05,
        gravity,
        domain_min,
        domain_max,
        // Off every axis, so that both the in-plane and the out-of-plane part act in 2D.
        angular_velocity: [1.5, -2.0, 7.0],
        rotation_centre: Vector::from_fn(|k, _| 0.02 * (k as f32 + 1.0)),
        viscosity_scale: 1.17,
        surface_tension_gamma: 0.0,
        surface_tension_sigma: 0.0,
        spacing: 0.0,
        density_spiky_scale: 0.0,
        density_kernel: sph::physics::density::DensityKernel::Poly6,
        surface_tension_model: sph::backend::SurfaceTensionModel::SurfaceStress,
        rotating_frame: 1,
        phases: sph::physics::multiphase::Phases::Single,
    };
    (f, p)
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

/// The device's copy of a particle set: fields sorted by (cell, id) in flat arrays, and the
/// dense grid's `cell_start` (ncell + 1 entries) and `cell_key`, as `sort_by_cell` leaves them.
struct Device<const D: usize> {
    g: GridGeometry<D>,
    cell_start: Vec<u32>,
    cell_key: Vec<u32>,
    pos: Vec<f32>,
    vel: Vec<f32>,
    /// `Fields::wall_velocity` ([A12] no-slip walls).
    wall_vel: Vec<f32>,
    acc: Vec<f32>,
    density: Vec<f32>,
    pressure: Vec<f32>,
    mass: Vec<f32>,
    kind: Vec<u32>,
    id: Vec<u32>,
}

impl<const D: usize> Device<D> {
    fn new(f: &Fields<D>, p: &StepParams<D>) -> Self {
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
        let vectors = |v: &[Vector<D>]| order.iter().flat_map(|&i| v[i].iter().copied()).collect();
        Self {
            g,
            cell_start,
            cell_key: order.iter().map(|&i| keys[i]).collect(),
            pos: vectors(&f.position),
            vel: vectors(&f.velocity),
            // Without no-slip walls the backend passes the velocities (a solid carries its own).
            wall_vel: vectors(if f.wall_velocity.is_empty() {
                &f.velocity
            } else {
                &f.wall_velocity
            }),
            acc: vectors(&f.acceleration),
            density: order.iter().map(|&i| f.density[i]).collect(),
            pressure: order.iter().map(|&i| f.pressure[i]).collect(),
            mass: order.iter().map(|&i| f.mass[i]).collect(),
            kind: order.iter().map(|&i| f.kind[i]).collect(),
            id: order.iter().map(|&i| f.id[i]).collect(),
        }
    }

    fn n(&self) -> u32 {
        self.kind.len() as u32
    }

    /// Index of each id.
    fn index_of_id(&self) -> Vec<usize> {
        index_of_id(&self.id)
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

/// A pointer to `x` as the shim's type for this dimension (the same `#[repr(C)]` struct).
fn ptr<T, U>(x: &T) -> *const U {
    (x as *const T).cast()
}

/// Calls the 2D or the 3D launcher.
macro_rules! launch {
    ($d:expr, $two:ident, $three:ident, $($arg:expr),* $(,)?) => {
        // SAFETY: every buffer holds n items (D floats each for vectors), `cell_start` holds
        // ncell + 1 entries, and the structs are the launcher's own type for this dimension.
        unsafe {
            match $d {
                2 => shim::$two($($arg),*),
                3 => shim::$three($($arg),*),
                d => unreachable!("dimension {d}"),
            }
        }
    };
}

/// `|x|` of a vector as f64.
fn norm<const D: usize>(v: &Vector<D>) -> f64 {
    f64::from(v.norm())
}

/// The particles `j` of `f` within `h` of particle `i` (brute force, `j != i`), with
/// `x_i − x_j` and its length.
fn neighbours<const D: usize>(f: &Fields<D>, h: f32, i: usize) -> Vec<(usize, Vector<D>, f32)> {
    (0..f.len())
        .filter(|&j| j != i)
        .filter_map(|j| {
            let d = f.position[i] - f.position[j];
            let r2 = d.norm_squared();
            (r2 < h * h).then(|| (j, d, r2.sqrt()))
        })
        .collect()
}

/// Σ over the neighbour terms of fluid particle `i` (and gravity) of their magnitudes: the scale
/// of the force stage's rounding. `f` in id order.
fn force_scale<const D: usize>(f: &Fields<D>, p: &StepParams<D>, terms: ForceTerms, i: usize) -> f64 {
    let s = p.smoothing();
    let (p_i, rho_i, u_i) = (f.pressure[i], f.density[i], f.velocity[i]);
    let mut sum = norm(&p.gravity);
    if terms.rotating_frame {
        sum += norm(&rotating_frame_acceleration(
            &p.angular_velocity,
            &p.rotation_centre,
            &f.position[i],
            &u_i,
        ));
    }
    for (j, d, r) in neighbours(f, p.h, i) {
        let grad = s.grad_w_spiky(&d, r) * p.pressure_gradient_scale;
        let (m_j, rho_j) = (f.mass[j], f.density[j]);
        sum += norm(&pressure_acceleration(
            p_i,
            rho_i,
            f.pressure[j],
            rho_j,
            m_j,
            &grad,
        ));
        if terms.artificial_viscosity {
            let u_ij = u_i - f.velocity[j];
            sum += norm(&artificial_viscous_acceleration(
                p.alpha, p.c, p.h, &d, &u_ij, rho_i, rho_j, m_j, &grad,
            ));
        }
        if terms.viscosity {
            let lap = s.laplacian_w_viscosity(r);
            let u_j = if f.kind[j] == FLUID {
                f.velocity[j]
            } else {
                f.wall_velocity[j]
            };
            sum += norm(&viscous_acceleration(
                p.mu * p.viscosity_scale,
                &u_i,
                &u_j,
                rho_i,
                rho_j,
                m_j,
                lap,
            ));
        }
    }
    sum
}

/// Runs one force variant on the shim; the accelerations by id.
fn forces_on_shim<const D: usize>(
    dev: &mut Device<D>,
    p: &StepParams<D>,
    terms: ForceTerms,
) -> Vec<Vector<D>> {
    macro_rules! variant {
        ($two:ident, $three:ident) => {
            launch!(
                D,
                $two,
                $three,
                dev.n(),
                ptr(p),
                ptr(&dev.g),
                dev.cell_start.as_ptr(),
                dev.cell_key.as_ptr(),
                dev.pos.as_ptr(),
                dev.vel.as_ptr(),
                dev.mass.as_ptr(),
                dev.density.as_ptr(),
                dev.pressure.as_ptr(),
                dev.kind.as_ptr(),
                dev.wall_vel.as_ptr(),
                dev.acc.as_mut_ptr(),
            )
        };
    }
    match (terms.viscosity, terms.artificial_viscosity, terms.rotating_frame) {
        (false, false, false) => variant!(sph_shim_forces_p_2, sph_shim_forces_p_3),
        (true, false, false) => variant!(sph_shim_forces_pv_2, sph_shim_forces_pv_3),
        (false, true, false) => variant!(sph_shim_forces_pa_2, sph_shim_forces_pa_3),
        (true, true, false) => variant!(sph_shim_forces_pva_2, sph_shim_forces_pva_3),
        (false, false, true) => variant!(sph_shim_forces_pr_2, sph_shim_forces_pr_3),
        (true, false, true) => variant!(sph_shim_forces_pvr_2, sph_shim_forces_pvr_3),
        (false, true, true) => variant!(sph_shim_forces_par_2, sph_shim_forces_par_3),
        (true, true, true) => variant!(sph_shim_forces_pvar_2, sph_shim_forces_pvar_3),
    }
    let at = dev.index_of_id();
    (0..at.len())
        .map(|id| Vector::from_fn(|k, _| dev.acc[at[id] * D + k]))
        .collect()
}

/// The CPU stage's accelerations by id.
fn forces_on_cpu<const D: usize>(f: &Fields<D>, p: &StepParams<D>, terms: ForceTerms) -> Vec<Vector<D>> {
    let mut cf = f.clone();
    let mut cpu = CpuBackend::<D>::new();
    cpu.sort_by_cell(&mut cf, p.h).expect("finite positions");
    cpu.forces(&mut cf, p, terms);
    let at = index_of_id(&cf.id);
    (0..at.len()).map(|id| cf.acceleration[at[id]]).collect()
}

/// Every term set, in `ForceTerms::index` order.
const ALL_TERMS: [ForceTerms; 8] = {
    let mut all = [ForceTerms {
        viscosity: false,
        artificial_viscosity: false,
        rotating_frame: false,
    }; 8];
    let mut k = 0;
    while k < 8 {
        all[k] = ForceTerms {
            viscosity: k & 1 != 0,
            artificial_viscosity: k & 2 != 0,
            rotating_frame: k & 4 != 0,
        };
        k += 1;
    }
    all
};

fn check_forces<const D: usize>(seed: u64) {
    let (f, p) = scene::<D>(seed);
    let mut dev = Device::new(&f, &p);
    let pressure_only = forces_on_cpu(&f, &p, ALL_TERMS[0]);
    for terms in ALL_TERMS {
        let cpu = forces_on_cpu(&f, &p, terms);
        let shim = forces_on_shim(&mut dev, &p, terms);
        let mut worst = 0.0f64;
        let mut term_effect = 0.0f64;
        for id in 0..f.len() {
            if f.kind[id] != FLUID {
                assert_eq!(shim[id], Vector::<D>::zeros(), "solid {id} gets no acceleration");
                continue;
            }
            let scale = force_scale(&f, &p, terms, id);
            for k in 0..D {
                let diff = f64::from(shim[id][k] - cpu[id][k]).abs();
                assert!(
                    diff <= SUM_ORDER * scale,
                    "{D}D {terms:?}: particle {id} axis {k}: shim {} cpu {} (scale {scale})",
                    shim[id][k],
                    cpu[id][k]
                );
                worst = worst.max(diff / scale);
                term_effect = term_effect.max(f64::from(cpu[id][k] - pressure_only[id][k]).abs() / scale);
            }
        }
        eprintln!("{D}D forces {terms:?}: largest |shim - cpu| / Σ|terms| = {worst:.2e}");
        if terms.viscosity || terms.artificial_viscosity || terms.rotating_frame {
            assert!(
                term_effect > 100.0 * SUM_ORDER,
                "{terms:?} must be visible: {term_effect:.2e}"
            );
        }
    }
}

#[test]
fn forces_match_the_cpu_stage_for_every_term_set_2d() {
    check_forces::<2>(0x9e37_79b9_7f4a_7c15);
}

#[test]
fn forces_match_the_cpu_stage_for_every_term_set_3d() {
    check_forces::<3>(0x2545_f491_4f6c_dd1d);
}

/// Runs the three correction-pressure kernels (one sweep): the increments are left in `delta_p`
/// and copied to `delta_p_prev`, the pressures updated in `dev`.
fn correction_pressure_on_shim<const D: usize>(
    dev: &mut Device<D>,
    p: &StepParams<D>,
    k: f32,
    has_prev: bool,
    delta_p: &mut [f32],
    delta_p_prev: &mut [f32],
) {
    let n = dev.n();
    launch!(
        D,
        sph_shim_correction_pressure_fluid_2,
        sph_shim_correction_pressure_fluid_3,
        n,
        p.rho0,
        k,
        MOMENTUM,
        i32::from(has_prev),
        dev.density.as_ptr(),
        dev.pressure.as_ptr(),
        dev.kind.as_ptr(),
        delta_p_prev.as_ptr(),
        delta_p.as_mut_ptr(),
    );
    launch!(
        D,
        sph_shim_correction_pressure_wall_2,
        sph_shim_correction_pressure_wall_3,
        n,
        ptr(p),
        ptr(&dev.g),
        dev.cell_start.as_ptr(),
        dev.cell_key.as_ptr(),
        dev.pos.as_ptr(),
        dev.density.as_ptr(),
        dev.pressure.as_ptr(),
        dev.kind.as_ptr(),
        delta_p.as_mut_ptr(),
    );
    launch!(
        D,
        sph_shim_correction_pressure_apply_2,
        sph_shim_correction_pressure_apply_3,
        n,
        delta_p.as_ptr(),
        dev.pressure.as_mut_ptr(),
        delta_p_prev.as_mut_ptr(),
    );
}

/// Stiffness of the correction's eq. (19) in the tests [m²/s²].
const STIFFNESS: f32 = 900.0;

/// Two correction sweeps (the second with heavy-ball momentum) on both sides: fluid pressures
/// are per-particle arithmetic and must be bitwise equal; a solid's is a weighted mean of its
/// fluid neighbours' increments, within [`SUM_ORDER`] of the mean of their magnitudes (plus its
/// pressure before, whose addition rounds alike).
fn check_correction_pressure<const D: usize>(seed: u64) {
    let (f, p) = scene::<D>(seed);
    let mut dev = Device::new(&f, &p);
    let mut cf = f.clone();
    let mut cpu = CpuBackend::<D>::new();
    cpu.sort_by_cell(&mut cf, p.h).expect("finite positions");
    cpu.begin_correction(&mut cf);
    let n = f.len();
    // Stale increments (as a device buffer holds after a re-sort): the first sweep must ignore
    // them, the second must use its predecessor's.
    let (mut delta_p, mut delta_p_prev) = (vec![0.0f32; n], vec![123.0f32; n]);
    let kernel = p.smoothing();
    // Each sweep adds its rounding to the solids' accumulated pressure: scales add up.
    let mut scale_so_far = vec![0.0f64; n];
    for sweep in 0..2 {
        let before: Vec<f32> = dev.pressure.clone();
        cpu.correction_pressure(&mut cf, &p, STIFFNESS);
        correction_pressure_on_shim(
            &mut dev,
            &p,
            STIFFNESS,
            sweep > 0,
            &mut delta_p,
            &mut delta_p_prev,
        );
        assert_eq!(delta_p, delta_p_prev, "the sweep's increments are remembered");
        let cpu_at = index_of_id(&cf.id);
        let dev_at = dev.index_of_id();
        // Device state in id order, for the solids' scales.
        let dp_by_id: Vec<f32> = (0..n).map(|id| delta_p[dev_at[id]]).collect();
        let (mut worst, mut changed) = (0.0f64, 0usize);
        for id in 0..n {
            let (shim, cpu_p) = (dev.pressure[dev_at[id]], cf.pressure[cpu_at[id]]);
            if f.kind[id] == FLUID {
                assert_eq!(
                    shim.to_bits(),
                    cpu_p.to_bits(),
                    "{D}D sweep {sweep}: fluid {id}: {shim} vs {cpu_p}"
                );
                changed += usize::from(shim != before[dev_at[id]]);
                continue;
            }
            let (mut weighted, mut weight) = (0.0f64, 0.0f64);
            for (j, _, r) in neighbours(&f, p.h, id) {
                if f.kind[j] == FLUID {
                    let w = f64::from(kernel.w(r * r));
                    weighted += f64::from(dp_by_id[j]).abs() * w;
                    weight += w;
                }
            }
            scale_so_far[id] +=
                f64::from(before[dev_at[id]]).abs() + if weight > 0.0 { weighted / weight } else { 0.0 };
            let scale = scale_so_far[id];
            let diff = f64::from(shim - cpu_p).abs();
            assert!(
                diff <= SUM_ORDER * scale + f64::from(f32::MIN_POSITIVE),
                "{D}D sweep {sweep}: solid {id}: shim {shim} cpu {cpu_p} (scale {scale})"
            );
            if scale > 0.0 {
                worst = worst.max(diff / scale);
            }
        }
        eprintln!(
            "{D}D correction_pressure sweep {sweep}: solids' largest |shim - cpu| / scale = {worst:.2e}"
        );
        assert!(
            changed > n / 4,
            "the sweep changes most fluid pressures ({changed})"
        );
    }
}

#[test]
fn correction_pressure_matches_the_cpu_stage_with_and_without_momentum_2d() {
    check_correction_pressure::<2>(0x1234_5678_9abc_def1);
}

#[test]
fn correction_pressure_matches_the_cpu_stage_with_and_without_momentum_3d() {
    check_correction_pressure::<3>(0x0fed_cba9_8765_4321);
}

/// One sweep's pressures on both sides, then `correction_displacement` + `apply_displacement`
/// against `correct_positions`, with `max_step` a quarter of the largest displacement so that
/// the scaling is exercised. Positions and velocities by id within [`SUM_ORDER`] of the
/// displacement's term sum (plus one f32 rounding of the value it is added to).
fn check_correct_positions<const D: usize>(seed: u64) {
    let (f, p) = scene::<D>(seed);
    let mut dev = Device::new(&f, &p);
    let mut cf = f.clone();
    let mut cpu = CpuBackend::<D>::new();
    cpu.sort_by_cell(&mut cf, p.h).expect("finite positions");
    cpu.begin_correction(&mut cf);
    cpu.correction_pressure(&mut cf, &p, STIFFNESS);
    let n = f.len();
    let (mut delta_p, mut delta_p_prev) = (vec![0.0f32; n], vec![0.0f32; n]);
    correction_pressure_on_shim(&mut dev, &p, STIFFNESS, false, &mut delta_p, &mut delta_p_prev);

    let tau = 2.0e-3f32;
    let mut displacement = vec![f32::NAN; n * D];
    let mut largest = 0i32;
    launch!(
        D,
        sph_shim_correction_displacement_2,
        sph_shim_correction_displacement_3,
        dev.n(),
        ptr(&p),
        ptr(&dev.g),
        dev.cell_start.as_ptr(),
        dev.cell_key.as_ptr(),
        dev.pos.as_ptr(),
        dev.mass.as_ptr(),
        dev.density.as_ptr(),
        delta_p.as_ptr(),
        dev.kind.as_ptr(),
        tau * tau,
        displacement.as_mut_ptr(),
        &mut largest,
    );
    let unscaled = extremes::max_from_bits(largest);
    let max_step = (0.25 * unscaled) as f32;
    let sweep = extremes::sweep(largest, max_step);
    let cpu_sweep = cpu.correct_positions(&mut cf, &p, tau, tau, max_step);
    assert!(sweep.scale < 0.3, "the scaling is exercised: {sweep:?}");
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    assert!(
        rel(sweep.scale, cpu_sweep.scale) <= SUM_ORDER,
        "{sweep:?} vs {cpu_sweep:?}"
    );
    assert!(
        rel(sweep.largest, cpu_sweep.largest) <= SUM_ORDER,
        "{sweep:?} vs {cpu_sweep:?}"
    );
    let (pos_before, vel_before) = (dev.pos.clone(), dev.vel.clone());
    launch!(
        D,
        sph_shim_apply_displacement_2,
        sph_shim_apply_displacement_3,
        dev.n(),
        sweep.scale as f32,
        tau,
        dev.kind.as_ptr(),
        displacement.as_ptr(),
        dev.pos.as_mut_ptr(),
        dev.vel.as_mut_ptr(),
    );

    let cpu_at = index_of_id(&cf.id);
    let dev_at = dev.index_of_id();
    let dp_by_id: Vec<f32> = (0..n).map(|id| delta_p[dev_at[id]]).collect();
    let kernel = p.smoothing();
    let eps = f64::from(f32::EPSILON);
    let (mut worst, mut moved) = (0.0f64, 0usize);
    for id in 0..n {
        let (i, c) = (dev_at[id], cpu_at[id]);
        if f.kind[id] != FLUID {
            for k in 0..D {
                assert_eq!(displacement[i * D + k], 0.0, "solids do not move");
                assert_eq!(dev.pos[i * D + k], pos_before[i * D + k]);
            }
            continue;
        }
        // Σ|terms| of Δx = τ² a^press(δp), times the scale.
        let mut terms = 0.0f64;
        for (j, d, r) in neighbours(&f, p.h, id) {
            let grad = kernel.grad_w_spiky(&d, r) * p.pressure_gradient_scale;
            let a = pressure_acceleration(
                dp_by_id[id],
                f.density[id],
                dp_by_id[j],
                f.density[j],
                f.mass[j],
                &grad,
            );
            terms += norm(&a);
        }
        // Once for the sum order of Δx, once for the scale, which inherits the largest |Δx|'s.
        let dx_tol = 2.0 * SUM_ORDER * f64::from(tau * tau) * terms * sweep.scale;
        for k in 0..D {
            let (x, x_cpu) = (f64::from(dev.pos[i * D + k]), f64::from(cf.position[c][k]));
            let (u, u_cpu) = (f64::from(dev.vel[i * D + k]), f64::from(cf.velocity[c][k]));
            assert!(
                (x - x_cpu).abs() <= dx_tol + eps * x_cpu.abs(),
                "{D}D: particle {id} axis {k}: x {x} vs {x_cpu} (tol {dx_tol})"
            );
            let du_tol = dx_tol / f64::from(tau) + eps * u_cpu.abs();
            assert!(
                (u - u_cpu).abs() <= du_tol,
                "{D}D: particle {id} axis {k}: u {u} vs {u_cpu} (tol {du_tol})"
            );
            if dx_tol > 0.0 {
                worst = worst.max((u - u_cpu).abs() * f64::from(tau) / (dx_tol / (2.0 * SUM_ORDER)));
            }
            moved += usize::from(dev.vel[i * D + k] != vel_before[i * D + k]);
        }
    }
    eprintln!(
        "{D}D correct_positions: scale {:.4} vs {:.4}; largest |Δu τ| / Σ|Δx terms| = {worst:.2e}",
        sweep.scale, cpu_sweep.scale
    );
    assert!(moved > n / 2, "most fluid particles move ({moved})");
}

#[test]
fn correct_positions_matches_the_cpu_stage_with_scaling_2d() {
    check_correct_positions::<2>(0x5555_aaaa_1234_9876);
}

#[test]
fn correct_positions_matches_the_cpu_stage_with_scaling_3d() {
    check_correct_positions::<3>(0x7777_1111_2222_3333);
}

/// `predicted_density` against `CpuBackend::predicted_density` for the poly6 density (`wcsph`)
/// and the scaled spiky one (`corrected`): fluid within [`SUM_ORDER`] of `τ Σ|m_j (u_i − u_j)·∇W_ρ|`
/// (the neighbour sum's order) plus one f32 rounding of the result (the addition to ρ0); solids
/// untouched, bitwise. Solids move with their own (rigid) velocities in the scene, so the walls'
/// terms are in the sums; masses vary by ±20 % so that `m_j` cannot pass for `m_i`. The starting
/// densities spread over `(0.98 ± 0.03) ρ0`, so that both sides of the base rule
/// (`velocity_solve_base`: ρ0 inside, the own density at the free surface) are taken.
fn check_predicted_density<const D: usize>(seed: u64, weight: DensityWeight) {
    let (mut f, mut p) = scene::<D>(seed);
    p.density_kernel = weight.kernel;
    p.density_spiky_scale = weight.spiky_scale;
    let mut rng = Rng(seed ^ 0x600d);
    for m in f.mass.iter_mut() {
        *m *= 1.0 + rng.sym(0.2);
    }
    for rho in f.density.iter_mut() {
        *rho = p.rho0 * (SURFACE_DENSITY_RATIO + rng.sym(0.03));
    }
    let surface = (0..f.len())
        .filter(|&i| f.kind[i] == FLUID && f.density[i] < SURFACE_DENSITY_RATIO * p.rho0)
        .count();
    let fluid = (0..f.len()).filter(|&i| f.kind[i] == FLUID).count();
    assert!(
        surface > 0 && surface < fluid,
        "{surface} of {fluid} below the ratio"
    );
    let mut dev = Device::new(&f, &p);
    let mut cf = f.clone();
    let mut cpu = CpuBackend::<D>::new();
    cpu.sort_by_cell(&mut cf, p.h).expect("finite positions");
    // About 1 % of ρ0 from the random velocities (|u| < 1 m/s over dx = 1 cm).
    let tau = 1.0e-4f32;
    cpu.begin_velocity_solve(&mut cf);
    cpu.predicted_density(&mut cf, &p, tau);
    let density_before = dev.density.clone();
    launch!(
        D,
        sph_shim_predicted_density_2,
        sph_shim_predicted_density_3,
        dev.n(),
        ptr(&p),
        ptr(&dev.g),
        dev.cell_start.as_ptr(),
        dev.cell_key.as_ptr(),
        dev.pos.as_ptr(),
        dev.vel.as_ptr(),
        dev.mass.as_ptr(),
        dev.kind.as_ptr(),
        density_before.as_ptr(),
        tau,
        dev.density.as_mut_ptr(),
    );
    let cpu_at = index_of_id(&cf.id);
    let dev_at = dev.index_of_id();
    let kernel = p.smoothing();
    let eps = f64::from(f32::EPSILON);
    let (mut worst, mut largest_change) = (0.0f64, 0.0f64);
    for id in 0..f.len() {
        let (shim, cpu_rho) = (dev.density[dev_at[id]], cf.density[cpu_at[id]]);
        if f.kind[id] != FLUID {
            assert_eq!(
                shim.to_bits(),
                density_before[dev_at[id]].to_bits(),
                "solid {id} untouched"
            );
            assert_eq!(cpu_rho.to_bits(), f.density[id].to_bits());
            continue;
        }
        let mut terms = 0.0f64;
        for (j, d, r) in neighbours(&f, p.h, id) {
            let grad = density_kernel_gradient(&kernel, weight, &d, r);
            terms += f64::from(f.mass[j] * (f.velocity[id] - f.velocity[j]).dot(&grad)).abs();
        }
        let scale = f64::from(tau) * terms;
        // The base rule itself, bitwise: the rate term is small against the base's distance.
        let base = velocity_solve_base(f.density[id], p.rho0);
        assert!(
            f64::from(cpu_rho - base).abs() <= scale * 1.01 + eps * f64::from(base),
            "{D}D: fluid {id}: cpu {cpu_rho} from base {base} (rate bound {scale})"
        );
        let diff = f64::from(shim - cpu_rho).abs();
        assert!(
            diff <= SUM_ORDER * scale + eps * f64::from(cpu_rho).abs(),
            "{D}D, {weight:?}: fluid {id}: shim {shim} cpu {cpu_rho} (scale {scale})"
        );
        worst = worst.max(diff);
        largest_change = largest_change.max(f64::from(cpu_rho - p.rho0).abs());
    }
    eprintln!(
        "{D}D predicted_density, {weight:?}: largest |shim - cpu| = {worst:.2e} kg/m³ \
         (f32 spacing at ρ0: {:.1e}), largest |ρ* − ρ0| = {largest_change:.3} kg/m³",
        f32::from_bits(p.rho0.to_bits() + 1) - p.rho0
    );
    // A missing or wrong term moves ρ* by a whole term; the velocities must be visible at all.
    assert!(
        largest_change > 1.0,
        "the velocities change the density: {largest_change}"
    );
}

#[test]
fn predicted_density_matches_the_cpu_stage_for_both_density_kernels_2d() {
    for weight in [DensityWeight::POLY6, DensityWeight::spiky(0.82)] {
        check_predicted_density::<2>(0x2468_ace0_1357_9bdf, weight);
    }
}

#[test]
fn predicted_density_matches_the_cpu_stage_for_both_density_kernels_3d() {
    for weight in [DensityWeight::POLY6, DensityWeight::spiky(0.82)] {
        check_predicted_density::<3>(0x1357_9bdf_2468_ace0, weight);
    }
}

/// `end_velocity_solve`: kept, `keep_pressure_decreases` against the CPU, per-particle
/// `min(p, p_start)`, bitwise (a NaN pressure takes the start's, as `f32::min`), velocities
/// untouched; discarded, the CPU's velocities and pressures are the start's again, bitwise (on
/// the device that path is two device-to-device copies, no kernel).
fn check_end_velocity_solve<const D: usize>(seed: u64) {
    let (f, p) = scene::<D>(seed);
    let mut rng = Rng(seed ^ 0x5a5a);
    let mut dev = Device::new(&f, &p);
    let n = f.len();
    // What the solve did: every pressure moved up or down by up to 1 kPa (kept >= 0 as the
    // correction keeps it), one fluid pressure NaN; random velocity changes.
    let mut pressure = f.pressure.clone();
    let mut velocity = f.velocity.clone();
    for id in 0..n {
        pressure[id] = (pressure[id] + rng.sym(1000.0)).max(0.0);
        velocity[id] += Vector::<D>::from_fn(|_, _| rng.sym(0.5));
    }
    let nan_id = (0..n).find(|&id| f.kind[id] == FLUID).expect("fluid");
    pressure[nan_id] = f32::NAN;
    for keep in [true, false] {
        let mut cf = f.clone();
        let mut cpu = CpuBackend::<D>::new();
        cpu.sort_by_cell(&mut cf, p.h).expect("finite positions");
        let start = cf.clone();
        cpu.begin_velocity_solve(&mut cf);
        for c in 0..n {
            let id = cf.id[c] as usize;
            cf.pressure[c] = pressure[id];
            cf.velocity[c] = velocity[id];
        }
        cpu.end_velocity_solve(&mut cf, keep);
        if !keep {
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(&cf.pressure),
                bits(&start.pressure),
                "{D}D: pressures restored"
            );
            assert_eq!(cf.velocity, start.velocity, "{D}D: velocities restored");
            continue;
        }
        let pressure_start = dev.pressure.clone();
        for (i, &id) in dev.id.iter().enumerate() {
            dev.pressure[i] = pressure[id as usize];
        }
        let vel_before = dev.vel.clone();
        launch!(
            D,
            sph_shim_keep_pressure_decreases_2,
            sph_shim_keep_pressure_decreases_3,
            dev.n(),
            pressure_start.as_ptr(),
            dev.pressure.as_mut_ptr(),
        );
        assert_eq!(dev.vel, vel_before, "the kernel changes no velocity");
        let cpu_at = index_of_id(&cf.id);
        let dev_at = dev.index_of_id();
        let mut lowered = 0usize;
        for id in 0..n {
            let (shim, cpu_p) = (dev.pressure[dev_at[id]], cf.pressure[cpu_at[id]]);
            assert_eq!(
                shim.to_bits(),
                cpu_p.to_bits(),
                "{D}D: particle {id}: {shim} vs {cpu_p}"
            );
            assert!(!shim.is_nan(), "{D}D: particle {id} keeps a number");
            lowered += usize::from(shim < f.pressure[id]);
        }
        assert!(lowered > n / 4, "{D}D: the solve released pressure ({lowered})");
    }
}

#[test]
fn end_velocity_solve_keeps_pressure_decreases_as_the_cpu_2d() {
    check_end_velocity_solve::<2>(0x0123_4567_89ab_cdef);
}

#[test]
fn end_velocity_solve_keeps_pressure_decreases_as_the_cpu_3d() {
    check_end_velocity_solve::<3>(0xfedc_ba98_7654_3210);
}

/// Solid forces of both sources (the force stage's pressures and viscosities; the correction's
/// increments with μ = α = 0): per solid, within [`SUM_ORDER`] of Σ over its particles and their
/// fluid neighbours of |force_on_solid| (each particle's f32 sum is where orders differ; the f64
/// sums over particles add ~1e-16).
fn check_solid_forces<const D: usize>(seed: u64) {
    let (f, p) = scene::<D>(seed);
    let mut dev = Device::new(&f, &p);
    let mut cf = f.clone();
    let mut cpu = CpuBackend::<D>::new();
    cpu.sort_by_cell(&mut cf, p.h).expect("finite positions");
    let n = f.len();
    let kernel = p.smoothing();
    // The device's correction increments, and the CPU's, from the same sweep.
    cpu.begin_correction(&mut cf);
    let forces_cpu = cpu.solid_forces(&cf, &p, SOLIDS, SolidForceSource::Forces);
    cpu.correction_pressure(&mut cf, &p, STIFFNESS);
    let correction_cpu = cpu.solid_forces(&cf, &p, SOLIDS, SolidForceSource::Correction);
    let (mut delta_p, mut delta_p_prev) = (vec![0.0f32; n], vec![0.0f32; n]);
    let pressure_before = dev.pressure.clone();

    for source in [SolidForceSource::Forces, SolidForceSource::Correction] {
        let (params, pressure, cpu_result) = match source {
            SolidForceSource::Forces => (p, pressure_before.clone(), &forces_cpu),
            SolidForceSource::Correction => {
                correction_pressure_on_shim(&mut dev, &p, STIFFNESS, false, &mut delta_p, &mut delta_p_prev);
                let params = StepParams {
                    mu: 0.0,
                    alpha: 0.0,
                    ..p
                };
                (params, delta_p.clone(), &correction_cpu)
            }
        };
        let mut out = vec![0.0f64; 3 * SOLIDS];
        launch!(
            D,
            sph_shim_solid_forces_2,
            sph_shim_solid_forces_3,
            dev.n(),
            ptr(&params),
            ptr(&dev.g),
            dev.cell_start.as_ptr(),
            dev.cell_key.as_ptr(),
            dev.pos.as_ptr(),
            dev.vel.as_ptr(),
            dev.mass.as_ptr(),
            dev.density.as_ptr(),
            pressure.as_ptr(),
            dev.kind.as_ptr(),
            dev.wall_vel.as_ptr(),
            out.as_mut_ptr(),
        );
        // Σ|terms| per solid, from the device's pressures in id order.
        let dev_at = dev.index_of_id();
        let pressure_by_id: Vec<f32> = (0..n).map(|id| pressure[dev_at[id]]).collect();
        let mut scale = [0.0f64; SOLIDS];
        for s in (0..n).filter(|&s| f.kind[s] != FLUID) {
            for (j, d, r) in neighbours(&f, p.h, s) {
                if f.kind[j] != FLUID {
                    continue;
                }
                let grad = kernel.grad_w_spiky(&d, r) * p.pressure_gradient_scale;
                scale[f.kind[s] as usize - 1] += norm(&force_on_solid(
                    &params,
                    [f.mass[s], pressure_by_id[s], f.density[s]],
                    [f.mass[j], pressure_by_id[j], f.density[j]],
                    &d,
                    [&f.velocity[s], &f.velocity[j]],
                    &f.wall_velocity[s],
                    &grad,
                    kernel.laplacian_w_viscosity(r),
                ));
            }
        }
        for solid in 0..SOLIDS {
            let shim = &out[3 * solid..3 * solid + 3];
            let cpu_f = cpu_result[solid];
            let mut worst = 0.0f64;
            for k in 0..3 {
                let diff = (shim[k] - cpu_f[k]).abs();
                assert!(
                    diff <= SUM_ORDER * scale[solid],
                    "{D}D {source:?}: solid {solid} axis {k}: shim {} cpu {} (scale {})",
                    shim[k],
                    cpu_f[k],
                    scale[solid]
                );
                worst = worst.max(diff / scale[solid]);
            }
            if D == 2 {
                assert_eq!(shim[2], 0.0, "z = 0 in 2D");
            }
            let magnitude = cpu_f.iter().map(|c| c * c).sum::<f64>().sqrt();
            assert!(
                magnitude > 1.0e-3 * scale[solid],
                "solid {solid} feels a net force"
            );
            eprintln!(
                "{D}D solid_forces {source:?} solid {solid}: |F| {magnitude:.4e}, largest |shim - cpu| / Σ|terms| = {worst:.2e}"
            );
        }
    }
}

#[test]
fn solid_forces_match_the_cpu_stage_for_both_sources_2d() {
    check_solid_forces::<2>(0xdead_beef_cafe_f00d);
}

#[test]
fn solid_forces_match_the_cpu_stage_for_both_sources_3d() {
    check_solid_forces::<3>(0x0bad_c0de_1357_9bdf);
}

/// Runs `state_extremes` over `f` as it is (the kernel has no neighbours, so any order works and
/// indices compare directly with the CPU's).
fn extremes_on_shim<const D: usize>(f: &Fields<D>, p: &StepParams<D>) -> DeviceExtremes {
    let mut out = DeviceExtremes::initial();
    let flat = |v: &[Vector<D>]| v.as_ptr().cast::<f32>();
    launch!(
        D,
        sph_shim_state_extremes_2,
        sph_shim_state_extremes_3,
        f.len() as u32,
        ptr(p),
        flat(&f.position),
        flat(&f.velocity),
        flat(&f.acceleration),
        f.density.as_ptr(),
        f.pressure.as_ptr(),
        f.kind.as_ptr(),
        &mut out,
    );
    out
}

/// The kernel's extremes against the CPU's: maxima bitwise (they are computed as on the CPU),
/// means to 1e-12 (f64 sums in another order), indices exactly.
fn compare_extremes<const D: usize>(
    f: &Fields<D>,
    p: &StepParams<D>,
    what: &str,
) -> (DeviceExtremes, Option<usize>) {
    let out = extremes_on_shim(f, p);
    let cpu = CpuBackend::<D>::new().state_extremes(f, p);
    let shim = out.finish(p.rho0);
    let bits = |x: f64| x.to_bits();
    assert_eq!(bits(shim.max_speed), bits(cpu.max_speed), "{what}: max speed");
    assert_eq!(
        bits(shim.max_acceleration),
        bits(cpu.max_acceleration),
        "{what}: max acceleration"
    );
    assert_eq!(
        bits(shim.max_abs_density_error),
        bits(cpu.max_abs_density_error),
        "{what}: max |e|"
    );
    assert_eq!(
        bits(shim.max_compression),
        bits(cpu.max_compression),
        "{what}: max compression"
    );
    assert_eq!(
        bits(shim.max_surface_deficit),
        bits(cpu.max_surface_deficit),
        "{what}: max surface deficit"
    );
    for (a, b, name) in [
        (
            shim.mean_abs_density_error,
            cpu.mean_abs_density_error,
            "mean |e|",
        ),
        (shim.mean_compression, cpu.mean_compression, "mean compression"),
    ] {
        assert!(
            a == b || (a.is_nan() && b.is_nan()) || (a - b).abs() <= 1.0e-12 * b.abs(),
            "{what}: {name}: {a} vs {b}"
        );
    }
    // The mean deficit is mean |e| - mean compression on both backends: the two sums' rounding
    // (f64, another order) is relative to mean |e|, not to the difference.
    let (a, b) = (shim.mean_surface_deficit, cpu.mean_surface_deficit);
    assert!(
        a == b || (a.is_nan() && b.is_nan()) || (a - b).abs() <= 1.0e-12 * cpu.mean_abs_density_error,
        "{what}: mean surface deficit: {a} vs {b}"
    );
    assert_eq!(shim.escaped, cpu.escaped, "{what}: escaped");
    assert_eq!(
        out.first_non_finite(),
        cpu.non_finite.map(|(i, _)| i),
        "{what}: non-finite"
    );
    assert_eq!(
        out.fluid_count as usize,
        f.kind.iter().filter(|&&k| k == FLUID).count()
    );
    (out, cpu.non_finite.map(|(i, _)| i))
}

fn check_state_extremes<const D: usize>(seed: u64) {
    let (mut f, p) = scene::<D>(seed);
    let mut rng = Rng(seed ^ 0xffff);
    for a in f.acceleration.iter_mut() {
        for k in 0..D {
            a[k] = rng.sym(50.0);
        }
    }
    let (out, _) = compare_extremes(&f, &p, "clean state");
    assert!(out.escaped == u32::MAX && out.non_finite == u32::MAX);

    let fluid: Vec<usize> = (0..f.len()).filter(|&i| f.kind[i] == FLUID).collect();
    let solid: Vec<usize> = (0..f.len()).filter(|&i| f.kind[i] != FLUID).collect();
    // Escaped: two fluid particles and one solid outside; the smallest fluid index counts.
    let mut escaped = f.clone();
    let (first, second) = (fluid[fluid.len() / 3], fluid[fluid.len() / 2]);
    escaped.position[second][0] = p.domain_max[0] + 0.5 * DX;
    escaped.position[first][D - 1] = p.domain_min[D - 1] - 0.5 * DX;
    escaped.position[solid[0]][0] = p.domain_min[0] - 1.0;
    let (out, _) = compare_extremes(&escaped, &p, "escaped");
    assert_eq!(out.escaped as usize, first);

    // A NaN pressure alone (on a solid) is not reported, as on the CPU, though the kernel saw it.
    let mut quiet = f.clone();
    quiet.pressure[solid[1]] = f32::NAN;
    let (out, reported) = compare_extremes(&quiet, &p, "NaN solid pressure");
    assert_eq!((out.non_finite as usize, reported), (solid[1], None));

    // A NaN velocity reports the first particle with any non-finite field: here an infinite
    // density at a smaller index than the NaN, and a NaN pressure further on.
    let mut broken = f.clone();
    let (a, b, c) = (
        fluid[fluid.len() / 4],
        fluid[fluid.len() / 2],
        fluid[3 * fluid.len() / 4],
    );
    broken.velocity[b][1] = f32::NAN;
    broken.density[a] = f32::INFINITY;
    broken.pressure[c] = f32::NAN;
    let (_, reported) = compare_extremes(&broken, &p, "NaN velocity");
    assert_eq!(reported, Some(a));

    // A negative density (ordered below every positive one) sets the largest error.
    let mut negative = f.clone();
    negative.density[fluid[7]] = -5.0;
    let (out, _) = compare_extremes(&negative, &p, "negative density");
    assert!(out.finish(p.rho0).max_abs_density_error > 1.0);

    // A NaN density: the CPU's largest density error is NaN, reported as 0 after `.max(0.0)`,
    // while the compression ignores it.
    let mut nan_density = f.clone();
    nan_density.density[fluid[5]] = -f32::NAN;
    let (_, reported) = compare_extremes(&nan_density, &p, "NaN density");
    assert_eq!(reported, Some(fluid[5]));
}

#[test]
fn device_extremes_mirror_the_kernel_struct_layout() {
    use std::mem::{offset_of, size_of};
    let rust = [
        size_of::<DeviceExtremes>(),
        offset_of!(DeviceExtremes, max_speed),
        offset_of!(DeviceExtremes, max_acceleration),
        offset_of!(DeviceExtremes, max_density),
        offset_of!(DeviceExtremes, min_density),
        offset_of!(DeviceExtremes, density_nan),
        offset_of!(DeviceExtremes, fluid_count),
        offset_of!(DeviceExtremes, non_finite),
        offset_of!(DeviceExtremes, escaped),
        offset_of!(DeviceExtremes, abs_error_sum),
        offset_of!(DeviceExtremes, compression_sum),
    ];
    for d in [2, 3] {
        let mut c = [0u32; 11];
        launch!(
            d,
            sph_shim_extremes_layout_2,
            sph_shim_extremes_layout_3,
            c.as_mut_ptr()
        );
        assert_eq!(c.map(|x| x as usize), rust, "{d}D");
    }
}

#[test]
fn state_extremes_match_the_cpu_stage_with_planted_faults_2d() {
    check_state_extremes::<2>(0x0123_4567_89ab_cdef);
}

#[test]
fn state_extremes_match_the_cpu_stage_with_planted_faults_3d() {
    check_state_extremes::<3>(0xfedc_ba98_7654_3210);
}

/// `correction_error`'s maxima are the CPU's f64 values rounded to f32 (rounding is monotone, so
/// the maximum of the rounded values is the rounded maximum); NaN gives 0 as on the CPU.
fn check_correction_error<const D: usize>(seed: u64) {
    let (mut f, p) = scene::<D>(seed);
    // One pressured particle expanded beyond every compression (±1 %), so that the residual's
    // |e| branch decides its maximum.
    let expanded = (0..f.len())
        .find(|&i| f.kind[i] == FLUID && f.pressure[i] > 0.0)
        .expect("one");
    f.density[expanded] = 0.97 * RHO0;
    for case in 0..2 {
        let mut out = [0i32; 2];
        launch!(
            D,
            sph_shim_correction_error_2,
            sph_shim_correction_error_3,
            f.len() as u32,
            p.rho0,
            f.density.as_ptr(),
            f.pressure.as_ptr(),
            f.kind.as_ptr(),
            out.as_mut_ptr(),
        );
        let cpu = CpuBackend::<D>::new().correction_error(&f, &p);
        let (compression, residual) = (extremes::max_from_bits(out[0]), extremes::max_from_bits(out[1]));
        assert_eq!(compression, f64::from(cpu.compression as f32), "case {case}");
        assert_eq!(residual, f64::from(cpu.residual as f32), "case {case}");
        assert!(compression > 0.0, "some fluid is compressed");
        if case == 0 {
            assert!(
                residual > compression,
                "the expansion of pressured particles counts"
            );
        } else {
            // The NaN wins the CPU's maximum, then `.max(0.0)` makes it 0; it must not be lost
            // to the compression's branch either.
            assert_eq!(residual, 0.0, "NaN residual reads 0, as on the CPU");
        }
        // Second case: a NaN density on a pressured particle.
        f.density[expanded] = f32::NAN;
    }
}

#[test]
fn correction_error_is_the_cpu_value_rounded_to_f32_2d() {
    check_correction_error::<2>(0x1111_2222_3333_4444);
}

#[test]
fn correction_error_is_the_cpu_value_rounded_to_f32_3d() {
    check_correction_error::<3>(0x5555_6666_7777_8888);
}

/// `integrate`, `store_step_start` and `rk_stage` are per-particle f32 arithmetic in the CPU's
/// order: bitwise equal.
fn check_integration<const D: usize>(seed: u64) {
    let (mut f, _) = scene::<D>(seed);
    let mut rng = Rng(seed ^ 0xabcd);
    for a in f.acceleration.iter_mut() {
        for k in 0..D {
            a[k] = rng.sym(30.0);
        }
    }
    let n = f.len() as u32;
    let flat = |v: &[Vector<D>]| -> Vec<f32> { v.iter().flat_map(|x| x.iter().copied()).collect() };
    let bits = |v: &[f32]| -> Vec<u32> { v.iter().map(|x| x.to_bits()).collect() };
    let mut cpu = CpuBackend::<D>::new();
    let mut cf = f.clone();
    let (mut pos, mut vel, acc) = (flat(&f.position), flat(&f.velocity), flat(&f.acceleration));
    let dt = 1.3e-3f32;

    cpu.integrate(&mut cf, dt);
    launch!(
        D,
        sph_shim_integrate_2,
        sph_shim_integrate_3,
        n,
        dt,
        f.kind.as_ptr(),
        acc.as_ptr(),
        vel.as_mut_ptr(),
        pos.as_mut_ptr()
    );
    assert_eq!(bits(&vel), bits(&flat(&cf.velocity)), "{D}D integrate: velocity");
    assert_eq!(bits(&pos), bits(&flat(&cf.position)), "{D}D integrate: position");
    assert_ne!(pos, flat(&f.position), "fluid moved");

    cpu.store_step_start(&mut cf);
    let (mut pos_start, mut vel_start) = (vec![0.0f32; pos.len()], vec![0.0f32; vel.len()]);
    launch!(
        D,
        sph_shim_store_step_start_2,
        sph_shim_store_step_start_3,
        n,
        pos.as_ptr(),
        vel.as_ptr(),
        pos_start.as_mut_ptr(),
        vel_start.as_mut_ptr(),
    );
    assert_eq!(bits(&pos_start), bits(&flat(&cf.position_start)));
    assert_eq!(bits(&vel_start), bits(&flat(&cf.velocity_start)));

    // Three SSP-RK3 stages (Shu–Osher coefficients), the state advancing in between.
    for (a, b) in [(0.0f32, 1.0f32), (0.75, 0.25), (1.0 / 3.0, 2.0 / 3.0)] {
        cpu.rk_stage(&mut cf, dt, a, b);
        launch!(
            D,
            sph_shim_rk_stage_2,
            sph_shim_rk_stage_3,
            n,
            dt,
            a,
            b,
            f.kind.as_ptr(),
            acc.as_ptr(),
            pos_start.as_ptr(),
            vel_start.as_ptr(),
            pos.as_mut_ptr(),
            vel.as_mut_ptr(),
        );
        assert_eq!(
            bits(&vel),
            bits(&flat(&cf.velocity)),
            "{D}D rk_stage ({a}, {b}): velocity"
        );
        assert_eq!(
            bits(&pos),
            bits(&flat(&cf.position)),
            "{D}D rk_stage ({a}, {b}): position"
        );
    }
    for i in (0..f.len()).filter(|&i| f.kind[i] != FLUID) {
        assert_eq!(cf.position[i], f.position[i], "solids stay");
        assert_eq!(&pos[i * D..(i + 1) * D], f.position[i].as_slice());
    }
}

#[test]
fn integration_kernels_equal_the_cpu_stages_bitwise_2d() {
    check_integration::<2>(0x2468_ace0_1357_9bdf);
}

#[test]
fn integration_kernels_equal_the_cpu_stages_bitwise_3d() {
    check_integration::<3>(0x1357_9bdf_2468_ace0);
}

/// `keep_out` is per-particle f32 comparisons and assignments in the CPU's order: positions and
/// velocities bitwise equal; the per-solid sums of `m Δu` (f64, in another order) to 1e-12.
/// The boxes: the floor and the left wall as one container's slabs (solid 0) cutting into the
/// fluid by a spacing, a moving plate (solid 1) in the middle of the block, so particles are
/// pushed out through every face and the velocity rule sees moving and fixed walls. With
/// `from_start`, every particle's step start lies up to 2 spacings away on each axis, so the
/// entry-face rule picks faces the nearest-face rule would not (asserted: the two results
/// differ), and some particles outside every box went through one (asserted: they are moved).
fn check_keep_out<const D: usize>(seed: u64, from_start: bool) -> Vec<Vector<D>> {
    let (mut f, _) = scene::<D>(seed);
    // Step starts off by a deterministic offset of up to 2 spacings per axis.
    f.position_start = (0..f.len())
        .map(|i| {
            let o = Vector::<D>::from_fn(|k, _| ((i * 7919 + k * 104_729) % 13) as f32 - 6.0);
            f.position[i] + o * (DX / 3.0)
        })
        .collect();
    let n_fluid = fluid_counts::<D>();
    let mut top = Vector::<D>::zeros();
    for k in 0..D {
        top[k] = n_fluid[k] as f32 * DX;
    }
    let mut boxes = KeepOutBox::<D>::container(Vector::<D>::repeat(DX), top, 2.0 * DX, true, 0);
    let mut plate = KeepOutBox::<D>::fixed(top * 0.4, top * 0.6, 1);
    plate.velocity[0] = 0.7;
    boxes.push(plate);
    let flat_boxes: Vec<f32> = boxes.iter().flat_map(KeepOutBox::kernel_floats).collect();
    let margin = 1e-5f32;
    let n = f.len() as u32;
    let flat = |v: &[Vector<D>]| -> Vec<f32> { v.iter().flat_map(|x| x.iter().copied()).collect() };
    let bits = |v: &[f32]| -> Vec<u32> { v.iter().map(|x| x.to_bits()).collect() };
    let mut cpu = CpuBackend::<D>::new();
    let mut cf = f.clone();
    let report = cpu.keep_out(&mut cf, &boxes, 2, margin, from_start);
    let start = flat(&f.position_start);
    let (mut pos, mut vel) = (flat(&f.position), flat(&f.velocity));
    let mut out = vec![0.0f64; 8];
    launch!(
        D,
        sph_shim_keep_out_2,
        sph_shim_keep_out_3,
        n,
        boxes.len() as u32,
        flat_boxes.as_ptr(),
        margin,
        f.kind.as_ptr(),
        f.mass.as_ptr(),
        start.as_ptr(),
        u32::from(from_start),
        pos.as_mut_ptr(),
        vel.as_mut_ptr(),
        out.as_mut_ptr(),
    );
    assert!(report.pushes > 20, "{D}D: only {} pushes", report.pushes);
    assert_eq!(bits(&pos), bits(&flat(&cf.position)), "{D}D keep_out: position");
    assert_eq!(bits(&vel), bits(&flat(&cf.velocity)), "{D}D keep_out: velocity");
    assert_eq!((out[0] + out[4]) as u64, report.pushes, "{D}D keep_out: pushes");
    for s in 0..2 {
        for k in 0..3 {
            let (gpu, cpu) = (out[4 * s + 1 + k], report.impulse[s][k]);
            assert!(
                (gpu - cpu).abs() <= 1e-12 * cpu.abs().max(1e-9),
                "{D}D keep_out: solid {s} axis {k}: {gpu} vs {cpu}"
            );
        }
    }
    // With the starts, some particle outside every box went through one and came back (the
    // crossing rule); without, none outside moved.
    let outside_moved = (0..f.len())
        .filter(|&i| f.kind[i] == FLUID && cf.position[i] != f.position[i])
        .filter(|&i| {
            let x = f.position[i];
            !boxes
                .iter()
                .any(|b| (0..D).all(|k| x[k] > b.min[k] && x[k] < b.max[k]))
        })
        .count();
    assert_eq!(
        outside_moved > 0,
        from_start,
        "{D}D: {outside_moved} outside particles moved"
    );
    // Nothing left inside any box.
    for i in (0..cf.len()).filter(|&i| cf.kind[i] == FLUID) {
        for b in &boxes {
            let x = cf.position[i];
            assert!(
                !(0..D).all(|k| x[k] > b.min[k] && x[k] < b.max[k]),
                "{D}D: particle {i} still inside"
            );
        }
    }
    cf.position
}

#[test]
fn keep_out_equals_the_cpu_stage_bitwise_2d() {
    let nearest = check_keep_out::<2>(0x0bad_cafe_1234_5678, false);
    let entry = check_keep_out::<2>(0x0bad_cafe_1234_5678, true);
    assert_ne!(nearest, entry, "the step start changes some particle's face");
}

#[test]
fn keep_out_equals_the_cpu_stage_bitwise_3d() {
    let nearest = check_keep_out::<3>(0x5678_1234_cafe_0bad, false);
    let entry = check_keep_out::<3>(0x5678_1234_cafe_0bad, true);
    assert_ne!(nearest, entry, "the step start changes some particle's face");
}

/// Stage `move_solids` (kernels/move_solids.cu) against `CpuBackend::move_solids`: the scene's
/// particles renumbered so the solids' ids follow the fluid's (as `Simulation` appends them),
/// stored in a shuffled order (as after sorts), reference positions off the current ones, one
/// displacement and velocity per solid. The kernel does the CPU's one f32 addition per
/// component, so positions and velocities are bitwise equal, solids land exactly on
/// `x0 + d`, and fluid particles are untouched.
fn check_move_solids<const D: usize>(seed: u64) {
    let (f0, _) = scene::<D>(seed);
    let mut rng = Rng(seed ^ 0x5eed);
    // Fluid first, then solids, as Simulation::new lays them out; then a shuffled storage order.
    let mut order: Vec<usize> = (0..f0.len()).filter(|&i| f0.kind[i] == FLUID).collect();
    let first_id = order.len() as u32;
    order.extend((0..f0.len()).filter(|&i| f0.kind[i] != FLUID));
    let mut f = Fields::<D>::default();
    for &i in &order {
        f.push(
            f0.position[i],
            f0.velocity[i],
            f0.mass[i],
            f0.density[i],
            f0.kind[i],
        );
    }
    let n = f.len();
    let mut perm: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        perm.swap(i, (rng.next() * (i + 1) as f32) as usize % (i + 1));
    }
    let mut shuffled = Fields::<D>::default();
    for &i in &perm {
        shuffled.push(f.position[i], f.velocity[i], f.mass[i], f.density[i], f.kind[i]);
        *shuffled.id.last_mut().expect("pushed") = f.id[i];
    }
    let f = shuffled;
    let mut reference = SolidReference::<D> {
        first_id,
        position: vec![Vector::zeros(); n - first_id as usize],
    };
    for i in (0..n).filter(|&i| f.kind[i] != FLUID) {
        let jitter = Vector::<D>::from_fn(|_, _| rng.sym(0.3 * DX));
        reference.position[(f.id[i] - first_id) as usize] = f.position[i] + jitter;
    }
    let kinematics: Vec<SolidKinematics<D>> = (0..SOLIDS)
        .map(|_| SolidKinematics {
            displacement: Vector::from_fn(|_, _| rng.sym(0.05)),
            velocity: Vector::from_fn(|_, _| rng.sym(0.8)),
            acceleration: Vector::from_fn(|_, _| rng.sym(9.0)),
        })
        .collect();
    let mut cf = f.clone();
    CpuBackend::<D>::new().move_solids(&mut cf, &reference, &kinematics);
    let flat = |v: &[Vector<D>]| -> Vec<f32> { v.iter().flat_map(|x| x.iter().copied()).collect() };
    let bits = |v: &[f32]| -> Vec<u32> { v.iter().map(|x| x.to_bits()).collect() };
    let (mut pos, mut vel) = (flat(&f.position), flat(&f.velocity));
    let x0 = flat(&reference.position);
    let motion: Vec<f32> = kinematics
        .iter()
        .flat_map(|k| {
            k.displacement
                .iter()
                .chain(k.velocity.iter())
                .copied()
                .collect::<Vec<_>>()
        })
        .collect();
    launch!(
        D,
        sph_shim_move_solids_2,
        sph_shim_move_solids_3,
        n as u32,
        f.kind.as_ptr(),
        f.id.as_ptr(),
        first_id,
        x0.as_ptr(),
        motion.as_ptr(),
        pos.as_mut_ptr(),
        vel.as_mut_ptr(),
    );
    assert_eq!(
        bits(&pos),
        bits(&flat(&cf.position)),
        "{D}D move_solids: position"
    );
    assert_eq!(
        bits(&vel),
        bits(&flat(&cf.velocity)),
        "{D}D move_solids: velocity"
    );
    let mut moved = 0;
    for i in 0..n {
        if f.kind[i] == FLUID {
            assert_eq!(cf.position[i], f.position[i], "fluid {i} stays");
            assert_eq!(cf.velocity[i], f.velocity[i], "fluid {i} keeps its velocity");
        } else {
            let k = &kinematics[f.kind[i] as usize - 1];
            let x0 = reference.position[(f.id[i] - first_id) as usize];
            assert_eq!(cf.position[i], x0 + k.displacement, "solid {i} at x0 + d");
            assert_eq!(cf.velocity[i], k.velocity, "solid {i} moves with d'");
            moved += usize::from(cf.position[i] != f.position[i]);
        }
    }
    assert!(moved > 0, "the solids were moved");
}

#[test]
fn move_solids_kernel_equals_the_cpu_stage_bitwise_2d() {
    check_move_solids::<2>(0x0dd_ba11_cafe_f00d);
}

#[test]
fn move_solids_kernel_equals_the_cpu_stage_bitwise_3d() {
    check_move_solids::<3>(0xfee1_600d_dead_beef);
}
