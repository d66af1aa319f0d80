//! `sph surface RUN_DIR`: the free surface (eq. (25)) of every frame of a finished run.

use crate::output::surface_series::{SURFACE_PVD, reconstruct_run};
use anyhow::Context;
use std::path::Path;

/// Reconstructs and writes `RUN_DIR/surface/surface_NNNNN.{vtp,ply}` and `RUN_DIR/surface.pvd`.
pub fn surface(dir: &Path) -> anyhow::Result<()> {
    let report =
        reconstruct_run(dir).with_context(|| format!("reconstructing the surface of {}", dir.display()))?;
    println!(
        "{} frames, {} vertices and {} triangles (segments in 2D) in total; open {} in ParaView",
        report.frames,
        report.vertices,
        report.elements,
        dir.join(SURFACE_PVD).display()
    );
    Ok(())
}
