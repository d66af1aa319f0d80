//! The `surface_normals` and `surface_tension` stages, for both surface-tension models (the
//! surface stress, `physics::surface_stress`, and [AAT13] eqs. 1–5) with one phase and with
//! several, on every backend, against brute-force sums over a droplet beside a slab of solid
//! particles, which both stages must ignore (fluid neighbours only).

use crate::setup::{DX, RHO0, Rng, SUM_ORDER, assert_close, backends, by_id, in_id_order, swap_particles};
use sph::fields::{FLUID, Fields};
use sph::math::Vector;
use sph::model::SurfaceTensionModel;
use sph::model::params::StepParams;
use sph::physics::density::DensityKernel;
use sph::physics::multiphase::Phases;
use sph::physics::surface_stress::{surface_stress_acceleration, tensile_factor};
use sph::physics::surface_tension::{normal_term, surface_tension_acceleration};

/// A jittered droplet of radius 4 dx (2D) / 3 dx (3D) centred at 0 (densities within 3 % of its
/// rest density, random accelerations that the stage adds to), and a slab of solid particles at
/// `x ≈ R + 2 dx` touching it. γ or σ' makes the tension comparable with the accelerations; with
/// several phases every other fluid particle has rest density, mass and density 0.8 of ρ0's.
/// Storage order shuffled and ids permuted, as `setup::scene`.
fn droplet<const D: usize>(
    seed: u64,
    model: SurfaceTensionModel,
    phases: Phases,
) -> (Fields<D>, StepParams<D>) {
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
        let light = phases == Phases::Multi && kind == FLUID && f.len() % 2 == 0;
        let rest = if light { 0.8 * RHO0 } else { RHO0 };
        f.push(
            x,
            Vector::zeros(),
            mass * rest / RHO0,
            rest * (1.0 + rng.sym(0.03)),
            kind,
        );
        if phases == Phases::Multi {
            f.rest_density.push(rest);
        }
        *f.acceleration.last_mut().expect("pushed") = Vector::from_fn(|_, _| rng.sym(1.0));
    }
    for i in (1..f.len()).rev() {
        let j = rng.below(i + 1);
        swap_particles(&mut f, i, j);
    }
    for i in (1..f.len()).rev() {
        f.id.swap(i, rng.below(i + 1));
    }
    let lo = Vector::<D>::from_element(-(span as f32 + 2.0) * DX);
    let akinci = model == SurfaceTensionModel::Akinci;
    let p = StepParams {
        h: 2.0 * DX,
        rho0: RHO0,
        c2: 400.0,
        pair: Default::default(),
        c: 20.0,
        pressure_gradient_scale: 1.05,
        gravity: Vector::zeros(),
        domain_min: lo,
        domain_max: -lo,
        angular_velocity: [0.0; 3],
        rotation_centre: Vector::zeros(),
        viscosity_scale: 1.0,
        surface_tension_gamma: if akinci { 2.0 } else { 0.0 },
        surface_tension_sigma: if akinci { 0.0 } else { 5.0 },
        spacing: DX,
        density_spiky_scale: 0.0,
        density_kernel: DensityKernel::Poly6,
        surface_tension_model: model,
        rotating_frame: 0,
        phases,
        density_diffusion: 0.0,
        artificial_viscosity_wall_factor: 1.0,
        periodic: sph::periodic::PeriodicAxes::NONE,
    };
    (f, p)
}

/// The fluid neighbours `j ≠ i` of fluid particle `i` of `f` within `h` (brute force), with
/// `x_i − x_j` and its squared length. The droplet's jitter keeps every pair far from coinciding
/// (`smoothing::pair_offset` leaves them alone).
fn fluid_neighbours<const D: usize>(f: &Fields<D>, h: f32, i: usize) -> Vec<(usize, Vector<D>, f32)> {
    (0..f.len())
        .filter(|&j| j != i && f.kind[j] == FLUID)
        .filter_map(|j| {
            let d = f.position[i] - f.position[j];
            let r2 = d.norm_squared();
            (r2 < h * h).then_some((j, d, r2))
        })
        .collect()
}

/// [AAT13] eq. (3) for fluid particle `i` (id order), `h Σ_j (m_j/ρ_j) ∇W`, each neighbour's
/// rest volume `m_j/ρ0_j` with the surface stress (`physics::surface_stress`); and the sum of
/// the terms' magnitudes.
fn reference_normal<const D: usize>(f: &Fields<D>, p: &StepParams<D>, i: usize) -> (Vector<D>, f64) {
    let kernel = p.smoothing();
    let rest_volume = p.surface_tension_model == SurfaceTensionModel::SurfaceStress;
    let (mut sum, mut scale) = (Vector::<D>::zeros(), 0.0f64);
    for (j, d, _) in fluid_neighbours(f, p.h, i) {
        let rho_j = if rest_volume {
            p.phases.rest_density(&f.rest_density, j, p.rho0)
        } else {
            f.density[j]
        };
        let t = normal_term(&kernel, f.mass[j], rho_j, &d);
        sum += t;
        scale += f64::from((t * p.h).norm());
    }
    (sum * p.h, scale)
}

/// The acceleration of fluid particle `i` (id order) after the stage, its input plus the pair
/// terms of its fluid neighbours from `normal` (by id), and the sum of the magnitudes of the
/// input and the terms: the surface stress's `m_j/(ρ0_i ρ0_j) (T_i + T_j)·∇W t`, or [AAT13]
/// eqs. (1)–(5).
fn reference_tension<const D: usize>(
    f: &Fields<D>,
    p: &StepParams<D>,
    normal: &[Vector<D>],
    i: usize,
) -> (Vector<D>, f64) {
    let kernel = p.smoothing();
    let rest = |j: usize| p.phases.rest_density(&f.rest_density, j, p.rho0);
    let w_dx = kernel.w(p.spacing * p.spacing);
    let (mut sum, mut scale) = (Vector::<D>::zeros(), f64::from(f.acceleration[i].norm()));
    for (j, d, r2) in fluid_neighbours(f, p.h, i) {
        let t = match p.surface_tension_model {
            SurfaceTensionModel::SurfaceStress => surface_stress_acceleration(
                p.surface_tension_sigma,
                p.h,
                f.mass[j],
                rest(i),
                rest(j),
                &normal[i],
                &normal[j],
                &(kernel.grad_w_spiky(&d, r2.sqrt()) * p.pressure_gradient_scale),
                tensile_factor(kernel.w(r2), w_dx),
            ),
            SurfaceTensionModel::Akinci => surface_tension_acceleration(
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
            ),
        };
        sum += t;
        scale += f64::from(t.norm());
    }
    (f.acceleration[i] + sum, scale)
}

/// Largest `|a − b|` per component over the particles of `fluid`, relative to `a`'s scale.
fn largest_change<const D: usize>(fluid: &[usize], a: &[(Vector<D>, f64)], b: &[(Vector<D>, f64)]) -> f64 {
    fluid
        .iter()
        .map(|&i| {
            (0..D)
                .map(|k| f64::from(a[i].0[k] - b[i].0[k]).abs() / a[i].1)
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

fn check<const D: usize>(seed: u64, model: SurfaceTensionModel, phases: Phases) {
    let (f, p) = droplet::<D>(seed, model, phases);
    let reference = in_id_order(&f);
    let n = reference.len();
    let fluid: Vec<usize> = (0..n).filter(|&i| reference.kind[i] == FLUID).collect();
    let normals = |f: &Fields<D>, p: &StepParams<D>| -> Vec<(Vector<D>, f64)> {
        (0..n)
            .map(|i| {
                if f.kind[i] == FLUID {
                    reference_normal(f, p, i)
                } else {
                    (Vector::zeros(), 0.0)
                }
            })
            .collect()
    };
    let tensions = |f: &Fields<D>, p: &StepParams<D>, normal: &[(Vector<D>, f64)]| {
        let normal: Vec<Vector<D>> = normal.iter().map(|(v, _)| *v).collect();
        (0..n)
            .map(|i| {
                if f.kind[i] == FLUID {
                    reference_tension(f, p, &normal, i)
                } else {
                    (f.acceleration[i], 0.0)
                }
            })
            .collect::<Vec<_>>()
    };
    let what = format!("{model:?} {phases:?}");

    // The reference is not vacuous: the droplet has a surface (|n| of order 1 there), the
    // stage moves accelerations by far more than the tolerance, a solid neighbour counted as
    // fluid would show, and so would the phases' rest densities in the surface stress.
    let want_normal = normals(&reference, &p);
    let want_tension = tensions(&reference, &p, &want_normal);
    let surface = fluid
        .iter()
        .map(|&i| want_normal[i].0.norm())
        .fold(0.0f32, f32::max);
    assert!(surface > 0.5, "{D}D {what}: largest |n| = {surface}");
    let input: Vec<(Vector<D>, f64)> = (0..n).map(|i| (reference.acceleration[i], 0.0)).collect();
    let mut variants = vec![("the tension", largest_change(&fluid, &want_tension, &input))];
    let mut all_fluid = reference.clone();
    all_fluid.kind.fill(FLUID);
    let wet = normals(&all_fluid, &p);
    variants.push((
        "solid neighbours in the normals",
        largest_change(&fluid, &want_normal, &wet),
    ));
    variants.push((
        "solid neighbours in the tension",
        largest_change(&fluid, &want_tension, &tensions(&all_fluid, &p, &want_normal)),
    ));
    if phases == Phases::Multi && model == SurfaceTensionModel::SurfaceStress {
        let single = StepParams {
            phases: Phases::Single,
            ..p
        };
        let one_phase = normals(&reference, &single);
        variants.push((
            "rest volumes in the normals",
            largest_change(&fluid, &want_normal, &one_phase),
        ));
        variants.push((
            "rest densities in the tension",
            largest_change(
                &fluid,
                &want_tension,
                &tensions(&reference, &single, &want_normal),
            ),
        ));
    }
    for (name, effect) in variants {
        assert!(
            effect > 100.0 * SUM_ORDER,
            "{D}D {what}: {name} must be visible: {effect:.2e}"
        );
    }

    for under in backends() {
        let (out, ()) = under.run(&f, &p, |b, f| {
            b.surface_normals(f, &p);
            b.surface_tension(f, &p);
        });
        let got_normal = by_id(&out, &out.normal);
        let got_acceleration = by_id(&out, &out.acceleration);
        for id in (0..n).filter(|&id| reference.kind[id] != FLUID) {
            assert_eq!(
                got_normal[id],
                Vector::<D>::zeros(),
                "{under:?} {D}D {what}: solid {id}: zero normal"
            );
            assert_eq!(
                got_acceleration[id], reference.acceleration[id],
                "{under:?} {D}D {what}: solid {id}: acceleration untouched"
            );
        }
        // The tension from the normals the backend computed (themselves checked against the
        // brute-force ones below), so that each stage's sum is compared on its own.
        let backend_normal: Vec<(Vector<D>, f64)> = got_normal.iter().map(|&v| (v, 0.0)).collect();
        let want_from_got = tensions(&reference, &p, &backend_normal);
        let (mut worst_n, mut worst_a) = (0.0f64, 0.0f64);
        for &id in &fluid {
            // Neighbour sums in another order: `SUM_ORDER` of the terms' magnitudes.
            let (n_want, n_scale) = want_normal[id];
            assert_close(
                under,
                &format!("{what} normal"),
                id,
                &got_normal[id],
                &n_want,
                SUM_ORDER * n_scale,
            );
            let (a_want, a_scale) = want_from_got[id];
            assert_close(
                under,
                &format!("{what} acceleration"),
                id,
                &got_acceleration[id],
                &a_want,
                SUM_ORDER * a_scale,
            );
            for k in 0..D {
                worst_n = worst_n.max(f64::from(got_normal[id][k] - n_want[k]).abs() / n_scale);
                worst_a = worst_a.max(f64::from(got_acceleration[id][k] - a_want[k]).abs() / a_scale);
            }
        }
        eprintln!(
            "{under:?} {D}D surface tension {what}: worst |got − want|/Σ|terms|: normals {worst_n:.2e}, accelerations {worst_a:.2e}"
        );
    }
}

/// Both models, one phase and several ([AAT13] reads no rest density: there the phases differ
/// only by their masses and densities).
#[test]
fn surface_normals_and_tension_are_the_brute_force_sums_for_every_model() {
    for model in [SurfaceTensionModel::SurfaceStress, SurfaceTensionModel::Akinci] {
        for phases in [Phases::Single, Phases::Multi] {
            check::<2>(0x9e37_79b9_7f4a_7c15, model, phases);
            check::<3>(0x2545_f491_4f6c_dd1d, model, phases);
        }
    }
}
