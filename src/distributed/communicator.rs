//! What the distributed run needs from its transport: an all-to-all exchange of byte buffers
//! and reductions whose result does not depend on arrival order.
//!
//! Two transports implement it: [`super::local::LocalWorld`] (ranks as threads of one process,
//! for tests and for checking a decomposition without MPI) and, with the `mpi` feature,
//! `super::mpi_world::MpiWorld` over rsmpi.

use super::error::DistributedError;

/// One rank's view of the group of ranks. Every rank calls the collective methods in the same
/// order, as MPI requires.
pub trait Communicator {
    /// This rank, `0..size()`.
    fn rank(&self) -> usize;

    /// Number of ranks.
    fn size(&self) -> usize;

    /// Sends `outgoing[r]` to rank `r` (an empty buffer for none; `outgoing[rank()]` comes back
    /// to this rank) and returns what each rank sent to this one, indexed by sender.
    fn exchange(&self, outgoing: Vec<Vec<u8>>) -> Result<Vec<Vec<u8>>, DistributedError>;

    /// Every rank's `values`, indexed by rank (all the same length on every rank).
    fn all_gather(&self, values: &[f64]) -> Result<Vec<Vec<f64>>, DistributedError> {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let received = self.exchange(vec![bytes; self.size()])?;
        received
            .iter()
            .map(|b| {
                if b.len() % 8 != 0 {
                    return Err(DistributedError::Malformed {
                        reason: "a gathered value is cut short",
                    });
                }
                Ok(b.chunks_exact(8)
                    .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
                    .collect())
            })
            .collect()
    }

    /// The element-wise sum of every rank's `values`, added in rank order so that every rank
    /// gets the same bits and a run on N ranks repeats itself.
    fn sum(&self, values: &[f64]) -> Result<Vec<f64>, DistributedError> {
        let all = self.all_gather(values)?;
        Ok((0..values.len())
            .map(|k| all.iter().map(|v| v[k]).sum())
            .collect())
    }

    /// The largest of every rank's `value`.
    fn max(&self, value: f64) -> Result<f64, DistributedError> {
        Ok(self
            .all_gather(&[value])?
            .iter()
            .map(|v| v[0])
            .fold(f64::NEG_INFINITY, f64::max))
    }

    /// The smallest of every rank's `value`.
    fn min(&self, value: f64) -> Result<f64, DistributedError> {
        Ok(self
            .all_gather(&[value])?
            .iter()
            .map(|v| v[0])
            .fold(f64::INFINITY, f64::min))
    }
}
