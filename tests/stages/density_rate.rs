//! The `density_rate` stage (the continuity equation with [F19] density diffusion) against a
//! brute-force sum of `physics::density_diffusion`'s terms, and `integrate_density`,
//! `store_density_start`, `rk_density_stage` per particle, on every backend.

use crate::setup::{SUM_ORDER, backends, by_id, in_id_order, neighbours, scene};
use sph::fields::{FLUID, Fields};
use sph::model::params::StepParams;
use sph::physics::density_diffusion::{DiffusionCoefficients, continuity_term, diffusion_term};

/// δ of the diffusion: the published typical value.
const DELTA: f32 = 0.1;
/// Time step [s] and the Shu–Osher coefficients of SSP-RK3's second stage.
const DT: f32 = 1.3e-3;
const RK: (f32, f32) = (0.75, 0.25);

/// `dρ_i/dt` by brute force over all pairs, and the sum of its terms' magnitudes, for fluid
/// particle `i` of `f` (id order): solids move with `wall_velocity` where `f` has it.
fn reference_rate<const D: usize>(f: &Fields<D>, p: &StepParams<D>, i: usize) -> (f64, f64) {
    let kernel = p.smoothing();
    let weight = p.density_weight();
    let c = DiffusionCoefficients::new(p.density_diffusion, p.h, p.c2, p.rho0, &p.gravity);
    let (mut sum, mut magnitude) = (0.0f64, 0.0f64);
    for (j, d, r) in neighbours(f, p.h, i) {
        let fluid = f.kind[j] == FLUID;
        let u_j = if fluid {
            f.velocity[j]
        } else {
            *f.wall_velocity.get(j).unwrap_or(&f.velocity[j])
        };
        let mut terms = vec![continuity_term(
            &kernel,
            weight,
            f.mass[j],
            &(f.velocity[i] - u_j),
            &d,
            r,
        )];
        if fluid {
            terms.push(diffusion_term(
                &kernel,
                weight,
                &c,
                f.density[i],
                f.density[j],
                f.mass[j],
                &d,
                r,
            ));
        }
        for t in terms {
            sum += f64::from(t);
            magnitude += f64::from(t).abs();
        }
    }
    (sum, magnitude)
}

fn check_density_rate<const D: usize>(seed: u64, no_slip: bool) {
    let (mut f, mut p) = scene::<D>(seed);
    p.density_diffusion = DELTA;
    if !no_slip {
        f.wall_velocity.clear();
    }
    let reference = in_id_order(&f);
    for under in backends() {
        let (out, ()) = under.run(&f, &p, |b, f| b.density_rate(f, &p));
        let got = by_id(&out, &out.density_rate);
        let mut worst = 0.0f64;
        let mut diffusion_seen = 0.0f64;
        for id in 0..reference.len() {
            if reference.kind[id] != FLUID {
                assert_eq!(got[id], 0.0, "{under:?}: solid {id} has no rate");
                continue;
            }
            let (want, magnitude) = reference_rate(&reference, &p, id);
            let diff = (f64::from(got[id]) - want).abs();
            // The f32 sum in another order: within SUM_ORDER of the terms' magnitudes.
            assert!(
                diff <= SUM_ORDER * magnitude,
                "{under:?} {D}D no-slip {no_slip}: particle {id}: {} against {want} (terms {magnitude})",
                got[id]
            );
            worst = worst.max(diff / magnitude);
            let without = {
                let q = StepParams {
                    density_diffusion: 0.0,
                    ..p
                };
                reference_rate(&reference, &q, id).0
            };
            diffusion_seen = diffusion_seen.max((want - without).abs());
        }
        // The scene's densities differ by up to 2 % of ρ0: the diffusion must show in the sum.
        assert!(diffusion_seen > 1e3, "{under:?} {D}D: diffusion {diffusion_seen}");
        eprintln!("{under:?} {D}D density_rate no-slip {no_slip}: worst relative {worst:.2e}");
    }
}

#[test]
fn density_rate_is_the_brute_force_continuity_and_diffusion_sum() {
    for no_slip in [true, false] {
        check_density_rate::<2>(0x9e37_79b9_7f4a_7c15, no_slip);
        check_density_rate::<3>(0x2545_f491_4f6c_dd1d, no_slip);
    }
}

/// After `density_rate`: symplectic Euler `ρ + dt dρ/dt`, and one SSP-RK3 stage
/// `a ρ^n + b (ρ + dt dρ/dt)` from the stored start, fluid only, with the backend's own rate.
/// Per particle, no sums: the same f32 operations, so bitwise.
fn check_density_integration<const D: usize>(seed: u64) {
    let (f, mut p) = scene::<D>(seed);
    p.density_diffusion = DELTA;
    let reference = in_id_order(&f);
    for under in backends() {
        for rk in [false, true] {
            let (out, ()) = under.run(&f, &p, |b, f| {
                b.density_rate(f, &p);
                if rk {
                    b.store_density_start(f);
                    b.rk_density_stage(f, DT, RK.0, RK.1);
                } else {
                    b.integrate_density(f, DT);
                }
            });
            let rate = by_id(&out, &out.density_rate);
            let got = by_id(&out, &out.density);
            let mut moved = 0;
            for id in 0..reference.len() {
                let rho = reference.density[id];
                let want = if reference.kind[id] != FLUID {
                    rho
                } else if rk {
                    rho * RK.0 + (rho + rate[id] * DT) * RK.1
                } else {
                    rho + rate[id] * DT
                };
                moved += usize::from(want != rho);
                assert_eq!(
                    got[id].to_bits(),
                    want.to_bits(),
                    "{under:?} {D}D rk {rk}: particle {id}: {} against {want}",
                    got[id]
                );
            }
            assert!(moved > 100, "{under:?} {D}D rk {rk}: {moved} densities changed");
        }
    }
}

#[test]
fn density_integration_is_euler_or_a_shu_osher_stage_per_particle_bitwise() {
    check_density_integration::<2>(0x1234_5678_9abc_def1);
    check_density_integration::<3>(0x0fed_cba9_8765_4321);
}
