//! The MPI transport (feature `mpi`): rsmpi over the system's MPI library (Open MPI from the
//! distribution's packages). One [`MpiWorld`] per process, made once at start-up.

use super::communicator::Communicator;
use super::error::DistributedError;
use mpi::Count;
use mpi::datatype::{Partition, PartitionMut};
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::{Communicator as _, CommunicatorCollectives as _};

/// `MPI_COMM_WORLD` of this process; MPI is finalised when it is dropped.
pub struct MpiWorld {
    world: SimpleCommunicator,
    // Dropped last: finalises MPI.
    _universe: Universe,
}

impl MpiWorld {
    /// Initialises MPI. Fails when it already was (one world per process).
    pub fn initialize() -> Result<Self, DistributedError> {
        let universe =
            mpi::initialize().ok_or_else(|| DistributedError::Mpi("MPI was already initialised".into()))?;
        let world = universe.world();
        Ok(Self {
            world,
            _universe: universe,
        })
    }
}

/// Offsets of consecutive blocks of `counts`.
fn displacements(counts: &[Count]) -> Vec<Count> {
    counts
        .iter()
        .scan(0, |at, &c| {
            let start = *at;
            *at += c;
            Some(start)
        })
        .collect()
}

impl Communicator for MpiWorld {
    fn rank(&self) -> usize {
        self.world.rank() as usize
    }

    fn size(&self) -> usize {
        self.world.size() as usize
    }

    fn exchange(&self, outgoing: Vec<Vec<u8>>) -> Result<Vec<Vec<u8>>, DistributedError> {
        let n = self.size();
        assert_eq!(outgoing.len(), n, "one buffer per rank");
        let too_large =
            || DistributedError::Mpi("a rank's halo or migration exceeds 2 GiB in one exchange".into());
        let send_counts: Vec<Count> = outgoing
            .iter()
            .map(|b| Count::try_from(b.len()).map_err(|_| too_large()))
            .collect::<Result<_, _>>()?;
        let mut recv_counts: Vec<Count> = vec![0; n];
        self.world.all_to_all_into(&send_counts[..], &mut recv_counts[..]);
        let send_displs = displacements(&send_counts);
        let recv_displs = displacements(&recv_counts);
        let total: usize = recv_counts.iter().map(|&c| c as usize).sum();
        Count::try_from(total).map_err(|_| too_large())?;
        let flat: Vec<u8> = outgoing.concat();
        let mut buffer = vec![0u8; total];
        {
            let send = Partition::new(&flat[..], &send_counts[..], &send_displs[..]);
            let mut recv = PartitionMut::new(&mut buffer[..], &recv_counts[..], &recv_displs[..]);
            self.world.all_to_all_varcount_into(&send, &mut recv);
        }
        Ok(recv_counts
            .iter()
            .zip(&recv_displs)
            .map(|(&c, &at)| buffer[at as usize..(at + c) as usize].to_vec())
            .collect())
    }
}
