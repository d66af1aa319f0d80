//! The `gradient_moment` stage (`physics::gradient_moment`) on every backend, against a
//! brute-force pass in f64 over all pairs.

use crate::setup::{backends, in_id_order, neighbours, scene};
use sph::fields::{FLUID, Fields};
use sph::model::params::StepParams;
use sph::physics::gradient_moment::{FULL_SUPPORT, KAPPA_QUANTUM, moment_terms};

/// Each fluid particle's Shepard sum and moment `κ_i` (id order), in f64 from the f32 terms.
fn reference<const D: usize>(f: &Fields<D>, p: &StepParams<D>) -> Vec<(f64, f64)> {
    let kernel = p.smoothing();
    (0..f.len())
        .filter(|&i| f.kind[i] == FLUID)
        .map(|i| {
            let own = moment_terms(
                &kernel,
                &sph::math::Vector::<D>::zeros(),
                0.0,
                f.mass[i] / f.density[i],
            );
            let (mut shepard, mut moment) = (f64::from(own[0]), f64::from(own[1]));
            for (j, d, r) in neighbours(f, p.h, i) {
                let t = moment_terms(&kernel, &d, r * r, f.mass[j] / f.density[j]);
                shepard += f64::from(t[0]);
                moment += f64::from(t[1]);
            }
            (shepard, moment)
        })
        .collect()
}

fn check<const D: usize>(seed: u64) {
    let (f, p) = scene::<D>(seed);
    let per_particle = reference(&in_id_order(&f), &p);
    // A particle within f32 rounding of the threshold may fall either side on a backend.
    let margin = 1e-5;
    let border = per_particle
        .iter()
        .filter(|(s, _)| (s - FULL_SUPPORT).abs() < margin)
        .count();
    assert_eq!(
        border, 0,
        "{D}D: the scene puts a particle on the threshold; pick another seed"
    );
    let full: Vec<f64> = per_particle
        .iter()
        .filter(|(s, _)| *s >= FULL_SUPPORT)
        .map(|&(_, m)| m)
        .collect();
    let fluid = per_particle.len();
    assert!(
        full.len() > fluid / 4 && full.len() < fluid,
        "{D}D: {} of {fluid} fluid particles have full support: the scene must have both kinds",
        full.len()
    );
    let want = full.iter().sum::<f64>() / full.len() as f64;
    for under in backends() {
        let (_, sums) = under.run(&f, &p, |b, f| b.gradient_moment(f, &p));
        assert_eq!(
            sums.count,
            full.len() as f64,
            "{under:?} {D}D: particles with full support"
        );
        let mean = sums.moment / sums.count;
        // f32 neighbour sums in another order than the reference: 1e-5 of each κ_i.
        assert!(
            (mean - want).abs() <= 1e-5 * want,
            "{under:?} {D}D: mean moment {mean} against {want}"
        );
        // The κ the step uses: the mean on the grid of `KAPPA_QUANTUM`.
        let kappa = sums.kappa().expect("some particles have full support");
        assert!(
            (kappa - mean).abs() <= 0.5 * KAPPA_QUANTUM,
            "{under:?} {D}D: kappa {kappa}"
        );
        assert_eq!(
            (kappa / KAPPA_QUANTUM).fract(),
            0.0,
            "{under:?} {D}D: kappa {kappa}"
        );
        eprintln!(
            "{under:?} {D}D gradient moment {kappa:.6} over {} particles",
            full.len()
        );
    }
}

#[test]
fn gradient_moment_is_the_mean_over_fully_supported_fluid() {
    check::<2>(0x9e37_79b9_7f4a_7c15);
    check::<3>(0x2545_f491_4f6c_dd1d);
}
