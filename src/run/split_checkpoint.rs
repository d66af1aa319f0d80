//! Checkpoints of a run split across ranks (docs/distributed.md, "Checkpoints").
//!
//! Rank k > 0 writes its own particles to `checkpoints/step_SSSSSSSSS_rK.bin`; once every
//! piece is on disk, rank 0 writes `checkpoint.bin` with its own particles, the run's state and
//! [`RankPieces`] (the step, every rank's count and region), then drops the pieces of older
//! steps. `checkpoint.bin` is written last and atomically, so it always names pieces that are
//! complete: a run killed at any moment resumes from the last checkpoint it finished.
//!
//! Resuming, every rank reads `checkpoint.bin` and the pieces, applies the whole state to the
//! whole simulation (`Simulation::restore` checks every particle as for one rank), and keeps
//! its share: on the same number of ranks exactly the particles it held, in their order, in
//! the regions of the checkpoint, so the run continues bit for bit; on another number the
//! regions are cut again from the particles' positions.

use super::{CHECKPOINT_FILE, Loop, Ranks, RunOptions, RunState, checked_checkpoint, run_state};
use crate::backend::BackendError;
use crate::distributed::packet::{append, pack};
use crate::distributed::{Decomposition, DistributedError, Region};
use crate::error::Error;
use crate::fields::Fields;
use crate::math::Vector;
use crate::run::folder::RunFolder;
use crate::solver::Simulation;
use crate::solver::checkpoint::{Checkpoint, CheckpointError};

/// What `checkpoint.bin` of a split run says about its pieces.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RankPieces {
    /// The step the pieces hold.
    pub step: u64,
    /// Particles of each rank, in rank order (rank 0's are in `checkpoint.bin`).
    pub counts: Vec<u64>,
    /// The domain box, lower and upper corner [m].
    pub domain: [Vec<f32>; 2],
    /// Each rank's region, lower and upper corner [m].
    pub regions: Vec<[Vec<f32>; 2]>,
}

/// The file of rank `rank`'s piece of the checkpoint at step `step`.
pub(super) fn piece_name(step: u64, rank: usize) -> String {
    format!("checkpoints/step_{step:09}_r{rank}.bin")
}

fn corners<const D: usize>(region: &Region<D>) -> [Vec<f32>; 2] {
    [
        region.lo.iter().copied().collect(),
        region.hi.iter().copied().collect(),
    ]
}

fn region<const D: usize>(corners: &[Vec<f32>; 2]) -> Option<Region<D>> {
    let [lo, hi] = corners;
    (lo.len() == D && hi.len() == D).then(|| Region {
        lo: Vector::<D>::from_iterator(lo.iter().copied()),
        hi: Vector::<D>::from_iterator(hi.iter().copied()),
    })
}

/// Every rank's piece of the checkpoint of the state now (see the module's doc).
pub(super) fn write<const D: usize>(
    sim: &mut Simulation<D>,
    options: &RunOptions,
    state: &mut Loop,
    ranks: &Ranks,
) -> Result<(), Error> {
    let Some(dir) = &options.out_dir else {
        return Ok(());
    };
    let (rank, size) = (ranks.rank(), ranks.size());
    let step = sim.clock().step;
    if let Some(w) = state.writers.as_mut() {
        for k in 1..size {
            w.folder.claim(&piece_name(step, k))?;
        }
    }
    ranks.barrier()?; // claimed before anyone writes
    let mut checkpoint = sim.checkpoint_owned(serde_json::Value::Null)?;
    if rank > 0 {
        checkpoint.write(&dir.join(piece_name(step, rank)))?;
    }
    let counts = ranks.counts(checkpoint.fields.len())?;
    ranks.barrier()?; // every piece on disk
    if rank > 0 {
        return Ok(());
    }
    let decomposition = sim
        .decomposition()
        .ok_or(crate::solver::ranks::SplitError::Unsupported(
            "a checkpoint of a split run from a whole simulation",
        ))?;
    let Some(mut run_state) = run_state(options, state)? else {
        return Ok(());
    };
    run_state.ranks = Some(RankPieces {
        step,
        counts,
        domain: corners(&decomposition.domain),
        regions: decomposition.regions.iter().map(corners).collect(),
    });
    let w = state.writers.as_mut().expect("rank 0 writes");
    let path = w.folder.claim(CHECKPOINT_FILE)?;
    checkpoint.header.metadata =
        serde_json::to_value(&run_state).map_err(|e| CheckpointError::Malformed {
            path: path.clone(),
            reason: format!("run state: {e}"),
        })?;
    checkpoint.write(&path)?;
    let current = format!("checkpoints/step_{step:09}_");
    for name in w.folder.listed("checkpoints/") {
        if !name.starts_with(&current) {
            w.folder.discard(&name)?;
        }
    }
    Ok(())
}

/// The checkpoint of the run in `options.out_dir` on every rank, applied to the whole `sim`
/// (rank 0 checks it against the folder it holds as a whole run's resume does).
pub(super) fn resume<const D: usize>(
    sim: &mut Simulation<D>,
    folder: Option<&RunFolder>,
    options: &RunOptions,
    ranks: &Ranks,
) -> Result<RunState, Error> {
    let checked = match folder {
        Some(folder) => checked_checkpoint::<D>(folder, options).map(Some),
        None => Ok(None),
    };
    if ranks.root_says(f64::from(u8::from(checked.is_ok())))? == 0.0 && !ranks.is_root() {
        return Err(BackendError::Ranks(DistributedError::RootStopped {
            reason: "it could not resume from the run folder's checkpoint",
        })
        .into());
    }
    let dir = options
        .out_dir
        .as_deref()
        .ok_or(crate::solver::ranks::SplitError::Unsupported(
            "resuming without a run folder",
        ))?;
    let (mut checkpoint, state) = match checked? {
        Some(found) => found,
        None => read_run_state::<D>(&dir.join(CHECKPOINT_FILE))?,
    };
    if let Some(pieces) = &state.ranks {
        let path = dir.join(CHECKPOINT_FILE);
        let bad = |reason: String| CheckpointError::Malformed {
            path: path.clone(),
            reason,
        };
        if pieces.counts.first() != Some(&(checkpoint.fields.len() as u64)) {
            return Err(bad("its own particles differ from the count it lists for rank 0".into()).into());
        }
        for (k, &count) in pieces.counts.iter().enumerate().skip(1) {
            let piece = Checkpoint::<D>::read(&dir.join(piece_name(pieces.step, k)))?;
            if piece.header.clock.step != pieces.step || piece.fields.len() as u64 != count {
                return Err(bad(format!(
                    "the piece of rank {k} holds step {} with {} particles, not step {} with {count}",
                    piece.header.clock.step,
                    piece.fields.len(),
                    pieces.step
                ))
                .into());
            }
            append_all(&mut checkpoint.fields, &piece.fields).map_err(|e| bad(e.to_string()))?;
        }
    }
    sim.restore(checkpoint)?;
    Ok(state)
}

/// Makes the whole `sim` this rank's share: the particles and regions of `pieces` when it was
/// checkpointed on as many ranks, else regions cut from the particles now.
pub(super) fn split<const D: usize>(
    sim: &mut Simulation<D>,
    ranks: &Ranks,
    pieces: Option<&RankPieces>,
) -> Result<(), Error> {
    let (rank, size) = (ranks.rank(), ranks.size());
    let stored = pieces.filter(|p| p.counts.len() == size && p.regions.len() == size);
    let regions: Option<(Region<D>, Vec<Region<D>>)> = stored.and_then(|p| {
        let domain = region::<D>(&p.domain)?;
        let regions: Option<Vec<Region<D>>> = p.regions.iter().map(region::<D>).collect();
        Some((domain, regions?))
    });
    match (stored, regions) {
        (Some(p), Some((domain, regions))) => {
            let start: u64 = p.counts[..rank].iter().sum();
            let block = start as usize..(start + p.counts[rank]) as usize;
            let decomposition = Decomposition { domain, regions };
            sim.split_with(
                ranks.comm.clone(),
                decomposition,
                ranks.method,
                ranks.rebalance,
                Some(block),
            )?;
        }
        _ => {
            sim.split_across_ranks(ranks.comm.clone(), ranks.method, ranks.rebalance)?;
        }
    }
    Ok(())
}

/// Appends every particle of `more` to `fields`.
fn append_all<const D: usize>(fields: &mut Fields<D>, more: &Fields<D>) -> Result<(), DistributedError> {
    let all: Vec<u32> = (0..more.len() as u32).collect();
    append(fields, &pack(more, &all)).map(|_| ())
}

/// A rank other than 0 reads `checkpoint.bin` itself (rank 0 checked it against the folder).
fn read_run_state<const D: usize>(path: &std::path::Path) -> Result<(Checkpoint<D>, RunState), Error> {
    let checkpoint = Checkpoint::<D>::read(path)?;
    let state: RunState = serde_json::from_value(checkpoint.header.metadata.clone()).map_err(|e| {
        CheckpointError::Malformed {
            path: path.to_path_buf(),
            reason: format!("run state: {e}"),
        }
    })?;
    Ok((checkpoint, state))
}
