//! `run_scene` split across ranks that are threads: rank 0 writes the run's tables and
//! summary as one rank would, and every frame is a `.pvtu` of one piece per rank that holds
//! every particle once.

use crate::common::scratch;
use sph::backend::partition::SharedCommunicator;
use sph::distributed::{LocalWorld, Method, Rebalance};
use sph::output::csv_read::CsvFile;
use sph::output::pvtu::read_pvtu_pieces;
use sph::output::vtu_read::read_vtu;
use sph::run::{Ranks, Restart, RunOptions, run_scene};
use sph::scene::{load_scene, locate_references};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

fn options(out: &Path, ranks: Option<Ranks>) -> RunOptions {
    RunOptions {
        out_dir: Some(out.to_path_buf()),
        force: false,
        backend: sph::backend::BackendKind::Cpu,
        threads: 1,
        scene_name: "dam_break_2d".into(),
        restart: Restart::default(),
        stop: None,
        ranks,
    }
}

fn table(dir: &Path, name: &str) -> CsvFile {
    CsvFile::read(&dir.join(name)).expect(name)
}

/// The value of `column` in every row of `file`.
fn column(file: &CsvFile, column: &str) -> Vec<f64> {
    let c = file.column(column).expect("column");
    (0..file.len())
        .map(|r| file.number(r, c).expect("number"))
        .collect()
}

/// The 2D dam break (spacing 0.01, corrected, to 0.1 s, a frame every 0.02 s, the front
/// probe) run whole and on 3 ranks (bisection): the same rows in `steps.csv`, `forces.csv`
/// and `probes.csv`, with times and values within rounding's reach (times within 0.1 ms: the
/// time step follows the largest speed; the front within 1 mm; the tank's impulse within
/// 1 %); `summary.json` with the same particles and fluid
/// mass; and 6 frames, each a `.pvtu` whose 3 pieces hold every particle once.
#[test]
fn a_split_run_writes_the_files_of_a_whole_one() {
    let sets = [
        "particles.spacing=0.01".to_string(),
        "solver.end_time=0.1".to_string(),
    ];
    let mut scene = load_scene(Path::new("scenes/dam_break_2d.toml"), &sets).expect("scene");
    // Without the reference directory: the front is sampled, not compared.
    locate_references(&mut scene, None);
    let whole_dir = scratch("split_output_whole");
    let whole = run_scene(&scene, &options(&whole_dir, None), &mut |_| {}).expect("whole run");
    let split_dir: PathBuf = scratch("split_output_split");
    let results = LocalWorld::run(3, |rank| {
        let comm: SharedCommunicator = Arc::new(Mutex::new(Box::new(rank)));
        let ranks = Ranks {
            comm,
            method: Method::Bisection,
            rebalance: Rebalance::Above(0.1),
            device: 0,
        };
        run_scene(&scene, &options(&split_dir, Some(ranks)), &mut |_| {}).map_err(|e| e.to_string())
    });
    let split = results
        .into_iter()
        .next()
        .expect("rank 0")
        .expect("no panic")
        .expect("split run");
    assert_eq!(split.status, "completed");
    assert_eq!(
        (split.particles, split.fluid_particles),
        (whole.particles, whole.fluid_particles)
    );
    assert_eq!(split.steps, whole.steps);
    assert_eq!(split.extra["fluid_mass"], whole.extra["fluid_mass"]);
    assert_eq!(split.extra["ranks"], 3);
    for name in ["steps.csv", "forces.csv", "probes.csv"] {
        let (a, b) = (table(&whole_dir, name), table(&split_dir, name));
        assert_eq!(a.header(), b.header(), "{name}");
        assert_eq!(a.len(), b.len(), "{name}: rows");
    }
    let close = |name: &str, col: &str, tolerance: f64| {
        let (a, b) = (
            column(&table(&whole_dir, name), col),
            column(&table(&split_dir, name), col),
        );
        let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (x, y) in a.iter().zip(&b) {
            assert!(
                (x - y).abs() <= tolerance * scale.max(1.0),
                "{name} {col}: {x} against {y}"
            );
        }
    };
    close("steps.csv", "t_s", 1e-4);
    // The force of one step is the correction's impulse over it, noisy from step to step:
    // compared as the impulse over the run.
    let impulse = |dir: &Path, col: &str| {
        let f = table(dir, "forces.csv");
        let (t, v) = (column(&f, "t_s"), column(&f, col));
        (1..t.len()).map(|k| v[k] * (t[k] - t[k - 1])).sum::<f64>()
    };
    for col in ["fx_N_per_m", "fy_N_per_m"] {
        let (a, b) = (impulse(&whole_dir, col), impulse(&split_dir, col));
        eprintln!("{col}: impulse {b} against {a}");
        assert!((a - b).abs() <= 0.01 * a.abs(), "{col}: impulse {b} against {a}");
    }
    close("probes.csv", "t_s", 1e-4);
    let (a, b) = (
        column(&table(&whole_dir, "probes.csv"), "front_m"),
        column(&table(&split_dir, "probes.csv"), "front_m"),
    );
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() < 1e-3, "front {y} against {x}");
    }
    // Frames: .pvtu headers, each with one piece per rank, every particle once.
    let pvd = std::fs::read_to_string(split_dir.join("particles.pvd")).expect("pvd");
    let frames: Vec<&str> = pvd
        .split("file=\"")
        .skip(1)
        .map(|s| s.split('"').next().expect("quoted"))
        .collect();
    assert_eq!(frames.len(), 6, "{pvd}");
    for frame in frames {
        assert!(frame.ends_with(".pvtu"), "{frame}");
        let header = split_dir.join(frame);
        let pieces = read_pvtu_pieces(&header).expect("pvtu");
        assert_eq!(pieces.len(), 3);
        let mut ids = Vec::new();
        for piece in pieces {
            let data = read_vtu(&header.parent().expect("frames").join(piece)).expect("piece");
            let id = data.point_array("id").expect("ids");
            ids.extend(id.values.iter().map(|v| *v as u64));
        }
        ids.sort_unstable();
        let n = ids.len();
        ids.dedup();
        assert_eq!(
            (n, ids.len() as u64),
            (whole.particles as usize, whole.particles),
            "{frame}"
        );
    }
}
