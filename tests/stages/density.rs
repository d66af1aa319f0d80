//! The `density` stage (eq. 18, both kernels, one phase and [HA06] several) and
//! `equation_of_state` (eq. 19), on every backend, against brute-force sums.

use crate::setup::{
    RHO0, SUM_ORDER, add_strays, backends, by_id, in_id_order, neighbours, scene, use_density_kernel,
    use_phases,
};
use sph::fields::{FLUID, Fields};
use sph::model::params::StepParams;
use sph::physics::density::{DensityKernel, density_kernel};
use sph::physics::eos;
use sph::physics::multiphase::Phases;

/// Eq. (18) by brute force, and the sum of its terms' magnitudes, for fluid particle `i` of `f`
/// (in id order); [HA06] `m_i Σ_j W_ij` with several phases.
fn reference_density<const D: usize>(f: &Fields<D>, p: &StepParams<D>, i: usize) -> f64 {
    let kernel = p.smoothing();
    let weight = p.density_weight();
    let self_term = density_kernel(&kernel, weight, 0.0);
    let sum: f64 = neighbours(f, p.h, i)
        .into_iter()
        .map(|(j, _, r)| {
            let m = if p.phases == Phases::Multi {
                f.mass[i]
            } else {
                f.mass[j]
            };
            f64::from(m * density_kernel(&kernel, weight, r * r))
        })
        .sum();
    sum + f64::from(f.mass[i] * self_term)
}

fn check_density<const D: usize>(seed: u64, density_kernel: DensityKernel, phases: Phases) {
    let (mut f, mut p) = scene::<D>(seed);
    add_strays(&mut f, &p, seed ^ 0x5151);
    use_density_kernel(&mut p, density_kernel);
    use_phases(&mut f, &mut p, phases, false);
    let reference = in_id_order(&f);
    for under in backends() {
        let (out, ()) = under.run(&f, &p, |b, f| b.density(f, &p));
        let got = by_id(&out, &out.density);
        let mut worst = 0.0f64;
        for id in 0..reference.len() {
            if reference.kind[id] != FLUID {
                assert_eq!(
                    got[id], reference.density[id],
                    "{under:?}: solid {id} keeps its density"
                );
                continue;
            }
            // Every term is positive: the sum is its own magnitude.
            let want = reference_density(&reference, &p, id);
            let diff = (f64::from(got[id]) - want).abs() / want;
            assert!(
                diff <= SUM_ORDER,
                "{under:?} {D}D {density_kernel:?} {phases:?}: particle {id}: {} against {want}",
                got[id]
            );
            worst = worst.max(diff);
        }
        eprintln!("{under:?} {D}D density {density_kernel:?} {phases:?}: worst relative {worst:.2e}");
    }
}

#[test]
fn density_is_the_brute_force_sum_for_both_kernels_and_phase_models() {
    for density_kernel in [DensityKernel::Poly6, DensityKernel::ScaledSpiky] {
        for phases in [Phases::Single, Phases::Multi] {
            check_density::<2>(0x9e37_79b9_7f4a_7c15, density_kernel, phases);
            check_density::<3>(0x2545_f491_4f6c_dd1d, density_kernel, phases);
        }
    }
}

fn check_equation_of_state<const D: usize>(seed: u64, phases: Phases) {
    let (mut f, mut p) = scene::<D>(seed);
    p.phases = phases;
    if phases == Phases::Multi {
        f.rest_density = (0..f.len())
            .map(|i| if f.id[i] % 2 == 0 { RHO0 / 8.0 } else { RHO0 })
            .collect();
    }
    let reference = in_id_order(&f);
    for under in backends() {
        let (out, ()) = under.run(&f, &p, |b, f| b.equation_of_state(f, &p));
        let got = by_id(&out, &out.pressure);
        for id in 0..reference.len() {
            // Per particle, no sum: the same f32 operations, so bitwise.
            let want = if reference.kind[id] == FLUID {
                let rho0 = phases.rest_density(&reference.rest_density, id, p.rho0);
                eos::pressure(reference.density[id], rho0, p.c2)
            } else {
                reference.pressure[id]
            };
            assert_eq!(
                got[id].to_bits(),
                want.to_bits(),
                "{under:?} {D}D {phases:?}: particle {id}: {} against {want}",
                got[id]
            );
        }
    }
}

#[test]
fn equation_of_state_is_eq_19_per_particle_bitwise() {
    for phases in [Phases::Single, Phases::Multi] {
        check_equation_of_state::<2>(0x1234_5678_9abc_def1, phases);
        check_equation_of_state::<3>(0x0fed_cba9_8765_4321, phases);
    }
}
