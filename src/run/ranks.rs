//! A run split across ranks (`mpirun -np N sph run`, docs/distributed.md): what the run driver
//! needs beyond the split simulation (`solver::ranks`).
//!
//! - Rank 0 owns the run folder: it takes the lock, writes `summary.json`, `steps.csv`,
//!   `forces.csv`, `bodies.csv`, `probes.csv` and the `.pvd` series. Every figure in them is
//!   global already (the reductions add over ranks), so they read as a single rank's would,
//!   but for rounding.
//! - Frames are parallel VTK: each rank writes its own particles as a piece
//!   (`frames/frame_NNNNN_rK.vtu`), and rank 0 writes the `.pvtu` header once every piece is
//!   on disk (`output::pvtu`).
//! - When the probes are due, the owned particles each probe reads (`probe::reach`: those
//!   within its kernel's reach, a front's furthest) are gathered on rank 0, which records them;
//!   the free surface reads every particle, and all are gathered for it.
//! - Every decision that ends or shapes the loop (a frame, a probe sample, a signal) is taken
//!   by rank 0 and shared, so no rank waits in a collective the others skipped.

use crate::backend::BackendError;
use crate::backend::partition::{SharedCommunicator, lock};
use crate::distributed::packet::{append, pack};
use crate::distributed::{DistributedError, Method, Rebalance};
use crate::error::Error;
use crate::fields::Fields;

/// How a run is split across ranks.
#[derive(Clone)]
pub struct Ranks {
    /// The transport: MPI under `mpirun`, threads in tests.
    pub comm: SharedCommunicator,
    /// How the domain is cut.
    pub method: Method,
    /// When it is cut again.
    pub rebalance: Rebalance,
    /// This rank's GPU for `--backend cuda` (its rank among the ranks on its machine; counted
    /// modulo the GPUs it sees, `Simulation::use_backend_on`).
    pub device: usize,
}

impl std::fmt::Debug for Ranks {
    fn fmt(&self, out: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            out,
            "Ranks {{ rank {} of {}, {:?}, {:?} }}",
            self.rank(),
            self.size(),
            self.method,
            self.rebalance
        )
    }
}

fn failed(e: DistributedError) -> Error {
    BackendError::Ranks(e).into()
}

impl Ranks {
    /// This rank.
    pub fn rank(&self) -> usize {
        lock(&self.comm).rank()
    }

    /// Number of ranks.
    pub fn size(&self) -> usize {
        lock(&self.comm).size()
    }

    /// Whether this rank writes the run's files.
    pub fn is_root(&self) -> bool {
        self.rank() == 0
    }

    /// Rank 0's `value`, on every rank.
    pub fn root_says(&self, value: f64) -> Result<f64, Error> {
        let all = lock(&self.comm).all_gather(&[value]).map_err(failed)?;
        Ok(all[0][0])
    }

    /// The largest of every rank's `value`, on every rank.
    pub fn largest(&self, value: f64) -> Result<f64, Error> {
        lock(&self.comm).max(value).map_err(failed)
    }

    /// Every rank's `count`, in rank order.
    pub fn counts(&self, count: usize) -> Result<Vec<u64>, Error> {
        let all = lock(&self.comm).all_gather(&[count as f64]).map_err(failed)?;
        Ok(all.iter().map(|c| c[0] as u64).collect())
    }

    /// Waits until every rank got here.
    pub fn barrier(&self) -> Result<(), Error> {
        lock(&self.comm).all_gather(&[]).map_err(failed)?;
        Ok(())
    }

    /// Every rank's `owned` particles on rank 0, in rank order (`None` on the other ranks).
    pub fn gather<const D: usize>(&self, owned: &Fields<D>) -> Result<Option<Fields<D>>, Error> {
        let everyone: Vec<u32> = (0..owned.len() as u32).collect();
        self.gather_some(owned, &everyone)
    }

    /// The particles `indices` (increasing) of every rank's `owned` on rank 0, in rank order
    /// (`None` on the other ranks).
    pub fn gather_some<const D: usize>(
        &self,
        owned: &Fields<D>,
        indices: &[u32],
    ) -> Result<Option<Fields<D>>, Error> {
        let comm = lock(&self.comm);
        let mut outgoing = vec![Vec::new(); comm.size()];
        outgoing[0] = pack(owned, indices);
        let received = comm.exchange(outgoing).map_err(failed)?;
        if comm.rank() != 0 {
            return Ok(None);
        }
        let mut all = Fields::default();
        for packet in &received {
            append(&mut all, packet).map_err(failed)?;
        }
        Ok(Some(all))
    }
}
