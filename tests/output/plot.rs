//! Integration tests for the PNG figure writer (`output::plot`).

use crate::common::{assert_no_tmp_left, scratch_dir as scratch};
use sph::output::plot::{Figure, PlotError, Series, SeriesStyle, write_png};
use std::path::Path;

/// The 8-byte signature every PNG file starts with.
const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

/// Width and height from the IHDR chunk, after checking the signature and
/// that IHDR is the first chunk (PNG spec, sections 5.2 and 11.2.2).
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert!(bytes.len() > 33, "file too short for a PNG header");
    assert_eq!(bytes[..8], PNG_SIGNATURE, "PNG signature");
    assert_eq!(
        u32::from_be_bytes(bytes[8..12].try_into().unwrap()),
        13,
        "IHDR length"
    );
    assert_eq!(&bytes[12..16], b"IHDR", "first chunk");
    let width = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    let height = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
    (width, height)
}

/// A series of `n` points of `f` on [0, 2].
fn curve(label: &str, n: usize, style: SeriesStyle, f: impl Fn(f64) -> f64) -> Series {
    let points = (0..n)
        .map(|i| {
            let x = 2.0 * i as f64 / (n - 1) as f64;
            (x, f(x))
        })
        .collect();
    Series {
        label: label.to_string(),
        points,
        style,
    }
}

/// A figure with no series yet.
fn figure(title: &str) -> Figure {
    Figure {
        title: title.to_string(),
        x_label: "T [-]".to_string(),
        y_label: "Z [-]".to_string(),
        ..Figure::default()
    }
}

#[test]
fn lines_and_markers_write_a_png_of_the_requested_size() {
    let dir = scratch("basic");
    let path = dir.join("front.png");
    let mut fig = figure("Surge front, n² = 1");
    fig.series
        .push(curve("SPH coarse", 100, SeriesStyle::Line, |t| 1.0 + 1.4 * t));
    fig.series
        .push(curve("SPH fine", 100, SeriesStyle::Line, |t| 1.0 + 1.5 * t));
    fig.series
        .push(curve("Martin & Moyce", 12, SeriesStyle::Markers, |t| {
            1.1 + 1.45 * t
        }));
    fig.vertical_lines.push((1.0, "t = 0.1 s".to_string()));
    write_png(&fig, &path, (800, 500)).unwrap();
    assert_eq!(png_size(&path), (800, 500));
    assert_no_tmp_left(&dir);
    // Overwriting an existing figure works, with another size.
    write_png(&fig, &path, (640, 480)).unwrap();
    assert_eq!(png_size(&path), (640, 480));
}

#[test]
fn log_log_figure_skips_non_positive_points() {
    let dir = scratch("loglog");
    let path = dir.join("convergence.png");
    let mut fig = figure("Convergence");
    fig.log_x = true;
    fig.log_y = true;
    let mut error = curve("L2 error", 6, SeriesStyle::Line, |h| 0.3 * h * h);
    error.points.push((0.0, 1.0)); // not drawable on a log axis
    error.points.push((1.0, -1.0));
    fig.series.push(error);
    fig.series
        .push(curve("slope 2", 2, SeriesStyle::Markers, |h| 0.25 * h * h));
    write_png(&fig, &path, (600, 400)).unwrap();
    assert_eq!(png_size(&path), (600, 400));
}

#[test]
fn wide_log_range_and_nan_points_are_drawn() {
    let dir = scratch("wide");
    let path = dir.join("wide.png");
    let mut fig = figure("Wide range");
    fig.log_y = true;
    let mut wide = curve("", 50, SeriesStyle::Markers, |x| 10f64.powf(6.0 * x - 4.0));
    wide.points.push((f64::NAN, 1.0));
    wide.points.push((1.0, f64::INFINITY));
    fig.series.push(wide);
    write_png(&fig, &path, (400, 300)).unwrap();
    assert_eq!(png_size(&path), (400, 300));
}

#[test]
fn empty_figure_is_an_error_not_a_panic() {
    let dir = scratch("empty");
    let path = dir.join("empty.png");
    let err = write_png(&figure("Empty"), &path, (400, 300)).unwrap_err();
    assert!(matches!(err, PlotError::NoData { .. }), "{err}");
    let mut fig = figure("Empty series");
    fig.series.push(Series {
        label: "nothing".to_string(),
        points: Vec::new(),
        style: SeriesStyle::Line,
    });
    fig.vertical_lines.push((1.0, "a mark is not data".to_string()));
    let err = write_png(&fig, &path, (400, 300)).unwrap_err();
    assert!(matches!(err, PlotError::NoData { .. }), "{err}");
    assert!(!path.exists());
    assert_no_tmp_left(&dir);
}

#[test]
fn all_nan_data_is_an_error_not_a_panic() {
    let dir = scratch("nan");
    let path = dir.join("nan.png");
    let mut fig = figure("NaN");
    fig.series.push(curve("nan", 10, SeriesStyle::Line, |_| f64::NAN));
    fig.series.push(Series {
        label: "inf".to_string(),
        points: vec![(f64::INFINITY, 1.0), (f64::NAN, f64::NAN)],
        style: SeriesStyle::Markers,
    });
    let err = write_png(&fig, &path, (400, 300)).unwrap_err();
    assert!(matches!(err, PlotError::NoData { .. }), "{err}");
    // Only non-positive values on a log axis: nothing to draw either.
    let mut fig = figure("Log of zero");
    fig.log_y = true;
    fig.series.push(curve("zero", 10, SeriesStyle::Line, |_| 0.0));
    let err = write_png(&fig, &path, (400, 300)).unwrap_err();
    assert!(matches!(err, PlotError::NoData { .. }), "{err}");
    assert!(!path.exists());
}

#[test]
fn constant_and_single_point_data_are_drawn() {
    let dir = scratch("constant");
    for (i, log) in [false, true].into_iter().enumerate() {
        let path = dir.join(format!("constant_{i}.png"));
        let mut fig = figure("Constant");
        fig.log_x = log;
        fig.log_y = log;
        fig.series.push(curve("constant", 5, SeriesStyle::Line, |_| 1.0));
        fig.series.push(Series {
            label: "one point".to_string(),
            points: vec![(1.0, 1.0)],
            style: SeriesStyle::Markers,
        });
        write_png(&fig, &path, (300, 200)).unwrap();
        assert_eq!(png_size(&path), (300, 200));
    }
}

#[test]
fn unusable_size_is_an_error() {
    let dir = scratch("size");
    let mut fig = figure("Size");
    fig.series.push(curve("line", 5, SeriesStyle::Line, |x| x));
    for size in [(0, 300), (300, 0), (10, 10), (100_000, 300)] {
        let err = write_png(&fig, &dir.join("size.png"), size).unwrap_err();
        assert!(matches!(err, PlotError::InvalidSize { .. }), "{size:?}: {err}");
    }
}

#[test]
fn unwritable_path_gives_an_error_naming_the_path() {
    let dir = scratch("unwritable");
    let path = dir.join("no_such_dir").join("figure.png");
    let mut fig = figure("Unwritable");
    fig.series.push(curve("line", 5, SeriesStyle::Line, |x| x));
    let err = write_png(&fig, &path, (400, 300)).unwrap_err();
    assert!(matches!(err, PlotError::Io { .. }), "{err}");
    let message = err.to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
}
