//! Domain decomposition across ranks (issue "Beyond one machine"): which rank owns which region
//! ([`decomposition`]), which particles travel where ([`halo`]), how they travel ([`packet`],
//! [`exchange`]) and over what ([`communicator`]: threads of one process in [`local`], MPI with
//! the `mpi` feature).
//!
//! The design, after PySPH's and GPUSPH's: each rank owns the particles inside its region and
//! receives, before each stage that sums over neighbours, copies of the particles of other ranks
//! within the kernel's support of its region (ghosts); a particle that leaves its rank's region
//! moves to the new owner with every field. Reductions add in rank order, so a run on N ranks
//! repeats itself bit for bit.

pub mod communicator;
pub mod decomposition;
pub mod error;
pub mod exchange;
pub mod halo;
pub mod local;
#[cfg(feature = "mpi")]
pub mod mpi_world;
pub mod packet;
pub mod rank_backend;

pub use communicator::Communicator;
pub use decomposition::{Decomposition, Method, Region, imbalance};
pub use error::DistributedError;
pub use exchange::{Traffic, gather_ghosts, migrate};
pub use local::{LocalRank, LocalWorld};
pub use rank_backend::{HaloTraffic, RankBackend, Rebalance};
