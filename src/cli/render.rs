//! `sph render RUN_DIR [--every N] [--view side|top|iso] [--color speed|pressure|density]`:
//! PNG pictures of a run's frames (the paper's Figs. 2–3).

use crate::render::projection::View;
use crate::render::{ColorField, RenderOptions, render_run};
use clap::ValueEnum;
use std::path::{Path, PathBuf};

/// `--view` on the command line.
#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum ViewArg {
    /// x–z plane, looking along +y (2D runs: their x–y plane).
    Side,
    /// x–y plane, looking down.
    Top,
    /// Oblique view from the front left, above.
    Iso,
}

/// `--color` on the command line.
#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum ColorArg {
    /// Speed |u| [m/s].
    Speed,
    /// Pressure.
    Pressure,
    /// Density.
    Density,
}

/// Renders the run in `run_dir`; the pictures go to `out` [default: RUN_DIR/render_<view>_<color>].
pub fn render(
    run_dir: &Path,
    out: Option<PathBuf>,
    every: usize,
    view: ViewArg,
    color: ColorArg,
    width: u32,
) -> anyhow::Result<()> {
    let options = RenderOptions {
        view: match view {
            ViewArg::Side => View::Side,
            ViewArg::Top => View::Top,
            ViewArg::Iso => View::Iso,
        },
        color: match color {
            ColorArg::Speed => ColorField::Speed,
            ColorArg::Pressure => ColorField::Pressure,
            ColorArg::Density => ColorField::Density,
        },
        every,
        width,
    };
    let name = |v: &dyn std::fmt::Debug| format!("{v:?}").to_lowercase();
    let out = out.unwrap_or_else(|| run_dir.join(format!("render_{}_{}", name(&view), name(&color))));
    // The errors name the directory or file at fault; no further context needed.
    let files = render_run(run_dir, &out, &options)?;
    println!("wrote {} pictures to {}", files.len(), out.display());
    Ok(())
}
