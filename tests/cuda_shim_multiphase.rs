//! The `multiphase` effect's kernels (the `_multiphase` entries of the stage files, `forces_*_mp`,
//! `wall_pressure_multiphase`, the velocity solve's `predicted_density_multiphase`), run on the
//! CPU through the host shim, against the multiphase branches of the rayon stages, on a jittered
//! two-phase state (2D).
#![cfg(feature = "cuda")]

use sph::backend::cpu::CpuBackend;
use sph::backend::cuda::extremes::DeviceExtremes;
use sph::backend::cuda::extremes::max_from_bits;
use sph::backend::cuda::grid::GridGeometry;
use sph::backend::cuda::shim;
use sph::backend::params::StepParams;
use sph::backend::{Backend, ForceTerms, SolidForceSource, WallModel};
use sph::fields::{FLUID, Fields, PermuteScratch};
use sph::math::{Real, Vector};
use sph::physics::correction::MOMENTUM;
use sph::run::simulation_from_scene;
use sph::scene::load_scene;
use std::path::Path;

/// A small deterministic generator (xorshift), so failures reproduce.
struct Rng(u64);

impl Rng {
    fn sym(&mut self, a: f32) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        let u = (self.0 >> 11) as f64 / (1u64 << 53) as f64;
        ((2.0 * u - 1.0) * f64::from(a)) as f32
    }
}

/// `scenes/two_layer_2d.toml` (oil 800 on water 1000, a container) with positions jittered by
/// ±0.2 dx, random velocities, and pressures from the multiphase equation of state, plus the
/// step parameters with viscosity.
fn state() -> (Fields<2>, StepParams<2>) {
    let scene = load_scene(Path::new("scenes/two_layer_2d.toml"), &[]).expect("shipped scene");
    let sim = simulation_from_scene::<2>(&scene).expect("builds");
    let params = sim.step_params();
    let mut f = sim.fields.clone();
    assert!(!f.rest_density.is_empty());
    let mut rng = Rng(0x9e3779b97f4a7c15);
    let dx = scene.spacing as f32;
    for i in 0..f.len() {
        if f.kind[i] == FLUID {
            f.position[i] += Vector::<2>::new(rng.sym(0.2 * dx), rng.sym(0.2 * dx));
            f.velocity[i] = Vector::<2>::new(rng.sym(0.1), rng.sym(0.1));
            f.pressure[i] = 500.0 + rng.sym(400.0);
        }
    }
    (f, params)
}

/// The dense grid the kernels read, built as `sort_by_cell` on the device does: keys from the
/// shim's `cell_hash`, particles ordered by (cell, id), `cell_start` the exclusive scan.
struct Dense {
    geometry: GridGeometry<2>,
    cell_start: Vec<u32>,
    cell_key: Vec<u32>,
}

fn dense_sort(f: &mut Fields<2>, p: &StepParams<2>) -> Dense {
    let geometry = GridGeometry::new(&p.domain_min, &p.domain_max, p.h).expect("small grid");
    let n = f.len();
    let ncell = geometry.cell_count();
    let mut key = vec![0u32; n];
    let mut count = vec![0u32; ncell + 1];
    // SAFETY: positions have 2n floats, key n entries, count ncell + 1.
    unsafe {
        shim::sph_shim_cell_hash_2(
            n as u32,
            &geometry,
            f.position.as_ptr().cast(),
            key.as_mut_ptr(),
            count.as_mut_ptr(),
        )
    };
    let mut perm: Vec<u32> = (0..n as u32).collect();
    perm.sort_by_key(|&i| (key[i as usize], f.id[i as usize]));
    f.permute(&perm, &mut PermuteScratch::default());
    let cell_key: Vec<u32> = perm.iter().map(|&i| key[i as usize]).collect();
    let mut cell_start = vec![0u32; ncell + 1];
    let mut sum = 0;
    for c in 0..=ncell {
        cell_start[c] = sum;
        sum += count[c];
    }
    Dense {
        geometry,
        cell_start,
        cell_key,
    }
}

/// `value` of every particle, indexed by id.
fn by_id<T: Copy>(f: &Fields<2>, value: &[T]) -> Vec<T> {
    let mut out = vec![value[0]; f.len()];
    for i in 0..f.len() {
        out[f.id[i] as usize] = value[i];
    }
    out
}

/// Largest `|a − b|` over the ids where `pick`, and the largest `|a|` there.
fn worst(a: &[f32], b: &[f32], pick: impl Fn(usize) -> bool) -> (f32, f32) {
    (0..a.len())
        .filter(|&i| pick(i))
        .fold((0.0f32, 0.0f32), |(d, m), i| {
            (d.max((a[i] - b[i]).abs()), m.max(a[i].abs()))
        })
}

/// Every multiphase kernel against its CPU twin. Tolerances: f32 sums of the same terms in
/// another order, ≤ ~60 terms: 1e-5 relative for the density (as tests/cuda_shim.rs); the
/// equation of state and the correction's increments are one expression per particle on the
/// same inputs, so bitwise; the extrapolated wall pressure, the accelerations and the
/// displacements sum terms of both signs, so 1e-4 of the field's largest value.
#[test]
fn multiphase_kernels_on_the_shim_match_the_cpu_stages() {
    let (input, p) = state();
    let mut cpu_f = input.clone();
    let mut cpu = CpuBackend::<2>::new();
    cpu.sort_by_cell(&mut cpu_f, p.h).expect("finite");
    let mut f = input.clone();
    let g = dense_sort(&mut f, &p);
    let n = f.len() as u32;
    let kind = by_id(&input, &input.kind);
    let fluid = |id: usize| kind[id] == FLUID;
    let solid = |id: usize| kind[id] != FLUID;

    // Density: [HA06] m_i Σ W.
    cpu.density(&mut cpu_f, &p);
    // SAFETY (every launch below): each buffer holds n items (2n floats for vectors), the grid
    // is the one `f` was sorted with.
    unsafe {
        shim::sph_shim_density_multiphase_2(
            n,
            &p,
            &g.geometry,
            g.cell_start.as_ptr(),
            g.cell_key.as_ptr(),
            f.position.as_ptr().cast(),
            f.mass.as_ptr(),
            f.kind.as_ptr(),
            f.density.as_mut_ptr(),
        )
    };
    let (a, b) = (by_id(&cpu_f, &cpu_f.density), by_id(&f, &f.density));
    let (d, m) = worst(&a, &b, fluid);
    eprintln!("density: worst {d:.3e} of {m:.1}");
    assert!(m > 700.0 && d <= 1e-5 * m, "density differs by {d}");
    // Both sides continue from the CPU's densities, so each later stage is compared alone.
    let cpu_density = a;
    for i in 0..f.len() {
        f.density[i] = cpu_density[f.id[i] as usize];
    }

    // Equation of state with each particle's own rest density: bitwise.
    cpu.equation_of_state(&mut cpu_f, &p);
    unsafe {
        shim::sph_shim_equation_of_state_multiphase_2(
            n,
            &p,
            f.density.as_ptr(),
            f.rest_density.as_ptr(),
            f.kind.as_ptr(),
            f.pressure.as_mut_ptr(),
        )
    };
    let (a, b) = (by_id(&cpu_f, &cpu_f.pressure), by_id(&f, &f.pressure));
    for id in (0..a.len()).filter(|&id| fluid(id)) {
        assert_eq!(a[id].to_bits(), b[id].to_bits(), "pressure of {id}");
    }
    assert!(a.iter().any(|&x| x > 0.0), "some fluid is compressed");

    // Wall pressure, the weakly compressible model (summed branch with the number density).
    let wall_acc = [Vector::<2>::zeros(); 1];
    cpu.wall_pressure(&mut cpu_f, &p, WallModel::ExtrapolatedOrSummed, &[]);
    unsafe {
        shim::sph_shim_wall_pressure_multiphase_2(
            n,
            &p,
            &g.geometry,
            g.cell_start.as_ptr(),
            g.cell_key.as_ptr(),
            f.position.as_ptr().cast(),
            f.mass.as_ptr(),
            f.kind.as_ptr(),
            wall_acc.as_ptr().cast(),
            1,
            f.pressure.as_mut_ptr(),
            f.density.as_mut_ptr(),
        )
    };
    let (a, b) = (by_id(&cpu_f, &cpu_f.pressure), by_id(&f, &f.pressure));
    let (d, m) = worst(&a, &b, solid);
    eprintln!("wall pressure: worst {d:.3e} of {m:.1}");
    assert!(m > 0.0 && d <= 1e-4 * m, "wall pressure differs by {d}");
    // Continue from the CPU's wall state.
    let (cpu_p, cpu_rho) = (a, by_id(&cpu_f, &cpu_f.density));
    for i in 0..f.len() {
        f.pressure[i] = cpu_p[f.id[i] as usize];
        f.density[i] = cpu_rho[f.id[i] as usize];
    }

    // Forces with viscosity, the volume-form pressure term.
    let terms = ForceTerms {
        viscosity: true,
        artificial_viscosity: false,
        rotating_frame: false,
    };
    cpu.forces(&mut cpu_f, &p, terms);
    unsafe {
        shim::sph_shim_forces_pv_mp_2(
            n,
            &p,
            &g.geometry,
            g.cell_start.as_ptr(),
            g.cell_key.as_ptr(),
            f.position.as_ptr().cast(),
            f.velocity.as_ptr().cast(),
            f.mass.as_ptr(),
            f.density.as_ptr(),
            f.pressure.as_ptr(),
            f.kind.as_ptr(),
            wall_velocity(&f),
            f.acceleration.as_mut_ptr().cast(),
        )
    };
    for k in 0..2 {
        let a: Vec<f32> = by_id(&cpu_f, &cpu_f.acceleration).iter().map(|v| v[k]).collect();
        let b: Vec<f32> = by_id(&f, &f.acceleration).iter().map(|v| v[k]).collect();
        let (d, m) = worst(&a, &b, fluid);
        eprintln!("acceleration[{k}]: worst {d:.3e} of {m:.1}");
        assert!(m > 1.0 && d <= 1e-4 * m, "acceleration[{k}] differs by {d}");
    }

    // Forces on the solid (the tank): the volume-form pressure term and the viscous one.
    let cpu_solid = cpu.solid_forces(&cpu_f, &p, 1, SolidForceSource::Forces);
    let mut out = [0.0f64; 3];
    unsafe {
        shim::sph_shim_solid_forces_multiphase_2(
            n,
            &p,
            &g.geometry,
            g.cell_start.as_ptr(),
            g.cell_key.as_ptr(),
            f.position.as_ptr().cast(),
            f.velocity.as_ptr().cast(),
            f.mass.as_ptr(),
            f.density.as_ptr(),
            f.pressure.as_ptr(),
            f.kind.as_ptr(),
            wall_velocity(&f),
            out.as_mut_ptr(),
        )
    };
    eprintln!("force on the tank: cpu {:?}, shim {out:?}", cpu_solid[0]);
    let scale = cpu_solid[0].iter().map(|c| c.abs()).fold(0.0, f64::max);
    assert!(scale > 0.0);
    for c in 0..2 {
        // f32 sums per solid particle in another order, then f64: 1e-4 of the largest component.
        assert!((out[c] - cpu_solid[0][c]).abs() <= 1e-4 * scale, "component {c}");
    }

    // The state's extremes against each particle's own rest density.
    let cpu_extremes = cpu.state_extremes(&cpu_f, &p);
    let mut device = [DeviceExtremes::initial()];
    unsafe {
        shim::sph_shim_state_extremes_multiphase_2(
            n,
            &p,
            f.position.as_ptr().cast(),
            f.velocity.as_ptr().cast(),
            f.acceleration.as_ptr().cast(),
            f.density.as_ptr(),
            f.pressure.as_ptr(),
            f.kind.as_ptr(),
            f.rest_density.as_ptr(),
            device.as_mut_ptr(),
        )
    };
    let shim_extremes = device[0].finish(p.rho0);
    eprintln!("extremes: cpu {cpu_extremes:?}\n          shim {shim_extremes:?}");
    // Speeds and accelerations are f32 maxima (exact); the mean errors are f64 sums of the same
    // terms in another order; the largest error goes through the density scaled to rho0,
    // rounded once to f32 (2^-24 relative of the density, 1e-6 of the error here).
    assert_eq!(cpu_extremes.max_speed, shim_extremes.max_speed);
    assert_eq!(cpu_extremes.max_acceleration, shim_extremes.max_acceleration);
    for (a, b) in [
        (
            cpu_extremes.mean_abs_density_error,
            shim_extremes.mean_abs_density_error,
        ),
        (cpu_extremes.mean_compression, shim_extremes.mean_compression),
        (
            cpu_extremes.max_abs_density_error,
            shim_extremes.max_abs_density_error,
        ),
        (cpu_extremes.max_compression, shim_extremes.max_compression),
        (
            cpu_extremes.max_surface_deficit,
            shim_extremes.max_surface_deficit,
        ),
        (
            cpu_extremes.mean_surface_deficit,
            shim_extremes.mean_surface_deficit,
        ),
    ] {
        assert!(a > 0.0 && (a - b).abs() <= 1e-5 * a, "cpu {a}, shim {b}");
    }

    // The correction: error, increments, displacement.
    let cpu_error = cpu.correction_error(&cpu_f, &p);
    let mut out = [0i32; 2];
    unsafe {
        shim::sph_shim_correction_error_multiphase_2(
            n,
            f.rest_density.as_ptr(),
            f.density.as_ptr(),
            f.pressure.as_ptr(),
            f.kind.as_ptr(),
            out.as_mut_ptr(),
        )
    };
    let (c, r) = (max_from_bits(out[0]), max_from_bits(out[1]));
    eprintln!("correction error: cpu {cpu_error:?}, shim {c:e}, {r:e}");
    assert!(cpu_error.compression > 0.0);
    assert!((c - cpu_error.compression).abs() <= 1e-6 * cpu_error.compression);
    assert!((r - cpu_error.residual).abs() <= 1e-6 * cpu_error.residual);
    let k = 2.0e3 as Real;
    cpu.begin_correction(&mut cpu_f);
    let before: Vec<Vector<2>> = by_id(&cpu_f, &cpu_f.position);
    let p_before = by_id(&cpu_f, &cpu_f.pressure);
    cpu.correction_pressure(&mut cpu_f, &p, k);
    let mut delta_p = vec![0.0f32; f.len()];
    let prev = vec![0.0f32; f.len()];
    unsafe {
        shim::sph_shim_correction_pressure_fluid_multiphase_2(
            n,
            f.rest_density.as_ptr(),
            k,
            MOMENTUM,
            0,
            f.density.as_ptr(),
            f.pressure.as_ptr(),
            f.kind.as_ptr(),
            prev.as_ptr(),
            delta_p.as_mut_ptr(),
        )
    };
    let cpu_dp: Vec<f32> = by_id(&cpu_f, &cpu_f.pressure)
        .iter()
        .zip(&p_before)
        .map(|(a, b)| a - b)
        .collect();
    let shim_dp = by_id(&f, &delta_p);
    for id in (0..cpu_dp.len()).filter(|&id| fluid(id)) {
        let p_new = p_before[id] + shim_dp[id];
        assert_eq!(
            (p_before[id] + cpu_dp[id]).to_bits(),
            p_new.to_bits(),
            "increment of {id}"
        );
    }
    // Displacement from the same increments (the CPU's, walls included), tau = 1 s.
    let cpu_increments: Vec<f32> = cpu_dp.clone();
    for i in 0..f.len() {
        delta_p[i] = cpu_increments[f.id[i] as usize];
    }
    cpu.correct_positions(&mut cpu_f, &p, 1.0, f32::INFINITY, f32::INFINITY);
    let mut displacement = vec![Vector::<2>::zeros(); f.len()];
    let mut largest = 0i32;
    unsafe {
        shim::sph_shim_correction_displacement_multiphase_2(
            n,
            &p,
            &g.geometry,
            g.cell_start.as_ptr(),
            g.cell_key.as_ptr(),
            f.position.as_ptr().cast(),
            f.mass.as_ptr(),
            f.density.as_ptr(),
            delta_p.as_ptr(),
            f.kind.as_ptr(),
            1.0,
            displacement.as_mut_ptr().cast(),
            &mut largest,
        )
    };
    let after = by_id(&cpu_f, &cpu_f.position);
    let shim_dx = by_id(&f, &displacement);
    for c in 0..2 {
        let a: Vec<f32> = (0..after.len()).map(|i| after[i][c] - before[i][c]).collect();
        let b: Vec<f32> = shim_dx.iter().map(|v| v[c]).collect();
        let (d, m) = worst(&a, &b, fluid);
        eprintln!("displacement[{c}]: worst {d:.3e} of {m:.3e}");
        // The CPU's Δx went through x + Δx − x in f32: one rounding of |x| ≤ 0.3 m, 3e-8 m.
        assert!(
            m > 0.0 && d <= 1e-4 * m + 6e-8,
            "displacement[{c}] differs by {d}"
        );
    }
}

/// The velocity solve's [HA06] density, `predicted_density_multiphase`, against
/// `CpuBackend::predicted_density` with both density kernels (poly6, and the `corrected` solver's
/// scaled spiky kernel): each particle's own mass and rest density, solids with their own
/// velocity. An f32 sum of the same terms in another order: within 1e-5 of the largest density
/// (as the density above); a missing term moves ρ* by ~1 kg/m³ here, 100 times that. Solids
/// untouched, bitwise.
#[test]
fn multiphase_predicted_density_on_the_shim_matches_the_cpu_stage() {
    let (input, params) = state();
    let kind = by_id(&input, &input.kind);
    let fluid = |id: usize| kind[id] == FLUID;
    for weight in [
        sph::physics::density::DensityWeight::POLY6,
        sph::physics::density::DensityWeight::spiky(0.82),
    ] {
        let mut p = params;
        p.density_kernel = weight.kernel;
        p.density_spiky_scale = weight.spiky_scale;
        let mut cpu_f = input.clone();
        let mut cpu = CpuBackend::<2>::new();
        cpu.sort_by_cell(&mut cpu_f, p.h).expect("finite");
        let mut f = input.clone();
        let g = dense_sort(&mut f, &p);
        let n = f.len() as u32;
        let tau = 1.0e-3 as Real;
        cpu.begin_velocity_solve(&mut cpu_f);
        cpu.predicted_density(&mut cpu_f, &p, tau);
        let before = by_id(&f, &f.density);
        let start = f.density.clone();
        // SAFETY: each buffer holds n items (2n floats for vectors), the grid is the one `f` was
        // sorted with.
        unsafe {
            shim::sph_shim_predicted_density_multiphase_2(
                n,
                &p,
                &g.geometry,
                g.cell_start.as_ptr(),
                g.cell_key.as_ptr(),
                f.position.as_ptr().cast(),
                f.velocity.as_ptr().cast(),
                f.mass.as_ptr(),
                f.rest_density.as_ptr(),
                f.kind.as_ptr(),
                start.as_ptr(),
                tau,
                f.density.as_mut_ptr(),
            )
        };
        let (a, b) = (by_id(&cpu_f, &cpu_f.density), by_id(&f, &f.density));
        let (d, m) = worst(&a, &b, fluid);
        let rest = by_id(&input, &input.rest_density);
        let change = (0..a.len())
            .filter(|&id| fluid(id))
            .map(|id| (a[id] - rest[id]).abs())
            .fold(0.0f32, f32::max);
        eprintln!("predicted density, {weight:?}: worst {d:.3e} of {m:.1}, largest |ρ* − ρ0_i| {change:.3}");
        assert!(m > 700.0 && d <= 1e-5 * m, "predicted density differs by {d}");
        assert!(change > 1.0, "the velocities change the density: {change}");
        for id in (0..a.len()).filter(|&id| !fluid(id)) {
            assert_eq!(b[id].to_bits(), before[id].to_bits(), "solid {id} untouched");
            assert_eq!(
                a[id].to_bits(),
                before[id].to_bits(),
                "solid {id} untouched on the CPU"
            );
        }
    }
}

/// The velocity solids carry in (17), as the backends pass it: the no-slip field where the
/// `wall_velocity` stage allocated it, else the velocity itself.
fn wall_velocity(f: &Fields<2>) -> *const f32 {
    if f.wall_velocity.len() == f.len() {
        f.wall_velocity.as_ptr().cast()
    } else {
        f.velocity.as_ptr().cast()
    }
}
