//! The `forces` stage, eqs. (15)–(17) and (6), for every term set (`ForceTerms`), with one
//! phase and with [HA06]'s volume-form pressure force, with no-slip wall velocities ([A12]
//! eqs. 22–23) and without, on every backend, against brute-force sums.

use crate::setup::{
    SUM_ORDER, add_strays, all_force_terms, assert_close, backends, by_id, in_id_order, neighbours, norm,
    scene, use_phases,
};
use sph::fields::{FLUID, Fields};
use sph::math::Vector;
use sph::model::ForceTerms;
use sph::model::pair_terms::PairTerm;
use sph::model::params::StepParams;
use sph::physics::artificial_viscosity::artificial_viscous_acceleration;
use sph::physics::multiphase::{self, Phases};
use sph::physics::pressure::pressure_acceleration;
use sph::physics::rotating_frame::rotating_frame_acceleration;
use sph::physics::viscosity::viscous_acceleration;

/// Each particle's neighbours (brute force, [`neighbours`]), listed once per scene.
type Pairs<const D: usize> = Vec<Vec<(usize, Vector<D>, f32)>>;

/// Eqs. (15)–(17) and (6) for fluid particle `i` of `f` (id order) by brute force, and the sum
/// of its terms' magnitudes (gravity and the rotating frame included): gravity, the rotating
/// frame ([B67] §3.2) when asked, and per neighbour (fluid or solid) the pressure term (16), or
/// [HA06]'s `−(p_i V_i² + p_j V_j²) ∇W/m_i` with several phases, the artificial viscosity
/// ([M92], its α times `p.artificial_viscosity_wall_factor` with a solid neighbour) and (17)
/// scaled by `viscosity_scale`, a solid neighbour carrying its no-slip velocity
/// where `wall_velocity` is allocated.
fn reference_acceleration<const D: usize>(
    f: &Fields<D>,
    p: &StepParams<D>,
    pairs: &Pairs<D>,
    terms: ForceTerms,
    i: usize,
) -> (Vector<D>, f64) {
    let kernel = p.smoothing();
    let (p_i, rho_i, u_i, m_i) = (f.pressure[i], f.density[i], f.velocity[i], f.mass[i]);
    let mut a = p.gravity;
    let mut scale = norm(&p.gravity);
    let mut add = |t: Vector<D>| {
        a += t;
        scale += norm(&t);
    };
    if terms.rotating_frame {
        add(rotating_frame_acceleration(
            &p.angular_velocity,
            &p.rotation_centre,
            &f.position[i],
            &u_i,
        ));
    }
    for &(j, d, r) in &pairs[i] {
        let (m_j, rho_j) = (f.mass[j], f.density[j]);
        let grad = kernel.grad_w_spiky(&d, r) * p.pressure_gradient_scale;
        add(match p.phases {
            Phases::Single => pressure_acceleration(p_i, rho_i, f.pressure[j], rho_j, m_j, &grad),
            Phases::Multi => multiphase::pressure_acceleration(
                multiphase::pressure_term(p_i, m_i, rho_i),
                multiphase::pressure_term(f.pressure[j], m_j, rho_j),
                m_i,
                &grad,
            ),
        });
        if terms.pair.contains(PairTerm::ArtificialViscosity) {
            let u_ij = u_i - f.velocity[j];
            let factor = if f.kind[j] == FLUID {
                1.0
            } else {
                p.artificial_viscosity_wall_factor
            };
            add(artificial_viscous_acceleration(
                p.pair.alpha * factor,
                p.c,
                p.h,
                &d,
                &u_ij,
                rho_i,
                rho_j,
                m_j,
                &grad,
            ));
        }
        if terms.pair.contains(PairTerm::Viscosity) {
            let u_j = match f.wall_velocity.get(j) {
                Some(wall) if f.kind[j] != FLUID => *wall,
                _ => f.velocity[j],
            };
            let lap = kernel.laplacian_w_viscosity(r);
            add(viscous_acceleration(
                p.pair.mu * p.viscosity_scale,
                &u_i,
                &u_j,
                rho_i,
                rho_j,
                m_j,
                lap,
            ));
        }
    }
    (a, scale)
}

/// The scene with strays, its phases and its wall velocities: with several phases every third
/// particle has an eighth of the rest density, mass and density (a light phase); without
/// `no_slip` the `wall_velocity` field is not allocated, so solids carry their own velocity.
fn forces_scene<const D: usize>(seed: u64, phases: Phases, no_slip: bool) -> (Fields<D>, StepParams<D>) {
    let (mut f, mut p) = scene::<D>(seed);
    add_strays(&mut f, &p, seed ^ 0x5151);
    use_phases(&mut f, &mut p, phases, true);
    if !no_slip {
        f.wall_velocity.clear();
    }
    (f, p)
}

/// Largest `|a − b|/scale` per component over fluid particles.
fn largest_change<const D: usize>(want: &[(Vector<D>, f64)], other: &[(Vector<D>, f64)]) -> f64 {
    want.iter()
        .zip(other)
        .map(|((a, scale), (b, _))| {
            (0..D)
                .map(|k| f64::from(a[k] - b[k]).abs() / scale)
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

fn check_forces<const D: usize>(seed: u64, phases: Phases, no_slip: bool, wall_factor: f32) {
    let (f, mut p) = forces_scene::<D>(seed, phases, no_slip);
    p.artificial_viscosity_wall_factor = wall_factor;
    let reference = in_id_order(&f);
    let n = reference.len();
    let pairs: Pairs<D> = (0..n).map(|i| neighbours(&reference, p.h, i)).collect();
    let fluid: Vec<usize> = (0..n).filter(|&i| reference.kind[i] == FLUID).collect();
    let all = |f: &Fields<D>, p: &StepParams<D>, terms: ForceTerms| -> Vec<(Vector<D>, f64)> {
        fluid
            .iter()
            .map(|&i| reference_acceleration(f, p, &pairs, terms, i))
            .collect()
    };
    for terms in all_force_terms() {
        let want = all(&reference, &p, terms);
        // Every part of the reference moves some acceleration by far more than the tolerance,
        // so that a backend that drops or mistakes it fails.
        let mut variants: Vec<(&str, Vec<(Vector<D>, f64)>)> = Vec::new();
        let mut unpressured = reference.clone();
        unpressured.pressure.fill(0.0);
        variants.push(("pressure (16)", all(&unpressured, &p, terms)));
        let weightless = StepParams {
            gravity: Vector::zeros(),
            ..p
        };
        variants.push(("gravity (6)", all(&reference, &weightless, terms)));
        for term in terms.pair.iter() {
            let without = ForceTerms {
                pair: terms.pair.without(term),
                ..terms
            };
            variants.push((term.label(), all(&reference, &p, without)));
        }
        if terms.pair.contains(PairTerm::ArtificialViscosity) {
            let other = StepParams {
                artificial_viscosity_wall_factor: 1.0 - wall_factor,
                ..p
            };
            variants.push((
                "the artificial viscosity's wall factor",
                all(&reference, &other, terms),
            ));
        }
        if terms.rotating_frame {
            let without = ForceTerms {
                rotating_frame: false,
                ..terms
            };
            variants.push(("rotating frame", all(&reference, &p, without)));
        }
        if phases == Phases::Multi {
            let single = StepParams {
                phases: Phases::Single,
                ..p
            };
            variants.push(("[HA06] volume form", all(&reference, &single, terms)));
        }
        let viscous = terms.pair.contains(PairTerm::Viscosity);
        if no_slip && viscous {
            let mut slip = reference.clone();
            slip.wall_velocity.clear();
            variants.push(("no-slip wall velocity", all(&slip, &p, terms)));
        }
        if !no_slip && viscous {
            let mut still = reference.clone();
            for i in (0..n).filter(|&i| still.kind[i] != FLUID) {
                still.velocity[i] = Vector::zeros();
            }
            variants.push(("the solids' own velocity", all(&still, &p, terms)));
        }
        for (name, other) in variants {
            let effect = largest_change(&want, &other);
            assert!(
                effect > 100.0 * SUM_ORDER,
                "{D}D {terms:?} {phases:?}: {name} must be visible: {effect:.2e}"
            );
        }

        let what = format!("forces {terms:?} {phases:?} no-slip {no_slip} wall factor {wall_factor}");
        for under in backends() {
            let (out, ()) = under.run(&f, &p, |b, f| b.forces(f, &p, terms));
            let got = by_id(&out, &out.acceleration);
            for id in (0..n).filter(|&id| reference.kind[id] != FLUID) {
                assert_eq!(
                    got[id],
                    Vector::<D>::zeros(),
                    "{under:?} {D}D {what}: solid {id} gets no acceleration"
                );
            }
            let mut worst = 0.0f64;
            for (&id, (a, scale)) in fluid.iter().zip(&want) {
                // A neighbour sum in another order: `SUM_ORDER` of the terms' magnitudes.
                assert_close(under, &what, id, &got[id], a, SUM_ORDER * scale);
                for k in 0..D {
                    worst = worst.max(f64::from(got[id][k] - a[k]).abs() / scale);
                }
            }
            eprintln!("{under:?} {D}D {what}: worst |got − want|/Σ|terms| {worst:.2e}");
        }
    }
}

#[test]
fn forces_are_the_brute_force_sums_for_every_term_set() {
    for phases in [Phases::Single, Phases::Multi] {
        check_forces::<2>(0x9e37_79b9_7f4a_7c15, phases, true, 1.0);
        check_forces::<3>(0x2545_f491_4f6c_dd1d, phases, true, 1.0);
    }
}

/// `fluid.artificial_viscosity_wall_factor`: [M92]'s α between fluid and solid particles times
/// the factor, on every backend; at 0 it acts between fluid particles only.
#[test]
fn the_wall_factor_scales_the_artificial_viscosity_across_walls() {
    for factor in [0.0, 0.25] {
        check_forces::<2>(0x5eed_0fa1_15ee_d001, Phases::Single, true, factor);
        check_forces::<3>(0x0ddb_a11c_0ffe_e002, Phases::Single, true, factor);
    }
}

#[test]
fn without_no_slip_velocities_a_solid_carries_its_own_velocity_in_17() {
    check_forces::<2>(0x0123_4567_89ab_cdef, Phases::Single, false, 1.0);
    check_forces::<3>(0xfedc_ba98_7654_3210, Phases::Single, false, 1.0);
}
