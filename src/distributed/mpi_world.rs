//! The MPI transport (feature `mpi`): rsmpi over the system's MPI library (Open MPI from the
//! distribution's packages). One [`MpiWorld`] per process, made once at start-up.

use super::communicator::Communicator;
use super::error::DistributedError;
use mpi::Count;
use mpi::Threading;
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
    /// Initialises MPI with `MPI_THREAD_SERIALIZED`: the run calls MPI from whichever thread
    /// steps the simulation (a worker of the run's thread pool), one call at a time (the
    /// communicator sits behind a mutex, `backend::partition::SharedCommunicator`). Fails when
    /// MPI already was initialised (one world per process) or the library cannot serialise
    /// calls from several threads.
    pub fn initialize() -> Result<Self, DistributedError> {
        let (universe, provided) = mpi::initialize_with_threading(Threading::Serialized)
            .ok_or_else(|| DistributedError::Mpi("MPI was already initialised".into()))?;
        if !matches!(provided, Threading::Serialized | Threading::Multiple) {
            return Err(DistributedError::Mpi(format!(
                "the MPI library provides thread level {provided:?}, and a run needs Serialized"
            )));
        }
        let world = universe.world();
        Ok(Self {
            world,
            _universe: universe,
        })
    }
}

// SAFETY: MPI was initialised with `MPI_THREAD_SERIALIZED` (checked in `initialize`), which
// allows calls from any thread as long as no two overlap; the run holds the world behind a
// mutex, so calls never overlap. The handles are plain integers or pointers to library state
// that is not tied to the initialising thread.
unsafe impl Send for MpiWorld {}

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
        // Never an empty allocation: an empty Vec's dangling address is 0x1, which Open MPI
        // reads as MPI_IN_PLACE and refuses; one spare byte gives each buffer a real address.
        let mut flat: Vec<u8> = Vec::with_capacity(outgoing.iter().map(Vec::len).sum::<usize>() + 1);
        for b in &outgoing {
            flat.extend_from_slice(b);
        }
        let sent = flat.len();
        flat.push(0);
        let mut buffer = vec![0u8; total + 1];
        {
            let send = Partition::new(&flat[..sent], &send_counts[..], &send_displs[..]);
            let mut recv = PartitionMut::new(&mut buffer[..total], &recv_counts[..], &recv_displs[..]);
            self.world.all_to_all_varcount_into(&send, &mut recv);
        }
        Ok(recv_counts
            .iter()
            .zip(&recv_displs)
            .map(|(&c, &at)| buffer[at as usize..(at + c) as usize].to_vec())
            .collect())
    }
}
