//! The validation suite's reader checks: the experimental reference files in
//! `SPH_REFERENCE_DIR` (docs/validation.md) read with the counts, first rows and peaks their
//! sources give. Run with `cargo test --release --features validation-data`.

mod reference_data;

use reference_data::reference_file;
use sph::validation::{read_column_force, read_surge_front};

/// Martin & Moyce's surge front, five digitisations.
const SURGE_FRONT: &str = "martin_moyce_1952_surge_front.csv";
/// Yeh & Petroff force, PySPH digitisation.
const FORCE_PYSPH: &str = "yeh_petroff_column_force_pysph.csv";
/// Yeh & Petroff force, ANUGA digitisation.
const FORCE_ANUGA: &str = "yeh_petroff_column_force_anuga.csv";

/// Number of points of `series` in `points`.
fn count(points: &[sph::validation::FrontPoint], series: &str) -> usize {
    points.iter().filter(|p| p.series == series).count()
}

#[test]
fn surge_front_has_the_rows_listed_in_sources_md() {
    let points = read_surge_front(&reference_file(SURGE_FRONT)).unwrap();
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
    let points = read_surge_front(&reference_file(SURGE_FRONT)).unwrap();
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
    let pysph = read_column_force(&reference_file(FORCE_PYSPH)).unwrap();
    assert_eq!(pysph.len(), 329);
    assert!(
        pysph.windows(2).all(|w| w[0].time <= w[1].time),
        "PySPH file is sorted in time"
    );
    let anuga = read_column_force(&reference_file(FORCE_ANUGA)).unwrap();
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
        let force = read_column_force(&reference_file(path)).unwrap();
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

mod readme_commands;

/// The README's commands that need the reference data run as written, with
/// `SPH_REFERENCE_DIR` set: their runs compare the front with Martin & Moyce's data.
#[test]
fn readme_reference_commands_run_as_written() {
    use readme_commands::{Needs, readme_blocks, run_block, scratch};
    let dir = scratch("reference");
    let reference = reference_data::reference_dir();
    let mut ran = 0;
    for block in readme_blocks().iter().filter(|b| b.needs == Needs::ReferenceData) {
        ran += run_block(block, &dir, Some(&reference));
    }
    assert!(ran >= 1, "the README shows no command with reference data");
    std::fs::remove_dir_all(&dir).expect("cleanup");
}
