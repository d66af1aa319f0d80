//! `sph surface RUN_DIR`: the free surface (eq. (25)) of every frame of a finished run.

use crate::output::surface_series::{SURFACE_PVD, reconstruct_run};
use anyhow::Context;
use std::path::Path;

/// Reconstructs and writes `RUN_DIR/surface/surface_NNNNN.vtp` and `RUN_DIR/surface.pvd`
/// with support `radius` spacings.
pub fn surface(dir: &Path, radius: f64) -> anyhow::Result<()> {
    if !(radius.is_finite() && radius > 0.0) {
        anyhow::bail!("--radius must be a positive number of spacings, got {radius}");
    }
    let report = reconstruct_run(dir, radius)
        .with_context(|| format!("reconstructing the surface of {}", dir.display()))?;
    println!(
        "{} frames, {} vertices and {} triangles (segments in 2D) in total; open {} in ParaView",
        report.frames,
        report.vertices,
        report.elements,
        dir.join(SURFACE_PVD).display()
    );
    Ok(())
}
