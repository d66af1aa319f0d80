//! The free-surface series of a run: one `surface/surface_NNNNN.vtp` per particle frame (same
//! index and time; triangles in 3D, line segments in 2D, arrays stored in the run's
//! [`Encoding`]), listed in `surface.pvd` beside `particles.pvd`. Written during
//! `sph run` when the scene has `[output] surface = true`, or afterwards from the frames of a
//! finished run by [`reconstruct_run`] (`sph surface RUN_DIR`).
//!
//! A separate `.pvd` (rather than a second part in `particles.pvd`) keeps the particle series
//! unchanged and lets ParaView open the surface alone or next to the particles.

use std::path::{Path, PathBuf};

use super::vtp::write_vtp;
use super::vtu::{read_vtu, read_vtu_header};
use super::{Encoding, OutputError, PvdSeries, read_summary};
use crate::math::{Real, Vector};
use crate::surface::{SurfaceError, SurfaceMesh, SurfaceParams, reconstruct};

/// Errors of writing a surface series.
#[derive(Debug, thiserror::Error)]
pub enum SurfaceOutputError {
    /// Reading frames or writing meshes failed.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The reconstruction refused the particles or parameters.
    #[error(transparent)]
    Surface(#[from] SurfaceError),
    /// The directory is not a finished run.
    #[error("{} is not a finished run directory: {reason}", dir.display())]
    NotARun {
        /// The directory given.
        dir: PathBuf,
        /// What is missing.
        reason: String,
    },
}

/// Name of the surface series file in a run directory.
pub const SURFACE_PVD: &str = "surface.pvd";

/// The mesh file of frame `index`, relative to the run folder.
pub fn surface_file(index: usize) -> String {
    format!("surface/surface_{index:05}.vtp")
}

/// Writes the surface meshes of a run directory and keeps `surface.pvd` current.
#[derive(Debug, Clone)]
pub struct SurfaceSeries {
    dir: PathBuf,
    pvd: PvdSeries,
    encoding: Encoding,
}

impl SurfaceSeries {
    /// A new, empty series in run directory `dir` (creates `dir/surface`), its meshes stored in
    /// `encoding`.
    pub fn create(dir: &Path, encoding: Encoding) -> Result<Self, OutputError> {
        let sub = dir.join("surface");
        super::safe_file::ensure_dir(&sub).map_err(|e| OutputError::io(&sub, e))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            pvd: PvdSeries::new(),
            encoding,
        })
    }

    /// A series continuing from the `(time [s], vtp file)` entries already written (restarts).
    pub fn resume(dir: &Path, entries: &[(f64, String)], encoding: Encoding) -> Result<Self, OutputError> {
        let mut series = Self::create(dir, encoding)?;
        for (t, file) in entries {
            series.pvd.push(*t, file.clone());
        }
        Ok(series)
    }

    /// The `(time [s], vtp file)` entries written so far.
    pub fn entries(&self) -> &[(f64, String)] {
        self.pvd.entries()
    }

    /// Writes `mesh` as frame `index` at time `time` [s], then rewrites `surface.pvd`. Returns the `.vtp` path relative to the run directory.
    pub fn push<const D: usize>(
        &mut self,
        index: usize,
        time: f64,
        mesh: &SurfaceMesh<D>,
    ) -> Result<String, OutputError> {
        let vtp = surface_file(index);
        write_vtp(&self.dir.join(&vtp), mesh, time, self.encoding)?;
        self.pvd.push(time, vtp.clone());
        self.pvd.write(&self.dir.join(SURFACE_PVD))?;
        Ok(vtp)
    }
}

/// Counts of what [`reconstruct_run`] wrote.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SurfaceRunReport {
    /// Frames reconstructed.
    pub frames: usize,
    /// Vertices over all frames.
    pub vertices: usize,
    /// Triangles (3D) or segments (2D) over all frames.
    pub elements: usize,
}

/// Reconstructs the free surface of every frame of the finished run in `dir`: reads the
/// dimension and spacing from `summary.json`, the frames from `particles.pvd`, keeps the
/// fluid particles (`kind` 0) and writes [`SurfaceSeries`] with
/// [`SurfaceParams::with_radius`]`(spacing, radius)` (`radius` in spacings, e.g.
/// [`crate::surface::DEFAULT_RADIUS`]), in the encoding of the first frame.
pub fn reconstruct_run(dir: &Path, radius: f64) -> Result<SurfaceRunReport, SurfaceOutputError> {
    let not_a_run = |reason: String| SurfaceOutputError::NotARun {
        dir: dir.to_path_buf(),
        reason,
    };
    if !dir.is_dir() {
        return Err(not_a_run("no such directory".into()));
    }
    let summary_path = dir.join("summary.json");
    if !summary_path.is_file() {
        return Err(not_a_run("no summary.json (did the run finish?)".into()));
    }
    let summary = read_summary(&summary_path)?;
    let length = |key: &str| {
        summary
            .extra
            .get(key)
            .and_then(serde_json::Value::as_f64)
            .ok_or_else(|| not_a_run(format!("summary.json has no number `{key}`")))
    };
    let spacing = length("spacing")?;
    let pvd_path = dir.join("particles.pvd");
    if !pvd_path.is_file() {
        return Err(not_a_run("no particles.pvd (were frames written?)".into()));
    }
    let frames = PvdSeries::read(&pvd_path)?;
    match summary.dimension {
        2 => surface_frames::<2>(dir, &frames, spacing, radius),
        3 => surface_frames::<3>(dir, &frames, spacing, radius),
        d => Err(SurfaceError::UnsupportedDimension(d).into()),
    }
}

fn surface_frames<const D: usize>(
    dir: &Path,
    frames: &PvdSeries,
    spacing: f64,
    radius: f64,
) -> Result<SurfaceRunReport, SurfaceOutputError> {
    let params = SurfaceParams::with_radius::<D>(spacing, radius);
    let encoding = match frames.entries().first() {
        Some((_, file)) => {
            let header = read_vtu_header(&dir.join(file))?;
            match (header.zlib, header.base64) {
                (true, _) => Encoding::Zlib,
                (false, true) => Encoding::Base64,
                (false, false) => Encoding::Raw,
            }
        }
        None => Encoding::default(),
    };
    let mut series = SurfaceSeries::create(dir, encoding)?;
    let mut report = SurfaceRunReport::default();
    for (index, (time, file)) in frames.entries().iter().enumerate() {
        let path = dir.join(file);
        let data = read_vtu(&path)?;
        let kind = data
            .point_array("kind")
            .filter(|a| a.components == 1)
            .map(|a| &a.values)
            .ok_or_else(|| OutputError::malformed(&path, "no one-component `kind` point array"))?;
        let fluid: Vec<Vector<D>> = data
            .points
            .iter()
            .zip(kind)
            .filter(|&(_, &k)| k == 0.0)
            .map(|(p, _)| Vector::<D>::from_fn(|k, _| p[k] as Real))
            .collect();
        let mesh = reconstruct(&fluid, &params)?;
        series.push(index, *time, &mesh)?;
        report.frames += 1;
        report.vertices += mesh.vertex_count();
        report.elements += mesh.elements.len();
    }
    Ok(report)
}
