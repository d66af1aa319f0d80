//! Integration tests for the validation reference-data readers and curve
//! comparison (`validation`).

use sph::validation::{
    CurveError, ValidationError, interpolate, read_column_force, read_surge_front, relative_error,
};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The shared reference data, next to the crate.
const SURGE_FRONT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/validation/martin_moyce_1952_surge_front.csv"
);
/// Yeh & Petroff force, PySPH digitisation.
const FORCE_PYSPH: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/validation/yeh_petroff_column_force_pysph.csv"
);
/// Yeh & Petroff force, ANUGA digitisation.
const FORCE_ANUGA: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/validation/yeh_petroff_column_force_anuga.csv"
);

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

/// Number of points of `series` in `points`.
fn count(points: &[sph::validation::FrontPoint], series: &str) -> usize {
    points.iter().filter(|p| p.series == series).count()
}

#[test]
fn surge_front_has_the_rows_listed_in_sources_md() {
    let points = read_surge_front(Path::new(SURGE_FRONT)).unwrap();
    assert_eq!(points.len(), 69);
    // Per-series counts from SOURCES.md, section 1.
    assert_eq!(count(&points, "MM1952_n2-1_jaxsph"), 20);
    assert_eq!(count(&points, "MM1952_n2-1_trixiparticles"), 10);
    assert_eq!(count(&points, "MM1952_n2-2_a1.125in_pysph"), 10);
    assert_eq!(count(&points, "MM1952_n2-2_a2.25in_pysph"), 15);
    assert_eq!(count(&points, "MM1952_n2-2_lethe"), 14);
    let square = points.iter().filter(|p| p.n2 == 1.0).count();
    assert_eq!(square, 30, "n^2 = 1 points (JAX-SPH + TrixiParticles)");
    assert!(points.iter().all(|p| p.n2 == 1.0 || p.n2 == 2.0));
    assert!(points.iter().all(|p| p.t >= 0.0 && p.z >= 1.0));
}

#[test]
fn surge_front_known_values() {
    let points = read_surge_front(Path::new(SURGE_FRONT)).unwrap();
    // First data row of the file: MM1952_n2-1_jaxsph,1,,0.43,1.11
    assert_eq!(
        points[0],
        sph::validation::FrontPoint {
            series: "MM1952_n2-1_jaxsph".to_string(),
            n2: 1.0,
            t: 0.43,
            z: 1.11,
        }
    );
    // SOURCES.md: the a = 2.25 in series runs to Z = 14.
    let z_max = points
        .iter()
        .filter(|p| p.series == "MM1952_n2-2_a2.25in_pysph")
        .map(|p| p.z)
        .fold(f64::MIN, f64::max);
    assert!((z_max - 14.0).abs() < 0.05, "{z_max}");
}

#[test]
fn column_force_files_have_the_rows_listed_in_sources_md() {
    let pysph = read_column_force(Path::new(FORCE_PYSPH)).unwrap();
    assert_eq!(pysph.len(), 329);
    assert!(
        pysph.windows(2).all(|w| w[0].time <= w[1].time),
        "PySPH file is sorted in time"
    );
    let anuga = read_column_force(Path::new(FORCE_ANUGA)).unwrap();
    assert_eq!(anuga.len(), 416);
    // First rows of each file, as written (`4.3E-19,-4.18E0` in ANUGA's).
    assert_eq!((pysph[0].time, pysph[0].force), (-0.002, -4.375));
    assert_eq!((anuga[0].time, anuga[0].force), (4.3e-19, -4.18));
}

#[test]
fn column_force_peaks_match_sources_md() {
    // SOURCES.md, section 5: PySPH peak 33.1 N at 0.396 s, minimum -11.7 N at 1.57 s;
    // ANUGA peak 33.3 N at 0.41 s, minimum -11.6 N at 1.57 s.
    for (path, peak, t_peak, min) in [
        (FORCE_PYSPH, 33.1, 0.396, -11.7),
        (FORCE_ANUGA, 33.3, 0.41, -11.6),
    ] {
        let force = read_column_force(Path::new(path)).unwrap();
        let max = force.iter().max_by(|a, b| a.force.total_cmp(&b.force)).unwrap();
        let low = force.iter().min_by(|a, b| a.force.total_cmp(&b.force)).unwrap();
        assert!(
            (max.force - peak).abs() < 0.05 && (max.time - t_peak).abs() < 0.005,
            "{path}: {max:?}"
        );
        assert!(
            (low.force - min).abs() < 0.05 && (low.time - 1.57).abs() < 0.01,
            "{path}: {low:?}"
        );
    }
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
    assert!((error.mean - expected.iter().sum::<f64>() / 3.0).abs() < 1e-15);
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
    assert!(matches!(err, ValidationError::Io { .. }), "{err}");
    assert!(err.to_string().contains("/nonexistent/sph/front.csv"), "{err}");
}
