//! The `damping_zone` stage on every backend: fluid velocities scaled by
//! `DampingZone::velocity_factor` ([AEA17], `physics::damping_zone`), solids untouched. Per
//! particle, without sums: the same f32 operations in the same order as the reference (the
//! kernels are compiled with `--fmad=false`), so compared bitwise.

use crate::setup::{backends, by_id, in_id_order, scene};
use sph::fields::FLUID;
use sph::math::Vector;
use sph::physics::damping_zone::DampingZone;

/// Time step [s] and strength [1/s]: `Δt β = 0.25`, so a damped velocity visibly differs.
const DT: f32 = 2.5e-3;
const BETA: f64 = 100.0;

fn check_damping<const D: usize>(seed: u64) {
    let (f, p) = scene::<D>(seed);
    let reference = in_id_order(&f);
    // A slanted zone across the middle third of the fluid's x range, so every backend sees
    // particles before it, in its ramp and past its end.
    let xs = || (0..reference.len()).filter(|&i| reference.kind[i] == FLUID);
    let lo = xs()
        .map(|i| reference.position[i][0])
        .fold(f32::INFINITY, f32::min);
    let hi = xs()
        .map(|i| reference.position[i][0])
        .fold(f32::NEG_INFINITY, f32::max);
    let (x0, x1) = (
        f64::from(lo + (hi - lo) / 3.0),
        f64::from(lo + 2.0 * (hi - lo) / 3.0),
    );
    let mut start = vec![x0; D];
    let mut end = vec![x1; D];
    start[1] = 0.0;
    end[1] = 0.1 * (x1 - x0);
    if D == 3 {
        start[2] = 0.0;
        end[2] = -0.05 * (x1 - x0);
    }
    let zone = DampingZone::<D>::new(&start, &end, BETA);
    let mut want = reference.velocity.clone();
    let (mut before, mut ramp, mut full) = (0, 0, 0);
    for i in xs() {
        let factor = zone.velocity_factor(&reference.position[i], DT);
        want[i] *= factor;
        let r = zone.ramp(&reference.position[i]);
        match r {
            0.0 => before += 1,
            1.0 => full += 1,
            _ => ramp += 1,
        }
    }
    assert!(
        before > 0 && ramp > 0 && full > 0,
        "{D}D: {before} / {ramp} / {full}"
    );
    let full_factor = 1.0 - DT * BETA as f32;
    for under in backends() {
        let (out, ()) = under.run(&f, &p, |b, f| b.damping_zone(f, &zone, DT));
        let got = by_id(&out, &out.velocity);
        for (id, (g, w)) in got.iter().zip(&want).enumerate() {
            assert_eq!(
                g.map(f32::to_bits),
                w.map(f32::to_bits),
                "{under:?} {D}D particle {id} (kind {})",
                reference.kind[id]
            );
        }
        let positions = by_id(&out, &out.position);
        assert_eq!(positions, reference.position, "{under:?} {D}D: positions stay");
        // Solids keep their velocity; fluid past the end loses the full Δt β.
        for id in 0..reference.len() {
            let (u0, u): (Vector<D>, Vector<D>) = (reference.velocity[id], got[id]);
            if reference.kind[id] != FLUID {
                assert_eq!(u, u0, "{under:?} {D}D solid particle {id}");
            } else if zone.ramp(&reference.position[id]) == 1.0 {
                assert!(
                    (u - u0 * full_factor).norm() <= 1e-6 * u0.norm(),
                    "{under:?} {D}D particle {id}"
                );
            }
        }
        eprintln!(
            "{under:?} {D}D damping_zone: bitwise equal ({before} before, {ramp} in the ramp, {full} past the end)"
        );
    }
}

#[test]
fn damping_zone_scales_fluid_velocities_by_the_factor_bitwise() {
    check_damping::<2>(0x5eed_0a11_d0d0_beef);
    check_damping::<3>(0x0dd0_5eed_beef_0a11);
}
