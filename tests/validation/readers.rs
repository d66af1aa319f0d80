//! Integration tests for the validation reference-data readers and curve
//! comparison (`validation`) on files the tests write; the shipped digitisations themselves
//! are read by the validation suite (`tests/validation_data.rs`).

use crate::common::tolerance::F64_FEW_OPERATIONS;
use sph::validation::{
    CurveError, ValidationError, interpolate, read_column_force, read_surge_front, relative_error,
};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// A file written under a fresh directory in the system temp dir; the directory is removed
/// when this is dropped.
struct TempCsv {
    dir: PathBuf,
    path: PathBuf,
}

impl std::ops::Deref for TempCsv {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.path
    }
}

impl Drop for TempCsv {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// Writes `text` to a fresh file under the system temp dir.
fn temp_csv(name: &str, text: &str) -> TempCsv {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "sph_validation_test_{}_{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    TempCsv { dir, path }
}

#[test]
fn interpolation_is_exact_on_a_piecewise_linear_curve() {
    let curve = [(0.0, 0.0), (1.0, 2.0), (3.0, 0.0), (3.0, 5.0), (4.0, 6.0)];
    assert_eq!(interpolate(&curve, 0.0), Some(0.0));
    assert_eq!(interpolate(&curve, 0.25), Some(0.5));
    assert_eq!(interpolate(&curve, 1.0), Some(2.0));
    assert_eq!(interpolate(&curve, 2.0), Some(1.0));
    assert_eq!(
        interpolate(&curve, 3.0),
        Some(0.0),
        "a jump gives its first point"
    );
    assert_eq!(interpolate(&curve, 3.5), Some(5.5));
    assert_eq!(interpolate(&curve, 4.0), Some(6.0));
    assert_eq!(interpolate(&curve, -0.1), None);
    assert_eq!(interpolate(&curve, 4.1), None);
    assert_eq!(interpolate(&curve, f64::NAN), None);
    assert_eq!(interpolate(&[], 1.0), None);
    assert_eq!(interpolate(&[(1.0, 7.0)], 1.0), Some(7.0));
}

#[test]
fn relative_error_on_hand_made_curves() {
    // Simulated: y = 2x on [0, 10]. Reference: exact at x = 1, 10 % high at
    // x = 2, 20 % low at x = 4; x = 5 is outside the range, x = 20 outside
    // the simulation, x = 3 has a zero reference value.
    let simulated = [(0.0, 0.0), (10.0, 20.0)];
    let reference = [
        (1.0, 2.0),
        (2.0, 4.4),
        (3.0, 0.0),
        (4.0, 6.4),
        (5.0, 1.0),
        (20.0, 40.0),
    ];
    let error = relative_error(&simulated, &reference, (0.5, 4.0)).unwrap();
    assert_eq!(error.count, 3);
    let expected = [0.0, (4.0_f64 - 4.4).abs() / 4.4, (8.0_f64 - 6.4).abs() / 6.4];
    assert_eq!(error.max, expected[2]);
    assert!((error.mean - expected.iter().sum::<f64>() / 3.0).abs() < F64_FEW_OPERATIONS);
    // A perfect match.
    let same = relative_error(&simulated, &[(2.5, 5.0), (7.5, 15.0)], (0.0, 10.0)).unwrap();
    assert_eq!(
        same,
        CurveError {
            max: 0.0,
            mean: 0.0,
            count: 2
        }
    );
    // Nothing to compare.
    assert_eq!(relative_error(&simulated, &reference, (11.0, 19.0)), None);
    assert_eq!(relative_error(&[], &reference, (0.0, 100.0)), None);
}

#[test]
fn bad_number_names_file_line_and_column() {
    let path = temp_csv("bad.csv", "time_s,force_x_N\n0.1,2.0\n0.2,abc\n");
    let err = read_column_force(&path).unwrap_err();
    match &err {
        ValidationError::BadNumber {
            path: p,
            line,
            column,
            position,
            text,
        } => {
            assert_eq!(p, &path.path);
            assert_eq!(*line, 3);
            assert_eq!(column, "force_x_N");
            assert_eq!(*position, 2);
            assert_eq!(text, "abc");
        }
        other => panic!("expected BadNumber, got {other}"),
    }
    let message = err.to_string();
    assert!(
        message.contains(&path.display().to_string()) && message.contains(":3: column 2 `force_x_N`"),
        "{message}"
    );
    // An empty cell in a required column is a bad number too.
    let path = temp_csv(
        "empty.csv",
        "series,n2_height_over_width,T_n_t_sqrt_g_over_a,Z_front_over_a\ns,1,,1.1\n",
    );
    let err = read_surge_front(&path).unwrap_err();
    assert!(
        matches!(&err, ValidationError::BadNumber { line: 2, column, .. } if column == "T_n_t_sqrt_g_over_a"),
        "{err}"
    );
}

#[test]
fn missing_column_names_column_and_file() {
    // Columns in another order are fine: they are found by name.
    let path = temp_csv("reordered.csv", "force_x_N,time_s\r\n2.5,0.1\r\n\r\n");
    let force = read_column_force(&path).unwrap();
    assert_eq!((force.len(), force[0].time, force[0].force), (1, 0.1, 2.5));
    let path = temp_csv("missing.csv", "time_s,force_y_N\n0.1,2.0\n");
    let err = read_column_force(&path).unwrap_err();
    assert!(
        matches!(&err, ValidationError::MissingColumn { column, .. } if column == "force_x_N"),
        "{err}"
    );
    let message = err.to_string();
    assert!(
        message.contains("force_x_N") && message.contains(&path.display().to_string()),
        "{message}"
    );
}

#[test]
fn malformed_and_missing_files_are_errors() {
    // A short row names its line and the first column it lacks.
    let path = temp_csv("short.csv", "time_s,force_x_N\n0.1\n");
    let err = read_column_force(&path).unwrap_err();
    assert!(
        matches!(
            err,
            ValidationError::Ragged {
                line: 2,
                expected: 2,
                found: 1,
                position: 2,
                ..
            }
        ),
        "{err}"
    );
    assert!(
        err.to_string().contains(":2: 1 fields, the header has 2"),
        "{err}"
    );
    // Quoted fields are read as RFC 4180 has them.
    let path = temp_csv("quoted.csv", "time_s,force_x_N\n\"0.1\",2\n");
    let force = read_column_force(&path).unwrap();
    assert_eq!((force[0].time, force[0].force), (0.1, 2.0));
    // Non-finite reference values are refused.
    let path = temp_csv("nan.csv", "time_s,force_x_N\n0.1,NaN\n");
    assert!(matches!(
        read_column_force(&path),
        Err(ValidationError::BadNumber { line: 2, .. })
    ));
    let path = temp_csv("blank.csv", "\n\n");
    assert!(matches!(
        read_surge_front(&path),
        Err(ValidationError::NoHeader { .. })
    ));
    let path = Path::new("/nonexistent/sph/front.csv");
    let err = read_surge_front(path).unwrap_err();
    assert!(
        matches!(
            err,
            ValidationError::File(sph::bounded_read::BoundedReadError::Io { .. })
        ),
        "{err}"
    );
    assert!(err.to_string().contains("/nonexistent/sph/front.csv"), "{err}");
}
