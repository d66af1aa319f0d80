//! Errors of the distributed run: a peer that stopped answering, a packet that does not parse.

use thiserror::Error;

/// What can go wrong between ranks.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum DistributedError {
    /// Another rank stopped (crashed, was killed, or returned early): the whole run must stop.
    #[error("rank {rank} stopped answering (it failed or was killed); the run stops on every rank")]
    PeerLost {
        /// The rank that is gone.
        rank: usize,
    },
    /// A packet of particles ended early or had bytes left over.
    #[error("malformed particle packet: {reason}")]
    Malformed {
        /// What was wrong.
        reason: &'static str,
    },
    /// Two ranks hold different sets of fields, so their particles cannot be merged.
    #[error("particle packet with fields {theirs:#x} where this rank holds {ours:#x}")]
    FieldMismatch {
        /// This rank's field mask (`packet::field_mask`).
        ours: u32,
        /// The packet's.
        theirs: u32,
    },
    /// A particle moved further between two halo rebuilds than the halo allows for, so a
    /// neighbour sum may have missed a particle of another rank.
    #[error(
        "a particle moved {moved:.3e} m between two halo rebuilds, more than the halo's margin of {margin:.3e} m; the step's sums near rank boundaries may be incomplete"
    )]
    HaloOutrun {
        /// The largest move [m].
        moved: f64,
        /// The margin [m] (`distributed::rank_backend`).
        margin: f64,
    },
    /// A ghost's fields differed from its owner's after a refresh (checked with
    /// `SPH_VERIFY_HALO`): a stage wrote a field its write list does not name.
    #[error(
        "a ghost's fields differ from its owner's after the refresh before {stage}: a stage's write list misses a field"
    )]
    StaleGhosts {
        /// The stage the refresh came before.
        stage: &'static str,
    },
    /// Rank 0 stopped the run before the ranks began (the others stop with this).
    #[error("rank 0 stopped the run: {reason}")]
    RootStopped {
        /// Why.
        reason: &'static str,
    },
    /// The MPI library reported an error.
    #[error("MPI: {0}")]
    Mpi(String),
}
