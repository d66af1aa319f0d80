//! The `state_extremes` stage (twin of `kernels/state_extremes.cu`).

use super::CpuBackend;
use crate::backend::StateExtremes;
use crate::fields::{FLUID, Fields};
use crate::math::{Vector, max_each_in_order, sum_in_order};
use crate::model::params::StepParams;
use rayon::prelude::*;

impl<const D: usize> CpuBackend<D> {
    pub(super) fn state_extremes(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> StateExtremes {
        let f = fields;
        let n = f.len();
        // Each particle's own rest density with the multiphase effect ([HA06]).
        let rest = &f.rest_density;
        let error = |i: usize| {
            let rho0 = f64::from(params.phases.rest_density(rest, i, params.rho0));
            (f64::from(f.density[i]) - rho0) / rho0
        };
        // A rank's own fluid (`backend::partition`): ghosts are counted by their owners.
        let partition = &self.partition;
        let fluid = |i: usize| f.kind[i] == FLUID && partition.counts(i);
        // The largest speed, acceleration, |error|, compression and deficit in one pass.
        let mut maxima = max_each_in_order(n, |i| {
            if !fluid(i) {
                return [0.0; 5];
            }
            let e = error(i);
            [
                f64::from(f.velocity[i].norm()),
                f64::from(f.acceleration[i].norm()),
                e.abs(),
                e.max(0.0),
                (-e).max(0.0),
            ]
        });
        let mut sums = sum_in_order(n, |i| {
            if !fluid(i) {
                return [0.0; 3];
            }
            let e = error(i);
            [1.0, e.abs(), e.max(0.0)]
        });
        self.partition.max(&mut maxima);
        self.partition.sum(&mut sums);
        let fluid = |i: usize| f.kind[i] == FLUID && self.partition.counts(i);
        let [max_speed, max_acceleration, max_abs, ..] = maxima;
        let non_finite = if (max_speed + max_acceleration + max_abs).is_finite() {
            None
        } else {
            first_non_finite(f)
        };
        let outside =
            |x: &Vector<D>| (0..D).any(|k| x[k] < params.domain_min[k] || x[k] > params.domain_max[k]);
        let escaped = (0..n)
            .into_par_iter()
            .find_first(|&i| fluid(i) && outside(&f.position[i]));
        StateExtremes {
            non_finite,
            ..StateExtremes::from_parts(maxima, sums, escaped)
        }
    }
}

/// First particle with a non-finite position, velocity, acceleration, density or pressure.
fn first_non_finite<const D: usize>(f: &Fields<D>) -> Option<(usize, &'static str)> {
    let finite = |v: &Vector<D>| v.iter().all(|c| c.is_finite());
    (0..f.len()).find_map(|i| {
        if !finite(&f.position[i]) {
            Some((i, "position"))
        } else if !finite(&f.velocity[i]) {
            Some((i, "velocity"))
        } else if !finite(&f.acceleration[i]) {
            Some((i, "acceleration"))
        } else if !f.density[i].is_finite() {
            Some((i, "density"))
        } else if !f.pressure[i].is_finite() {
            Some((i, "pressure"))
        } else {
            None
        }
    })
}
