//! The velocity solve's warm start (`warm_start_velocity_solve`, `record_velocity_solve`,
//! `velocity_solve_records`, `restore_velocity_solve_records`), on every backend: a slot's next
//! solve starts from `max(P_start + (P − P_start)_last, 0)` by particle id, bitwise (the same f32
//! sum and clamp); other slots, solids, a given-up solve and cleared records leave `P_start`;
//! records copied out and restored (a checkpoint) give the same warm start.

use crate::correction_reference::{snapshot, stiffness};
use crate::setup::backends;
use crate::velocity_solve::solve_scene;
use sph::backend::SolveRecord;
use sph::fields::{FLUID, Fields};
use sph::physics::density::DensityKernel;
use sph::physics::multiphase::Phases;

/// The solve's `τ` [s], as `velocity_solve`'s.
const TAU: f32 = 1.0e-4;

/// What the driver's sequence leaves, each in id order.
struct Snapshots<const D: usize> {
    /// The first solve's start and its last iterate (recorded in slot 1).
    start: Fields<D>,
    last: Fields<D>,
    /// The second solve's start, and its pressure after the warm start of slots 0, 2 and 1.
    second_start: Fields<D>,
    other_slots: Fields<D>,
    warm: Fields<D>,
    /// Starts and warm starts of slot 1 after a given-up solve, and after restoring no records.
    after_given_up: (Fields<D>, Fields<D>),
    after_cleared: (Fields<D>, Fields<D>),
    /// The records of a kept solve as copied out (in the order of `ids`), and the start and warm
    /// start of slot 1 after restoring them into a fresh backend state.
    ids: Vec<u32>,
    records: Vec<SolveRecord>,
    restored: (Fields<D>, Fields<D>),
}

fn check_warm_start<const D: usize>(seed: u64) {
    let (f, p) = solve_scene::<D>(seed, DensityKernel::ScaledSpiky, Phases::Single);
    let k = stiffness(&p, TAU);
    for under in backends() {
        let (_, s) = under.run(&f, &p, |b, f| {
            let solve = |b: &mut dyn sph::backend::Backend<D>, f: &mut Fields<D>| {
                b.predicted_density(f, &p, TAU);
                b.mix_velocity_pressure(f, &p, k);
                b.velocity_from_pressure(f, &p, TAU);
            };
            b.begin_velocity_solve(f, &p);
            let start = snapshot(b, f);
            for _ in 0..3 {
                solve(b, f);
            }
            let last = snapshot(b, f);
            b.record_velocity_solve(f, 1, true);
            b.end_velocity_solve(f, true);
            b.begin_velocity_solve(f, &p);
            let second_start = snapshot(b, f);
            b.warm_start_velocity_solve(f, 0);
            b.warm_start_velocity_solve(f, 2);
            let other_slots = snapshot(b, f);
            b.warm_start_velocity_solve(f, 1);
            let warm = snapshot(b, f);
            // Given up: slot 1's records stop counting.
            solve(b, f);
            b.record_velocity_solve(f, 1, false);
            b.end_velocity_solve(f, false);
            b.begin_velocity_solve(f, &p);
            let given_up_start = snapshot(b, f);
            b.warm_start_velocity_solve(f, 1);
            let after_given_up = (given_up_start, snapshot(b, f));
            solve(b, f);
            b.record_velocity_solve(f, 1, true);
            b.end_velocity_solve(f, true);
            let ids = f.id.clone();
            let records = b.velocity_solve_records(&ids).expect("records");
            b.restore_velocity_solve_records(&ids, &vec![SolveRecord::default(); ids.len()])
                .expect("restored");
            b.begin_velocity_solve(f, &p);
            let cleared_start = snapshot(b, f);
            b.warm_start_velocity_solve(f, 1);
            let after_cleared = (cleared_start, snapshot(b, f));
            b.end_velocity_solve(f, false);
            b.restore_velocity_solve_records(&ids, &records)
                .expect("restored");
            b.begin_velocity_solve(f, &p);
            let restored_start = snapshot(b, f);
            b.warm_start_velocity_solve(f, 1);
            let restored = (restored_start, snapshot(b, f));
            b.end_velocity_solve(f, false);
            Snapshots {
                start,
                last,
                second_start,
                other_slots,
                warm,
                after_given_up,
                after_cleared,
                ids,
                records,
                restored,
            }
        });
        let n = s.start.len();
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(&s.other_slots.pressure),
            bits(&s.second_start.pressure),
            "{under:?} {D}D: slots without records leave P_start"
        );
        let mut changed = 0;
        for i in 0..n {
            let p0 = s.second_start.pressure[i];
            let want = if s.start.kind[i] == FLUID {
                (p0 + (s.last.pressure[i] - s.start.pressure[i])).max(0.0)
            } else {
                p0
            };
            assert_eq!(
                s.warm.pressure[i].to_bits(),
                want.to_bits(),
                "{under:?} {D}D: warm start of particle {i} (kind {}): {} against {want}",
                s.start.kind[i],
                s.warm.pressure[i]
            );
            changed += usize::from(s.warm.pressure[i] != p0);
        }
        let fluid = (0..n).filter(|&i| s.start.kind[i] == FLUID).count();
        assert!(
            changed > fluid / 10,
            "{under:?} {D}D: the warm start moved {changed} of {fluid} fluid pressures"
        );
        for (label, after) in [("given up", &s.after_given_up), ("cleared", &s.after_cleared)] {
            let (got, start) = (&after.1.pressure, &after.0.pressure);
            assert_eq!(
                bits(got),
                bits(start),
                "{under:?} {D}D: after a {label} record the warm start leaves P_start"
            );
        }
        // The records as copied out: slot 1 for the fluid, nothing else; restored, the same
        // warm start.
        let kind_of = |id: u32| s.start.kind[id as usize];
        for (&id, r) in s.ids.iter().zip(&s.records) {
            let fluid = kind_of(id) == FLUID;
            assert!(
                r[0].is_none() && r[2].is_none() && r[1].is_some() == fluid,
                "{under:?} {D}D: records of particle {id} (kind {}): {r:?}",
                kind_of(id)
            );
        }
        let (start, warm) = &s.restored;
        for (&id, r) in s.ids.iter().zip(&s.records) {
            let i = id as usize;
            let want = r[1].map_or(start.pressure[i], |dp| (start.pressure[i] + dp).max(0.0));
            assert_eq!(
                warm.pressure[i].to_bits(),
                want.to_bits(),
                "{under:?} {D}D: warm start of particle {id} from restored records"
            );
        }
        eprintln!("{under:?} {D}D warm start: {changed} of {fluid} fluid pressures, bitwise");
    }
}

#[test]
fn warm_start_adds_the_same_slots_last_increments_by_id() {
    check_warm_start::<2>(0x5eed_0001_2345_6789);
    check_warm_start::<3>(0x5eed_9876_5432_1000);
}
