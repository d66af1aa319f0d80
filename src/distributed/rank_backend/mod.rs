//! One rank's backend in a run split across ranks: the stages of the backend it wraps, with
//! the rank's ghosts kept current around them (docs/distributed.md, "Runs across ranks").
//!
//! - Every `sort_by_cell` rebuilds the halo: ghosts are dropped, particles that left the rank's
//!   region migrate to their owners with every field, the owned particles within
//!   the halo's width (two supports plus twice the margin) of another region go there as
//!   ghosts, and the whole set is sorted.
//!   The wrapped backend's reductions then count owned particles only and add across ranks
//!   (`backend::partition`).
//! - Before each stage that sums over neighbours, if any stage wrote fields since the last
//!   exchange, the ghosts get every field of their owners again (a refresh, in the same order
//!   as the rebuild's). Stages run on ghosts too; what they compute there is overwritten by the
//!   next refresh. A value computed on a ghost and read by a neighbour before a refresh (the
//!   correction's pressure increments of the walls) is exact because the halo is two supports
//!   wide: a ghost within one support of the region has all its neighbours here.
//! - A backend whose state lives on a device (CUDA) is staged through the host: a rebuild
//!   downloads every field, exchanges, reloads the device and sorts there; a refresh downloads
//!   the written fields, exchanges and writes them back in place (`Backend::download_some`,
//!   `Backend::upload_some`). Its reductions skip ghosts on the device (the owned mask of
//!   `backend::partition`).
//! - Between rebuilds particles may move at most the margin given to [`RankBackend::new`]; a rebuild that finds
//!   a particle moved further reports [`super::DistributedError::HaloOutrun`] rather than sums
//!   that may have missed a neighbour.

use super::communicator::Communicator;
use super::decomposition::{Decomposition, Method, imbalance};
use super::error::DistributedError;
use super::exchange::{migrate, sent_bytes};
use super::halo::halo_sends;
use super::packet::{append, field_mask, pack, pack_fields, scatter};
use crate::backend::partition::{Partition, SharedCommunicator, lock};
use crate::backend::{Backend, BackendError};
use crate::fields::{Field, Fields};
use crate::grid::GridError;
use crate::math::{Real, Vector};
use crate::model::params::StepParams;
use crate::periodic::Periodic;
use std::collections::HashMap;

mod stages;

/// When a split run cuts the domain again (`sph run --rebalance`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rebalance {
    /// Keep the regions of the start.
    Never,
    /// At a halo rebuild whose per-rank particle counts have an imbalance
    /// (`distributed::imbalance`, `max/mean − 1`) above this: regions are cut again at the
    /// particle-count quantiles of the moment, by the run's method, and particles migrate.
    Above(f64),
}

/// What this rank did and sent since the backend was made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HaloTraffic {
    /// Halo rebuilds (one per sort).
    pub rebuilds: u64,
    /// Times the regions were cut again ([`Rebalance`]).
    pub rebalances: u64,
    /// Particles this rank owned at the last rebuild.
    pub owned: u64,
    /// Ghosts this rank held at the last rebuild.
    pub ghosts: u64,
    /// Ghost refreshes between rebuilds.
    pub refreshes: u64,
    /// Bytes of migrating particles.
    pub migration_bytes: u64,
    /// Bytes of ghosts sent at rebuilds.
    pub ghost_bytes: u64,
    /// Bytes of refreshes.
    pub refresh_bytes: u64,
}

/// The halo since the last rebuild: who gets which particles, by id and by current index.
#[derive(Debug, Default)]
struct Halo<const D: usize> {
    /// Per rank, the ids of this rank's particles sent there as ghosts, in sending order.
    send_ids: Vec<Vec<u32>>,
    /// Per rank, the ids of the ghosts received from it, in its sending order.
    recv_ids: Vec<Vec<u32>>,
    /// `send_ids`, `recv_ids` as indices in the current (last sorted) order.
    send_index: Vec<Vec<u32>>,
    recv_index: Vec<Vec<u32>>,
    /// Every ghost id (to drop them at the next rebuild, whatever the order then).
    ghosts: HashMap<u32, ()>,
    /// Positions [m] right after the rebuild's sort, in that order (for the drift check).
    anchor: Vec<Vector<D>>,
}

/// One rank's share of a split run around the backend that runs its stages.
pub struct RankBackend<const D: usize> {
    inner: Box<dyn Backend<D> + Send>,
    comm: SharedCommunicator,
    decomposition: Decomposition<D>,
    method: Method,
    rebalance: Rebalance,
    width: Real,
    margin: Real,
    halo: Option<Halo<D>>,
    /// The fields (mask, bit `k`: `Field::ALL[k]`) a stage wrote since the last exchange.
    dirty: u32,
    /// After every refresh, also check every field of every ghost against its owner's
    /// (`Backend::verify_halo`, or `SPH_VERIFY_HALO` set in the environment): the check that
    /// the stages' write lists below are complete.
    verify: bool,
    error: Option<BackendError>,
    traffic: HaloTraffic,
}

impl<const D: usize> RankBackend<D> {
    /// Rank `comm.rank()` of `decomposition` (cut by `method`, again when `rebalance` says),
    /// running its stages on `inner`. `reach` is the kernel's support [m]; particles may move
    /// `margin` [m] between two sorts. The rank holds `particles` particles of its own and no
    /// ghosts yet.
    ///
    /// # Errors
    /// [`BackendError::Unavailable`] when `inner` cannot run a rank's share.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        mut inner: Box<dyn Backend<D> + Send>,
        comm: SharedCommunicator,
        decomposition: Decomposition<D>,
        method: Method,
        rebalance: Rebalance,
        reach: Real,
        margin: Real,
        particles: usize,
    ) -> Result<Self, BackendError> {
        inner.set_partition(Partition::Rank {
            owned: vec![true; particles],
            comm: comm.clone(),
            error: None,
        })?;
        Ok(Self {
            inner,
            comm,
            decomposition,
            method,
            rebalance,
            width: 2.0 * reach + 2.0 * margin,
            margin,
            halo: None,
            dirty: u32::MAX,
            verify: std::env::var_os("SPH_VERIFY_HALO").is_some(),
            error: None,
            traffic: HaloTraffic::default(),
        })
    }

    fn fail(&mut self, error: DistributedError) {
        self.error.get_or_insert(BackendError::Ranks(error));
    }

    /// Drops the ghosts, migrates, gathers the ghosts again, sorts and indexes the halo.
    ///
    /// A backend that holds the state on a device (`Backend::holds_state`) is staged through
    /// the host: every field downloaded (the step-start copies too: a correction may sort
    /// within a stage), exchanged here, reloaded, sorted there, and the new order's ids and
    /// positions downloaded for the halo's index.
    fn rebuild(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) -> Result<(), GridError> {
        let staged = self.inner.holds_state();
        if staged {
            let r = self.inner.download_some(fields, &Field::ALL);
            self.keep(r);
        }
        if let Err(e) = self.exchange_particles(fields, &params.periodic()) {
            self.fail(e);
        }
        if staged {
            let r = self.inner.reload(fields, params);
            self.keep(r);
        }
        self.inner.sort_by_cell(fields, params)?;
        if staged {
            let r = self.inner.download_some(fields, &[Field::Id, Field::Position]);
            self.keep(r);
        }
        self.index(fields);
        Ok(())
    }

    /// Keeps the first failure of a backend call (the stages return none; the step reports it
    /// at its end).
    fn keep(&mut self, result: Result<(), BackendError>) {
        if let Err(e) = result {
            self.error.get_or_insert(e);
        }
    }

    fn exchange_particles(
        &mut self,
        fields: &mut Fields<D>,
        periodic: &Periodic<D>,
    ) -> Result<(), DistributedError> {
        let comm = self.comm.clone();
        let comm = lock(&comm);
        let rank = comm.rank();
        if let Some(halo) = self.halo.take() {
            // Drift since the last rebuild, over this rank's own particles (a particle wrapped
            // across a periodic face moved by its minimum image, not a period).
            let mut drift: f64 = 0.0;
            if halo.anchor.len() == fields.len() {
                for (i, x) in fields.position.iter().enumerate() {
                    if !halo.ghosts.contains_key(&fields.id[i]) {
                        drift = drift.max(f64::from(periodic.minimum_image(x - halo.anchor[i]).norm()));
                    }
                }
            }
            let drift = comm.max(drift)?;
            if drift > f64::from(self.margin) {
                return Err(DistributedError::HaloOutrun {
                    moved: drift,
                    margin: f64::from(self.margin),
                });
            }
            let kept: Vec<u32> = (0..fields.len() as u32)
                .filter(|&i| !halo.ghosts.contains_key(&fields.id[i as usize]))
                .collect();
            if kept.len() < fields.len() {
                fields.keep(&kept);
            }
        }
        self.migrate(&**comm, fields)?;
        if let Rebalance::Above(limit) = self.rebalance {
            let counts: Vec<usize> = comm
                .all_gather(&[fields.len() as f64])?
                .iter()
                .map(|c| c[0] as usize)
                .collect();
            if imbalance(&counts) > limit {
                // Every rank cuts the same regions from every position, gathered in rank order.
                let bytes: Vec<u8> = fields
                    .position
                    .iter()
                    .flat_map(|x| x.iter().flat_map(|c| c.to_le_bytes()).collect::<Vec<u8>>())
                    .collect();
                let all = comm.exchange(vec![bytes; comm.size()])?;
                let mut points = Vec::with_capacity(counts.iter().sum());
                for b in &all {
                    for chunk in b.chunks_exact(4 * D) {
                        let mut x = Vector::<D>::zeros();
                        for (k, c) in chunk.chunks_exact(4).enumerate() {
                            x[k] = Real::from_le_bytes(c.try_into().expect("4 bytes"));
                        }
                        points.push(x);
                    }
                }
                self.decomposition =
                    Decomposition::build(self.decomposition.domain, &points, comm.size(), self.method);
                self.traffic.rebalances += 1;
                self.migrate(&**comm, fields)?;
            }
        }
        self.traffic.owned = fields.len() as u64;
        // Ghosts, appended after the owned particles.
        let sends = halo_sends(&self.decomposition, &fields.position, rank, self.width, periodic);
        let packets: Vec<Vec<u8>> = sends.iter().map(|indices| pack(fields, indices)).collect();
        self.traffic.ghost_bytes += sent_bytes(&packets, rank) as u64;
        let send_ids: Vec<Vec<u32>> = sends
            .iter()
            .map(|indices| indices.iter().map(|&i| fields.id[i as usize]).collect())
            .collect();
        let mut recv_ids = Vec::with_capacity(comm.size());
        let mut ghosts = HashMap::new();
        for packet in &comm.exchange(packets)? {
            let first = fields.len();
            let count = append(fields, packet)?;
            let ids = fields.id[first..first + count].to_vec();
            ghosts.extend(ids.iter().map(|&id| (id, ())));
            recv_ids.push(ids);
        }
        self.traffic.rebuilds += 1;
        self.traffic.ghosts = (fields.len() as u64).saturating_sub(self.traffic.owned);
        self.halo = Some(Halo {
            send_ids,
            recv_ids,
            ghosts,
            ..Halo::default()
        });
        Ok(())
    }

    /// Sends every particle another region owns there and appends those sent here.
    fn migrate(&mut self, comm: &dyn Communicator, fields: &mut Fields<D>) -> Result<(), DistributedError> {
        let moved = migrate(comm, &self.decomposition, fields)?;
        self.traffic.migration_bytes += moved.bytes_sent as u64;
        Ok(())
    }

    /// After a sort: the halo's current indices, the owned mask the reductions count, and the
    /// positions the next drift check starts from.
    fn index(&mut self, fields: &Fields<D>) {
        let Some(halo) = self.halo.as_mut() else {
            return;
        };
        let at: HashMap<u32, u32> = fields
            .id
            .iter()
            .enumerate()
            .map(|(i, &id)| (id, i as u32))
            .collect();
        let lookup = |ids: &Vec<Vec<u32>>| -> Vec<Vec<u32>> {
            ids.iter()
                .map(|list| list.iter().map(|id| at[id]).collect())
                .collect()
        };
        halo.send_index = lookup(&halo.send_ids);
        halo.recv_index = lookup(&halo.recv_ids);
        let mut owned = vec![true; fields.len()];
        for list in &halo.recv_index {
            for &i in list {
                owned[i as usize] = false;
            }
        }
        halo.anchor.clone_from(&fields.position);
        // Errors of the old partition stay reported.
        if let Some(e) = self.inner.take_error() {
            self.error.get_or_insert(e);
        }
        let partition = Partition::Rank {
            owned,
            comm: self.comm.clone(),
            error: None,
        };
        if let Err(e) = self.inner.set_partition(partition) {
            self.error.get_or_insert(e);
        }
        self.dirty = 0;
    }

    /// Sends the owners' current values of the fields a stage wrote since the last exchange to
    /// their ghosts, before `stage` reads them.
    fn refresh(&mut self, fields: &mut Fields<D>, stage: &'static str) {
        if self.dirty == 0 || self.halo.is_none() {
            return; // nothing written, or before the first sort (no ghosts)
        }
        // A device's state comes to the host first: the written fields, or all of them for the
        // check below.
        let staged = self.inner.holds_state();
        if staged {
            let which = if self.verify {
                Field::ALL.to_vec()
            } else {
                fields_in(self.dirty)
            };
            let r = self.inner.download_some(fields, &which);
            self.keep(r);
        }
        let mask = self.dirty & field_mask(fields);
        if mask == 0 {
            return;
        }
        let Some(halo) = self.halo.as_ref() else {
            return;
        };
        let exchange = |fields: &mut Fields<D>, mask: u32| -> Result<u64, DistributedError> {
            let comm = lock(&self.comm);
            let packets: Vec<Vec<u8>> = halo
                .send_index
                .iter()
                .map(|idx| pack_fields(fields, idx, mask))
                .collect();
            let bytes = sent_bytes(&packets, comm.rank()) as u64;
            let received = comm.exchange(packets)?;
            if received.len() != halo.recv_index.len() {
                return Err(DistributedError::Malformed {
                    reason: "a refresh from another number of ranks",
                });
            }
            for (packet, indices) in received.iter().zip(&halo.recv_index) {
                scatter(fields, packet, indices)?;
            }
            Ok(bytes)
        };
        let mut result = exchange(fields, mask);
        if self.verify && result.is_ok() {
            // Every field of every ghost must now be its owner's: a second, whole exchange
            // may not change a bit.
            let before = fields.clone();
            result = exchange(fields, u32::MAX).and_then(|bytes| {
                let all = field_mask(fields);
                let unchanged = halo
                    .recv_index
                    .iter()
                    .all(|idx| pack_fields(&before, idx, all) == pack_fields(fields, idx, all));
                if unchanged {
                    Ok(bytes)
                } else {
                    Err(DistributedError::StaleGhosts { stage })
                }
            });
        }
        match result {
            Ok(bytes) => {
                self.traffic.refreshes += 1;
                self.traffic.refresh_bytes += bytes;
                if staged {
                    // The ghosts' new rows go back to the device.
                    let r = self.inner.upload_some(fields, &fields_in(mask));
                    self.keep(r);
                }
            }
            Err(e) => self.fail(e),
        }
        self.dirty = 0;
    }

    /// A stage that sums over neighbours: the ghosts refreshed first; it writes `writes`.
    fn summing<T>(
        &mut self,
        fields: &mut Fields<D>,
        stage: &'static str,
        writes: &[Field],
        run: impl FnOnce(&mut dyn Backend<D>, &mut Fields<D>) -> T,
    ) -> T {
        self.refresh(fields, stage);
        let out = run(self.inner.as_mut(), fields);
        self.wrote(writes);
        out
    }

    /// A stage of each particle on its own: it writes `writes`.
    fn local<T>(
        &mut self,
        fields: &mut Fields<D>,
        writes: &[Field],
        run: impl FnOnce(&mut dyn Backend<D>, &mut Fields<D>) -> T,
    ) -> T {
        let out = run(self.inner.as_mut(), fields);
        self.wrote(writes);
        out
    }

    /// Marks `writes` as changed since the last exchange.
    fn wrote(&mut self, writes: &[Field]) {
        for f in writes {
            let k = Field::ALL
                .iter()
                .position(|a| a == f)
                .expect("every field is in Field::ALL");
            self.dirty |= 1 << k;
        }
    }
}

/// The fields of `mask` (bit `k`: `Field::ALL[k]`).
fn fields_in(mask: u32) -> Vec<Field> {
    Field::ALL
        .iter()
        .enumerate()
        .filter(|(k, _)| mask & (1 << k) != 0)
        .map(|(_, f)| *f)
        .collect()
}
