//! PNG line and marker plots ([`write_png`]) for comparing simulated curves
//! with experiments: simulation curves as lines, digitised experiment data
//! as markers, optional vertical marks (for example a time of interest).
//!
//! Drawing uses `plotters` with its bitmap backend and the pure-Rust
//! `ab_glyph` text renderer, so no system font library (fontconfig,
//! freetype) is needed. The one font, DejaVu Sans (Bitstream Vera licence,
//! `assets/DejaVuSans-LICENSE.txt`), is embedded in the binary and
//! registered with plotters as the `sans-serif` family on first use.
//!
//! Axis ranges follow the data: every finite point of every series (on a
//! logarithmic axis only the positive ones) plus the vertical marks, padded
//! by 5 % of the span on each side (of the decades on a logarithmic axis).
//!
//! As the other whole-file writers in [`crate::output`], the image is first
//! written to a sibling temporary file and then renamed over the target.

use std::cell::Cell;
use std::fs;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

/// DejaVu Sans, embedded so that text needs no system font.
const FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// The font family name under which [`FONT`] is registered; plotters' own
/// defaults (legend, tick labels) ask for this family.
pub(crate) const FONT_FAMILY: &str = "sans-serif";

/// Smallest accepted image side \[px\]: room for the title, axis labels and ticks.
pub const MIN_SIZE: u32 = 200;

/// Largest accepted image side \[px\] (keeps the RGB buffer under 300 MB).
pub const MAX_SIZE: u32 = 10_000;

/// Fraction of the data span added on each side of an axis.
const MARGIN: f64 = 0.05;

/// Series colours, cycled: the Tableau 10 palette (distinct, colour-blind aware).
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Colour of the vertical marks and their labels.
const MARK_COLOUR: RGBColor = RGBColor(90, 90, 90);

/// Errors produced by [`write_png`].
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// No series has a point that can be drawn (finite, and positive on a
    /// logarithmic axis).
    #[error("figure `{title}` has no finite data to plot")]
    NoData {
        /// Title of the figure.
        title: String,
    },
    /// The requested image size is outside [`MIN_SIZE`]..=[`MAX_SIZE`] on a side.
    #[error("image size {width}x{height} px is outside {MIN_SIZE}..={MAX_SIZE} px per side")]
    InvalidSize {
        /// Requested width \[px\].
        width: u32,
        /// Requested height \[px\].
        height: u32,
    },
    /// The data span of an axis is too large to be represented (it
    /// overflows `f64` once padded).
    #[error("{axis} axis range {low:.3e}..{high:.3e} is too large to plot")]
    AxisRange {
        /// `"x"` or `"y"`.
        axis: &'static str,
        /// Smallest value on the axis.
        low: f64,
        /// Largest value on the axis.
        high: f64,
    },
    /// Creating, writing or renaming the image file failed.
    #[error("cannot write figure {}: {source}", path.display())]
    Io {
        /// The requested output file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// `plotters` failed to draw or encode the image (including font errors).
    #[error("drawing figure {} failed: {message}", path.display())]
    Drawing {
        /// The requested output file.
        path: PathBuf,
        /// The plotters error, as text.
        message: String,
    },
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeriesStyle {
    /// A solid polyline through the points in the given order (simulation curves).
    Line,
    /// One marker per point, no connecting line (experiment data).
    Markers,
    /// A polyline with a marker at each point (few measured points, e.g. timings).
    LineMarkers,
}

/// One curve of a [`Figure`].
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend entry; an empty label leaves the series out of the legend.
    pub label: String,
    /// Data points `(x, y)` in the units of the figure's axes; non-finite
    /// points (and on a logarithmic axis non-positive ones) are skipped.
    pub points: Vec<(f64, f64)>,
    /// Line or markers.
    pub style: SeriesStyle,
}

/// A 2D plot: axes, series and optional vertical marks.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Figure {
    /// Title above the plot.
    pub title: String,
    /// Label of the horizontal axis, with its unit (`"t [s]"`).
    pub x_label: String,
    /// Label of the vertical axis, with its unit (`"F [N]"`).
    pub y_label: String,
    /// Logarithmic horizontal axis.
    pub log_x: bool,
    /// Logarithmic vertical axis.
    pub log_y: bool,
    /// The curves, drawn in order; colours are assigned by position.
    pub series: Vec<Series>,
    /// Dashed vertical lines at `x` (axis units) with a text label, for
    /// example the time of a snapshot. They widen the x range to include them.
    pub vertical_lines: Vec<(f64, String)>,
}

/// Draws `figure` and writes it as a PNG image of `size` = (width, height) \[px\]
/// to `path`, whatever the extension of `path`.
///
/// The image is drawn into a unique hidden `.tmp.png` sibling (the encoder picks its format
/// from the extension) and renamed over `path` once complete, so `path`
/// never holds a half-written image; on failure the temporary file is
/// removed and `path` is left untouched.
///
/// # Errors
/// [`PlotError::NoData`] when no point can be drawn, [`PlotError::InvalidSize`],
/// [`PlotError::AxisRange`] for spans that overflow `f64`, [`PlotError::Io`]
/// naming `path` when the file cannot be created or renamed, and
/// [`PlotError::Drawing`] for failures inside plotters.
pub fn write_png(figure: &Figure, path: &Path, size: (u32, u32)) -> Result<(), PlotError> {
    let (width, height) = size;
    if !(MIN_SIZE..=MAX_SIZE).contains(&width) || !(MIN_SIZE..=MAX_SIZE).contains(&height) {
        return Err(PlotError::InvalidSize { width, height });
    }
    let no_data = || PlotError::NoData {
        title: figure.title.clone(),
    };
    let x_data = figure
        .series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| drawable(**p, figure))
        .map(|p| p.0);
    let x_marks = figure
        .vertical_lines
        .iter()
        .map(|m| m.0)
        .filter(|&x| usable(x, figure.log_x));
    let x_range = axis_range("x", x_data.chain(x_marks), figure.log_x)?.ok_or_else(no_data)?;
    let y_data = figure
        .series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| drawable(**p, figure))
        .map(|p| p.1);
    let y_range = axis_range("y", y_data, figure.log_y)?.ok_or_else(no_data)?;

    let tmp = tmp_png_path(path);
    let io_error = |source| PlotError::Io {
        path: path.to_path_buf(),
        source,
    };
    // Create the file here so that an unwritable location is reported as an
    // I/O error rather than as an image-encoder message.
    super::safe_file::create_new(&tmp).map_err(io_error)?;
    let ranges = (&x_range, &y_range);
    let (x, y) = (x_range.clone(), y_range.clone());
    let drawn = match (figure.log_x, figure.log_y) {
        (false, false) => render(figure, &tmp, size, ranges, x, y),
        (true, false) => render(figure, &tmp, size, ranges, x.log_scale(), y),
        (false, true) => render(figure, &tmp, size, ranges, x, y.log_scale()),
        (true, true) => render(figure, &tmp, size, ranges, x.log_scale(), y.log_scale()),
    };
    finish_png(&tmp, path, drawn)
}

/// Writes an 8-bit RGB image (`pixels`: row-major from the top-left, 3 bytes per pixel, `size` =
/// (width, height) [px]) as a PNG to `path`, atomically as [`write_png`] (drawn into
/// a unique hidden `.tmp.png` sibling, renamed once complete). For pictures drawn pixel by pixel, such as the
/// particle frames of `sph render`.
///
/// # Errors
/// [`PlotError::InvalidSize`] when a side is zero, above [`MAX_SIZE`] or `pixels` does not hold
/// `3 · width · height` bytes, [`PlotError::Io`] and [`PlotError::Drawing`] as [`write_png`].
pub fn write_rgb_png(pixels: &[u8], size: (u32, u32), path: &Path) -> Result<(), PlotError> {
    let (width, height) = size;
    let expected = 3 * width as usize * height as usize;
    if width == 0 || height == 0 || width > MAX_SIZE || height > MAX_SIZE || pixels.len() != expected {
        return Err(PlotError::InvalidSize { width, height });
    }
    let tmp = tmp_png_path(path);
    let io_error = |source| PlotError::Io {
        path: path.to_path_buf(),
        source,
    };
    super::safe_file::create_new(&tmp).map_err(io_error)?;
    let drawn = (|| {
        let mut backend = BitMapBackend::new(&tmp, size);
        backend
            .blit_bitmap((0, 0), size, pixels)
            .map_err(|e| e.to_string())?;
        backend.present().map_err(|e| e.to_string())
    })();
    finish_png(&tmp, path, drawn)
}

/// The end of an atomic PNG write: the temporary file `tmp` becomes `path` once `drawn`
/// succeeded; on any failure `tmp` is removed and the error names `path`.
fn finish_png(tmp: &Path, path: &Path, drawn: Result<(), String>) -> Result<(), PlotError> {
    let result = match drawn {
        Err(message) => Err(PlotError::Drawing {
            path: path.to_path_buf(),
            message,
        }),
        Ok(()) => fs::rename(tmp, path).map_err(|source| PlotError::Io {
            path: path.to_path_buf(),
            source,
        }),
    };
    if result.is_err() {
        let _ = fs::remove_file(tmp);
    }
    result
}

/// The temporary sibling the image is drawn into: `fig.png` -> `.fig.png.PID-N.tmp.png`.
fn tmp_png_path(path: &Path) -> PathBuf {
    super::safe_file::unique_tmp_path(path, ".png")
}

/// Whether `v` can be placed on an axis: finite, and on a log axis positive
/// (subnormal values, below `f64::MIN_POSITIVE`, count as zero there).
fn usable(v: f64, log: bool) -> bool {
    v.is_finite() && (!log || v >= f64::MIN_POSITIVE)
}

/// Whether a data point can be placed on both axes of `figure`.
fn drawable((x, y): (f64, f64), figure: &Figure) -> bool {
    usable(x, figure.log_x) && usable(y, figure.log_y)
}

/// The padded axis range covering `values` (all already [`usable`]), or
/// `None` when there are none. A zero or negligible span is widened so that
/// plotters gets a proper interval.
fn axis_range(
    axis: &'static str,
    values: impl Iterator<Item = f64>,
    log: bool,
) -> Result<Option<Range<f64>>, PlotError> {
    let Some((low, high)) = values.fold(None, |acc: Option<(f64, f64)>, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    }) else {
        return Ok(None);
    };
    let range = if log {
        // Pad in decades; a span below 1e-6 decades becomes +-0.1 decade.
        let (l0, l1) = (low.log10(), high.log10());
        let pad = if l1 - l0 < 1e-6 { 0.1 } else { MARGIN * (l1 - l0) };
        let (mut l0, mut l1) = (l0 - pad, l1 + pad);
        // plotters places ticks only from a power of ten on: make sure the
        // axis holds one by widening a sub-decade range to whole decades.
        if l0.ceil() > l1.floor() {
            (l0, l1) = (l0.floor(), l1.ceil());
        }
        10f64.powf(l0).max(f64::MIN_POSITIVE)..10f64.powf(l1).min(f64::MAX)
    } else {
        // Scaled before subtracting so that the span itself cannot overflow.
        let span = MARGIN * high - MARGIN * low;
        let scale = low.abs().max(high.abs());
        let pad = if span <= 1e-9 * scale || span == 0.0 {
            if scale > 0.0 { MARGIN * scale } else { 1.0 }
        } else {
            span
        };
        (low - pad)..(high + pad)
    };
    if !(range.end - range.start).is_finite() {
        return Err(PlotError::AxisRange { axis, low, high });
    }
    Ok(Some(range))
}

/// Registers the embedded font with plotters once per process.
pub(crate) fn register_embedded_font() -> Result<(), String> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            register_font(FONT_FAMILY, FontStyle::Normal, FONT)
                .map_err(|_| "the embedded DejaVu Sans font could not be parsed".to_string())
        })
        .clone()
}

/// Base text height \[px\] for an image of `size`.
fn font_size((width, height): (u32, u32)) -> f64 {
    (f64::from(width.min(height)) / 40.0).clamp(11.0, 40.0)
}

/// How the tick labels of one axis are written; chosen once per axis so
/// that all its labels share one style.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TickFormat {
    /// Exponent notation (`2.5e-4`) for the whole axis.
    exponent: bool,
    /// Digits after the decimal point (of the mantissa in exponent notation);
    /// `None` on a logarithmic axis, where each label gets what it needs.
    digits: Option<usize>,
}

impl TickFormat {
    /// The format for an axis showing `range` (about 10 ticks on a linear axis).
    pub(crate) fn new(range: &Range<f64>, log: bool) -> Self {
        let magnitude = range.start.abs().max(range.end.abs());
        let smallest = if log { range.start } else { magnitude };
        let exponent = magnitude >= 1e5 || smallest < 1e-3;
        if log {
            return TickFormat {
                exponent,
                digits: None,
            };
        }
        let step_exp = ((range.end - range.start) / 10.0).log10().floor();
        let digits = if exponent {
            magnitude.log10().floor() - step_exp
        } else {
            1.0 - step_exp
        };
        TickFormat {
            exponent,
            digits: Some(digits.clamp(0.0, 10.0) as usize),
        }
    }

    /// The label for tick value `v`, trailing zeros removed.
    pub(crate) fn label(&self, v: f64) -> String {
        let text = match (self.exponent, self.digits) {
            (true, Some(d)) => format!("{v:.d$e}"),
            (true, None) => format!("{v:.0e}"),
            (false, Some(d)) => format!("{v:.d$}"),
            (false, None) => {
                let d = (-v.abs().log10().floor()).clamp(0.0, 10.0) as usize;
                format!("{v:.d$}")
            }
        };
        let (mantissa, exp) = match text.split_once('e') {
            Some((m, e)) => (m, Some(e)),
            None => (text.as_str(), None),
        };
        let mut mantissa = mantissa;
        if mantissa.contains('.') {
            mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        }
        if mantissa == "-0" {
            mantissa = "0";
        }
        match exp {
            Some(e) if mantissa != "0" => format!("{mantissa}e{e}"),
            _ => mantissa.to_string(),
        }
    }
}

/// Tick label formatter for one axis. On a logarithmic axis only the ticks
/// at 1, 2 and 5 times a power of ten are labelled (plotters puts a grid
/// line at every integer multiple), and a tick repeating the previous value
/// (plotters emits each decade twice when it subdivides) gets no label.
fn tick_formatter(range: &Range<f64>, log: bool) -> impl Fn(&f64) -> String {
    let format = TickFormat::new(range, log);
    let previous = Cell::new(f64::NAN);
    move |&v: &f64| {
        if !log {
            return format.label(v);
        }
        let repeated = ((v - previous.get()) / v).abs() < 1e-9;
        previous.set(v);
        let mantissa = v / 10f64.powf(v.log10().floor());
        let labelled = [1.0, 2.0, 5.0, 10.0].iter().any(|m| (mantissa - m).abs() < 1e-6);
        if repeated || !labelled {
            String::new()
        } else {
            format.label(v)
        }
    }
}

/// Number of bold ticks to ask plotters for: about 10 on a linear axis; on a
/// logarithmic axis spanning 3 decades or more, one per decade (no
/// subdivisions), else enough that plotters subdivides each decade.
fn tick_count(range: &Range<f64>, log: bool) -> usize {
    let decades = (range.end / range.start).log10();
    match (log, decades >= 3.0) {
        (false, _) => 10,
        (true, true) => (decades.floor() as usize).min(12),
        (true, false) => 30,
    }
}

/// Draws the whole figure into the bitmap file `tmp`; errors as text.
/// `ranges` are the plain (x, y) ranges behind the coordinates `x` and `y`.
fn render<X, Y>(
    figure: &Figure,
    tmp: &Path,
    size: (u32, u32),
    ranges: (&Range<f64>, &Range<f64>),
    x: X,
    y: Y,
) -> Result<(), String>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    register_embedded_font()?;
    let text = font_size(size);
    let root = BitMapBackend::new(tmp, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let x_format = tick_formatter(ranges.0, figure.log_x);
    let y_format = tick_formatter(ranges.1, figure.log_y);
    let mut chart = ChartBuilder::on(&root)
        .caption(&figure.title, (FONT_FAMILY, 1.3 * text))
        .margin((0.8 * text) as u32)
        .x_label_area_size((3.0 * text) as u32)
        .y_label_area_size((4.5 * text) as u32)
        .build_cartesian_2d(x, y)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc(figure.x_label.as_str())
        .y_desc(figure.y_label.as_str())
        .label_style((FONT_FAMILY, 0.85 * text))
        .axis_desc_style((FONT_FAMILY, text))
        .x_labels(tick_count(ranges.0, figure.log_x))
        .y_labels(tick_count(ranges.1, figure.log_y))
        .x_label_formatter(&x_format)
        .y_label_formatter(&y_format)
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.12))
        .draw()
        .map_err(|e| e.to_string())?;

    let stroke = (text / 7.0).round().max(1.0) as u32;
    let marker = (text / 3.0).round().max(2.0) as i32;
    let mut labelled = false;
    let mut marker_index = 0;
    for (i, series) in figure.series.iter().enumerate() {
        let colour = PALETTE[i % PALETTE.len()];
        let points = series.points.iter().copied().filter(|&p| drawable(p, figure));
        let legend_style = colour.stroke_width(stroke);
        let annotation = match series.style {
            SeriesStyle::Line => {
                let annotation = chart
                    .draw_series(LineSeries::new(points, colour.stroke_width(stroke)))
                    .map_err(|e| e.to_string())?;
                annotation.legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], legend_style))
            }
            SeriesStyle::Markers => {
                // Successive marker series alternate shapes so they stay
                // distinguishable where colours are hard to tell apart.
                let shape = marker_index % 3;
                marker_index += 1;
                let style = colour.stroke_width(stroke);
                let annotation = chart
                    .draw_series(points.map(|p| marker_element(p, shape, marker, style)))
                    .map_err(|e| e.to_string())?;
                annotation.legend(move |(x, y)| marker_element((x + 10, y), shape, marker, style))
            }
            SeriesStyle::LineMarkers => {
                let points: Vec<(f64, f64)> = points.collect();
                chart
                    .draw_series(LineSeries::new(
                        points.iter().copied(),
                        colour.stroke_width(stroke),
                    ))
                    .map_err(|e| e.to_string())?;
                let style = colour.filled();
                let annotation = chart
                    .draw_series(points.into_iter().map(|p| Circle::new(p, marker, style)))
                    .map_err(|e| e.to_string())?;
                annotation.legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(0, 0), (20, 0)], legend_style)
                        + Circle::new((10, 0), marker, style)
                })
            }
        };
        if !series.label.is_empty() {
            annotation.label(series.label.as_str());
            labelled = true;
        }
    }

    let (y_low, y_high) = {
        let r = chart.y_range();
        (r.start, r.end)
    };
    for (x, label) in &figure.vertical_lines {
        if !usable(*x, figure.log_x) {
            continue;
        }
        let dash = (text / 2.0) as u32;
        chart
            .draw_series(DashedLineSeries::new(
                [(*x, y_low), (*x, y_high)],
                dash,
                dash / 2 + 1,
                MARK_COLOUR.stroke_width(stroke),
            ))
            .map_err(|e| e.to_string())?;
        if !label.is_empty() {
            let (px, py) = chart.backend_coord(&(*x, y_high));
            let style = TextStyle::from((FONT_FAMILY, 0.85 * text)).color(&MARK_COLOUR);
            root.draw(&Text::new(
                label.as_str(),
                (px + stroke as i32 + 3, py + 3),
                style,
            ))
            .map_err(|e| e.to_string())?;
        }
    }

    if labelled {
        chart
            .configure_series_labels()
            .label_font((FONT_FAMILY, 0.85 * text))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.5))
            .position(SeriesLabelPosition::UpperLeft)
            .draw()
            .map_err(|e| e.to_string())?;
    }
    root.present().map_err(|e| e.to_string())
}

/// One marker of shape `shape` (0 circle, 1 triangle, 2 cross) of radius `r` \[px\].
fn marker_element<DB: DrawingBackend, C>(
    at: C,
    shape: usize,
    r: i32,
    style: ShapeStyle,
) -> DynElement<'static, DB, C>
where
    C: Clone + 'static,
{
    match shape {
        0 => Circle::new(at, r, style).into_dyn(),
        1 => TriangleMarker::new(at, r + 1, style).into_dyn(),
        _ => Cross::new(at, r, style).into_dyn(),
    }
}
