//! Solids that turn (`boundary::rigid`) on every backend: `move_solids` places each particle at
//! `c + d + R (x0 − c)` with the velocity `d' + ω × r`, and `wall_pressure` ([A12] eq. 27) uses
//! the wall's acceleration at each particle, `d'' + α × r + ω × (ω × r)`, not one per solid.

use crate::boundary::{other_bits, reference_wall_pressure};
use crate::setup::{Rng, backends, by_id, in_id_order, solid_scene};
use sph::backend::WallModel;
use sph::boundary::motion::{Rotation, SolidKinematics, SolidReference, Turn};
use sph::fields::FLUID;
use sph::math::Vector;

/// A unit axis: `z` in 2D, a random direction in 3D.
fn axis<const D: usize>(rng: &mut Rng) -> [f64; 3] {
    if D == 2 {
        return [0.0, 0.0, 1.0];
    }
    let v = [rng.sym(1.0), rng.sym(1.0), 0.5 + rng.next()].map(f64::from);
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / n)
}

/// `R x` in f64 by Rodrigues' formula, `x cos θ + (n × x) sin θ + n (n · x)(1 − cos θ)`,
/// written here from the angle, independently of `Turn`'s `R − I`.
fn rotate(n: [f64; 3], theta: f64, x: [f64; 3]) -> [f64; 3] {
    let (s, c) = theta.sin_cos();
    let nx = cross(n, x);
    let dot = n[0] * x[0] + n[1] * x[1] + n[2] * x[2];
    [0, 1, 2].map(|k| x[k] * c + nx[k] * s + n[k] * dot * (1.0 - c))
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn embed<const D: usize>(v: &Vector<D>) -> [f64; 3] {
    [0, 1, 2].map(|k| if k < D { f64::from(v[k]) } else { 0.0 })
}

/// The mean position of the solids [m]: a pivot inside the scene.
fn centre<const D: usize>(reference: &SolidReference<D>) -> Vec<f64> {
    let n = reference.position.len() as f64;
    (0..D)
        .map(|k| reference.position.iter().map(|x| f64::from(x[k])).sum::<f64>() / n)
        .collect()
}

/// A turn of `theta` [rad] about `axis` through `pivot` with the translation, velocity and
/// acceleration of the pivot drawn from `rng`.
fn turning<const D: usize>(rng: &mut Rng, pivot: &[f64], axis: [f64; 3], theta: f64) -> SolidKinematics<D> {
    SolidKinematics {
        displacement: Vector::from_fn(|_, _| rng.sym(0.05)),
        velocity: Vector::from_fn(|_, _| rng.sym(0.8)),
        acceleration: Vector::from_fn(|_, _| rng.sym(9.0)),
        rotation: Rotation::About(Turn::about_axis(pivot, axis, theta, 7.0, -300.0)),
    }
}

/// `move_solids` with solid 1 turning by 0.4 rad and solid 2 translating: on every backend each
/// solid particle sits bitwise where `SolidKinematics::position` puts it, with
/// `velocity_at` there (the kernels repeat its f32 operations, `--fmad=false`); and that is
/// `c + d + R (x0 − c)`, `d' + ω × R (x0 − c)` evaluated in f64 from the angle, within f32
/// rounding of the inputs (positions of order 0.1 m: 1e-6 m; speeds ω |r| of order 1 m/s:
/// 1e-5 m/s).
fn check_turning_solids<const D: usize>(seed: u64) {
    let (f, p, reference) = solid_scene::<D>(seed);
    let mut rng = Rng(seed ^ 0x7a11);
    let pivot = centre(&reference);
    let (n, theta) = (axis::<D>(&mut rng), 0.4);
    let kinematics = vec![
        turning::<D>(&mut rng, &pivot, n, theta),
        SolidKinematics {
            displacement: Vector::from_fn(|_, _| rng.sym(0.05)),
            velocity: Vector::from_fn(|_, _| rng.sym(0.8)),
            ..SolidKinematics::rest()
        },
    ];
    let r = in_id_order(&f);
    let first = reference.first_id as usize;
    for under in backends() {
        let (out, ()) = under.run(&f, &p, |b, f| b.move_solids(f, &reference, &kinematics));
        let got = in_id_order(&out);
        let (mut turned, mut worst_x, mut worst_u) = (0, 0.0f64, 0.0f64);
        for id in 0..r.len() {
            assert_eq!(
                other_bits(&got, id),
                other_bits(&r, id),
                "{under:?} {D}D: particle {id}"
            );
            if r.kind[id] == FLUID {
                assert_eq!(
                    got.position[id], r.position[id],
                    "{under:?} {D}D: fluid {id} stays"
                );
                continue;
            }
            let k = &kinematics[r.kind[id] as usize - 1];
            let x0 = reference.position[id - first];
            let x = k.position(&x0);
            let bits = |v: &Vector<D>| v.map(f32::to_bits);
            assert_eq!(
                bits(&got.position[id]),
                bits(&x),
                "{under:?} {D}D: position of {id}"
            );
            assert_eq!(
                bits(&got.velocity[id]),
                bits(&k.velocity_at(&x)),
                "{under:?} {D}D: velocity of {id}"
            );
            if r.kind[id] != 1 {
                continue;
            }
            turned += 1;
            let arm = rotate(
                n,
                theta,
                [0, 1, 2].map(|c| embed(&x0)[c] - pivot.get(c).copied().unwrap_or(0.0)),
            );
            let spin = cross(n.map(|c| 7.0 * c), arm);
            for c in 0..D {
                let want_x = pivot[c] + f64::from(k.displacement[c]) + arm[c];
                let want_u = f64::from(k.velocity[c]) + spin[c];
                worst_x = worst_x.max((f64::from(got.position[id][c]) - want_x).abs());
                worst_u = worst_u.max((f64::from(got.velocity[id][c]) - want_u).abs());
            }
        }
        assert!(turned > 50, "{under:?} {D}D: {turned} particles turned");
        assert!(
            worst_x < 1e-6,
            "{under:?} {D}D: position off the f64 rotation by {worst_x:e} m"
        );
        assert!(
            worst_u < 1e-5,
            "{under:?} {D}D: velocity off ω × r by {worst_u:e} m/s"
        );
    }
}

#[test]
fn move_solids_turns_particles_about_the_pivot_on_every_backend() {
    check_turning_solids::<2>(0x51de_ba5e_0f1a_9000);
    check_turning_solids::<3>(0x0ddf_1a9c_afe0_0123);
}

/// `wall_pressure` with a floor that turns fast (ω = 7 rad/s, α = −300 rad/s² about the
/// solids' centre): the wall acceleration differs from particle to particle by `α × r`
/// (3 m/s² per cm of arm), which moves the extrapolated pressure of many walls far beyond the
/// tolerance compared to the same floor translating with its pivot's `d''`; every backend
/// matches the brute-force reference (`boundary::reference_wall_pressure` with
/// `acceleration_at`) within its summation-order tolerance.
fn check_turning_wall_pressure<const D: usize>(seed: u64) {
    let (f, p, reference) = solid_scene::<D>(seed);
    let mut rng = Rng(seed ^ 0x0a11);
    let pivot = centre(&reference);
    let n = axis::<D>(&mut rng);
    let turn = turning::<D>(&mut rng, &pivot, n, 0.0);
    let translation = SolidKinematics {
        rotation: Rotation::None,
        ..turn
    };
    let model = WallModel::Extrapolated;
    let r = in_id_order(&f);
    let want = |kinematics: &[SolidKinematics<D>]| -> Vec<(f64, f64)> {
        (0..r.len())
            .map(|w| match r.kind[w] {
                FLUID => (0.0, 0.0),
                _ => reference_wall_pressure(&r, &p, model, kinematics, w),
            })
            .collect()
    };
    let turning = vec![turn, SolidKinematics::rest()];
    let (with_turn, without) = (want(&turning), want(&[translation, SolidKinematics::rest()]));
    let changed = (0..r.len())
        .filter(|&w| r.kind[w] == 1)
        .filter(|&w| (with_turn[w].0 - without[w].0).abs() > 100.0 * with_turn[w].1.max(without[w].1))
        .count();
    assert!(changed > 10, "{D}D: the turn changed {changed} wall pressures");
    for under in backends() {
        let (out, ()) = under.run(&f, &p, |b, f| b.wall_pressure(f, &p, model, &turning));
        let pressure = by_id(&out, &out.pressure);
        for id in (0..r.len()).filter(|&id| r.kind[id] != FLUID) {
            let (p_want, p_tol) = with_turn[id];
            let dp = (f64::from(pressure[id]) - p_want).abs();
            assert!(
                dp <= p_tol,
                "{under:?} {D}D: wall {id}: p {} want {p_want} ± {p_tol:.2e}",
                pressure[id]
            );
        }
    }
}

#[test]
fn wall_pressure_uses_each_particles_acceleration_on_a_turning_solid() {
    check_turning_wall_pressure::<2>(0x7e57_0fa1_1b0b);
    check_turning_wall_pressure::<3>(0x0123_4567_89ab_cdef);
}
