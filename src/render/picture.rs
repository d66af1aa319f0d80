//! One rendered frame, as the paper's Figs. 2–3: particles as discs coloured by a field, solid
//! particles grey, the simulated time in the top-left corner and a labelled colour bar on the
//! right.
//!
//! Layout, in units of the text height `t` (width / 64, 11 to 32 px): a margin of `t` round
//! the picture, a top row of `2.4 t` for the time, and a right panel of `9.5 t` for the colour
//! bar. The picture keeps the aspect ratio of the particles' extent (1 m is the same number of
//! pixels across and up), at most 1.6 times as tall as the image is wide.

use super::RenderError;
use super::colormap::{ColorRange, solid_grey, viridis};
use super::frames::FrameParticles;
use super::projection::Projection;
use super::raster::Canvas;
use crate::output::plot::{FONT_FAMILY, TickFormat, register_embedded_font};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Smallest accepted image width [px]: room for the picture and the colour bar.
pub const MIN_WIDTH: u32 = 160;

/// Largest accepted image width [px] (as the charts' limit).
pub const MAX_WIDTH: u32 = crate::output::plot::MAX_SIZE;

/// Background of the picture.
const BACKGROUND: [u8; 3] = [255, 255, 255];

/// How much darker the farthest solid particle of a 3D view is than the nearest.
const DEPTH_DARKENING: f64 = 0.45;

/// Text and outline colour.
const INK: [u8; 3] = [0, 0, 0];

/// How every frame of one rendering is drawn; fixed over the run so frames are comparable.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameStyle {
    /// The camera.
    pub projection: Projection,
    /// 3D cues: a dark rim on fluid discs, solid greys darkening with depth (over the depth
    /// range drawn in the frame).
    pub shaded: bool,
    /// Extent of the picture plane drawn, `(u_min, u_max, v_min, v_max)` [m].
    pub bounds: (f64, f64, f64, f64),
    /// Disc radius [m] (half the particle spacing).
    pub radius: f64,
    /// Values at the ends of the colour bar.
    pub range: ColorRange,
    /// Colour bar label with its unit (`"speed [m/s]"`).
    pub label: String,
    /// In 3D, the fluid's bounding box over the run `(min, max)` [m]: solid particles on the
    /// viewer's side of it are not drawn ([`Projection::cuts_away`]).
    pub cutaway: Option<([f64; 3], [f64; 3])>,
    /// Image width [px].
    pub width: u32,
}

/// Pixel geometry of a frame, derived from its [`FrameStyle`].
#[derive(Debug, Clone, Copy, PartialEq)]
struct Layout {
    height: u32,
    /// Text height [px].
    text: f64,
    /// Pixels per metre.
    scale: f64,
    /// Pixel position of (u_min, v_max), the picture's top-left corner.
    origin: (f64, f64),
    /// Colour bar `(x0, y0, x1, y1)` [px], exclusive ends.
    bar: (i64, i64, i64, i64),
}

impl FrameStyle {
    /// The image size (width, height) [px] this style draws.
    ///
    /// # Errors
    /// As [`render_frame`].
    pub fn size(&self) -> Result<(u32, u32), RenderError> {
        Ok((self.width, self.layout()?.height))
    }

    fn layout(&self) -> Result<Layout, RenderError> {
        let (u0, u1, v0, v1) = self.bounds;
        let (du, dv) = (u1 - u0, v1 - v0);
        if !(MIN_WIDTH..=MAX_WIDTH).contains(&self.width) {
            return Err(RenderError::Width { width: self.width });
        }
        if !(du > 0.0 && dv > 0.0 && du.is_finite() && dv.is_finite() && self.radius > 0.0) {
            return Err(RenderError::Extent {
                du,
                dv,
                radius: self.radius,
            });
        }
        let width = f64::from(self.width);
        let text = (width / 64.0).clamp(11.0, 32.0);
        let margin = text.round();
        let top = (2.4 * text).round();
        let panel = (9.5 * text).round();
        let area_w = width - panel - 2.0 * margin;
        let mut scale = area_w / du;
        if scale * dv > 1.6 * width {
            scale = 1.6 * width / dv;
        }
        let (pic_w, pic_h) = (scale * du, scale * dv);
        let area_h = pic_h.max(12.0 * text);
        let height = (top + area_h + margin).round();
        if height > f64::from(MAX_WIDTH) {
            return Err(RenderError::Width { width: self.width });
        }
        let origin = (margin + 0.5 * (area_w - pic_w), top + 0.5 * (area_h - pic_h));
        let bar_x0 = (width - panel + 0.8 * text).round();
        let bar = (
            bar_x0 as i64,
            (top + 1.8 * text).round() as i64,
            (bar_x0 + 1.2 * text).round() as i64,
            (height - margin - 0.5 * text).round() as i64,
        );
        Ok(Layout {
            height: height as u32,
            text,
            scale,
            origin,
            bar,
        })
    }
}

/// Draws one frame at simulated time `time` [s]: discs in the painter's order (farthest
/// first), then the colour bar and the text.
///
/// # Errors
/// [`RenderError::Width`] for a width outside [`MIN_WIDTH`]..=[`MAX_WIDTH`] (or a picture that
/// would be taller than that), [`RenderError::Extent`] for empty bounds or a non-positive
/// radius, [`RenderError::Text`] when the text cannot be drawn.
pub fn render_frame(
    particles: &FrameParticles,
    time: f64,
    style: &FrameStyle,
) -> Result<Canvas, RenderError> {
    let layout = style.layout()?;
    let mut canvas = Canvas::new(style.width, layout.height, BACKGROUND);
    draw_particles(&mut canvas, particles, style, &layout);
    draw_color_bar(&mut canvas, &layout);
    draw_text(&mut canvas, time, style, &layout)?;
    Ok(canvas)
}

/// The discs, farthest first; ties keep the index order so a frame always draws the same.
fn draw_particles(canvas: &mut Canvas, particles: &FrameParticles, style: &FrameStyle, layout: &Layout) {
    let n = particles
        .position
        .len()
        .min(particles.value.len())
        .min(particles.kind.len());
    let mut order: Vec<(f64, usize)> = (0..n)
        .filter(|&i| {
            !(particles.kind[i] != 0
                && style
                    .cutaway
                    .is_some_and(|(lo, hi)| style.projection.cuts_away(particles.position[i], lo, hi)))
        })
        .map(|i| (style.projection.project(particles.position[i]).depth, i))
        .collect();
    order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    // Depth range of what is drawn: the farthest is sorted first, the nearest last.
    let (far, near) = match (order.first(), order.last()) {
        (Some(f), Some(n)) => (f.0, n.0),
        _ => (0.0, 0.0),
    };
    let (u0, _, _, v1) = style.bounds;
    let r = style.radius * layout.scale;
    for (_, i) in order {
        let p = style.projection.project(particles.position[i]);
        let x = layout.origin.0 + (p.u - u0) * layout.scale;
        let y = layout.origin.1 + (v1 - p.v) * layout.scale;
        // Solids are drawn without rims (a rim on every wall particle is a texture the PNG
        // compressor cannot shrink); in 3D their grey darkens with distance instead, so the
        // floor and the walls of a tank read as separate faces.
        if particles.kind[i] != 0 {
            let grey = solid_grey(particles.kind[i]);
            let color = if style.shaded {
                // 0 at the farthest drawn particle, 1 at the nearest.
                let nearness = (p.depth - far) / (near - far).max(f64::MIN_POSITIVE);
                let f = 1.0 - DEPTH_DARKENING * (1.0 - nearness);
                grey.map(|v| (f64::from(v) * f).round() as u8)
            } else {
                grey
            };
            canvas.disc(x, y, r, color, false);
        } else {
            canvas.disc(x, y, r, style.range.color(particles.value[i]), style.shaded);
        }
    }
}

/// The colour bar: the colour map bottom (low) to top (high) inside a one-pixel outline.
fn draw_color_bar(canvas: &mut Canvas, layout: &Layout) {
    let (x0, y0, x1, y1) = layout.bar;
    let rows = (y1 - y0 - 1).max(1) as f64;
    for y in y0..y1 {
        canvas.fill_rect(x0, y, x1, y + 1, viridis((y1 - 1 - y) as f64 / rows));
    }
    canvas.fill_rect(x0 - 1, y0 - 1, x1 + 1, y0, INK);
    canvas.fill_rect(x0 - 1, y1, x1 + 1, y1 + 1, INK);
    canvas.fill_rect(x0 - 1, y0, x0, y1, INK);
    canvas.fill_rect(x1, y0, x1 + 1, y1, INK);
}

/// The time, the colour bar's label, its ticks and their values.
fn draw_text(canvas: &mut Canvas, time: f64, style: &FrameStyle, layout: &Layout) -> Result<(), RenderError> {
    let text_error = |e: &dyn std::fmt::Display| RenderError::Text {
        message: e.to_string(),
    };
    register_embedded_font().map_err(|e| text_error(&e))?;
    let (x0, y0, x1, y1) = layout.bar;
    let t = layout.text;
    let range = style.range;
    let count = (((y1 - y0) as f64 / (2.5 * t)) as usize).clamp(2, 8);
    let ticks = range.ticks(count);
    let format = TickFormat::new(&(range.low..range.high), false);
    let tick_y = |v: f64| y1 - 1 - (range.fraction(v) * (y1 - y0 - 1) as f64).round() as i64;
    let tick_len = (0.4 * t).round() as i64;
    for &v in &ticks {
        let y = tick_y(v);
        canvas.fill_rect(x1, y, x1 + tick_len, y + 1, INK);
    }
    let (width, height) = (canvas.width, canvas.height);
    let root = BitMapBackend::with_buffer(&mut canvas.pixels, (width, height)).into_drawing_area();
    let ink = RGBColor(INK[0], INK[1], INK[2]);
    let font = |size: f64| TextStyle::from((FONT_FAMILY, size)).color(&ink);
    root.draw(&Text::new(
        format!("t = {time:.3} s"),
        (t.round() as i32, (0.6 * t).round() as i32),
        font(1.2 * t),
    ))
    .map_err(|e| text_error(&e))?;
    root.draw(&Text::new(
        style.label.clone(),
        ((x0 - 1) as i32, (layout.bar.1 as f64 - 1.5 * t).round() as i32),
        font(0.9 * t),
    ))
    .map_err(|e| text_error(&e))?;
    let left = font(0.85 * t).pos(Pos::new(HPos::Left, VPos::Center));
    for &v in &ticks {
        root.draw(&Text::new(
            format.label(v),
            (
                (x1 + tick_len + (0.3 * t).round() as i64) as i32,
                tick_y(v) as i32,
            ),
            left.clone(),
        ))
        .map_err(|e| text_error(&e))?;
    }
    root.present().map_err(|e| text_error(&e))
}
