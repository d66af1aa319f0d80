//! The `solid_forces` stage (Fig. 4) on every backend, for both sources (the force stage's
//! pressures with (16) and every pair term; the correction's increments `δp` of eqs. 23–24
//! with none) and both phase models ([HA06] volume-form pressure term), against brute-force sums
//! of each term's physics function over every solid particle and its fluid neighbours.

use crate::setup::{SOLIDS, SUM_ORDER, add_strays, backends, in_id_order, neighbours, scene, use_phases};
use sph::backend::SolidForceSource;
use sph::fields::{FLUID, Fields};
use sph::math::Vector;
use sph::model::pair_terms::{PairTerm, PairTerms};
use sph::model::params::StepParams;
use sph::physics::artificial_viscosity::artificial_viscous_acceleration;
use sph::physics::correction::pressure_increment;
use sph::physics::multiphase::{self, Phases};
use sph::physics::pressure::pressure_acceleration;
use sph::physics::viscosity::viscous_acceleration;

/// Stiffness `k` [m²/s²] of the correction sweep: with densities within 1 % of ρ0, increments
/// of the order of the scene's pressures.
const STIFFNESS: f32 = 900.0;

/// The correction's increments `δp` [Pa] by brute force, with their tolerances, per particle of
/// `f` (id order), for the first sweep after `begin_correction` (no momentum): fluid
/// `physics::correction::pressure_increment` (the same f32 operations; one rounding of
/// `p + k (ρ − ρ0)` allowed for a fused multiply-add), solids the [A12] extrapolation of the
/// fluid increments without gravity, `δp_w = max(p_w + Σ δp_f W / Σ W, 0) − p_w`: the two sums
/// within [`SUM_ORDER`] of their terms' magnitudes, plus the fluid increments' tolerances and
/// two roundings of `p_w + r`.
fn reference_increments<const D: usize>(f: &Fields<D>, p: &StepParams<D>) -> Vec<(f32, f64)> {
    let kernel = p.smoothing();
    let fluid: Vec<(f32, f64)> = (0..f.len())
        .map(|i| {
            let rho0 = p.phases.rest_density(&f.rest_density, i, p.rho0);
            let dp = pressure_increment(f.density[i], rho0, f.pressure[i], STIFFNESS);
            let rounding = f32::EPSILON * (f.pressure[i].abs() + (STIFFNESS * (f.density[i] - rho0)).abs());
            (dp, f64::from(rounding))
        })
        .collect();
    (0..f.len())
        .map(|w| {
            if f.kind[w] == FLUID {
                return fluid[w];
            }
            let (mut sw, mut sp, mut magnitude) = (0.0f64, 0.0f64, 0.0f64);
            for (j, d, _) in neighbours(f, p.h, w) {
                if f.kind[j] == FLUID {
                    let wj = kernel.w(d.norm_squared());
                    sw += f64::from(wj);
                    sp += f64::from(fluid[j].0 * wj);
                    magnitude += f64::from((fluid[j].0 * wj).abs()) + fluid[j].1 * f64::from(wj);
                }
            }
            let p_w = f64::from(f.pressure[w]);
            if sw <= 0.0 {
                return (0.0, 0.0);
            }
            let r = sp / sw;
            let dp = (p_w + r).max(0.0) - p_w;
            let tol =
                SUM_ORDER * (magnitude + r.abs() * sw) / sw + 2.0 * f64::from(f32::EPSILON) * (p_w + r.abs());
            (dp as f32, tol)
        })
        .collect()
}

/// What the reference sums: the pair terms as the stage has them, or with one term changed to
/// show that it matters.
#[derive(Clone, Copy, PartialEq)]
enum Variant {
    Stage,
    /// Solids carry their own velocity in (17) instead of `Fields::wall_velocity`.
    OwnVelocity,
}

/// The force [N] on each solid by brute force, and its tolerance per axis: `m_s` times the
/// pressure term (16) (or [HA06]'s volume form) and each pair term of `terms` from the solid's
/// side, each evaluated by its physics function; each solid particle's f32 sum of pair terms is
/// within [`SUM_ORDER`] of the sum of the magnitudes of its parts (the f64 sums over particles
/// add nothing comparable), plus the pressures' own tolerances through the pressure part.
fn reference_forces<const D: usize>(
    f: &Fields<D>,
    p: &StepParams<D>,
    terms: PairTerms,
    pressure: &[(f32, f64)],
    variant: Variant,
) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let kernel = p.smoothing();
    let multi = p.phases == Phases::Multi;
    let (mut force, mut tol) = (vec![[0.0f64; 3]; SOLIDS], vec![[0.0f64; 3]; SOLIDS]);
    for s in (0..f.len()).filter(|&s| f.kind[s] != FLUID) {
        let slot = f.kind[s] as usize - 1;
        let viscous_u = match variant {
            Variant::Stage => &f.wall_velocity[s],
            Variant::OwnVelocity => &f.velocity[s],
        };
        for (j, d, r) in neighbours(f, p.h, s) {
            if f.kind[j] != FLUID {
                continue;
            }
            let grad = kernel.grad_w_spiky(&d, r) * p.pressure_gradient_scale;
            let ((p_s, tol_s), (p_j, tol_j)) = (pressure[s], pressure[j]);
            let (m_s, rho_s, m_j, rho_j) = (f.mass[s], f.density[s], f.mass[j], f.density[j]);
            // [HA06]: the volume-form pressure term, `−(p_s V_s² + p_j V_j²) ∇W`.
            let (pressure_part, sensitivity) = if multi {
                let (q_s, q_j) = (
                    multiphase::pressure_term(p_s, m_s, rho_s),
                    multiphase::pressure_term(p_j, m_j, rho_j),
                );
                let v = |m: f32, rho: f32| f64::from(m / rho).powi(2);
                let part = multiphase::pressure_acceleration(q_s, q_j, 1.0, &grad);
                (part, v(m_s, rho_s) * tol_s + v(m_j, rho_j) * tol_j)
            } else {
                let v = |rho: f32| f64::from(m_s) * f64::from(m_j) / f64::from(rho).powi(2);
                (
                    pressure_acceleration(p_s, rho_s, p_j, rho_j, m_j, &grad) * m_s,
                    v(rho_s) * tol_s + v(rho_j) * tol_j,
                )
            };
            let parts: Vec<Vector<D>> = terms
                .iter()
                .map(|term| match term {
                    PairTerm::ArtificialViscosity => {
                        let u_sj = f.velocity[s] - f.velocity[j];
                        artificial_viscous_acceleration(
                            p.pair.alpha,
                            p.c,
                            p.h,
                            &d,
                            &u_sj,
                            rho_s,
                            rho_j,
                            m_j,
                            &grad,
                        ) * m_s
                    }
                    PairTerm::Viscosity => {
                        let lap = kernel.laplacian_w_viscosity(r);
                        let mu = p.pair.mu * p.viscosity_scale;
                        viscous_acceleration(mu, viscous_u, &f.velocity[j], rho_s, rho_j, m_j, lap) * m_s
                    }
                })
                .collect();
            let pair = parts.iter().fold(pressure_part, |sum, part| sum + part);
            for k in 0..D {
                force[slot][k] += f64::from(pair[k]);
                let magnitude: f64 = parts.iter().map(|x| f64::from(x[k].abs())).sum();
                tol[slot][k] += SUM_ORDER * (f64::from(pressure_part[k].abs()) + magnitude)
                    + sensitivity * f64::from(grad[k].abs());
            }
        }
    }
    (force, tol)
}

fn check_solid_forces<const D: usize>(seed: u64, source: SolidForceSource, phases: Phases) {
    let (mut f, mut p) = scene::<D>(seed);
    add_strays(&mut f, &p, seed ^ 0x5151);
    use_phases(&mut f, &mut p, phases, true);
    let r = in_id_order(&f);
    let terms = source.pair_terms();
    let pressure: Vec<(f32, f64)> = match source {
        SolidForceSource::Forces(_) => r.pressure.iter().map(|&x| (x, 0.0)).collect(),
        SolidForceSource::Correction => reference_increments(&r, &p),
    };
    let (want, tol) = reference_forces(&r, &p, terms, &pressure, Variant::Stage);
    let what = format!("{D}D {source:?} {phases:?}");
    // Each term moves some solid's force far beyond the tolerance, so none passes vacuously.
    let effect = |(other, _): (Vec<[f64; 3]>, Vec<[f64; 3]>)| {
        (0..SOLIDS)
            .flat_map(|s| (0..D).map(move |k| (s, k)))
            .map(|(s, k)| (other[s][k] - want[s][k]).abs() / tol[s][k])
            .fold(0.0, f64::max)
    };
    let no_pressure = vec![(0.0, 0.0); r.len()];
    let mut effects = vec![(
        "pressure",
        effect(reference_forces(&r, &p, terms, &no_pressure, Variant::Stage)),
    )];
    for term in terms.iter() {
        let without = terms.without(term);
        effects.push((
            term.label(),
            effect(reference_forces(&r, &p, without, &pressure, Variant::Stage)),
        ));
    }
    if terms.contains(PairTerm::Viscosity) {
        effects.push((
            "wall velocity",
            effect(reference_forces(&r, &p, terms, &pressure, Variant::OwnVelocity)),
        ));
    }
    if phases == Phases::Multi {
        let single = StepParams {
            phases: Phases::Single,
            ..p
        };
        effects.push((
            "volume form",
            effect(reference_forces(&r, &single, terms, &pressure, Variant::Stage)),
        ));
    }
    for (term, e) in &effects {
        assert!(
            *e > 100.0,
            "{what}: the {term} term moves the forces by only {e:.1} tolerances"
        );
    }
    for under in backends() {
        let (_, got) = under.run(&f, &p, |b, f| {
            if source == SolidForceSource::Correction {
                b.begin_correction(f);
                b.correction_pressure(f, &p, STIFFNESS);
            }
            b.solid_forces(f, &p, SOLIDS, source)
        });
        assert_eq!(got.len(), SOLIDS, "{under:?} {what}: one force per solid");
        let mut worst = 0.0f64;
        for s in 0..SOLIDS {
            for k in 0..3 {
                let diff = (got[s][k] - want[s][k]).abs();
                assert!(
                    diff <= tol[s][k],
                    "{under:?} {what}: solid {s} axis {k}: {} want {} ± {:.2e}",
                    got[s][k],
                    want[s][k],
                    tol[s][k]
                );
                if k < D {
                    worst = worst.max(diff / tol[s][k]);
                }
            }
            let magnitude = want[s].iter().map(|c| c * c).sum::<f64>().sqrt();
            assert!(
                magnitude > 1.0e3 * tol[s][0].max(tol[s][1]),
                "{what}: solid {s} feels a net force"
            );
        }
        let effects: Vec<String> = effects.iter().map(|(t, e)| format!("{t} {e:.1e}")).collect();
        eprintln!(
            "{under:?} {what} solid_forces: worst |ΔF| / tolerance {worst:.2e}; terms move it by {} tolerances",
            effects.join(", ")
        );
    }
}

#[test]
fn solid_forces_are_the_brute_force_pair_sums_for_both_sources_and_phase_models() {
    // Every pair term on for the force stage's source; none for the correction's.
    let all = PairTerm::ALL.into_iter().fold(PairTerms::NONE, PairTerms::with);
    for source in [SolidForceSource::Forces(all), SolidForceSource::Correction] {
        for phases in [Phases::Single, Phases::Multi] {
            check_solid_forces::<2>(0xdead_beef_cafe_f00d, source, phases);
            check_solid_forces::<3>(0x0bad_c0de_1357_9bdf, source, phases);
        }
    }
}
