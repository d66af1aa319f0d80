//! The one CSV reader (`output::CsvFile`): bad input is an error naming the file, the line and
//! the column, and the files the program writes read back through it with their unit-named
//! columns (`output::csv`'s convention).

use crate::common::scene::tank_2d_with_post;
use crate::common::scratch;
use crate::common::tolerance::F32_ROUNDING;
use sph::bench::{BENCH_COLUMNS, BenchRow, STAGE_COLUMNS, stages_csv, to_csv};
use sph::fields::{FLUID, Fields};
use sph::math::Vector;
use sph::output::{CsvFile, CsvReadError};
use sph::probe::ProbeLog;
use sph::scene::parse_scene;
use std::path::{Path, PathBuf};

/// A fresh empty directory under the system temp dir.
fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_missing_column_names_the_file_the_header_line_and_the_column() {
    let dir = scratch("missing");
    let path = write(&dir, "steps.csv", "step,t_s,dt_s\n1,0.1,0.1\n");
    let table = CsvFile::read(&path).unwrap();
    let err = table.column("max_compression").unwrap_err();
    assert!(
        matches!(&err, CsvReadError::MissingColumn { path: p, column, .. }
            if p == &path && column == "max_compression"),
        "{err:?}"
    );
    assert_eq!(
        err.to_string(),
        format!(
            "{}:1: no column `max_compression` in the header (step,t_s,dt_s)",
            path.display()
        )
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_bad_number_names_the_file_line_and_column() {
    let dir = scratch("bad");
    // Line 4 (after a blank line), column 3.
    let path = write(&dir, "probes.csv", "t_s,front_m,post_N\n0,0.1,2\n\n0.1,0.2,x2\n");
    let table = CsvFile::read(&path).unwrap();
    assert_eq!(table.number(0, 2).unwrap(), 2.0);
    let err = table.number(1, 2).unwrap_err();
    match &err {
        CsvReadError::BadNumber {
            path: p,
            line,
            column,
            position,
            text,
        } => {
            assert_eq!(
                (p.as_path(), *line, column.as_str()),
                (path.as_path(), 4, "post_N")
            );
            assert_eq!((*position, text.as_str()), (3, "x2"));
        }
        other => panic!("expected BadNumber, got {other:?}"),
    }
    assert_eq!(
        err.to_string(),
        format!("{}:4: column 3 `post_N`: `x2` is not a number", path.display())
    );
    // An empty cell is not a number, but may be read as "not measured".
    let path = write(&dir, "sweep.csv", "variant,max_compression\na,\n");
    let table = CsvFile::read(&path).unwrap();
    assert!(matches!(
        table.number(0, 1),
        Err(CsvReadError::BadNumber { line: 2, .. })
    ));
    assert_eq!(table.optional_number(0, 1).unwrap(), None);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_ragged_row_names_the_file_line_and_column() {
    let dir = scratch("ragged");
    let path = write(&dir, "forces.csv", "t_s,solid,fx_N\n0,a,1\n0.1,a\n");
    let err = CsvFile::read(&path).unwrap_err();
    assert!(
        matches!(
            &err,
            CsvReadError::Ragged {
                line: 3,
                expected: 3,
                found: 2,
                position: 3,
                ..
            }
        ),
        "{err:?}"
    );
    assert_eq!(
        err.to_string(),
        format!(
            "{}:3: 2 fields, the header has 3 (first missing column: 3)",
            path.display()
        )
    );
    let path = write(&dir, "long.csv", "a,b\r\n1,2\r\n3,4,5\r\n");
    let err = CsvFile::read(&path).unwrap_err().to_string();
    assert!(
        err.ends_with(":3: 3 fields, the header has 2 (first extra column: 3)"),
        "{err}"
    );
    // A quoted comma is part of its field, not a separator.
    let path = write(&dir, "quoted.csv", "t_s,solid\n0,\"plate, left\"\n");
    assert_eq!(CsvFile::read(&path).unwrap().text(0, 1), "plate, left");
    // Nothing but blank lines: no header.
    let path = write(&dir, "empty.csv", "\n  \n");
    assert!(matches!(CsvFile::read(&path), Err(CsvReadError::NoHeader { .. })));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn probes_csv_reads_back_with_unit_named_columns() {
    let dir = scratch("probes");
    let text = tank_2d_with_post("kind = \"wcsph\"\nend_time = 1.0\n", "");
    let scene = parse_scene(&text, "csv test", &[]).expect("valid scene");
    let mut f = Fields::<2>::default();
    f.push(Vector::<2>::new(0.3, 0.1), Vector::zeros(), 1.0, 1000.0, FLUID);
    let mut log = ProbeLog::create(&scene, Some(&dir), 0.1).expect("log");
    let forces = [[0.0; 3], [1.0 / 3.0, 0.0, 0.0]];
    log.record(0.0, 0.0, &f, &forces, true).expect("record");
    log.record(0.1, 0.1, &f, &forces, false).expect("record");
    drop(log);
    let table = CsvFile::read(&dir.join("probes.csv")).unwrap();
    // 2D: the force probe is per metre of depth.
    assert_eq!(table.header(), ["t_s", "front_m", "post_force_N_per_m"]);
    assert_eq!(table.len(), 2);
    let front = table.numbers(table.column("front_m").unwrap()).unwrap();
    assert!(front.iter().all(|z| (*z - 0.3).abs() < F32_ROUNDING), "{front:?}");
    let force = table
        .number(1, table.column("post_force_N_per_m").unwrap())
        .unwrap();
    assert_eq!(
        force.to_bits(),
        (1.0f64 / 3.0).to_bits(),
        "written in round-trip notation"
    );
    std::fs::remove_dir_all(&dir).unwrap();

    // 3D: newtons.
    let text = text
        .replace("dimension = 2", "dimension = 3")
        .replace("[-0.05, -0.05]", "[-0.05, -0.05, -0.05]")
        .replace("[1.65, 1.0]", "[1.65, 1.0, 0.3]")
        .replace("[0.0, -9.81]", "[0.0, -9.81, 0.0]")
        .replace("min = [0.0, 0.0]", "min = [0.0, 0.0, 0.0]")
        .replace("min = [1.0, 0.0]", "min = [1.0, 0.0, 0.0]")
        .replace("[0.26, 0.5]", "[0.26, 0.5, 0.2]")
        .replace("[1.6, 0.8]", "[1.6, 0.8, 0.25]")
        .replace("[1.1, 0.3]", "[1.1, 0.3, 0.2]");
    let scene = parse_scene(&text, "csv test 3d", &[]).expect("valid 3D scene");
    let dir = scratch("probes3d");
    drop(ProbeLog::create(&scene, Some(&dir), 0.1).expect("log"));
    let table = CsvFile::read(&dir.join("probes.csv")).unwrap();
    assert_eq!(table.header(), ["t_s", "front_m", "post_force_N"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

fn bench_row(backend: &str, device: &str, speedup: Option<f64>) -> BenchRow {
    BenchRow {
        particles: 10_000,
        backend: backend.into(),
        device: device.into(),
        spacing: 0.005,
        seconds_per_step: 0.1 + 0.2,
        seconds_per_sweep: 1.0 / 3.0,
        sweeps_per_step: 12.5,
        particle_steps_per_second: 3.3e4,
        interactions_per_second: 7.1e8,
        bytes_per_particle: 345.0,
        peak_resident_per_particle: f64::NAN,
        neighbours: 20.75,
        speedup,
        stages: vec![("density".into(), 1.5e-3), ("forces".into(), 2.5e-3)],
        stage_sweeps: (0.0, 0.0),
    }
}

#[test]
fn bench_tables_read_back_with_unit_named_columns() {
    let rows = [
        bench_row("cpu", "2 threads", None),
        bench_row("cuda", "NVIDIA H200, 141 GB", Some(31.5)),
    ];
    let table = CsvFile::parse(Path::new("bench.csv"), to_csv(&rows).as_bytes()).unwrap();
    assert_eq!(table.header(), BENCH_COLUMNS);
    assert_eq!(table.len(), 2);
    let column = |name: &str| table.column(name).unwrap();
    // A device name with a comma stays one field.
    assert_eq!(table.text(1, column("device")), "NVIDIA H200, 141 GB");
    assert_eq!(table.number(0, column("step_time_s")).unwrap(), 0.1 + 0.2);
    assert_eq!(table.number(0, column("sweep_time_s")).unwrap(), 1.0 / 3.0);
    assert_eq!(table.number(0, column("spacing_m")).unwrap(), 0.005);
    assert_eq!(table.number(0, column("memory_B_per_particle")).unwrap(), 345.0);
    assert!(
        table
            .number(0, column("peak_resident_B_per_particle"))
            .unwrap()
            .is_nan()
    );
    assert_eq!(table.optional_number(0, column("speedup")).unwrap(), None);
    assert_eq!(table.optional_number(1, column("speedup")).unwrap(), Some(31.5));

    let stages = CsvFile::parse(Path::new("bench_stages.csv"), stages_csv(&rows).as_bytes()).unwrap();
    assert_eq!(stages.header(), STAGE_COLUMNS);
    assert_eq!(stages.len(), 4);
    assert_eq!(stages.text(3, 2), "forces");
    assert_eq!(stages.number(3, 3).unwrap(), 2.5e-3);
}
