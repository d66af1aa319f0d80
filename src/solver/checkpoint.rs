//! Checkpoints: the whole state a step depends on, written atomically and read back so that a
//! restarted run continues bit for bit.
//!
//! A step depends on the fields (positions, velocities, the last accelerations for the time
//! step, densities, the pressures the `corrected` solver carries, masses, kinds, ids, in their
//! current order), the clock (with the last step's `dt`, by which symplectic Euler advances the
//! density of the `density_diffusion` effect at the next step's start), the run statistics and
//! the last forces on solids; every step starts with a fresh sort (`step.rs`), so no grid or
//! scratch state is needed (the density rate is recomputed before every use).
//!
//! File layout (little endian): the magic `SPHCKPT1`, `u32` dimension, `u64` particle count,
//! `u64` length and the JSON of [`Header`] (plus the caller's metadata), then the arrays
//! position, velocity, acceleration (`n·D` f32 each), density, pressure, mass (`n` f32), kind, id
//! (`n` u32), where the `corrected` solver's velocity solves kept records (the warm start,
//! `Backend::record_velocity_solve`) per particle a `u32` mask of the slots that hold one and
//! `VELOCITY_SOLVE_SLOTS` f32 increments (0 where none), and an FNV-1a 64-bit checksum of
//! everything before it. It is written to
//! a unique temporary sibling created exclusively (`output::safe_file`), flushed to disk and
//! renamed over `<path>`, so `<path>` always holds a complete
//! checkpoint.

use super::stage::Stage;
use super::{Clock, RunStats, Simulation};
use crate::backend::{BackendError, SolveRecord, VELOCITY_SOLVE_SLOTS};
use crate::fields::{FLUID, Fields};
use crate::math::{Real, Vector};
use std::io::Write;
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 8] = b"SPHCKPT1";

/// The scalar state of a checkpoint, stored as JSON in the file.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Header {
    /// Simulated time and steps.
    pub clock: Clock,
    /// Density-error and correction statistics so far.
    pub stats: RunStats,
    /// Force of the fluid on each solid at the last step [N].
    pub solid_force: Vec<[f64; 3]>,
    /// Moment of that force about the origin [N m] (`Simulation::solid_moments`); absent from
    /// checkpoints written before it was kept, which restore it as zero.
    #[serde(default)]
    pub solid_moment: Vec<[f64; 3]>,
    /// Each solid's floating body (`solver::floating`), `None` for the others; empty without
    /// floating solids.
    #[serde(default)]
    pub bodies: Vec<Option<super::floating::BodyRecord>>,
    /// Whatever the caller keeps with the state (the run driver: output bookkeeping).
    pub metadata: serde_json::Value,
}

/// The state of a simulation between two steps.
#[derive(Clone, Debug)]
pub struct Checkpoint<const D: usize> {
    /// Scalars.
    pub header: Header,
    /// Particle fields, in the simulation's current order (`position_start` and
    /// `velocity_start` are empty: they only live inside a step; so is `normal`, recomputed by
    /// the `surface_normals` stage before every use).
    pub fields: Fields<D>,
    /// Each particle's velocity-solve records, in the order of `fields`
    /// (`Backend::velocity_solve_records`); empty where none counts (`wcsph`, a split run, the
    /// first step).
    pub solve_records: Vec<SolveRecord>,
}

/// Errors reading, writing or applying a checkpoint.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    /// The file could not be read or written.
    #[error("checkpoint {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file is not a complete checkpoint of this program.
    #[error("checkpoint {path} is damaged or not a checkpoint: {reason}")]
    Malformed {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// The checkpoint does not belong to this simulation.
    #[error("checkpoint does not match the scene: {reason}")]
    Mismatch {
        /// What differs.
        reason: String,
    },
    /// The backend could not hand over its state.
    #[error(transparent)]
    Backend(#[from] BackendError),
}

/// FNV-1a, 64 bit: detects a truncated or altered file (not an adversary).
pub(crate) fn fnv1a(bytes: &[u8], mut hash: u64) -> u64 {
    for &b in bytes {
        hash ^= u64::from(b);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    hash
}
pub(crate) const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

fn put_reals(out: &mut Vec<u8>, values: impl Iterator<Item = Real>) {
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
}

impl<const D: usize> Simulation<D> {
    /// The current state (copied from the device first for a device-resident backend), with
    /// `metadata` kept in its header.
    ///
    /// # Errors
    /// [`CheckpointError::Backend`] when the device copy fails.
    pub fn checkpoint(&mut self, metadata: serde_json::Value) -> Result<Checkpoint<D>, CheckpointError> {
        self.sync_fields()?;
        let mut solve_records = self.backend.velocity_solve_records(&self.fields.id)?;
        if solve_records.iter().all(|r| r.iter().all(Option::is_none)) {
            solve_records.clear();
        }
        let mut fields = self.fields.clone();
        fields.position_start.clear();
        fields.velocity_start.clear();
        fields.wall_velocity.clear();
        // Recomputed by the `surface_normals` stage before every use.
        fields.normal.clear();
        Ok(Checkpoint {
            header: Header {
                clock: self.clock,
                stats: self.stats,
                solid_force: self.solid_force.clone(),
                solid_moment: self.solid_moment.clone(),
                bodies: if self.floating.iter().any(Option::is_some) {
                    self.floating
                        .iter()
                        .map(|b| b.as_ref().map(|b| b.record()))
                        .collect()
                } else {
                    Vec::new()
                },
                metadata,
            },
            fields,
            solve_records,
        })
    }

    /// Continues from `checkpoint`, which must come from a simulation of the same scene: the
    /// same particles (count, and the mass and kind of every id) and solids.
    ///
    /// # Errors
    /// [`CheckpointError::Mismatch`] naming what differs; [`CheckpointError::Backend`] when the
    /// backend cannot take the state.
    pub fn restore(&mut self, checkpoint: Checkpoint<D>) -> Result<(), CheckpointError> {
        let mismatch = |reason: String| CheckpointError::Mismatch { reason };
        let (ours, theirs) = (&self.fields, &checkpoint.fields);
        // Fluid particles that left the domain may have been removed (`solver::escape`), and
        // open boundaries remove and create them (`solver::open`).
        let created_mass = self.open.as_ref().map(|o| o.template.mass.to_bits());
        if theirs.len() > ours.len() && created_mass.is_none() {
            return Err(mismatch(format!(
                "{} particles in the checkpoint, {} in the scene",
                theirs.len(),
                ours.len()
            )));
        }
        if checkpoint.header.solid_force.len() != self.solid_names.len() {
            return Err(mismatch(format!(
                "{} solids in the checkpoint, {} in the scene",
                checkpoint.header.solid_force.len(),
                self.solid_names.len()
            )));
        }
        // Every id once, with the scene's mass and kind for that id.
        let mut by_id = vec![usize::MAX; ours.len()];
        for (i, &id) in ours.id.iter().enumerate() {
            by_id[id as usize] = i;
        }
        let mut seen = vec![false; ours.len()];
        let mut created = Vec::new();
        for k in 0..theirs.len() {
            let id = theirs.id[k] as usize;
            let Some(&i) = by_id.get(id) else {
                // A particle an inflow created: fluid, of the lattice mass, once.
                if created_mass == Some(theirs.mass[k].to_bits()) && theirs.kind[k] == FLUID {
                    created.push(id);
                    continue;
                }
                return Err(mismatch(format!("particle id {id} is not in the scene")));
            };
            if std::mem::replace(&mut seen[id], true) {
                return Err(mismatch(format!("particle id {id} appears twice")));
            }
            if ours.kind[i] != theirs.kind[k] || ours.mass[i].to_bits() != theirs.mass[k].to_bits() {
                return Err(mismatch(format!(
                    "particle {id} differs in kind or mass (spacing, boxes or solids changed?)"
                )));
            }
        }
        created.sort_unstable();
        if let Some(w) = created.windows(2).find(|w| w[0] == w[1]) {
            return Err(mismatch(format!("particle id {} appears twice", w[0])));
        }
        if let Some(i) = (0..ours.len()).find(|&i| !seen[ours.id[i] as usize] && ours.kind[i] != FLUID) {
            return Err(mismatch(format!(
                "solid particle {} of the scene is not in the checkpoint",
                ours.id[i]
            )));
        }
        let no_slip = !self.fields.wall_velocity.is_empty();
        // The phases' rest densities are the scene's (the masses matched above), by id.
        let rest_density: Vec<crate::math::Real> = if ours.rest_density.is_empty() {
            Vec::new()
        } else {
            theirs
                .id
                .iter()
                .map(|&id| ours.rest_density[by_id[id as usize]])
                .collect()
        };
        let solve_records = checkpoint.solve_records;
        if !solve_records.is_empty() && solve_records.len() != checkpoint.fields.len() {
            return Err(mismatch(format!(
                "{} velocity-solve records for {} particles",
                solve_records.len(),
                checkpoint.fields.len()
            )));
        }
        self.fields = checkpoint.fields;
        self.fields.rest_density = rest_density;
        if no_slip {
            // Recomputed by every stage before use: allocated again, not stored.
            self.fields.wall_velocity = vec![Vector::zeros(); self.fields.len()];
        }
        if self.plan.contains(&Stage::Correction) {
            // Written by every stage before a probe reads it: not stored.
            self.fields.acting_pressure.clone_from(&self.fields.pressure);
        }
        self.clock = checkpoint.header.clock;
        // A checkpoint after the first step holds the settled state (a settle at step 0 that
        // was checkpointed before stepping runs again: it finds nothing left to move).
        self.settled = self.clock.step > 0;
        self.stats = checkpoint.header.stats;
        self.solid_moment = if checkpoint.header.solid_moment.len() == self.solid_names.len() {
            checkpoint.header.solid_moment
        } else {
            vec![[0.0; 3]; self.solid_names.len()]
        };
        self.solid_force = checkpoint.header.solid_force;
        if self.floating.iter().any(Option::is_some) {
            let records = &checkpoint.header.bodies;
            let matches = records.len() == self.floating.len()
                && records
                    .iter()
                    .zip(&self.floating)
                    .all(|(r, b)| r.is_some() == b.is_some());
            if !matches {
                return Err(mismatch(
                    "the checkpoint's floating bodies differ from the scene's".into(),
                ));
            }
            for (r, b) in records.iter().zip(&mut self.floating) {
                if let (Some(r), Some(b)) = (r, b) {
                    b.restore(r);
                }
            }
        }
        self.fields_stale = false;
        // The solids stand where the checkpoint has them; the next stage places them again.
        self.solids_placed_at = None;
        self.reload_backend()?;
        self.backend
            .restore_velocity_solve_records(&self.fields.id, &solve_records)?;
        Ok(())
    }
}

fn malformed(path: &Path, reason: &str) -> CheckpointError {
    CheckpointError::Malformed {
        path: path.to_path_buf(),
        reason: reason.into(),
    }
}

/// The file's bytes without the checksum, once the magic and the checksum are checked.
fn verified(path: &Path) -> Result<Vec<u8>, CheckpointError> {
    let mut bytes = std::fs::read(path).map_err(|source| CheckpointError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    if bytes.len() < 36 || &bytes[..8] != MAGIC {
        return Err(malformed(path, "no SPHCKPT1 header"));
    }
    let sum = bytes.split_off(bytes.len() - 8);
    if fnv1a(&bytes, FNV_OFFSET).to_le_bytes()[..] != sum[..] {
        return Err(malformed(path, "checksum mismatch (truncated or altered)"));
    }
    Ok(bytes)
}

/// The header of the checkpoint at `path` and its dimension, without its arrays (for finding
/// the scene a run came from before knowing its dimension).
///
/// # Errors
/// As [`Checkpoint::read`].
pub fn read_header(path: &Path) -> Result<(usize, Header), CheckpointError> {
    let bytes = verified(path)?;
    let body = bytes.as_slice();
    let bad = |reason: &str| malformed(path, reason);
    let dim = u32::from_le_bytes(body[8..12].try_into().expect("4 bytes")) as usize;
    let len = usize::try_from(u64::from_le_bytes(body[20..28].try_into().expect("8 bytes")))
        .map_err(|_| bad("header length overflows"))?;
    let json = body
        .get(28..28usize.saturating_add(len))
        .ok_or_else(|| bad("header runs past the end"))?;
    let header = serde_json::from_slice(json).map_err(|e| bad(&format!("header: {e}")))?;
    Ok((dim, header))
}

impl<const D: usize> Checkpoint<D> {
    /// Writes the checkpoint to `path` atomically (temporary file, flush to disk, rename).
    ///
    /// # Errors
    /// [`CheckpointError::Io`] naming the file.
    pub fn write(&self, path: &Path) -> Result<(), CheckpointError> {
        let io = |source| CheckpointError::Io {
            path: path.to_path_buf(),
            source,
        };
        let f = &self.fields;
        let n = f.len();
        let header = serde_json::to_vec(&self.header).map_err(|e| io(std::io::Error::other(e)))?;
        let mut out = Vec::with_capacity(64 + header.len() + n * (3 * D + 5) * 4);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&(D as u32).to_le_bytes());
        out.extend_from_slice(&(n as u64).to_le_bytes());
        out.extend_from_slice(&(header.len() as u64).to_le_bytes());
        out.extend_from_slice(&header);
        for v in [&f.position, &f.velocity, &f.acceleration] {
            put_reals(&mut out, v.iter().flat_map(|x| x.iter().copied()));
        }
        for v in [&f.density, &f.pressure, &f.mass] {
            put_reals(&mut out, v.iter().copied());
        }
        for v in [&f.kind, &f.id] {
            for x in v.iter() {
                out.extend_from_slice(&x.to_le_bytes());
            }
        }
        for record in &self.solve_records {
            let mask = (0..VELOCITY_SOLVE_SLOTS).fold(0u32, |m, s| m | (u32::from(record[s].is_some()) << s));
            out.extend_from_slice(&mask.to_le_bytes());
            put_reals(&mut out, record.iter().map(|r| r.unwrap_or(0.0)));
        }
        let sum = fnv1a(&out, FNV_OFFSET);
        out.extend_from_slice(&sum.to_le_bytes());
        let tmp = crate::output::safe_file::unique_tmp_path(path, "");
        let write = || -> std::io::Result<()> {
            let mut file = crate::output::safe_file::create_new(&tmp)?;
            file.write_all(&out)?;
            file.sync_all()?;
            std::fs::rename(&tmp, path)
        };
        write().map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            io(e)
        })
    }

    /// Reads a checkpoint written by [`Checkpoint::write`].
    ///
    /// # Errors
    /// [`CheckpointError::Io`], or [`CheckpointError::Malformed`] for a truncated, altered or
    /// foreign file, or one of another dimension.
    pub fn read(path: &Path) -> Result<Self, CheckpointError> {
        let bytes = verified(path)?;
        let body = bytes.as_slice();
        let bad = |reason: &str| malformed(path, reason);
        let u32_at = |at: usize| u32::from_le_bytes(body[at..at + 4].try_into().expect("4 bytes"));
        let u64_at = |at: usize| u64::from_le_bytes(body[at..at + 8].try_into().expect("8 bytes"));
        let dim = u32_at(8) as usize;
        if dim != D {
            return Err(bad(&format!("a {dim}D checkpoint, the scene is {D}D")));
        }
        let n = usize::try_from(u64_at(12)).map_err(|_| bad("particle count overflows"))?;
        let header_len = usize::try_from(u64_at(20)).map_err(|_| bad("header length overflows"))?;
        let arrays = n
            .checked_mul((3 * D + 5) * 4)
            .and_then(|a| a.checked_add(28 + header_len))
            .ok_or_else(|| bad("sizes overflow"))?;
        let record_bytes = (1 + VELOCITY_SOLVE_SLOTS) * 4;
        let with_records = n.checked_mul(record_bytes).and_then(|r| r.checked_add(arrays));
        let has_records = match body.len() {
            len if len == arrays => false,
            len if Some(len) == with_records && n > 0 => true,
            _ => return Err(bad("length does not match its particle count")),
        };
        let header: Header =
            serde_json::from_slice(&body[28..28 + header_len]).map_err(|e| bad(&format!("header: {e}")))?;
        let mut at = 28 + header_len;
        let mut reals = |count: usize| -> Vec<Real> {
            let v = body[at..at + 4 * count]
                .chunks_exact(4)
                .map(|c| Real::from_le_bytes(c.try_into().expect("4 bytes")))
                .collect();
            at += 4 * count;
            v
        };
        let vectors = |flat: Vec<Real>| -> Vec<Vector<D>> {
            flat.chunks_exact(D).map(Vector::<D>::from_column_slice).collect()
        };
        let position = vectors(reals(n * D));
        let velocity = vectors(reals(n * D));
        let acceleration = vectors(reals(n * D));
        let density = reals(n);
        let pressure = reals(n);
        let mass = reals(n);
        let words: Vec<u32> = body[at..at + 8 * n]
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes(c.try_into().expect("4 bytes")))
            .collect();
        let (kind, id) = words.split_at(n);
        let solve_records = if has_records {
            body[at + 8 * n..]
                .chunks_exact(record_bytes)
                .map(|c| {
                    let word = |k: usize| c[4 * k..4 * k + 4].try_into().expect("4 bytes");
                    let mask = u32::from_le_bytes(word(0));
                    std::array::from_fn(|s| (mask >> s & 1 == 1).then(|| Real::from_le_bytes(word(1 + s))))
                })
                .collect()
        } else {
            Vec::new()
        };
        Ok(Self {
            header,
            solve_records,
            fields: Fields {
                position,
                velocity,
                acceleration,
                density,
                pressure,
                mass,
                kind: kind.to_vec(),
                id: id.to_vec(),
                position_start: Vec::new(),
                velocity_start: Vec::new(),
                wall_velocity: Vec::new(),
                normal: Vec::new(),
                // Not stored: `Simulation::restore` takes it from the scene by id.
                rest_density: Vec::new(),
                // Recomputed by the `density_rate` stage before every use; the step start is
                // stored by the step's first stage.
                density_rate: Vec::new(),
                density_start: Vec::new(),
                // Not stored: `Simulation::restore` starts it from the restored pressure.
                acting_pressure: Vec::new(),
            },
        })
    }
}
