//! A simulation split across ranks (`crate::distributed`): every rank builds the whole scene,
//! keeps the particles of its region and runs its stages on a [`RankBackend`], which exchanges
//! ghosts and migrating particles and makes every reduction global. The driver (`step.rs`) is
//! the same; every rank takes the same decisions (time step, sorts, sweeps) because each one
//! rests on a reduction over all ranks.

use super::Simulation;
use crate::backend::BackendError;
use crate::backend::cpu::CpuBackend;
use crate::backend::partition::SharedCommunicator;
use crate::distributed::{Decomposition, HaloTraffic, Method, RankBackend, Rebalance, Region};
use crate::fields::Fields;
use crate::math::Real;
use crate::solver::checkpoint::{Checkpoint, CheckpointError};

/// How far [m], in units of the kernel's support, a particle may move between two sorts of a
/// split run (`RankBackend::margin`). A step moves particles by under a quarter support (the
/// time step's CFL limit) and the correction re-sorts after `RESORT_DRIFT` supports, so half a
/// support leaves room; a move past it is an error, not a silent miss.
pub const HALO_MARGIN: f64 = 0.5;

/// Why a simulation cannot be split across ranks.
#[derive(Debug, thiserror::Error)]
pub enum SplitError {
    /// The scene uses something a split run does not handle yet.
    #[error("a run across ranks does not support {0} yet")]
    Unsupported(&'static str),
    /// A rank stopped (its message).
    #[error("a rank failed: {0}")]
    RankFailed(String),
    /// The backend cannot run a rank's share.
    #[error(transparent)]
    Backend(#[from] BackendError),
}

impl<const D: usize> Simulation<D> {
    /// Makes this simulation (the whole scene, built the same way on every rank) rank
    /// `comm.rank()`'s share: the domain box is cut among the ranks by `method` at particle-count
    /// quantiles (`distributed::decomposition`), the particles of other regions are dropped,
    /// and the stages run on a [`RankBackend`] around the backend in use (the CPU, or this
    /// rank's GPU, staged through the host), which cuts the regions again as `rebalance` says.
    /// Returns the regions of the start.
    ///
    /// # Errors
    /// [`SplitError::Backend`] when the backend cannot take the rank's particles.
    pub fn split_across_ranks(
        &mut self,
        comm: SharedCommunicator,
        method: Method,
        rebalance: Rebalance,
    ) -> Result<Decomposition<D>, SplitError> {
        let size = crate::backend::partition::lock(&comm).size();
        let domain = Region {
            lo: self.config.domain_min,
            hi: self.config.domain_max,
        };
        self.sync_fields()?;
        let decomposition = Decomposition::build(domain, &self.fields.position, size, method);
        self.split_with(comm, decomposition.clone(), method, rebalance, None)?;
        Ok(decomposition)
    }

    /// [`Simulation::split_across_ranks`] into the given regions, keeping the particles of
    /// `mine` (indices, increasing), or those in this rank's region when `None` (a resumed run
    /// keeps the particles it owned at the checkpoint, in their order there).
    ///
    /// # Errors
    /// [`SplitError::Backend`] when the backend cannot take the rank's particles.
    pub fn split_with(
        &mut self,
        comm: SharedCommunicator,
        decomposition: Decomposition<D>,
        method: Method,
        rebalance: Rebalance,
        mine: Option<std::ops::Range<usize>>,
    ) -> Result<(), SplitError> {
        self.sync_fields()?;
        let rank = crate::backend::partition::lock(&comm).rank();
        let kept: Vec<u32> = match mine {
            Some(block) => (block.start as u32..block.end as u32).collect(),
            None => (0..self.fields.len() as u32)
                .filter(|&i| decomposition.owner(&self.fields.position[i as usize]) == rank)
                .collect(),
        };
        self.fields.keep(&kept);
        let reach = self.config.h as Real;
        let margin = (HALO_MARGIN * self.config.h) as Real;
        // The backend in use (and its device) runs the rank's stages, from the rank's particles.
        let mut inner = std::mem::replace(&mut self.backend, Box::new(CpuBackend::new()));
        self.use_backend_from(move |fields, params| {
            inner.reload(fields, params)?;
            let backend = RankBackend::new(
                inner,
                comm,
                decomposition,
                method,
                rebalance,
                reach,
                margin,
                fields.len(),
            )?;
            Ok(Box::new(backend))
        })?;
        Ok(())
    }

    /// What this rank did and sent so far, for a split run.
    pub fn halo_traffic(&self) -> Option<HaloTraffic> {
        self.backend.halo_traffic()
    }

    /// Checks from now on, after every ghost refresh of a split run, that every field of every
    /// ghost is its owner's; a difference stops the step with `DistributedError::StaleGhosts`.
    /// Costs a second, whole exchange per refresh (for tests and debugging).
    pub fn verify_halo(&mut self) {
        self.backend.verify_halo();
    }

    /// The regions of a split run now (`None` for a whole simulation).
    pub fn decomposition(&self) -> Option<Decomposition<D>> {
        self.backend.decomposition()
    }

    /// [`Simulation::checkpoint`] of this rank's own particles (without its ghosts).
    ///
    /// # Errors
    /// [`CheckpointError::Backend`] when the device copy fails.
    pub fn checkpoint_owned(
        &mut self,
        metadata: serde_json::Value,
    ) -> Result<Checkpoint<D>, CheckpointError> {
        let mut checkpoint = self.checkpoint(metadata)?;
        let partition = self.backend.partition();
        let kept: Vec<u32> = (0..checkpoint.fields.len() as u32)
            .filter(|&i| partition.counts(i as usize))
            .collect();
        if kept.len() < checkpoint.fields.len() {
            checkpoint.fields.keep(&kept);
            if !checkpoint.solve_records.is_empty() {
                checkpoint.solve_records = kept
                    .iter()
                    .map(|&i| checkpoint.solve_records[i as usize])
                    .collect();
            }
        }
        Ok(checkpoint)
    }

    /// Particles and fluid mass [kg] (2D: per metre) of the whole run: summed over ranks when
    /// split (every rank must call it then), this simulation's own otherwise.
    pub fn totals_over_ranks(&mut self) -> (u64, f64) {
        let f = &self.fields;
        let partition = self.backend.partition();
        let mut totals = crate::math::sum_in_order(f.len(), |i| {
            if !partition.counts(i) {
                return [0.0; 2];
            }
            let fluid_mass = if f.kind[i] == crate::fields::FLUID {
                f64::from(f.mass[i])
            } else {
                0.0
            };
            [1.0, fluid_mass]
        });
        self.backend.sum_over_ranks(&mut totals);
        (totals[0] as u64, totals[1])
    }

    /// This rank's own particles (all of them for a whole simulation), without its ghosts, in
    /// the order of the last sort.
    ///
    /// # Errors
    /// [`BackendError`] when the fields cannot be copied from the backend.
    pub fn owned_fields(&mut self) -> Result<Fields<D>, BackendError> {
        self.sync_fields()?;
        let partition = self.backend.partition();
        let kept: Vec<u32> = (0..self.fields.len() as u32)
            .filter(|&i| partition.counts(i as usize))
            .collect();
        let mut owned = self.fields.clone();
        if kept.len() < owned.len() {
            owned.keep(&kept);
        }
        Ok(owned)
    }
}
