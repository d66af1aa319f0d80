//! The `gradient_moment` stage (twin of `kernels/gradient_moment.cu`).

use super::CpuBackend;
use crate::fields::{FLUID, Fields};
use crate::math::sum_in_order;
use crate::model::params::StepParams;
use crate::physics::gradient_moment::{MomentSums, moment_terms};

impl<const D: usize> CpuBackend<D> {
    pub(super) fn gradient_moment(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> MomentSums {
        let kernel = params.smoothing();
        let (grid, f, partition) = (&self.grid, fields, &self.partition);
        let mut sums = sum_in_order(f.len(), |i| {
            // A rank's own fluid (`backend::partition`): ghosts are counted by their owners.
            if f.kind[i] != FLUID || !partition.counts(i) {
                return [0.0; 2];
            }
            let mut s = [0.0; 2];
            grid.for_each_neighbour(&f.position, i, |j, d, r2| {
                let t = moment_terms(&kernel, &d, r2, f.mass[j] / f.density[j]);
                s[0] += t[0];
                s[1] += t[1];
            });
            let m = MomentSums::of_particle(s);
            [m.moment, m.count]
        });
        self.partition.sum(&mut sums);
        MomentSums {
            moment: sums[0],
            count: sums[1],
        }
    }
}
