//! The velocity solve's warm start: each integrator stage's solve starts from the increments
//! its solve of the previous step ended with (twin of `backend::cuda::warm_start` and of
//! `kernels/anderson.cu`'s `velocity_solve_warm_start` and `velocity_solve_record`).

use super::CpuBackend;
use crate::backend::{SolveRecord, VELOCITY_SOLVE_SLOTS};
use crate::fields::{FLUID, Fields};
use crate::math::Real;
use rayon::prelude::*;

/// Every slot's records, by particle id (`id * VELOCITY_SOLVE_SLOTS + slot`, so that a larger
/// id only lengthens them): the increment `P − P_start` [Pa] and the number of the slot's solve
/// that recorded it. A record counts when its number is the slot's count of solves, that is when
/// the slot's last solve wrote it (a particle that was not fluid then, or that a rank did not
/// hold, has an older number). They survive `Backend::reload`: ids do not change.
#[derive(Clone, Debug, Default)]
pub(super) struct VelocitySolveRecords {
    solves: [u32; VELOCITY_SOLVE_SLOTS],
    recorded_by: Vec<u32>,
    increment: Vec<Real>,
}

impl VelocitySolveRecords {
    /// Bytes held (for memory reports).
    pub(super) fn heap_bytes(&self) -> usize {
        self.recorded_by.capacity() * 4 + self.increment.capacity() * 4
    }
}

impl<const D: usize> CpuBackend<D> {
    pub(super) fn warm_start_velocity_solve(&mut self, fields: &mut Fields<D>, slot: usize) {
        let r = &self.solve_records;
        let solves = r.solves[slot];
        if solves == 0 {
            return;
        }
        let (kind, id) = (&fields.kind, &fields.id);
        fields.pressure.par_iter_mut().enumerate().for_each(|(i, p)| {
            let k = id[i] as usize * VELOCITY_SOLVE_SLOTS + slot;
            if kind[i] == FLUID && r.recorded_by.get(k) == Some(&solves) {
                *p = (*p + r.increment[k]).max(0.0);
            }
        });
    }

    pub(super) fn record_velocity_solve(&mut self, fields: &Fields<D>, slot: usize, keep: bool) {
        let r = &mut self.solve_records;
        let next = r.solves[slot].wrapping_add(1);
        if keep {
            let ids = fields.id.iter().map(|&k| k as usize + 1).max().unwrap_or(0);
            if r.recorded_by.len() < ids * VELOCITY_SOLVE_SLOTS {
                r.recorded_by.resize(ids * VELOCITY_SOLVE_SLOTS, 0);
                r.increment.resize(ids * VELOCITY_SOLVE_SLOTS, 0.0);
            }
            let start = &self.pressure_solve_start;
            for i in 0..fields.len() {
                if fields.kind[i] == FLUID {
                    let k = fields.id[i] as usize * VELOCITY_SOLVE_SLOTS + slot;
                    r.recorded_by[k] = next;
                    r.increment[k] = fields.pressure[i] - start[i];
                }
            }
        }
        r.solves[slot] = next;
    }

    pub(super) fn velocity_solve_records(&self, ids: &[u32]) -> Vec<SolveRecord> {
        let r = &self.solve_records;
        ids.iter()
            .map(|&id| {
                std::array::from_fn(|slot| {
                    let k = id as usize * VELOCITY_SOLVE_SLOTS + slot;
                    let counts = r.solves[slot] != 0 && r.recorded_by.get(k) == Some(&r.solves[slot]);
                    counts.then(|| r.increment[k])
                })
            })
            .collect()
    }

    pub(super) fn restore_velocity_solve_records(&mut self, ids: &[u32], records: &[SolveRecord]) {
        self.solve_records = VelocitySolveRecords::default();
        if records.iter().all(|r| r.iter().all(Option::is_none)) {
            return;
        }
        let r = &mut self.solve_records;
        let len = ids.iter().map(|&k| k as usize + 1).max().unwrap_or(0) * VELOCITY_SOLVE_SLOTS;
        r.solves = [1; VELOCITY_SOLVE_SLOTS];
        r.recorded_by = vec![0; len];
        r.increment = vec![0.0; len];
        for (&id, record) in ids.iter().zip(records) {
            for (slot, value) in record.iter().enumerate() {
                if let Some(v) = value {
                    let k = id as usize * VELOCITY_SOLVE_SLOTS + slot;
                    r.recorded_by[k] = 1;
                    r.increment[k] = *v;
                }
            }
        }
    }
}
