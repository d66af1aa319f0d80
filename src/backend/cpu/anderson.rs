//! The CPU side of the velocity solve's Anderson acceleration (`solver::anderson`): the
//! window's difference vectors, the previous iterate, and the mixing step
//! (`Backend::mix_velocity_pressure`). Twin of `backend::cuda::anderson`.

use crate::backend::partition::Partition;
use crate::fields::{FLUID, Fields};
use crate::math::{REDUCTION_CHUNK, Real};
use crate::physics::correction;
use crate::physics::multiphase::Phases;
use crate::solver::anderson::{AndersonState, WINDOW};
use rayon::prelude::*;

/// The host state and the vectors [Pa] of the acceleration: per ring slot the difference
/// `Δf_j` of consecutive iterates and the sum `ΔP_j + Δf_j` (all the mix reads of `ΔP_j`), the
/// previous iterate `P` with its `f = g(P) − P`, and the current `f`.
#[derive(Debug, Default)]
pub(super) struct AndersonBuffers {
    state: AndersonState,
    dp_df: Vec<Vec<Real>>,
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
        let slots: usize = self.dp_df.iter().chain(&self.df).map(Vec::capacity).sum();
        (slots + self.previous.capacity() + self.previous_f.capacity() + self.f.capacity()) * 4
    }

    /// One accelerated sweep on the fluid pressure of `fields` from the predicted density in
    /// `fields.density`: `g(P) = max(P + k (ρ* − ρ0), 0)` (`physics::correction::pressure_increment`,
    /// stiffness `k` [m²/s²], `rho0` [kg/m³] or each particle's own with the multiphase effect),
    /// mixed with the window's iterates, `P ≥ 0` (note 6).
    ///
    /// Two parallel passes: `f`, the new differences and every dot product in one (chunks of
    /// `REDUCTION_CHUNK` summed in order, as `math::sum_in_order` sums them, so the sums do not
    /// depend on the thread count), then the mixed pressure with the previous iterate saved. At
    /// a few thousand particles a parallel pass costs about what its work does, so the passes
    /// are fused (docs/performance.md, "The corrected solver's sweeps").
    pub(super) fn mix<const D: usize>(
        &mut self,
        fields: &mut Fields<D>,
        phases: Phases,
        rho0: Real,
        k: Real,
        partition: &mut Partition,
    ) {
        let n = fields.len();
        if self.dp_df.len() != WINDOW {
            self.dp_df = vec![Vec::new(); WINDOW];
            self.df = vec![Vec::new(); WINDOW];
        }
        self.f.resize(n, 0.0);
        self.previous.resize(n, 0.0);
        self.previous_f.resize(n, 0.0);
        for v in self.dp_df.iter_mut().chain(self.df.iter_mut()) {
            v.resize(n, 0.0);
        }
        let state = &mut self.state;
        let has_previous = state.has_previous;
        let s = state.next;
        // The differences the new one is dotted with (its own slot included), and those `f` is
        // fitted by once it is pushed.
        let valid = (state.held + 1).min(WINDOW);
        let held_after = if has_previous { valid } else { 0 };
        let (kind, density, rest) = (&fields.kind, &fields.density, &fields.rest_density);
        let pressure = &fields.pressure;
        let (previous, previous_f) = (&self.previous, &self.previous_f);
        let counted = &*partition;
        // The new slot's vectors are written; the others are read (`split_at_mut` around `s`).
        let dp_df_new = &mut self.dp_df[s];
        let (df_before, df_rest) = self.df.split_at_mut(s);
        let (df_new, df_after) = df_rest.split_first_mut().expect("WINDOW slots");
        let (df_before, df_after) = (&*df_before, &*df_after);
        let slot_df = |l: usize, i: usize, df_s: Real| -> Real {
            match l.cmp(&s) {
                std::cmp::Ordering::Less => df_before[l][i],
                std::cmp::Ordering::Equal => df_s,
                std::cmp::Ordering::Greater => df_after[l - s - 1][i],
            }
        };
        let partial: Vec<([f64; WINDOW], [f64; WINDOW])> = self
            .f
            .par_chunks_mut(REDUCTION_CHUNK)
            .zip(dp_df_new.par_chunks_mut(REDUCTION_CHUNK))
            .zip(df_new.par_chunks_mut(REDUCTION_CHUNK))
            .enumerate()
            .map(|(c, ((f, dp_df), df))| {
                let mut dots = [0.0f64; WINDOW];
                let mut rhs = [0.0f64; WINDOW];
                for (o, f_i) in f.iter_mut().enumerate() {
                    let i = c * REDUCTION_CHUNK + o;
                    // f = g(P) − P for fluid, 0 for solids.
                    *f_i = if kind[i] == FLUID {
                        let rho0 = phases.rest_density(rest, i, rho0);
                        correction::pressure_increment(density[i], rho0, pressure[i], k)
                    } else {
                        0.0
                    };
                    if has_previous {
                        df[o] = *f_i - previous_f[i];
                        // Only `ΔP_j + Δf_j` enters the mix: summed once here, the same f32
                        // sum the mix would take.
                        dp_df[o] = (pressure[i] - previous[i]) + df[o];
                    }
                    if !counted.counts(i) {
                        continue; // a ghost: its owner adds it
                    }
                    if has_previous {
                        for l in 0..valid {
                            dots[l] += f64::from(df[o]) * f64::from(slot_df(l, i, df[o]));
                        }
                    }
                    for l in 0..held_after {
                        rhs[l] += f64::from(slot_df(l, i, df[o])) * f64::from(*f_i);
                    }
                }
                (dots, rhs)
            })
            .collect();
        let (mut dots, mut rhs) = ([0.0f64; WINDOW], [0.0f64; WINDOW]);
        for (d, r) in &partial {
            for l in 0..WINDOW {
                dots[l] += d[l];
                rhs[l] += r[l];
            }
        }
        if has_previous {
            partition.sum(&mut dots);
            state.push(&dots);
        }
        let held = state.held;
        debug_assert_eq!(held, held_after);
        partition.sum(&mut rhs);
        let gamma = state.coefficients(&rhs).map(|g| g as Real);
        state.has_previous = true;
        let (slots_dp_df, f) = (&self.dp_df, &self.f);
        fields
            .pressure
            .par_iter_mut()
            .zip(self.previous.par_iter_mut())
            .enumerate()
            .for_each(|(i, (p, previous))| {
                *previous = *p;
                if kind[i] == FLUID {
                    let mut mixed = *p + f[i];
                    for l in 0..held {
                        mixed -= gamma[l] * slots_dp_df[l][i];
                    }
                    *p = mixed.max(0.0); // note 6
                }
            });
        // This `f` becomes the previous one: a swap, the next call rewrites `f` whole.
        std::mem::swap(&mut self.f, &mut self.previous_f);
    }
}
