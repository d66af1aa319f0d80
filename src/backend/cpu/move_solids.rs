//! The `move_solids` and `keep_out` stages (twins of `kernels/move_solids.cu` and
//! `kernels/keep_out.cu`).

use super::CpuBackend;
use crate::boundary::keep_out::{KeepOutBox, KeepOutReport, push_moment};
use crate::boundary::motion::{SolidKinematics, SolidReference};
use crate::fields::{FLUID, Fields};
use crate::math::Vector;
use rayon::prelude::*;

/// One push of the guard: the solid, the axis, the fluid's momentum change along it [kg m/s]
/// and that change's angular momentum about the origin [kg m²/s].
type Push = (u32, usize, f64, [f64; 3]);

impl<const D: usize> CpuBackend<D> {
    pub(super) fn move_solids(
        &mut self,
        fields: &mut Fields<D>,
        reference: &SolidReference<D>,
        kinematics: &[SolidKinematics<D>],
    ) {
        let (kind, id) = (&fields.kind, &fields.id);
        fields
            .position
            .par_iter_mut()
            .zip(fields.velocity.par_iter_mut())
            .enumerate()
            .for_each(|(i, (x, u))| {
                if kind[i] != FLUID {
                    let k = &kinematics[kind[i] as usize - 1];
                    *x = k.position(&reference.position[(id[i] - reference.first_id) as usize]);
                    *u = k.velocity_at(x);
                }
            });
    }

    pub(super) fn keep_out(
        &mut self,
        fields: &mut Fields<D>,
        boxes: &[KeepOutBox<D>],
        solids: usize,
        margin: f32,
        from_step_start: bool,
    ) -> KeepOutReport {
        let mut report = KeepOutReport::none(solids);
        if boxes.is_empty() {
            return report;
        }
        let partition = &self.partition;
        let (kind, mass) = (&fields.kind, &fields.mass);
        // The step's start positions, stored by `store_step_start` (SSP-RK3): the side each
        // particle came from (`KeepOutBox::push_out`).
        let start: &[Vector<D>] = if from_step_start {
            &fields.position_start
        } else {
            &[]
        };
        // Each particle's pushes (`Push`), gathered in index order and summed in that
        // order, so the result does not depend on the thread count.
        let pushes: Vec<Vec<Push>> = fields
            .position
            .par_iter_mut()
            .zip(fields.velocity.par_iter_mut())
            .enumerate()
            .filter_map(|(i, (x, u))| {
                if kind[i] != FLUID {
                    return None;
                }
                let from = start.get(i);
                let mut mine = Vec::new();
                for b in boxes {
                    let before = *u;
                    if let Some(axis) = b.push_out(x, u, margin, from) {
                        let dp = f64::from(mass[i]) * (f64::from(u[axis]) - f64::from(before[axis]));
                        mine.push((b.solid, axis, dp, push_moment(x, axis, dp)));
                    }
                }
                // A ghost is pushed as its owner is, which counts the push.
                (!mine.is_empty() && partition.counts(i)).then_some(mine)
            })
            .collect();
        let mut pushes_here = 0u64;
        for (solid, axis, dp, moment) in pushes.into_iter().flatten() {
            pushes_here += 1;
            if let Some(slot) = report.impulse.get_mut(solid as usize) {
                slot[axis] += dp;
            }
            if let Some(slot) = report.angular_impulse.get_mut(solid as usize) {
                for c in 0..3 {
                    slot[c] += moment[c];
                }
            }
        }
        // Over ranks: the pushes, then each solid's impulse and angular impulse.
        let mut totals = vec![pushes_here as f64];
        for (j, l) in report.impulse.iter().zip(&report.angular_impulse) {
            totals.extend(j.iter().chain(l.iter()));
        }
        self.partition.sum(&mut totals);
        report.pushes = totals[0] as u64;
        for ((j, l), t) in report
            .impulse
            .iter_mut()
            .zip(report.angular_impulse.iter_mut())
            .zip(totals[1..].chunks_exact(6))
        {
            j.copy_from_slice(&t[..3]);
            l.copy_from_slice(&t[3..]);
        }
        report
    }
}
