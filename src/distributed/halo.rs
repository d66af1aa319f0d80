//! Which particles a rank sends to which: its halo (the ghosts other ranks need for their
//! neighbour sums) and its departures (the particles that now belong to another rank).

use super::decomposition::Decomposition;
use crate::math::{Real, Vector};
use crate::periodic::Periodic;

/// For every rank `r`, the indices (increasing) of the particles of `positions`, owned by
/// `rank`, that lie within `width` [m] of region `r` (none for `rank` itself). A particle near a
/// corner goes to every rank whose region is that close. `width` is the kernel's support `h`
/// plus how far particles may move before the halo is rebuilt. Along a `periodic` axis the
/// distance is to the nearest image of the region: the ghost keeps its position, and the
/// receiver's neighbour search takes the minimum image as it does for its own particles.
pub fn halo_sends<const D: usize>(
    decomposition: &Decomposition<D>,
    positions: &[Vector<D>],
    rank: usize,
    width: Real,
    periodic: &Periodic<D>,
) -> Vec<Vec<u32>> {
    let mut sends = vec![Vec::new(); decomposition.ranks()];
    for (to, region) in decomposition.regions.iter().enumerate() {
        if to == rank {
            continue;
        }
        sends[to] = positions
            .iter()
            .enumerate()
            .filter(|(_, x)| region.distance_periodic(x, periodic) < width)
            .map(|(i, _)| i as u32)
            .collect();
    }
    sends
}

/// For every rank `r`, the indices (increasing) of the particles of `positions` that `r` owns
/// and `rank` does not; and the indices `rank` keeps.
pub fn departures<const D: usize>(
    decomposition: &Decomposition<D>,
    positions: &[Vector<D>],
    rank: usize,
) -> (Vec<Vec<u32>>, Vec<u32>) {
    let mut leaving = vec![Vec::new(); decomposition.ranks()];
    let mut kept = Vec::with_capacity(positions.len());
    for (i, x) in positions.iter().enumerate() {
        let owner = decomposition.owner(x);
        if owner == rank {
            kept.push(i as u32);
        } else {
            leaving[owner].push(i as u32);
        }
    }
    (leaving, kept)
}
