//! The JSON run summary written at the end of (or during) a run.

use std::io::Write;
use std::path::Path;

use serde::{Deserialize, Deserializer, Serialize};

use super::{OutputError, write_atomically};

/// Reads an `f64` that may have been written as `null` (serde_json writes
/// non-finite floats as `null`); `null` becomes NaN.
fn f64_or_nan<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// The value of a number missing from an older summary: not known.
fn nan() -> f64 {
    f64::NAN
}

/// Summary of one solver run, serialised as pretty JSON by
/// [`write_summary`].
///
/// Non-finite floating-point values (e.g. errors of a diverged run) are
/// written as JSON `null` and read back as NaN.
#[derive(Serialize, Deserialize, Debug, Clone, Default, PartialEq)]
pub struct Summary {
    /// Scene name (usually the scene file stem).
    pub scene: String,
    /// The scene file the run was started from (absolute), when known: `sph plot` reads the
    /// probes' reference data from it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene_file: Option<std::path::PathBuf>,
    /// The `--set` overrides the run was started with.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub scene_overrides: Vec<String>,
    /// Spatial dimension, 2 or 3.
    pub dimension: usize,
    /// Solver / pressure-correction scheme name.
    pub solver: String,
    /// Compute backend (e.g. `"cpu"`, `"cuda"`).
    pub backend: String,
    /// Number of CPU worker threads used.
    pub threads: usize,
    /// Total number of particles (fluid + solid/boundary).
    pub particles: u64,
    /// Number of fluid particles (kind 0).
    pub fluid_particles: u64,
    /// Number of completed time steps.
    pub steps: u64,
    /// Simulated physical time reached, in seconds.
    #[serde(deserialize_with = "f64_or_nan")]
    pub simulated_time: f64,
    /// Wall-clock duration of the time loop, in seconds.
    #[serde(deserialize_with = "f64_or_nan")]
    pub wall_seconds: f64,
    /// Throughput: `particles * steps / wall_seconds`, in particle-steps per
    /// second.
    #[serde(deserialize_with = "f64_or_nan")]
    pub particle_steps_per_second: f64,
    /// Largest compression over the run (dimensionless): the maximum over steps and fluid
    /// particles `i` of `max(ρ_i − ρ0_i, 0)/ρ0_i`, `ρ0_i` the particle's rest density. This is
    /// what the `corrected` solver controls (eq. (24), PAPER.md note 6): it stays below
    /// `solver.delta` while every correction converges (`extra.unconverged_stages = 0`).
    ///
    /// Taken on the state at the start of every step (density summed afresh after the sort):
    /// the states the run passes through at `t^0, t^1, …`, the same measurement for every
    /// solver, so `wcsph` and `corrected` runs compare. For `corrected` that state is the one
    /// the previous step's last correction left (the density re-summed in another order, so it
    /// may exceed the correction's own value by f32 rounding, ~1e-7); the largest compression
    /// after any correction, intermediate Runge–Kutta stages and the start-up settle included,
    /// is `extra.max_compression_after_correction`.
    #[serde(default = "nan", deserialize_with = "f64_or_nan")]
    pub max_compression: f64,
    /// Mean compression (dimensionless): the average over steps of the per-step mean over
    /// fluid particles of `max(ρ − ρ0, 0)/ρ0` (same states as [`Self::max_compression`]).
    #[serde(default = "nan", deserialize_with = "f64_or_nan")]
    pub mean_compression: f64,
    /// Largest free-surface deficit over the run (dimensionless): the maximum over steps and
    /// fluid particles of `max(ρ0 − ρ, 0)/ρ0`. A particle at the free surface has neighbours on
    /// one side only, so its summed density (eq. (18)) falls short of `ρ0` by tens of percent
    /// without the fluid being expanded; no solver drives this to zero, and it is reported
    /// apart from the compression so that neither hides the other.
    #[serde(default = "nan", deserialize_with = "f64_or_nan")]
    pub max_surface_deficit: f64,
    /// Mean free-surface deficit (dimensionless): the average over steps of the per-step mean
    /// over fluid particles of `max(ρ0 − ρ, 0)/ρ0`.
    #[serde(default = "nan", deserialize_with = "f64_or_nan")]
    pub mean_surface_deficit: f64,
    /// Status of the run: `"running"` while it runs, then `"completed"`, `"failed: …"` (the
    /// error) or `"interrupted (signal N)"`.
    pub status: String,
    /// The run's identifier (kept across resumes; [`crate::run::RunIdentity`]).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub run_id: String,
    /// FNV-1a hash of the scene file the run started from (16 hex digits).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub scene_hash: String,
    /// What the user should know about the results (e.g. a weakly compressible run whose
    /// compression shows its sound speed is too low for the flow).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// Number of `.vtu` frames written.
    pub output_frames: u64,
    /// Free-form additional values (scene- or backend-specific metrics).
    #[serde(default)]
    pub extra: serde_json::Map<String, serde_json::Value>,
}

/// Writes `summary` to `path` as pretty-printed JSON (temporary file +
/// rename).
pub fn write_summary(path: &Path, summary: &Summary) -> Result<(), OutputError> {
    let json = serde_json::to_vec_pretty(summary).map_err(|source| OutputError::Json {
        path: path.to_path_buf(),
        source,
    })?;
    write_atomically(path, |w| {
        w.write_all(&json)?;
        w.write_all(b"\n")
    })
}

/// Reads a summary written by [`write_summary`].
pub fn read_summary(path: &Path) -> Result<Summary, OutputError> {
    let text = std::fs::read(path).map_err(|e| OutputError::io(path, e))?;
    serde_json::from_slice(&text).map_err(|source| OutputError::Json {
        path: path.to_path_buf(),
        source,
    })
}
