//! Moving particles between ranks: migration (a particle whose position another rank owns moves
//! there with all its fields) and the halo (copies of the particles within the kernel's reach of
//! another rank's region, its ghosts).

use super::communicator::Communicator;
use super::decomposition::Decomposition;
use super::error::DistributedError;
use super::halo::{departures, halo_sends};
use super::packet::{append, pack};
use crate::fields::Fields;
use crate::math::Real;

/// What one exchange moved on this rank.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Traffic {
    /// Particles sent to other ranks.
    pub sent: usize,
    /// Particles received from other ranks.
    pub received: usize,
    /// Bytes sent to other ranks.
    pub bytes_sent: usize,
}

/// Sends every particle of `fields` that another rank's region owns to that rank, removes it
/// here, and appends the particles other ranks sent (in rank order, each rank's in its own
/// order). Fields travel bit for bit (`packet`).
pub fn migrate<C: Communicator + ?Sized, const D: usize>(
    comm: &C,
    decomposition: &Decomposition<D>,
    fields: &mut Fields<D>,
) -> Result<Traffic, DistributedError> {
    let (leaving, kept) = departures(decomposition, &fields.position, comm.rank());
    let packets: Vec<Vec<u8>> = leaving.iter().map(|indices| pack(fields, indices)).collect();
    let traffic = Traffic {
        sent: leaving.iter().map(Vec::len).sum(),
        received: 0,
        bytes_sent: sent_bytes(&packets, comm.rank()),
    };
    if kept.len() < fields.len() {
        fields.keep(&kept);
    }
    let received = comm.exchange(packets)?;
    let mut arrived = 0;
    for packet in &received {
        arrived += append(fields, packet)?;
    }
    Ok(Traffic {
        received: arrived,
        ..traffic
    })
}

/// The ghosts of this rank: copies of the particles of other ranks within `width` [m] of this
/// rank's region, in rank order, with every field. `owned` are this rank's own particles.
pub fn gather_ghosts<C: Communicator + ?Sized, const D: usize>(
    comm: &C,
    decomposition: &Decomposition<D>,
    owned: &Fields<D>,
    width: Real,
) -> Result<(Fields<D>, Traffic), DistributedError> {
    let sends = halo_sends(
        decomposition,
        &owned.position,
        comm.rank(),
        width,
        &crate::periodic::Periodic::none(),
    );
    let packets: Vec<Vec<u8>> = sends.iter().map(|indices| pack(owned, indices)).collect();
    let traffic = Traffic {
        sent: sends.iter().map(Vec::len).sum(),
        received: 0,
        bytes_sent: sent_bytes(&packets, comm.rank()),
    };
    let received = comm.exchange(packets)?;
    let mut ghosts = Fields::default();
    let mut arrived = 0;
    for packet in &received {
        arrived += append(&mut ghosts, packet)?;
    }
    Ok((
        ghosts,
        Traffic {
            received: arrived,
            ..traffic
        },
    ))
}

/// Bytes of `packets` bound for other ranks than `rank`.
pub(super) fn sent_bytes(packets: &[Vec<u8>], rank: usize) -> usize {
    packets
        .iter()
        .enumerate()
        .filter(|(r, _)| *r != rank)
        .map(|(_, p)| p.len())
        .sum()
}
