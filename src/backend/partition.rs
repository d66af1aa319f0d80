//! Which particles a backend's reductions count, and how one rank's partial results combine
//! with the other ranks' (a run split across ranks, `crate::distributed`).
//!
//! A rank's fields hold its own particles and, after them in sort order anywhere, ghosts: copies
//! of other ranks' particles within reach of its region. Every reduction (the time step's
//! extremes, the correction's residual and sweep scale, the velocity solve's inner products, the
//! forces on solids, the no-penetration guard's impulse) adds over owned particles only and then
//! across ranks, in rank order, so every rank gets the same bits.

use crate::distributed::{Communicator, DistributedError};
use crate::math::max_or_nan;
use std::sync::{Arc, Mutex};

/// A communicator the rank's backend and its ghost exchange share (one per rank, used from the
/// thread that steps the simulation).
pub type SharedCommunicator = Arc<Mutex<Box<dyn Communicator + Send>>>;

/// The partition of a backend that holds the whole simulation.
pub static WHOLE: Partition = Partition::Whole;

/// Whether a backend holds every particle or one rank's share.
#[derive(Default)]
pub enum Partition {
    /// The whole simulation: every particle counts, nothing to combine.
    #[default]
    Whole,
    /// One rank of several.
    Rank {
        /// `owned[i]`: particle `i` (current sort order) is this rank's, not a ghost.
        owned: Vec<bool>,
        /// The ranks' transport.
        comm: SharedCommunicator,
        /// The first failed collective since the last `take_error` (the stages return no
        /// errors; the step reports it at its end).
        error: Option<DistributedError>,
    },
}

impl std::fmt::Debug for Partition {
    fn fmt(&self, out: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Partition::Whole => write!(out, "Whole"),
            Partition::Rank { owned, .. } => write!(out, "Rank {{ {} particles }}", owned.len()),
        }
    }
}

impl Partition {
    /// Whether particle `i` enters this rank's reductions (not a ghost).
    #[inline(always)]
    pub fn counts(&self, i: usize) -> bool {
        match self {
            Partition::Whole => true,
            Partition::Rank { owned, .. } => owned.get(i).copied().unwrap_or(false),
        }
    }

    /// This rank's number; `None` for the whole simulation.
    pub fn rank(&self) -> Option<usize> {
        match self {
            Partition::Whole => None,
            Partition::Rank { comm, .. } => Some(lock(comm).rank()),
        }
    }

    /// Replaces each of `values` by its sum over ranks (added in rank order).
    pub fn sum(&mut self, values: &mut [f64]) {
        if let Partition::Rank { comm, error, .. } = self {
            match lock(comm).sum(values) {
                Ok(total) => values.copy_from_slice(&total),
                Err(e) => {
                    error.get_or_insert(e);
                }
            }
        }
    }

    /// Replaces each of `values` by its largest over ranks (a NaN anywhere stays NaN, as
    /// `math::max_or_nan` keeps it within a rank).
    pub fn max(&mut self, values: &mut [f64]) {
        if let Partition::Rank { comm, error, .. } = self {
            match lock(comm).all_gather(values) {
                Ok(all) => {
                    for (k, v) in values.iter_mut().enumerate() {
                        *v = all.iter().map(|r| r[k]).fold(f64::NEG_INFINITY, max_or_nan);
                    }
                }
                Err(e) => {
                    error.get_or_insert(e);
                }
            }
        }
    }

    /// The first failed collective since the last call, if any.
    pub fn take_error(&mut self) -> Option<DistributedError> {
        match self {
            Partition::Whole => None,
            Partition::Rank { error, .. } => error.take(),
        }
    }
}

/// The communicator, even if another holder panicked while holding it (its state is the
/// transport's, which reports a lost peer by itself).
pub fn lock(comm: &SharedCommunicator) -> std::sync::MutexGuard<'_, Box<dyn Communicator + Send>> {
    comm.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}
