//! `sph plot RUN_DIR [--scene SCENE]`: PNG charts of a run's CSV logs: forces on each solid
//! (the paper's Fig. 4), probes, density error, correction iterations and time step per step;
//! with the run's scene, each probe against its reference data. Without `--scene`, the scene
//! file the run was started from (`scene_file` and `scene_overrides` in `summary.json`) is used
//! when it is still there.

use crate::charts::write_run_charts;
use anyhow::Context;
use std::path::{Path, PathBuf};

/// Writes the charts of the run in `run_dir` to `out` [default: RUN_DIR/plots].
pub fn plot(
    run_dir: &Path,
    out: Option<PathBuf>,
    scene: Option<&Path>,
    sets: &[String],
    reference_dir: Option<&Path>,
) -> anyhow::Result<()> {
    let scene = scene_of_run(run_dir, scene, sets, reference_dir)?;
    let out = out.unwrap_or_else(|| run_dir.join("plots"));
    // The errors name the directory or file at fault; no further context needed.
    let files = write_run_charts(run_dir, &out, scene.as_ref())?;
    println!("wrote {} charts to {}", files.len(), out.display());
    Ok(())
}

/// The scene at `scene` with `sets`, else the one the run in `run_dir` was started from
/// ([`run_scene`]).
pub(super) fn scene_of_run(
    run_dir: &Path,
    scene: Option<&Path>,
    sets: &[String],
    reference_dir: Option<&Path>,
) -> anyhow::Result<Option<crate::scene::Scene>> {
    anyhow::ensure!(
        scene.is_some() || sets.is_empty(),
        "--set needs --scene (it overrides the scene's keys)"
    );
    Ok(match scene {
        Some(path) => Some(
            super::load_located(path, sets, reference_dir, true)
                .with_context(|| format!("loading scene {}", path.display()))?,
        ),
        None => run_scene(run_dir, reference_dir),
    })
}

/// The scene the run in `run_dir` was started from, as its `summary.json` names it, if that file
/// still loads; otherwise none (the charts are drawn without reference data, and a line says
/// why when the file was named).
fn run_scene(run_dir: &Path, reference_dir: Option<&Path>) -> Option<crate::scene::Scene> {
    let summary = crate::output::read_summary(&run_dir.join("summary.json")).ok()?;
    let file = summary.scene_file?;
    match super::load_located(&file, &summary.scene_overrides, reference_dir, true) {
        Ok(scene) => Some(scene),
        Err(e) => {
            eprintln!(
                "note: no reference data: the run's scene {} does not load ({e})",
                file.display()
            );
            None
        }
    }
}
