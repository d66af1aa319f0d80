//! Fluid particles that leave the domain box (a splash over a side wall, a droplet thrown
//! out): removed, or the run stops ([`EscapePolicy`], `solver.on_escape` in a scene).
//!
//! Removal happens at the start of a step, on the host: the fields are synced, every fluid
//! particle outside the domain (the test `StateExtremes::escaped` applies) is dropped from
//! every field in order ([`crate::fields::Fields::keep`]), and the backend is built again from
//! the remaining particles on its device (`Backend::reload`). The count goes to the step's report,
//! the run's statistics, `steps.csv` and `summary.json`. A checkpoint then holds fewer
//! particles than the scene; restoring it accepts that as long as every missing particle is
//! fluid.

use super::{Simulation, StepError};
use crate::fields::FLUID;

/// What a step does when a fluid particle is outside the domain box.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EscapePolicy {
    /// Remove it, count it and go on (the default: a splash that leaves the tank should not
    /// end a long run).
    #[default]
    Remove,
    /// Stop with [`StepError::Escaped`] naming the particle (strict conservation: the
    /// hard-case scenes, which check that no fluid is lost).
    Stop,
}

impl EscapePolicy {
    /// The name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            EscapePolicy::Remove => "remove",
            EscapePolicy::Stop => "stop",
        }
    }
}

impl<const D: usize> Simulation<D> {
    /// Removes every fluid particle outside the domain box from the (synced) host fields and
    /// rebuilds the backend; returns how many went.
    pub(super) fn remove_escaped(&mut self) -> Result<u64, StepError> {
        let step = self.clock.step;
        let (lo, hi) = (self.config.domain_min, self.config.domain_max);
        let f = &self.fields;
        let outside = |i: usize| (0..D).any(|k| f.position[i][k] < lo[k] || f.position[i][k] > hi[k]);
        // Split across ranks, a rank removes its own particles only (a ghost goes with its
        // owner's next halo) and the count is over all ranks.
        let partition = self.backend.partition();
        let gone = |i: usize| f.kind[i] == FLUID && outside(i) && partition.counts(i);
        let kept: Vec<u32> = (0..f.len()).filter(|&i| !gone(i)).map(|i| i as u32).collect();
        let mut removed = [(0..f.len()).filter(|&i| gone(i)).count() as f64];
        let any = kept.len() < f.len();
        self.backend.sum_over_ranks(&mut removed);
        let removed = removed[0] as u64;
        if any {
            self.fields.keep(&kept);
        }
        self.stats.removed_particles += removed;
        // Split across ranks, every rank rebuilds when any removed (its next sort is then a
        // collective halo rebuild on every rank).
        if removed > 0 {
            self.reload_backend()
                .map_err(|source| StepError::Backend { step, source })?;
        }
        Ok(removed)
    }
}
