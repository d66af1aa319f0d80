//! The `surface_normals` and `surface_tension` kernels of `kernels/surface_tension.cu`, both
//! models (the surface stress, `physics::surface_stress`, with one phase and with two; [AAT13]
//! Akinci, Akinci & Teschner 2013), run on the CPU through the host shim
//! (`backend::cuda::shim`), against the rayon stages they mirror, per particle `id`, on a small
//! random droplet in 2D and 3D with a few solid particles beside it (which must be ignored:
//! fluid neighbours only). These run everywhere, GPU or not.
//!
//! Tolerance (as `tests/cuda_shim_dynamics.rs`): each pair term is the same f32 arithmetic on
//! both sides; only the order of the neighbour sums differs, which moves a sum of N terms by at
//! most 2 (N − 1) u Σ|t_j| (u = 2^-24); [`SUM_ORDER`] = 1e-5 of Σ|t_j| covers N up to ~80.
#![cfg(feature = "cuda")]

use sph::backend::cpu::CpuBackend;
use sph::backend::cuda::grid::GridGeometry;
use sph::backend::cuda::shim;
use sph::backend::params::StepParams;
use sph::backend::{Backend, SurfaceTensionModel};
use sph::fields::{FLUID, Fields};
use sph::math::Vector;
use sph::physics::surface_stress::{surface_stress_acceleration, tensile_factor};
use sph::physics::surface_tension::{normal_term, surface_tension_acceleration};
use sph::smoothing::{Smoothing, pair_offset};

/// Relative tolerance of a neighbour sum against the sum of its terms' magnitudes.
const SUM_ORDER: f64 = 1.0e-5;
/// Lattice spacing [m]; `h = 2 dx`.
const DX: f32 = 0.01;
/// Rest density [kg/m³].
const RHO0: f32 = 1000.0;

/// A small deterministic generator (xorshift), so failures reproduce.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn sym(&mut self, a: f32) -> f32 {
        a * (2.0 * self.next() - 1.0)
    }
}

/// Which model, and for the surface stress whether the fluid has two phases.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Model {
    Akinci,
    Stress,
    StressTwoPhases,
}

/// A jittered droplet of radius 4 dx (2D) / 3 dx (3D) centred at 0, densities within 3 % of ρ0
/// and random accelerations (the stage adds to them), and a slab of solid particles at
/// `x ≈ R + dx` touching it. γ or σ' is chosen so the surface tension is comparable with the
/// accelerations; with two phases every other fluid particle has rest density 0.8 ρ0 (and
/// that mass).
fn droplet<const D: usize>(seed: u64, model: Model) -> (Fields<D>, StepParams<D>) {
    let mut rng = Rng(seed);
    let radius: i32 = if D == 2 { 4 } else { 3 };
    let mass = RHO0 * DX.powi(D as i32);
    let mut f = Fields::<D>::default();
    let span = radius + 2;
    let extent = (2 * span + 1) as usize;
    for c in 0..extent.pow(D as u32) {
        let mut idx = [0i32; 3];
        let mut rest = c;
        for k in idx.iter_mut().take(D) {
            *k = (rest % extent) as i32 - span;
            rest /= extent;
        }
        let r2: i32 = idx.iter().take(D).map(|k| k * k).sum();
        let kind = if r2 <= radius * radius {
            FLUID
        } else if idx[0] == span && (1..D).all(|k| idx[k].abs() <= 2) {
            1
        } else {
            continue;
        };
        let x = Vector::<D>::from_fn(|k, _| (idx[k] as f32 + rng.sym(0.2)) * DX);
        let light = model == Model::StressTwoPhases && kind == FLUID && f.len() % 2 == 0;
        let rest = if light { 0.8 * RHO0 } else { RHO0 };
        f.push(
            x,
            Vector::zeros(),
            mass * rest / RHO0,
            rest * (1.0 + rng.sym(0.03)),
            kind,
        );
        if model == Model::StressTwoPhases {
            f.rest_density.push(rest);
        }
        if kind == FLUID {
            *f.acceleration.last_mut().expect("pushed") = Vector::from_fn(|_, _| rng.sym(1.0));
        }
    }
    let lo = Vector::<D>::from_element(-(span as f32 + 2.0) * DX);
    let p = StepParams {
        h: 2.0 * DX,
        rho0: RHO0,
        c2: 400.0,
        mu: 0.0,
        alpha: 0.0,
        c: 20.0,
        pressure_gradient_scale: 1.0,
        gravity: Vector::zeros(),
        domain_min: lo,
        domain_max: -lo,
        angular_velocity: [0.0; 3],
        rotation_centre: Vector::zeros(),
        viscosity_scale: 1.0,
        surface_tension_gamma: if model == Model::Akinci { 2.0 } else { 0.0 },
        surface_tension_sigma: if model == Model::Akinci { 0.0 } else { 5.0 },
        spacing: DX,
        density_spiky_scale: 0.0,
        density_kernel: sph::physics::density::DensityKernel::Poly6,
        surface_tension_model: if model == Model::Akinci {
            SurfaceTensionModel::Akinci
        } else {
            SurfaceTensionModel::SurfaceStress
        },
        rotating_frame: 0,
        phases: if model == Model::StressTwoPhases {
            sph::physics::multiphase::Phases::Multi
        } else {
            sph::physics::multiphase::Phases::Single
        },
    };
    (f, p)
}

/// Key of the dense-grid cell of `x`, as `cell_of` and `cell_key` of `kernels/sph.cuh`.
fn cell_key<const D: usize>(g: &GridGeometry<D>, x: &Vector<D>) -> u32 {
    let mut key = 0u32;
    for k in (0..D).rev() {
        let c = ((x[k] - g.origin[k]) * g.inv_cell).floor();
        let hi = g.dims[k] as i32 - 2;
        let c = if c.is_nan() || c < 1.0 {
            1
        } else if c > hi as f32 {
            hi as u32
        } else {
            c as u32
        };
        key = key * g.dims[k] + c;
    }
    key
}

/// `v` flattened in the device order `order`.
fn flat<const D: usize>(v: &[Vector<D>], order: &[usize]) -> Vec<f32> {
    order.iter().flat_map(|&i| v[i].iter().copied()).collect()
}

/// The rest density of particle `j` as the stages read it.
fn rest<const D: usize>(f: &Fields<D>, p: &StepParams<D>, j: usize) -> f32 {
    p.phases.rest_density(&f.rest_density, j, p.rho0)
}

/// Σ_j |term| of the normal (times h) and of the acceleration of particle `i` (input order),
/// brute force, for the tolerance.
fn term_scales<const D: usize>(
    f: &Fields<D>,
    p: &StepParams<D>,
    normal: &[Vector<D>],
    i: usize,
) -> (f64, f64) {
    let kernel = Smoothing::<D>::new(p.h).expect("2D or 3D");
    let stress = p.surface_tension_model == SurfaceTensionModel::SurfaceStress;
    let w_dx = kernel.w(p.spacing * p.spacing);
    let (mut sn, mut sa) = (0.0f64, f64::from(f.acceleration[i].norm()));
    for j in 0..f.len() {
        let d = f.position[i] - f.position[j];
        let r2 = d.norm_squared();
        if f.kind[j] != FLUID || r2 >= p.h * p.h {
            continue;
        }
        let (d, r2) = pair_offset(d, r2, i, j, p.h);
        let volume_density = if stress { rest(f, p, j) } else { f.density[j] };
        sn += f64::from((normal_term(&kernel, f.mass[j], volume_density, &d) * p.h).norm());
        if j == i {
            continue;
        }
        let a = if stress {
            let grad = kernel.grad_w_spiky(&d, r2.sqrt()) * p.pressure_gradient_scale;
            surface_stress_acceleration(
                p.surface_tension_sigma,
                p.h,
                f.mass[j],
                rest(f, p, i),
                rest(f, p, j),
                &normal[i],
                &normal[j],
                &grad,
                tensile_factor(kernel.w(r2), w_dx),
            )
        } else {
            surface_tension_acceleration(
                p.surface_tension_gamma,
                p.rho0,
                p.h,
                f.mass[j],
                f.density[i],
                f.density[j],
                &normal[i],
                &normal[j],
                &d,
                r2.sqrt(),
            )
        };
        sa += f64::from(a.norm());
    }
    (sn, sa)
}

fn check<const D: usize>(seed: u64, model: Model) {
    let (f, p) = droplet::<D>(seed, model);
    let n = f.len();
    // CPU stages, results by id.
    let mut cf = f.clone();
    let mut cpu = CpuBackend::<D>::new();
    cpu.sort_by_cell(&mut cf, p.h).expect("finite positions");
    cpu.surface_normals(&mut cf, &p);
    let mut cpu_normal = vec![Vector::<D>::zeros(); n];
    for i in 0..n {
        cpu_normal[cf.id[i] as usize] = cf.normal[i];
    }
    cpu.surface_tension(&mut cf, &p);
    let mut cpu_acc = vec![Vector::<D>::zeros(); n];
    for i in 0..n {
        cpu_acc[cf.id[i] as usize] = cf.acceleration[i];
    }
    // The device layout: sorted by (cell, id), with the dense grid's ranges.
    let g = GridGeometry::new(&p.domain_min, &p.domain_max, p.h).expect("a small domain");
    let keys: Vec<u32> = f.position.iter().map(|x| cell_key(&g, x)).collect();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| (keys[i], f.id[i]));
    let mut cell_start = vec![0u32; g.cell_count() + 1];
    for &k in &keys {
        cell_start[k as usize + 1] += 1;
    }
    for c in 0..g.cell_count() {
        cell_start[c + 1] += cell_start[c];
    }
    let cell_key: Vec<u32> = order.iter().map(|&i| keys[i]).collect();
    let pos = flat(&f.position, &order);
    let mass: Vec<f32> = order.iter().map(|&i| f.mass[i]).collect();
    let density: Vec<f32> = order.iter().map(|&i| f.density[i]).collect();
    let kind: Vec<u32> = order.iter().map(|&i| f.kind[i]).collect();
    let has_rest = u32::from(p.phases == sph::physics::multiphase::Phases::Multi);
    let rest: Vec<f32> = order
        .iter()
        .map(|&i| f.rest_density.get(i).copied().unwrap_or(f32::NAN))
        .collect();
    let mut normal = vec![f32::NAN; n * D];
    // SAFETY: every buffer holds n items (D floats each for vectors), cell_start ncell + 1.
    unsafe {
        let args = (n as u32, &p as *const StepParams<D>, &g as *const GridGeometry<D>);
        match D {
            2 => shim::sph_shim_surface_normals_2(
                args.0,
                args.1.cast(),
                args.2.cast(),
                cell_start.as_ptr(),
                cell_key.as_ptr(),
                pos.as_ptr(),
                mass.as_ptr(),
                density.as_ptr(),
                rest.as_ptr(),
                has_rest,
                kind.as_ptr(),
                normal.as_mut_ptr(),
            ),
            _ => shim::sph_shim_surface_normals_3(
                args.0,
                args.1.cast(),
                args.2.cast(),
                cell_start.as_ptr(),
                cell_key.as_ptr(),
                pos.as_ptr(),
                mass.as_ptr(),
                density.as_ptr(),
                rest.as_ptr(),
                has_rest,
                kind.as_ptr(),
                normal.as_mut_ptr(),
            ),
        }
    }
    // The tension kernel gets the CPU's normals, so it is compared on its own.
    let cpu_normal_flat = flat(&cpu_normal, &order);
    let mut acc = flat(&f.acceleration, &order);
    // SAFETY: as above.
    unsafe {
        let args = (n as u32, &p as *const StepParams<D>, &g as *const GridGeometry<D>);
        match D {
            2 => shim::sph_shim_surface_tension_2(
                args.0,
                args.1.cast(),
                args.2.cast(),
                cell_start.as_ptr(),
                cell_key.as_ptr(),
                pos.as_ptr(),
                mass.as_ptr(),
                density.as_ptr(),
                rest.as_ptr(),
                has_rest,
                kind.as_ptr(),
                cpu_normal_flat.as_ptr(),
                acc.as_mut_ptr(),
            ),
            _ => shim::sph_shim_surface_tension_3(
                args.0,
                args.1.cast(),
                args.2.cast(),
                cell_start.as_ptr(),
                cell_key.as_ptr(),
                pos.as_ptr(),
                mass.as_ptr(),
                density.as_ptr(),
                rest.as_ptr(),
                has_rest,
                kind.as_ptr(),
                cpu_normal_flat.as_ptr(),
                acc.as_mut_ptr(),
            ),
        }
    }
    let (mut worst_n, mut worst_a, mut surface, mut tension) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (at, &id) in order.iter().enumerate() {
        let shim_n = Vector::<D>::from_fn(|k, _| normal[at * D + k]);
        let shim_a = Vector::<D>::from_fn(|k, _| acc[at * D + k]);
        if f.kind[id] != FLUID {
            assert_eq!(shim_n, Vector::<D>::zeros(), "solid {id}: zero normal");
            assert_eq!(
                cpu_normal[id],
                Vector::<D>::zeros(),
                "solid {id}: zero normal (cpu)"
            );
            assert_eq!(shim_a, f.acceleration[id], "solid {id}: acceleration untouched");
            continue;
        }
        let (sn, sa) = term_scales(&f, &p, &cpu_normal, id);
        for k in 0..D {
            let dn = f64::from(shim_n[k] - cpu_normal[id][k]).abs();
            let da = f64::from(shim_a[k] - cpu_acc[id][k]).abs();
            assert!(
                dn <= SUM_ORDER * sn,
                "{D}D normal of {id} axis {k}: shim {} cpu {}",
                shim_n[k],
                cpu_normal[id][k]
            );
            assert!(
                da <= SUM_ORDER * sa,
                "{D}D acceleration of {id} axis {k}: shim {} cpu {}",
                shim_a[k],
                cpu_acc[id][k]
            );
            worst_n = worst_n.max(dn / sn);
            worst_a = worst_a.max(da / sa);
        }
        surface = surface.max(f64::from(cpu_normal[id].norm()));
        tension = tension.max(f64::from((cpu_acc[id] - f.acceleration[id]).norm()) / sa);
    }
    eprintln!(
        "{D}D {model:?}: largest |shim - cpu| / Σ|terms|: normals {worst_n:.2e}, accelerations {worst_a:.2e}"
    );
    // The terms are visible: surface particles have |n| of order 1, and the stage moves the
    // accelerations by far more than the tolerance.
    assert!(surface > 0.5, "largest |n| = {surface}");
    assert!(
        tension > 100.0 * SUM_ORDER,
        "largest change {tension:.2e} of Σ|terms|"
    );
}

#[test]
fn surface_tension_kernels_match_the_cpu_stages_on_a_droplet_2d() {
    for model in [Model::Akinci, Model::Stress, Model::StressTwoPhases] {
        check::<2>(0x9e37_79b9_7f4a_7c15, model);
    }
}

#[test]
fn surface_tension_kernels_match_the_cpu_stages_on_a_droplet_3d() {
    for model in [Model::Akinci, Model::Stress, Model::StressTwoPhases] {
        check::<3>(0x2545_f491_4f6c_dd1d, model);
    }
}
