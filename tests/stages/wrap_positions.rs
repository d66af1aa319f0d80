//! Periodic boundaries (`sph::periodic`) on every backend, on the stage-test scene made
//! periodic along x with the period `[−2 dx, n dx)`: the left wall then sits across the seam
//! from the fluid's right end, one to two spacings away, so the seam is inside every support.
//! - `wrap_positions`: a fluid particle that left the period comes back one period away, mass
//!   and velocity bitwise kept, solids untouched; per particle, the same f32 operations as
//!   `Periodic::wrap`, so compared bitwise. A particle that `integrate` carries across the face
//!   enters at the other side with its mass and momentum.
//! - The neighbour search across the seam: the `density` stage against a brute-force sum over
//!   minimum-image offsets (`SUM_ORDER`, as `density.rs`), which a grid that missed the seam
//!   fails by whole terms at the ends of the fluid.

use crate::setup::{DX, SUM_ORDER, backends, by_id, in_id_order, scene};
use sph::fields::{FLUID, Fields};
use sph::math::Vector;
use sph::model::params::StepParams;
use sph::periodic::PeriodicAxes;

/// The stage-test scene, periodic along x over `[−2 dx, n_x dx)`: the walls' and the fluid's
/// x range, so every particle starts inside the period.
fn periodic_scene<const D: usize>(seed: u64) -> (Fields<D>, StepParams<D>) {
    let (f, mut p) = scene::<D>(seed);
    let right = (0..f.len())
        .map(|i| f.position[i][0])
        .fold(f32::NEG_INFINITY, f32::max);
    p.periodic = PeriodicAxes::NONE.with(0);
    p.domain_min[0] = -2.0 * DX;
    // The lattice's next column: the period is a whole number of spacings.
    p.domain_max[0] = ((right / DX).floor() + 1.0) * DX;
    assert!(
        f.position
            .iter()
            .all(|x| x[0] >= p.domain_min[0] && x[0] < p.domain_max[0])
    );
    (f, p)
}

fn check_wrap<const D: usize>(seed: u64) {
    let (mut f, p) = periodic_scene::<D>(seed);
    let (lo, hi) = (p.domain_min[0], p.domain_max[0]);
    // Fluid particles (by storage index, fluid only) put just past either face, on the excluded
    // face itself, and one a hair below the lower face.
    let fluid: Vec<usize> = (0..f.len()).filter(|&i| f.kind[i] == FLUID).collect();
    let outside = [hi + 0.3 * DX, lo - 0.4 * DX, hi, lo - 1e-9, hi + 1.7 * DX];
    for (k, &x) in outside.iter().enumerate() {
        f.position[fluid[7 * k + 3]][0] = x;
    }
    let reference = in_id_order(&f);
    let periodic = p.periodic();
    let want: Vec<Vector<D>> = (0..reference.len())
        .map(|i| {
            if reference.kind[i] == FLUID {
                periodic.wrap(reference.position[i])
            } else {
                reference.position[i]
            }
        })
        .collect();
    let moved = (0..reference.len())
        .filter(|&i| want[i] != reference.position[i])
        .count();
    assert_eq!(moved, outside.len(), "{D}D: every particle outside moves");
    for under in backends() {
        let (out, ()) = under.run(&f, &p, |b, f| b.wrap_positions(f, &p));
        let got = by_id(&out, &out.position);
        for id in 0..reference.len() {
            assert_eq!(
                got[id].map(f32::to_bits),
                want[id].map(f32::to_bits),
                "{under:?} {D}D particle {id} from {:?}",
                reference.position[id]
            );
            if reference.kind[id] == FLUID {
                assert!(
                    got[id][0] >= lo && got[id][0] < hi,
                    "{under:?} {D}D particle {id}"
                );
            }
        }
        assert_eq!(by_id(&out, &out.mass), reference.mass, "{under:?}: masses kept");
        assert_eq!(
            by_id(&out, &out.velocity),
            reference.velocity,
            "{under:?}: velocities kept"
        );
        eprintln!("{under:?} {D}D wrap_positions: bitwise equal, {moved} particles moved");
    }
}

#[test]
fn wrap_positions_moves_leavers_one_period_and_keeps_mass_and_velocity() {
    check_wrap::<2>(0x0bad_5eed_0a11_d0d0);
    check_wrap::<3>(0x5eed_d0d0_0bad_0a11);
}

/// A fluid particle half a spacing below the upper face moving at +1 m/s along x is carried
/// 0.8 dx across it by `integrate` and enters at the lower face, 0.3 dx inside; its mass and
/// velocity, and the fluid's total mass and momentum, are kept (to f32 rounding of the sums).
fn check_crossing<const D: usize>(seed: u64) {
    let (mut f, mut p) = periodic_scene::<D>(seed);
    p.gravity = Vector::zeros();
    let (lo, hi) = (p.domain_min[0], p.domain_max[0]);
    let i = (0..f.len()).find(|&i| f.kind[i] == FLUID).expect("fluid");
    f.position[i][0] = hi - 0.5 * DX;
    f.velocity[i] = Vector::zeros();
    f.velocity[i][0] = 1.0;
    f.acceleration.iter_mut().for_each(|a| *a = Vector::zeros());
    let id = f.id[i] as usize;
    let dt = 0.8 * DX;
    let momentum = |f: &Fields<D>| -> Vec<f64> {
        (0..D)
            .map(|k| {
                (0..f.len())
                    .filter(|&i| f.kind[i] == FLUID)
                    .map(|i| f64::from(f.mass[i]) * f64::from(f.velocity[i][k]))
                    .sum()
            })
            .collect()
    };
    let mass = |f: &Fields<D>| -> f64 { f.mass.iter().map(|&m| f64::from(m)).sum() };
    for under in backends() {
        let (out, ()) = under.run(&f, &p, |b, f| {
            b.integrate(f, dt);
            b.wrap_positions(f, &p);
        });
        let x = by_id(&out, &out.position)[id];
        assert!(
            (x[0] - (lo + 0.3 * DX)).abs() <= 1e-6,
            "{under:?} {D}D: entered at {x:?}, expected x = {}",
            lo + 0.3 * DX
        );
        assert_eq!(by_id(&out, &out.velocity)[id][0], 1.0, "{under:?}: velocity kept");
        assert_eq!(mass(&out), mass(&f), "{under:?}: total mass kept");
        for (a, b) in momentum(&out).iter().zip(momentum(&f)) {
            assert!((a - b).abs() <= 1e-9 * mass(&f), "{under:?}: momentum {a} vs {b}");
        }
    }
}

#[test]
fn a_particle_leaving_one_face_enters_the_other_with_its_mass_and_momentum() {
    check_crossing::<2>(0x1eaf_5eed_0a11_d0d0);
    check_crossing::<3>(0x5eed_1eaf_d0d0_0a11);
}

/// Eq. (18) by brute force over minimum-image offsets, for fluid particle `i` of `f` (id order).
fn reference_density<const D: usize>(f: &Fields<D>, p: &StepParams<D>, i: usize) -> (f64, usize) {
    let kernel = p.smoothing();
    let periodic = p.periodic();
    let mut across = 0;
    let mut sum = 0.0;
    for j in 0..f.len() {
        let raw = f.position[i] - f.position[j];
        let d = periodic.minimum_image(raw);
        let r2 = d.norm_squared();
        if r2 < p.h * p.h {
            across += usize::from(d != raw);
            sum += f64::from(f.mass[j] * kernel.w(r2));
        }
    }
    (sum, across)
}

fn check_density_across<const D: usize>(seed: u64) {
    let (f, p) = periodic_scene::<D>(seed);
    let reference = in_id_order(&f);
    let (mut seam, mut worst) = (0, 0.0f64);
    for under in backends() {
        let (out, ()) = under.run(&f, &p, |b, f| b.density(f, &p));
        let got = by_id(&out, &out.density);
        for id in (0..reference.len()).filter(|&i| reference.kind[i] == FLUID) {
            let (want, across) = reference_density(&reference, &p, id);
            seam += usize::from(across > 0);
            let diff = (f64::from(got[id]) - want).abs() / want;
            assert!(
                diff <= SUM_ORDER,
                "{under:?} {D}D: particle {id} ({across} neighbours across the seam): {} against {want}",
                got[id]
            );
            worst = worst.max(diff);
        }
        eprintln!("{under:?} {D}D periodic density: worst {worst:.2e} of the sum");
    }
    assert!(seam > 0, "{D}D: fluid particles see across the seam");
}

#[test]
fn density_sums_across_the_periodic_seam_on_every_backend() {
    check_density_across::<2>(0x5ea3_0a11_d0d0_beef);
    check_density_across::<3>(0x0a11_5ea3_beef_d0d0);
}
