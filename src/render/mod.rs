//! PNG pictures of a run's particle frames (`sph render`), as the paper's Figs. 2–3 snapshots
//! of the dam break against a column.
//!
//! [`render_run`] reads the `.vtu` frames listed in a run's `particles.pvd` twice, each pass
//! parallel over frames (rayon): the first fixes what must not change from frame to frame (the
//! colour range, the picture's extent, the fluid's bounding box for the cut-away of near
//! walls), the second draws each selected frame and writes `frame_NNNNN.png` (NNNNN = the
//! frame's index in the series). The first pass covers every frame of the run whatever `every`
//! is, so `--every 10` draws the same colours as `--every 1`.
//!
//! Files: [`colormap`] (viridis, the range and its ticks), [`projection`] (views and the
//! cut-away), [`raster`] (the pixel buffer and discs), [`frames`] (reading the run),
//! [`picture`] (one frame's layout, colour bar and text).

pub mod colormap;
pub mod frames;
pub mod picture;
pub mod projection;
pub mod raster;

use crate::output::OutputError;
use crate::output::plot::{PlotError, write_rgb_png};
use colormap::{ColorRange, quantile_range};
use frames::{RunFrames, read_frame};
use picture::{FrameStyle, render_frame};
use projection::{Projection, View};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// Fraction of fluid particles left out at each end of a frame's values when fixing the colour
/// range (0.5 %): a few splashing or wall-pressed particles would otherwise squeeze the bulk of
/// the fluid into one colour. Values beyond the range take the end colours.
pub const RANGE_QUANTILE: f64 = 0.005;

/// The field that colours the fluid particles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColorField {
    /// Speed |u| [m/s].
    Speed,
    /// Pressure p [Pa] (3D) or [N/m] (2D).
    Pressure,
    /// Density ρ [kg/m³] (3D) or [kg/m²] (2D).
    Density,
}

impl ColorField {
    /// The colour bar label, with the unit of a `dimension`-D run.
    pub fn label(self, dimension: usize) -> &'static str {
        match (self, dimension) {
            (ColorField::Speed, _) => "speed [m/s]",
            (ColorField::Pressure, 2) => "pressure [N/m]",
            (ColorField::Pressure, _) => "pressure [Pa]",
            (ColorField::Density, 2) => "density [kg/m²]",
            (ColorField::Density, _) => "density [kg/m³]",
        }
    }
}

/// What `sph render` draws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderOptions {
    /// The view of a 3D run (a 2D run has only [`View::Side`], its x–y plane).
    pub view: View,
    /// The field colouring the fluid.
    pub color: ColorField,
    /// Draw every `every`-th frame (the first is frame 0).
    pub every: usize,
    /// Image width [px]; the height follows the picture's aspect ratio.
    pub width: u32,
}

/// Errors of [`render_run`].
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The run directory does not exist.
    #[error("run directory {} does not exist", dir.display())]
    NoRunDir {
        /// The directory asked for.
        dir: PathBuf,
    },
    /// The run directory has no frames.
    #[error("{} has no frames (no particles.pvd, or it lists none)", dir.display())]
    NoFrames {
        /// The run directory.
        dir: PathBuf,
    },
    /// A frame lacks an array the picture needs.
    #[error("frame {} has no usable `{name}` array", frame.display())]
    MissingArray {
        /// The frame file.
        frame: PathBuf,
        /// The array's name.
        name: &'static str,
    },
    /// No particle spacing could be found (no summary.json, and the first frame has fewer than
    /// two distinct points).
    #[error("no particle spacing: no summary.json and {} has fewer than two distinct points", frame.display())]
    Spacing {
        /// The first frame.
        frame: PathBuf,
    },
    /// A 2D run was asked for a 3D view.
    #[error("view {view} needs a 3D run; {} is 2D (use --view side)", dir.display())]
    ViewNeeds3d {
        /// The view asked for.
        view: &'static str,
        /// The run directory.
        dir: PathBuf,
    },
    /// `every` is zero.
    #[error("--every must be at least 1")]
    Every,
    /// The image width is outside the accepted range.
    #[error(
        "image width {width} px is outside {}..={} px (or makes the picture taller than that)",
        picture::MIN_WIDTH,
        picture::MAX_WIDTH
    )]
    Width {
        /// The width asked for [px].
        width: u32,
    },
    /// The picture's extent is empty or not finite (no particle, or non-finite positions).
    #[error("the particles span {du} x {dv} m with disc radius {radius} m: nothing to draw")]
    Extent {
        /// Horizontal extent [m].
        du: f64,
        /// Vertical extent [m].
        dv: f64,
        /// Disc radius [m].
        radius: f64,
    },
    /// The text of a frame could not be drawn.
    #[error("drawing text failed: {message}")]
    Text {
        /// The plotters error, as text.
        message: String,
    },
    /// Reading the run's files or creating the output directory failed.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// Writing a PNG failed.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// The name of a view on the command line.
fn view_name(view: View) -> &'static str {
    match view {
        View::Side => "side",
        View::Top => "top",
        View::Iso => "iso",
    }
}

/// What the first pass learns from one frame.
#[derive(Debug, Clone, Copy)]
struct FrameExtent {
    /// Low and high quantile of the fluid's values.
    values: Option<(f64, f64)>,
    /// Picture-plane extent of all particles `(u_min, u_max, v_min, v_max)` [m].
    plane: (f64, f64, f64, f64),
    /// Fluid bounding box `(min, max)` [m].
    fluid: ([f64; 3], [f64; 3]),
}

impl FrameExtent {
    fn empty() -> Self {
        FrameExtent {
            values: None,
            plane: (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY),
            fluid: ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
        }
    }

    fn merge(self, o: Self) -> Self {
        let values = match (self.values, o.values) {
            (Some(a), Some(b)) => Some((a.0.min(b.0), a.1.max(b.1))),
            (a, b) => a.or(b),
        };
        let (a, b) = (self.plane, o.plane);
        FrameExtent {
            values,
            plane: (a.0.min(b.0), a.1.max(b.1), a.2.min(b.2), a.3.max(b.3)),
            fluid: (
                std::array::from_fn(|k| self.fluid.0[k].min(o.fluid.0[k])),
                std::array::from_fn(|k| self.fluid.1[k].max(o.fluid.1[k])),
            ),
        }
    }
}

/// The first pass over one frame.
fn frame_extent(path: &Path, field: ColorField, projection: &Projection) -> Result<FrameExtent, RenderError> {
    let particles = read_frame(path, field)?;
    let mut extent = FrameExtent::empty();
    let mut fluid_values = Vec::with_capacity(particles.value.len());
    for (i, p) in particles.position.iter().enumerate() {
        if p.iter().any(|c| !c.is_finite()) {
            continue;
        }
        let q = projection.project(*p);
        let e = &mut extent.plane;
        *e = (e.0.min(q.u), e.1.max(q.u), e.2.min(q.v), e.3.max(q.v));
        if particles.kind[i] == 0 {
            fluid_values.push(particles.value[i]);
            for k in 0..3 {
                extent.fluid.0[k] = extent.fluid.0[k].min(f64::from(p[k]));
                extent.fluid.1[k] = extent.fluid.1[k].max(f64::from(p[k]));
            }
        }
    }
    extent.values = quantile_range(&mut fluid_values, RANGE_QUANTILE);
    Ok(extent)
}

/// Renders the run in `run_dir` into `out_dir` (created if needed); returns the written files
/// in frame order.
///
/// # Errors
/// Every [`RenderError`]; the first failing frame stops the rendering (frames already written
/// stay, each complete).
pub fn render_run(
    run_dir: &Path,
    out_dir: &Path,
    options: &RenderOptions,
) -> Result<Vec<PathBuf>, RenderError> {
    if options.every == 0 {
        return Err(RenderError::Every);
    }
    let run = RunFrames::open(run_dir)?;
    let projection = match (run.dimension, options.view) {
        (2, View::Side) => Projection::plane(),
        (2, view) => {
            return Err(RenderError::ViewNeeds3d {
                view: view_name(view),
                dir: run_dir.to_path_buf(),
            });
        }
        (_, view) => Projection::of_view(view),
    };
    let extent = run
        .frames
        .par_iter()
        .map(|(_, path)| frame_extent(path, options.color, &projection))
        .try_reduce(FrameExtent::empty, |a, b| Ok(a.merge(b)))?;
    let (low, high) = extent.values.unwrap_or((0.0, 1.0));
    let range = match options.color {
        // Speeds start at rest.
        ColorField::Speed => ColorRange::new(0.0, high),
        _ => ColorRange::new(low, high),
    };
    let radius = 0.5 * run.spacing;
    let pad = 2.0 * radius;
    let (u0, u1, v0, v1) = extent.plane;
    let style = FrameStyle {
        projection,
        shaded: run.dimension == 3,
        bounds: (u0 - pad, u1 + pad, v0 - pad, v1 + pad),
        radius,
        range,
        label: options.color.label(run.dimension).to_string(),
        cutaway: (run.dimension == 3 && extent.fluid.0[0].is_finite()).then_some(extent.fluid),
        width: options.width,
    };
    // Checked once here so that a bad width fails before any file is written.
    style.size()?;
    std::fs::create_dir_all(out_dir).map_err(|e| OutputError::io(out_dir, e))?;
    run.frames
        .par_iter()
        .enumerate()
        .filter(|(k, _)| k % options.every == 0)
        .map(|(k, (time, path))| {
            let particles = read_frame(path, options.color)?;
            let canvas = render_frame(&particles, *time, &style)?;
            let file = out_dir.join(format!("frame_{k:05}.png"));
            write_rgb_png(&canvas.pixels, (canvas.width, canvas.height), &file)?;
            Ok(file)
        })
        .collect()
}
