//! The CPU side of the velocity solve's Anderson acceleration (`solver::anderson`): the
//! window's difference vectors, the previous iterate, and the mixing step
//! (`Backend::mix_velocity_pressure`). Twin of `backend::cuda::anderson`.

use crate::backend::partition::Partition;
use crate::fields::{FLUID, Fields};
use crate::math::{Real, sum_in_order};
use crate::physics::correction;
use crate::physics::multiphase::Phases;
use crate::solver::anderson::{AndersonState, WINDOW};
use rayon::prelude::*;

/// The host state and the vectors [Pa] of the acceleration: per ring slot the differences
/// `ΔP_j`, `Δf_j` of consecutive iterates, the previous iterate `P` with its `f = g(P) − P`,
/// and the current `f`.
#[derive(Debug, Default)]
pub(super) struct AndersonBuffers {
    state: AndersonState,
    dp: Vec<Vec<Real>>,
    df: Vec<Vec<Real>>,
    previous: Vec<Real>,
    previous_f: Vec<Real>,
    f: Vec<Real>,
}

impl AndersonBuffers {
    /// Forgets every iterate (a new solve); the vectors keep their memory.
    pub(super) fn reset(&mut self) {
        self.state.reset();
    }

    /// Bytes held by the vectors.
    pub(super) fn heap_bytes(&self) -> usize {
        let slots: usize = self.dp.iter().chain(&self.df).map(Vec::capacity).sum();
        (slots + self.previous.capacity() + self.previous_f.capacity() + self.f.capacity()) * 4
    }

    /// One accelerated sweep on the fluid pressure of `fields` from the predicted density in
    /// `fields.density`: `g(P) = max(P + k (ρ* − ρ0), 0)` (`physics::correction::pressure_increment`,
    /// stiffness `k` [m²/s²], `rho0` [kg/m³] or each particle's own with the multiphase effect),
    /// mixed with the window's iterates, `P ≥ 0` (note 6).
    pub(super) fn mix<const D: usize>(
        &mut self,
        fields: &mut Fields<D>,
        phases: Phases,
        rho0: Real,
        k: Real,
        partition: &mut Partition,
    ) {
        let n = fields.len();
        let (kind, density, rest) = (&fields.kind, &fields.density, &fields.rest_density);
        // f = g(P) − P for fluid, 0 for solids.
        self.f.resize(n, 0.0);
        self.f.par_iter_mut().enumerate().for_each(|(i, out)| {
            *out = if kind[i] == FLUID {
                let rho0 = phases.rest_density(rest, i, rho0);
                correction::pressure_increment(density[i], rho0, fields.pressure[i], k)
            } else {
                0.0
            };
        });
        if self.dp.len() != WINDOW {
            self.dp = vec![Vec::new(); WINDOW];
            self.df = vec![Vec::new(); WINDOW];
        }
        let state = &mut self.state;
        if state.has_previous {
            let s = state.next;
            let (dp, df) = (&mut self.dp[s], &mut self.df[s]);
            dp.resize(n, 0.0);
            df.resize(n, 0.0);
            let (p, prev, f, prev_f) = (&fields.pressure, &self.previous, &self.f, &self.previous_f);
            dp.par_iter_mut()
                .zip(df.par_iter_mut())
                .enumerate()
                .for_each(|(i, (dp, df))| {
                    *dp = p[i] - prev[i];
                    *df = f[i] - prev_f[i];
                });
            let valid = (state.held + 1).min(WINDOW);
            let slots = &self.df;
            let counted = &*partition;
            let mut dots = sum_in_order::<WINDOW, _>(n, |i| {
                let mut t = [0.0; WINDOW];
                if !counted.counts(i) {
                    return t; // a ghost: its owner adds it
                }
                for (l, out) in t.iter_mut().enumerate().take(valid) {
                    *out = f64::from(slots[s][i]) * f64::from(slots[l][i]);
                }
                t
            });
            partition.sum(&mut dots);
            state.push(&dots);
        }
        let held = state.held;
        let (slots_dp, slots_df, f) = (&self.dp, &self.df, &self.f);
        let counted = &*partition;
        let mut rhs = sum_in_order::<WINDOW, _>(n, |i| {
            let mut t = [0.0; WINDOW];
            if !counted.counts(i) {
                return t;
            }
            for (l, out) in t.iter_mut().enumerate().take(held) {
                *out = f64::from(slots_df[l][i]) * f64::from(f[i]);
            }
            t
        });
        partition.sum(&mut rhs);
        let gamma = state.coefficients(&rhs).map(|g| g as Real);
        state.has_previous = true;
        self.previous.clone_from(&fields.pressure);
        fields.pressure.par_iter_mut().enumerate().for_each(|(i, p)| {
            if kind[i] == FLUID {
                let mut mixed = *p + f[i];
                for l in 0..held {
                    mixed -= gamma[l] * (slots_dp[l][i] + slots_df[l][i]);
                }
                *p = mixed.max(0.0); // note 6
            }
        });
        // This `f` becomes the previous one: a swap, the next call rewrites `f` whole.
        std::mem::swap(&mut self.f, &mut self.previous_f);
    }
}
