//! Integration tests for the output module.

use crate::common::{assert_no_tmp_left, scratch};
use sph::output::{
    CsvFile, Encoding, ForceLog, Frame, OutputError, PvdSeries, Summary, VtkType, VtuSection, read_summary,
    read_vtu, read_vtu_header, read_vtu_points, write_summary, write_vtu,
};

use nalgebra::SVector;
use proptest::prelude::*;
use std::path::Path;

/// A fresh empty scratch directory under the system temp dir.
/// Owned particle data for building a [`Frame`].
#[derive(Debug, Clone)]
struct Particles<const D: usize> {
    position: Vec<SVector<f32, D>>,
    velocity: Vec<SVector<f32, D>>,
    density: Vec<f32>,
    pressure: Vec<f32>,
    kind: Vec<u32>,
    id: Vec<u32>,
}

impl<const D: usize> Particles<D> {
    /// Deterministic pseudo-random particles (simple LCG, includes awkward
    /// values like negative zero, subnormals and large magnitudes).
    fn generate(n: usize, seed: u64) -> Self {
        let mut s = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let mut next = move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 32) as u32
        };
        let mut f = move || {
            let bits = next();
            let x = f32::from_bits(bits);
            if x.is_finite() {
                x
            } else {
                (bits % 1000) as f32 * 0.001
            }
        };
        let vec = |f: &mut dyn FnMut() -> f32| SVector::<f32, D>::from_fn(|_, _| f());
        let position = (0..n).map(|_| vec(&mut f)).collect();
        let velocity = (0..n).map(|_| vec(&mut f)).collect();
        let density = (0..n).map(|_| f()).collect();
        let pressure = (0..n).map(|i| if i % 7 == 0 { -0.0 } else { f() }).collect();
        let kind = (0..n).map(|i| (i as u32 * 2654435761) % 5).collect();
        let id = (0..n as u32).rev().collect();
        Particles {
            position,
            velocity,
            density,
            pressure,
            kind,
            id,
        }
    }

    fn frame(&self, time: f64) -> Frame<'_, D> {
        Frame {
            time,
            position: &self.position,
            velocity: &self.velocity,
            density: &self.density,
            pressure: &self.pressure,
            kind: &self.kind,
            id: &self.id,
        }
    }
}

fn pad3<const D: usize>(v: &SVector<f32, D>) -> [f32; 3] {
    let mut out = [0.0f32; 3];
    for c in 0..D.min(3) {
        out[c] = v[c];
    }
    out
}

/// Checks that `path` holds exactly `p` at time `time`, bit for bit.
fn check_round_trip<const D: usize>(path: &Path, p: &Particles<D>, time: f64) {
    let n = p.position.len();
    let data = read_vtu(path).unwrap();
    assert_eq!(data.header.number_of_points, n);
    assert_eq!(data.header.number_of_cells, n);
    assert_eq!(data.header.time.map(f64::to_bits), Some(time.to_bits()));

    let bits3 = |v: &[f32; 3]| v.map(f32::to_bits);
    assert_eq!(data.points.len(), n);
    for (got, want) in data.points.iter().zip(&p.position) {
        assert_eq!(bits3(got), bits3(&pad3(want)));
    }

    let names: Vec<&str> = data.point_data.iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["velocity", "density", "pressure", "kind", "id"]);

    let vel = data.point_array("velocity").unwrap();
    assert_eq!((vel.components, vel.data_type), (3, VtkType::Float32));
    assert_eq!(vel.values.len(), 3 * n);
    for (i, v) in p.velocity.iter().enumerate() {
        let want = pad3(v);
        for c in 0..3 {
            assert_eq!((vel.values[3 * i + c] as f32).to_bits(), want[c].to_bits());
        }
    }
    for (name, want) in [("density", &p.density), ("pressure", &p.pressure)] {
        let a = data.point_array(name).unwrap();
        assert_eq!((a.components, a.data_type), (1, VtkType::Float32));
        let got: Vec<u32> = a.values.iter().map(|x| (*x as f32).to_bits()).collect();
        let want: Vec<u32> = want.iter().map(|x| x.to_bits()).collect();
        assert_eq!(got, want, "{name}");
    }
    let kind = data.point_array("kind").unwrap();
    assert_eq!((kind.components, kind.data_type), (1, VtkType::UInt32));
    let got: Vec<u32> = kind.values.iter().map(|x| *x as u32).collect();
    assert_eq!(got, p.kind);
    let id = data.point_array("id").unwrap();
    assert_eq!((id.components, id.data_type), (1, VtkType::UInt32));
    let got: Vec<u32> = id.values.iter().map(|x| *x as u32).collect();
    assert_eq!(got, p.id);

    // Vertex cells.
    let conn = data.cell_array("connectivity").unwrap();
    let offs = data.cell_array("offsets").unwrap();
    let types = data.cell_array("types").unwrap();
    assert_eq!(types.data_type, VtkType::UInt8);
    assert!((0..n).all(|i| conn.values[i] == i as f64 && offs.values[i] == (i + 1) as f64));
    assert!(types.values.iter().all(|&t| t == 1.0));
    assert_eq!(
        (conn.values.len(), offs.values.len(), types.values.len()),
        (n, n, n)
    );
}

/// Checks the XML header structure of a file in `encoding`; for `raw` also that the appended
/// blocks tile the appended section exactly up to the closing tags.
fn check_header(path: &Path, n: usize, encoding: Encoding) {
    let h = read_vtu_header(path).unwrap();
    assert_eq!(h.number_of_points, n);
    assert!(h.header_u64);
    assert_eq!(
        (h.zlib, h.base64),
        (encoding == Encoding::Zlib, encoding == Encoding::Base64)
    );
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(h.file_len, bytes.len() as u64);
    let text = String::from_utf8_lossy(&bytes[..h.appended_start as usize]);
    assert!(text.starts_with("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\""));
    assert!(text.contains(&format!("NumberOfPoints=\"{n}\"")));
    assert_eq!(
        text.contains("compressor=\"vtkZLibDataCompressor\""),
        encoding == Encoding::Zlib
    );
    let appended_tag = if encoding == Encoding::Base64 {
        "<AppendedData encoding=\"base64\">\n   _"
    } else {
        "<AppendedData encoding=\"raw\">\n   _"
    };
    assert!(text.ends_with(appended_tag), "{text}");
    assert!(bytes.ends_with(b"\n  </AppendedData>\n</VTKFile>\n"));

    let appended: Vec<_> = h.arrays.iter().filter(|a| a.offset.is_some()).collect();
    let names: Vec<(VtuSection, &str)> = appended.iter().map(|a| (a.section, a.name.as_str())).collect();
    assert_eq!(
        names,
        [
            (VtuSection::PointData, "velocity"),
            (VtuSection::PointData, "density"),
            (VtuSection::PointData, "pressure"),
            (VtuSection::PointData, "kind"),
            (VtuSection::PointData, "id"),
            (VtuSection::Points, "Points"),
            (VtuSection::Cells, "connectivity"),
            (VtuSection::Cells, "offsets"),
            (VtuSection::Cells, "types"),
        ]
    );
    let offsets: Vec<u64> = appended.iter().map(|a| a.offset.unwrap()).collect();
    assert_eq!(offsets[0], 0);
    assert!(offsets.windows(2).all(|w| w[0] < w[1]), "{offsets:?}");
    if encoding != Encoding::Raw {
        return;
    }
    let mut expected_offset = 0u64;
    for a in &appended {
        let off = a.offset.unwrap();
        assert_eq!(off, expected_offset, "offset of {}", a.name);
        let start = (h.appended_start + off) as usize;
        let nbytes = u64::from_le_bytes(bytes[start..start + 8].try_into().unwrap());
        assert_eq!(
            nbytes,
            (n * a.components * a.data_type.size()) as u64,
            "{}",
            a.name
        );
        expected_offset = off + 8 + nbytes;
    }
    let end = (h.appended_start + expected_offset) as usize;
    assert_eq!(&bytes[end..], b"\n  </AppendedData>\n</VTKFile>\n");
}

#[test]
fn vtu_2d_and_3d_round_trip_small_and_empty_in_every_encoding() {
    let dir = scratch("small");
    for encoding in Encoding::ALL {
        for n in [0usize, 1, 2, 17] {
            let p2 = Particles::<2>::generate(n, n as u64);
            let path = dir.join(format!("f2_{n}.vtu"));
            write_vtu(&path, &p2.frame(0.125 * n as f64), encoding).unwrap();
            check_round_trip(&path, &p2, 0.125 * n as f64);
            check_header(&path, n, encoding);

            let p3 = Particles::<3>::generate(n, 100 + n as u64);
            let path = dir.join(format!("f3_{n}.vtu"));
            write_vtu(&path, &p3.frame(1e-7), encoding).unwrap();
            check_round_trip(&path, &p3, 1e-7);
            check_header(&path, n, encoding);
            assert_no_tmp_left(&dir);
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn vtu_large_round_trip_in_every_encoding() {
    let dir = scratch("large");
    let n = 100_000;
    for encoding in Encoding::ALL {
        let p3 = Particles::<3>::generate(n, 7);
        let path = dir.join("big3.vtu");
        write_vtu(&path, &p3.frame(2.5), encoding).unwrap();
        check_round_trip(&path, &p3, 2.5);
        check_header(&path, n, encoding);

        let p2 = Particles::<2>::generate(n, 8);
        let path = dir.join("big2.vtu");
        write_vtu(&path, &p2.frame(3.5), encoding).unwrap();
        check_round_trip(&path, &p2, 3.5);
        check_header(&path, n, encoding);

        // The convenience reader agrees.
        let (points, arrays) = read_vtu_points(&path).unwrap();
        assert_eq!(points.len(), n);
        assert_eq!(arrays.len(), 5);
        assert_eq!((arrays[0].0.as_str(), arrays[0].1), ("velocity", 3));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn vtu_million_particles_is_fast() {
    let dir = scratch("million");
    let n = 1_000_000;
    let p = Particles::<3>::generate(n, 9);
    let path = dir.join("m.vtu");
    for encoding in Encoding::ALL {
        let t0 = std::time::Instant::now();
        write_vtu(&path, &p.frame(0.0), encoding).unwrap();
        let dt = t0.elapsed();
        let size = std::fs::metadata(&path).unwrap().len();
        eprintln!(
            "write_vtu 1e6 particles (3D, {}): {dt:?}, {size} bytes",
            encoding.name()
        );
        // Generous bound (debug builds, slow disks); typically well under 1 s.
        assert!(dt.as_secs_f64() < 20.0, "{dt:?}");
        // 49 bytes of arrays per particle: raw holds them all, base64 4/3 of them.
        match encoding {
            Encoding::Raw => assert!(size > 49 * n as u64),
            Encoding::Base64 => assert!(size > 65 * n as u64),
            // Random bits barely compress, but the cell arrays (13 bytes) do.
            Encoding::Zlib => assert!(size < 49 * n as u64),
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn fluid_subset_keeps_the_ids_of_the_fluid_particles() {
    let p = Particles::<2>::generate(40, 11);
    let frame = p.frame(0.5);
    let fluid = frame.fluid();
    let want: Vec<usize> = (0..40).filter(|&i| p.kind[i] == 0).collect();
    assert!(!want.is_empty() && want.len() < 40);
    assert_eq!(fluid.id, want.iter().map(|&i| p.id[i]).collect::<Vec<_>>());
    assert_eq!(
        fluid.position,
        want.iter().map(|&i| p.position[i]).collect::<Vec<_>>()
    );
    assert_eq!(
        fluid.pressure,
        want.iter().map(|&i| p.pressure[i]).collect::<Vec<_>>()
    );
    assert!(fluid.kind.iter().all(|&k| k == 0));
    assert_eq!(fluid.frame().checked_len().unwrap(), want.len());
}

#[test]
fn vtu_one_dimensional_pads_with_zeros() {
    let dir = scratch("one_d");
    let p = Particles::<1>::generate(5, 3);
    let path = dir.join("f1.vtu");
    write_vtu(&path, &p.frame(1.0), Encoding::Zlib).unwrap();
    check_round_trip(&path, &p, 1.0);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn vtu_length_mismatch_is_error() {
    let dir = scratch("mismatch");
    let p = Particles::<2>::generate(4, 1);
    let path = dir.join("bad.vtu");
    let short = &p.density[..3];
    let mut frame = p.frame(0.0);
    frame.density = short;
    match write_vtu(&path, &frame, Encoding::default()) {
        Err(OutputError::LengthMismatch {
            field,
            expected,
            found,
        }) => assert_eq!((field, expected, found), ("density", 4, 3)),
        other => panic!("expected LengthMismatch, got {other:?}"),
    }
    let mut frame = p.frame(0.0);
    frame.kind = &p.kind[..0];
    assert!(matches!(
        write_vtu(&path, &frame, Encoding::default()),
        Err(OutputError::LengthMismatch { field: "kind", .. })
    ));
    assert!(!path.exists());
    assert_no_tmp_left(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn vtu_unsupported_dimension_is_error() {
    let dir = scratch("dim4");
    let pos = vec![SVector::<f32, 4>::zeros(); 1];
    let frame = Frame {
        time: 0.0,
        position: &pos,
        velocity: &pos,
        density: &[1.0],
        pressure: &[0.0],
        kind: &[0],
        id: &[0],
    };
    assert!(matches!(
        write_vtu(&dir.join("x.vtu"), &frame, Encoding::default()),
        Err(OutputError::UnsupportedDimension(4))
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn vtu_overwrite_replaces_file() {
    let dir = scratch("overwrite");
    let path = dir.join("f.vtu");
    let a = Particles::<3>::generate(50, 1);
    let b = Particles::<3>::generate(3, 2);
    write_vtu(&path, &a.frame(1.0), Encoding::Zlib).unwrap();
    write_vtu(&path, &b.frame(2.0), Encoding::Zlib).unwrap();
    check_round_trip(&path, &b, 2.0);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn reader_rejects_malformed_files_without_panicking() {
    let dir = scratch("malformed");
    let p = Particles::<3>::generate(10, 4);
    let bad = dir.join("bad.vtu");
    let check = |cases: &[Vec<u8>], full: usize| {
        for (i, c) in cases.iter().enumerate() {
            std::fs::write(&bad, c).unwrap();
            match read_vtu(&bad) {
                Err(OutputError::Malformed { path, .. }) => assert_eq!(path, bad),
                Ok(_) if c.len() >= full - 30 && c.len() <= full => {
                    // Truncating only the closing tags leaves the data intact.
                }
                other => panic!("case {i} (len {}): expected Malformed, got {other:?}", c.len()),
            }
        }
    };
    for encoding in Encoding::ALL {
        let good = dir.join("good.vtu");
        write_vtu(&good, &p.frame(1.0), encoding).unwrap();
        let bytes = std::fs::read(&good).unwrap();
        let h = read_vtu_header(&good).unwrap();
        let mut cases: Vec<Vec<u8>> = vec![
            Vec::new(),
            b"not xml at all".to_vec(),
            b"<VTKFile type=\"UnstructuredGrid\"><AppendedData encoding=\"raw\">_".to_vec(),
        ];
        // Every truncation of the file.
        for cut in (0..bytes.len()).step_by(37) {
            cases.push(bytes[..cut].to_vec());
        }
        // Corrupted block headers (byte counts, block counts).
        for a in h.arrays.iter().filter_map(|a| a.offset) {
            let mut c = bytes.clone();
            let at = (h.appended_start + a) as usize;
            c[at..at + 8].copy_from_slice(&u64::MAX.to_le_bytes());
            cases.push(c.clone());
            c[at..at + 8].copy_from_slice(&3u64.to_le_bytes());
            cases.push(c);
        }
        // Header edits.
        let text = String::from_utf8_lossy(&bytes[..h.appended_start as usize]).into_owned();
        let tail = &bytes[h.appended_start as usize..];
        let mut edits = vec![
            ("offset=\"0\"", "offset=\"99999999999\""),
            ("NumberOfPoints=\"10\"", "NumberOfPoints=\"11\""),
            ("NumberOfPoints=\"10\"", "NumberOfPoints=\"-1\""),
            ("type=\"Float32\"", "type=\"Float128\""),
            ("format=\"appended\"", "format=\"binary\""),
            ("header_type=\"UInt64\"", "header_type=\"UInt16\""),
            ("byte_order=\"LittleEndian\"", "byte_order=\"BigEndian\""),
            ("NumberOfComponents=\"3\"", "NumberOfComponents=\"0\""),
            ("<Piece", "<Piece x=\"&bogus;\""),
        ];
        match encoding {
            Encoding::Zlib => {
                edits.push(("vtkZLibDataCompressor", "vtkLZ4DataCompressor"));
                edits.push((" compressor=\"vtkZLibDataCompressor\"", ""));
            }
            Encoding::Base64 => edits.push(("encoding=\"base64\"", "encoding=\"raw\"")),
            Encoding::Raw => edits.push(("encoding=\"raw\"", "encoding=\"base64\"")),
        }
        for (from, to) in edits {
            assert!(text.contains(from), "{from}");
            let mut c = text.replacen(from, to, 1).into_bytes();
            c.extend_from_slice(tail);
            cases.push(c);
        }
        check(&cases, bytes.len());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn pvd_lists_frames_in_order() {
    let dir = scratch("pvd");
    let pvd = dir.join("run.pvd");
    let mut series = PvdSeries::new();
    assert!(series.is_empty());
    let p = Particles::<2>::generate(3, 5);
    let times = [0.0, 0.1, 0.2 + 1e-12, 1e-20, 12345.678];
    for (i, &t) in times.iter().enumerate() {
        let name = format!("frame_{i:05}.vtu");
        write_vtu(&dir.join(&name), &p.frame(t), Encoding::default()).unwrap();
        series.push(t, name);
        series.write(&pvd).unwrap();
        let back = PvdSeries::read(&pvd).unwrap();
        assert_eq!(back, series);
        assert_no_tmp_left(&dir);
    }
    let back = PvdSeries::read(&pvd).unwrap();
    assert_eq!(back.len(), times.len());
    for (i, (t, f)) in back.entries().iter().enumerate() {
        assert_eq!(t.to_bits(), times[i].to_bits());
        assert_eq!(f, &format!("frame_{i:05}.vtu"));
        assert!(dir.join(f).exists());
    }
    let text = std::fs::read_to_string(&pvd).unwrap();
    assert!(text.contains("<VTKFile type=\"Collection\""));
    assert!(text.contains("<DataSet timestep=\"0.1\" group=\"\" part=\"0\" file=\"frame_00001.vtu\"/>"));
    let positions: Vec<usize> = (0..times.len())
        .map(|i| text.find(&format!("frame_{i:05}.vtu")).unwrap())
        .collect();
    assert!(positions.windows(2).all(|w| w[0] < w[1]));

    // Names needing escaping survive.
    let mut odd = PvdSeries::new();
    odd.push(1.0, "a&b <\"c\">.vtu");
    odd.write(&pvd).unwrap();
    assert_eq!(PvdSeries::read(&pvd).unwrap(), odd);

    // Restart helper.
    let mut s = back.clone();
    s.truncate_after(0.1);
    assert_eq!(s.len(), 3);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn force_log_round_trips_exactly() {
    let dir = scratch("csv");
    let path = dir.join("forces.csv");
    let rows: Vec<(f64, &str, [f64; 3])> = vec![
        (0.0, "cylinder", [1.0, -2.5, 0.0]),
        (0.1, "cylinder", [0.1 + 0.2, 1.0 / 3.0, -0.0]),
        (1e-300, "plate, left", [f64::MAX, f64::MIN_POSITIVE, 5e-324]),
        (123456789.123, "say \"hi\"", [-1e20, 1e-7, 6.02214076e23]),
    ];
    let mut log = ForceLog::create(&path, 3).unwrap();
    for (t, s, f) in &rows[..2] {
        log.push(*t, s, *f).unwrap();
    }
    log.flush().unwrap();
    // Flushed rows are visible while the log is still open.
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text.lines().count(), 3);
    for (t, s, f) in &rows[2..] {
        log.push(*t, s, *f).unwrap();
    }
    log.flush().unwrap();
    let table = CsvFile::read(&path).unwrap();
    assert_eq!(table.header(), ["t_s", "solid", "fx_N", "fy_N", "fz_N"]);
    assert_eq!(table.len(), rows.len());
    for (r, (t, s, f)) in rows.iter().enumerate() {
        assert_eq!(table.number(r, 0).unwrap().to_bits(), t.to_bits());
        assert_eq!(table.text(r, 1), *s);
        for c in 0..3 {
            assert_eq!(
                table.number(r, 2 + c).unwrap().to_bits(),
                f[c].to_bits(),
                "row {r}"
            );
        }
    }
    // A 2D run's forces are per metre of depth, without a z component.
    let path = dir.join("forces_2d.csv");
    let mut log = ForceLog::create(&path, 2).unwrap();
    log.push(0.5, "tank", [3.0, -4.0, 0.0]).unwrap();
    log.flush().unwrap();
    let table = CsvFile::read(&path).unwrap();
    assert_eq!(table.header(), ["t_s", "solid", "fx_N_per_m", "fy_N_per_m"]);
    assert_eq!(
        table.number(0, table.column("fy_N_per_m").unwrap()).unwrap(),
        -4.0
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

fn sample_summary() -> Summary {
    let mut extra = serde_json::Map::new();
    extra.insert("dt".into(), serde_json::json!(1e-4));
    extra.insert("iterations".into(), serde_json::json!([3, 4, 5]));
    Summary {
        scene: "dam_break".into(),
        scene_file: Some("/runs/scenes/dam_break.toml".into()),
        scene_overrides: vec!["solver.dt=1e-4".into()],
        dimension: 2,
        solver: "ipc".into(),
        backend: "cpu".into(),
        threads: 2,
        particles: 12345,
        fluid_particles: 10000,
        steps: 999,
        simulated_time: 0.1 + 0.2,
        wall_seconds: 12.75,
        particle_steps_per_second: 12345.0 * 999.0 / 12.75,
        max_compression: 0.0123456789,
        mean_compression: 1.0 / 3.0,
        max_surface_deficit: 0.375,
        mean_surface_deficit: 1.0 / 7.0,
        status: "completed".into(),
        run_id: "0123456789abcdef".into(),
        scene_hash: "fedcba9876543210".into(),
        warnings: vec!["a warning".into()],
        output_frames: 11,
        extra,
    }
}

#[test]
fn summary_round_trips() {
    let dir = scratch("summary");
    let path = dir.join("summary.json");
    let s = sample_summary();
    write_summary(&path, &s).unwrap();
    assert_no_tmp_left(&dir);
    let back = read_summary(&path).unwrap();
    assert_eq!(back, s);
    let via_serde: Summary = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(via_serde, s);
    assert_eq!(via_serde.simulated_time.to_bits(), s.simulated_time.to_bits());
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\n  \"scene\": \"dam_break\""));

    // Non-finite values (diverged run) come back as NaN instead of failing.
    let mut diverged = s.clone();
    diverged.status = "diverged".into();
    diverged.max_compression = f64::NAN;
    diverged.mean_compression = f64::INFINITY;
    write_summary(&path, &diverged).unwrap();
    let back = read_summary(&path).unwrap();
    assert!(back.max_compression.is_nan() && back.mean_compression.is_nan());
    assert_eq!(back.status, "diverged");
    // The headline numbers are named for what they are; one missing (a summary of another
    // version) reads as not known.
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("\"max_surface_deficit\": 0.375") && !text.contains("density_error"));
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    json.as_object_mut().unwrap().remove("max_surface_deficit");
    std::fs::write(&path, json.to_string()).unwrap();
    assert!(read_summary(&path).unwrap().max_surface_deficit.is_nan());

    std::fs::write(&path, "{ not json").unwrap();
    assert!(matches!(read_summary(&path), Err(OutputError::Json { .. })));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn missing_directory_is_io_error_naming_path() {
    let dir = scratch("missing");
    let gone = dir.join("does/not/exist");
    let p = Particles::<2>::generate(2, 1);

    let check = |err: OutputError, target: &Path| {
        let msg = err.to_string();
        match &err {
            OutputError::Io { path, .. } => {
                assert!(path.starts_with(&gone), "{path:?}");
                assert!(path.to_string_lossy().starts_with(&*target.to_string_lossy()));
            }
            other => panic!("expected Io, got {other:?}"),
        }
        assert!(msg.contains(&*target.to_string_lossy()), "{msg}");
    };
    let f = gone.join("f.vtu");
    check(write_vtu(&f, &p.frame(0.0), Encoding::default()).unwrap_err(), &f);
    let f = gone.join("s.pvd");
    check(PvdSeries::new().write(&f).unwrap_err(), &f);
    let f = gone.join("forces.csv");
    check(ForceLog::create(&f, 3).unwrap_err(), &f);
    let f = gone.join("summary.json");
    check(write_summary(&f, &sample_summary()).unwrap_err(), &f);
    let f = gone.join("r.vtu");
    check(read_vtu(&f).unwrap_err(), &f);
    check(PvdSeries::read(&f).unwrap_err(), &f);
    check(read_summary(&f).unwrap_err(), &f);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn writing_below_a_regular_file_is_io_error() {
    // A path whose parent is a file cannot be created, even by root.
    let dir = scratch("notadir");
    let file = dir.join("plain");
    std::fs::write(&file, b"x").unwrap();
    let p = Particles::<3>::generate(2, 1);
    let f = file.join("f.vtu");
    match write_vtu(&f, &p.frame(0.0), Encoding::default()) {
        Err(OutputError::Io { path, .. }) => assert!(path.starts_with(&file)),
        other => panic!("expected Io, got {other:?}"),
    }
    assert!(matches!(
        ForceLog::create(&file.join("f.csv"), 2),
        Err(OutputError::Io { .. })
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

fn arb_vecs<const D: usize>(n: usize) -> impl Strategy<Value = Vec<SVector<f32, D>>> {
    let finite = any::<f32>().prop_map(|x| if x.is_finite() { x } else { 0.5 });
    proptest::collection::vec(proptest::array::uniform::<_, D>(finite), n)
        .prop_map(|v| v.into_iter().map(SVector::<f32, D>::from).collect())
}

fn arb_particles<const D: usize>() -> impl Strategy<Value = (f64, Particles<D>)> {
    (0usize..64).prop_flat_map(move |n| {
        (
            any::<f64>(),
            arb_vecs::<D>(n),
            arb_vecs::<D>(n),
            proptest::collection::vec(any::<f32>(), n),
            proptest::collection::vec(any::<f32>(), n),
            proptest::collection::vec(any::<u32>(), n),
            proptest::collection::vec(any::<u32>(), n),
        )
            .prop_map(|(t, position, velocity, density, pressure, kind, id)| {
                (
                    t,
                    Particles {
                        position,
                        velocity,
                        density,
                        pressure,
                        kind,
                        id,
                    },
                )
            })
    })
}

/// Like `check_round_trip` but NaN-tolerant (proptest feeds arbitrary bits;
/// NaN payloads survive because f32 -> f64 -> f32 preserves quiet NaNs, but
/// compare NaN-ness only to be safe) and time compared by value.
fn check_prop<const D: usize>(path: &Path, t: f64, p: &Particles<D>) -> Result<(), TestCaseError> {
    let data = read_vtu(path).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let same = |a: f32, b: f32| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    prop_assert_eq!(data.points.len(), p.position.len());
    let ht = data.header.time.unwrap();
    prop_assert!(ht.to_bits() == t.to_bits() || (ht.is_nan() && t.is_nan()));
    for (g, w) in data.points.iter().zip(&p.position) {
        let w = pad3(w);
        prop_assert!((0..3).all(|c| same(g[c], w[c])));
    }
    let vel = data.point_array("velocity").unwrap();
    for (i, v) in p.velocity.iter().enumerate() {
        let w = pad3(v);
        prop_assert!((0..3).all(|c| same(vel.values[3 * i + c] as f32, w[c])));
    }
    for (name, want) in [("density", &p.density), ("pressure", &p.pressure)] {
        let a = data.point_array(name).unwrap();
        prop_assert_eq!(a.values.len(), want.len());
        prop_assert!(a.values.iter().zip(want.iter()).all(|(g, w)| same(*g as f32, *w)));
    }
    let kind: Vec<u32> = data
        .point_array("kind")
        .unwrap()
        .values
        .iter()
        .map(|x| *x as u32)
        .collect();
    prop_assert_eq!(&kind, &p.kind);
    let id: Vec<u32> = data
        .point_array("id")
        .unwrap()
        .values
        .iter()
        .map(|x| *x as u32)
        .collect();
    prop_assert_eq!(&id, &p.id);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn prop_vtu_round_trip_2d((t, p) in arb_particles::<2>()) {
        let dir = scratch("prop2");
        let path = dir.join("p.vtu");
        for encoding in Encoding::ALL {
            write_vtu(&path, &p.frame(t), encoding).unwrap();
            check_prop(&path, t, &p)?;
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn prop_vtu_round_trip_3d((t, p) in arb_particles::<3>()) {
        let dir = scratch("prop3");
        let path = dir.join("p.vtu");
        for encoding in Encoding::ALL {
            write_vtu(&path, &p.frame(t), encoding).unwrap();
            check_prop(&path, t, &p)?;
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
