//! The frames and surfaces read by an independent reader: `vtkio` 0.7, the VTK XML reader of
//! splashsurf 0.14. It reads `base64` appended data (its raw variant is not compiled in), so the
//! base64 files go through it; the default `zlib` files are checked against the base64 ones of
//! the same run, array by array (CPU runs are bitwise reproducible). `tests/readers/read_outputs.py`
//! does the same with VTK's own reader and meshio.
//!
//! Checked: every array equals what the writer was given (exactly, as f32/u32), `id` is a
//! permutation of 0..N that follows each particle (between two frames a particle moves by at
//! most `2 Δt max(|u|max, |g| Δt)`, while the storage order changes), the `TimeValue` of each
//! file equals its time in the `.pvd`, and 2D surfaces are line cells, 3D surfaces triangles.

use crate::common::run::{SPH as BIN, run_scene};
use crate::common::scratch;
use crate::common::tolerance::F32_ROUNDING;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use nalgebra::SVector;
use sph::math::Vector;
use sph::output::vtp::{read_vtp, write_vtp};
use sph::output::{Encoding, Frame, PvdSeries, read_vtu, write_vtu};
use sph::surface::SurfaceMesh;
use vtkio::model::{Attribute, DataSet, IOBuffer, Piece, VertexNumbers};

/// |g| of the scenes below [m/s²].
const GRAVITY: f64 = 9.81;

/// One `.vtu` or `.vtp` file as vtkio reads it.
#[derive(Debug, Default)]
struct Read {
    points: Vec<f32>,
    arrays: HashMap<String, IOBuffer>,
    /// Cells of a `.vtp`: `(connectivity, offsets)` of `Lines` and of `Polys`.
    lines: Option<(Vec<u64>, Vec<u64>)>,
    polys: Option<(Vec<u64>, Vec<u64>)>,
    /// `TimeValue`, read from the file's text (vtkio does not keep field data).
    time: f64,
}

fn read_with_vtkio(path: &Path) -> Read {
    let mut vtk = vtkio::Vtk::import(path).unwrap_or_else(|e| panic!("vtkio reads {}: {e}", path.display()));
    vtk.load_all_pieces().expect("pieces load");
    let mut out = Read {
        time: time_value(path),
        ..Read::default()
    };
    let points = |b: IOBuffer| match b {
        IOBuffer::F32(v) => v,
        other => panic!("Points are {other:?}"),
    };
    let attributes = |attrs: Vec<Attribute>| -> HashMap<String, IOBuffer> {
        attrs
            .into_iter()
            .filter_map(|a| match a {
                Attribute::DataArray(d) => Some((d.name, d.data)),
                Attribute::Field { .. } => None,
            })
            .collect()
    };
    let xml = |v: Option<VertexNumbers>| v.map(VertexNumbers::into_xml);
    match vtk.data {
        DataSet::UnstructuredGrid { pieces, .. } => {
            assert_eq!(pieces.len(), 1);
            let Piece::Inline(p) = pieces.into_iter().next().unwrap() else {
                panic!("piece not loaded")
            };
            out.points = points(p.points);
            out.arrays = attributes(p.data.point);
            let (conn, offsets) = p.cells.cell_verts.into_xml();
            let n = out.points.len() / 3;
            assert_eq!(
                conn,
                (0..n as u64).collect::<Vec<_>>(),
                "one vertex cell per particle"
            );
            assert_eq!(offsets, (1..=n as u64).collect::<Vec<_>>());
            assert!(p.cells.types.iter().all(|t| *t == vtkio::model::CellType::Vertex));
        }
        DataSet::PolyData { pieces, .. } => {
            assert_eq!(pieces.len(), 1);
            let Piece::Inline(p) = pieces.into_iter().next().unwrap() else {
                panic!("piece not loaded")
            };
            out.points = points(p.points);
            out.arrays = attributes(p.data.point);
            out.lines = xml(p.lines);
            out.polys = xml(p.polys);
        }
        other => panic!("unexpected data set {other:?}"),
    }
    out
}

/// The `TimeValue` field of a VTK XML file, from its text.
fn time_value(path: &Path) -> f64 {
    let bytes = std::fs::read(path).expect("file");
    let text = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]);
    let at = text.find("Name=\"TimeValue\"").expect("TimeValue field");
    let rest = &text[at..];
    let start = rest.find('>').unwrap() + 1;
    let end = rest.find("</DataArray>").unwrap();
    rest[start..end].trim().parse().expect("a number")
}

fn f32s(b: &IOBuffer) -> &[f32] {
    match b {
        IOBuffer::F32(v) => v,
        other => panic!("expected Float32, got {other:?}"),
    }
}

fn u32s(b: &IOBuffer) -> &[u32] {
    match b {
        IOBuffer::U32(v) => v,
        other => panic!("expected UInt32, got {other:?}"),
    }
}

fn pad3<const D: usize>(v: &[SVector<f32, D>]) -> Vec<f32> {
    v.iter()
        .flat_map(|p| (0..3).map(move |c| if c < D { p[c] } else { 0.0 }))
        .collect()
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn library_frames_read_back_exactly<const D: usize>(dir: &Path) {
    let n = 1000usize;
    let vec = |i: usize, k: f32| SVector::<f32, D>::from_fn(|c, _| (i * 7 + c) as f32 * k - 1.5);
    let position: Vec<_> = (0..n).map(|i| vec(i, 0.01)).collect();
    let velocity: Vec<_> = (0..n).map(|i| vec(i, -0.3)).collect();
    let density: Vec<f32> = (0..n).map(|i| 1000.0 + i as f32 * 0.125).collect();
    let pressure: Vec<f32> = (0..n).map(|i| (i as f32).sin() * 1e4).collect();
    let kind: Vec<u32> = (0..n as u32).map(|i| i % 3).collect();
    let id: Vec<u32> = (0..n as u32).map(|i| (i * 389) % n as u32).collect();
    let frame = Frame {
        time: 0.0625,
        position: &position,
        velocity: &velocity,
        density: &density,
        pressure: &pressure,
        kind: &kind,
        id: &id,
    };
    let path = dir.join(format!("frame{D}.vtu"));
    write_vtu(&path, &frame, Encoding::Base64).unwrap();
    let read = read_with_vtkio(&path);
    assert_eq!(read.time, 0.0625);
    assert_eq!(bits(&read.points), bits(&pad3(&position)));
    assert_eq!(bits(f32s(&read.arrays["velocity"])), bits(&pad3(&velocity)));
    assert_eq!(bits(f32s(&read.arrays["density"])), bits(&density));
    assert_eq!(bits(f32s(&read.arrays["pressure"])), bits(&pressure));
    assert_eq!(u32s(&read.arrays["kind"]), kind.as_slice());
    assert_eq!(u32s(&read.arrays["id"]), id.as_slice());
}

#[test]
fn vtkio_reads_base64_frames_exactly_in_2d_and_3d() {
    let dir = scratch("library");
    library_frames_read_back_exactly::<2>(&dir);
    library_frames_read_back_exactly::<3>(&dir);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn vtkio_reads_base64_surfaces_as_lines_in_2d_and_triangles_in_3d() {
    let dir = scratch("surfaces");
    let seg = SurfaceMesh::<2> {
        positions: vec![
            Vector::<2>::new(0.5, 0.0),
            Vector::<2>::new(0.0, 2.0),
            Vector::<2>::new(1.0, 1.0),
        ],
        normals: vec![Vector::<2>::new(1.0, 0.0); 3],
        elements: vec![[0, 1], [1, 2], [2, 0]],
    };
    write_vtp(&dir.join("s.vtp"), &seg, 0.5, Encoding::Base64).unwrap();
    let read = read_with_vtkio(&dir.join("s.vtp"));
    assert_eq!(read.time, 0.5);
    assert_eq!(read.points, [0.5, 0.0, 0.0, 0.0, 2.0, 0.0, 1.0, 1.0, 0.0]);
    assert_eq!(f32s(&read.arrays["Normals"]), &[1.0, 0.0, 0.0].repeat(3));
    assert_eq!(read.lines, Some((vec![0, 1, 1, 2, 2, 0], vec![2, 4, 6])));
    assert!(read.polys.is_none_or(|(c, _)| c.is_empty()));

    let tri = SurfaceMesh::<3> {
        positions: vec![
            Vector::<3>::new(0.0, 0.0, 0.0),
            Vector::<3>::new(1.0, 0.0, 0.0),
            Vector::<3>::new(0.0, 1.0, 0.5),
            Vector::<3>::new(0.0, 0.0, 1.0),
        ],
        normals: vec![Vector::<3>::new(0.0, 0.0, 1.0); 4],
        elements: vec![[0, 1, 2], [0, 2, 3]],
    };
    write_vtp(&dir.join("t.vtp"), &tri, 1.25, Encoding::Base64).unwrap();
    let read = read_with_vtkio(&dir.join("t.vtp"));
    assert_eq!(read.time, 1.25);
    assert_eq!(read.polys, Some((vec![0, 1, 2, 0, 2, 3], vec![3, 6])));
    assert!(read.lines.is_none_or(|(c, _)| c.is_empty()));
    std::fs::remove_dir_all(&dir).ok();
}

/// A small dam break in a container (gravity, a solid tank) in `dimension`; `output` is
/// appended to `[output]`.
fn dam_break(dir: &Path, dimension: usize, output: &str) -> PathBuf {
    let (domain, fluid, tank, spacing, end) = if dimension == 2 {
        (
            "min = [-0.1, -0.1]\nmax = [0.7, 0.5]",
            "min = [0.0, 0.0]\nmax = [0.2, 0.3]",
            "min = [0.0, 0.0]\nmax = [0.6, 0.4]",
            0.02,
            0.08,
        )
    } else {
        (
            "min = [-0.2, -0.2, -0.2]\nmax = [0.6, 0.5, 0.4]",
            "min = [0.0, 0.0, 0.0]\nmax = [0.16, 0.24, 0.2]",
            "min = [0.0, 0.0, 0.0]\nmax = [0.4, 0.3, 0.2]",
            0.04,
            0.06,
        )
    };
    let g = if dimension == 2 {
        format!("[0.0, -{GRAVITY}]")
    } else {
        format!("[0.0, -{GRAVITY}, 0.0]")
    };
    let scene = dir.join(format!("dam_{dimension}d.toml"));
    std::fs::write(
        &scene,
        format!(
            "name = \"dam\"\ndimension = {dimension}\neffects = [\"gravity\"]\n\n[domain]\n{domain}\n\n\
[particles]\nspacing = {spacing}\nsmoothing_ratio = 2.0\n\n[fluid]\nrho0 = 1000.0\nsound_speed = 20.0\n\
gravity = {g}\n\n[[fluid_box]]\n{fluid}\n\n[[solid]]\nname = \"tank\"\nshape = \"container\"\n{tank}\n\n\
[solver]\nkind = \"wcsph\"\nend_time = {end}\n\n[output]\ninterval = {interval}\n{output}\n",
            interval = end / 4.0,
        ),
    )
    .expect("scene");
    scene
}

/// Positions by id of one frame read by vtkio, and its largest speed [m/s].
fn by_id(read: &Read) -> (HashMap<u32, [f32; 3]>, f64) {
    let ids = u32s(&read.arrays["id"]);
    let speed = f32s(&read.arrays["velocity"])
        .chunks_exact(3)
        .map(|u| f64::from(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt())
        .fold(0.0, f64::max);
    let map = ids
        .iter()
        .zip(read.points.chunks_exact(3))
        .map(|(&id, p)| (id, [p[0], p[1], p[2]]))
        .collect();
    (map, speed)
}

/// What one frame leaves for the next: time [s], positions by id [m], largest speed [m/s], ids
/// in storage order.
type Previous = (f64, HashMap<u32, [f32; 3]>, f64, Vec<u32>);

/// Checks the base64 run in `out` through vtkio and compares it with the zlib run in `zlib`.
fn check_run(out: &Path, zlib: &Path, dimension: usize) {
    let frames = PvdSeries::read(&out.join("particles.pvd")).expect("particles.pvd");
    assert_eq!(frames.len(), 5, "frames at 0, T/4, ..., T");
    let mut previous: Option<Previous> = None;
    let mut reordered = false;
    for (t, file) in frames.entries() {
        let read = read_with_vtkio(&out.join(file));
        assert_eq!(read.time, *t, "{file}: TimeValue and .pvd time");
        let ids = u32s(&read.arrays["id"]).to_vec();
        let mut sorted = ids.clone();
        sorted.sort_unstable();
        assert!(
            sorted.iter().enumerate().all(|(i, &id)| id == i as u32),
            "{file}: id is a permutation of 0..N"
        );
        // The zlib file of the same frame holds the same values, read by the crate's reader.
        let other = read_vtu(&zlib.join(file)).expect("zlib frame");
        assert!(other.header.zlib);
        assert_eq!(other.header.time, Some(*t));
        let same = |name: &str, values: &[f64]| {
            let got: Vec<f64> = match &read.arrays[name] {
                IOBuffer::F32(v) => v.iter().map(|&x| f64::from(x)).collect(),
                IOBuffer::U32(v) => v.iter().map(|&x| f64::from(x)).collect(),
                other => panic!("{other:?}"),
            };
            assert!(got == values, "{file}: {name} differs between base64 and zlib");
        };
        for name in ["velocity", "density", "pressure", "kind", "id"] {
            same(name, &other.point_array(name).expect(name).values);
        }
        let points: Vec<f32> = other.points.iter().flatten().copied().collect();
        assert_eq!(bits(&points), bits(&read.points), "{file}: points");
        if dimension == 2 {
            assert!(read.points.chunks_exact(3).all(|p| p[2] == 0.0));
        }

        let (positions, speed) = by_id(&read);
        if let Some((t0, before, speed0, ids0)) = &previous {
            let dt = t - t0;
            let bound = 2.0 * dt * speed.max(*speed0).max(GRAVITY * dt) + F32_ROUNDING;
            let worst = before
                .iter()
                .map(|(id, p)| {
                    let q = positions[id];
                    ((0..3).map(|c| f64::from(q[c] - p[c]).powi(2)).sum::<f64>()).sqrt()
                })
                .fold(0.0, f64::max);
            assert!(
                worst <= bound,
                "{file}: a particle moved {worst} m, bound {bound} m"
            );
            assert!(worst > 0.0, "{file}: the fluid moves");
            reordered |= *ids0 != ids;
        }
        previous = Some((*t, positions, speed, ids));
    }
    assert!(
        reordered,
        "the storage order changes between frames, so ids are needed"
    );

    let surfaces = PvdSeries::read(&out.join("surface.pvd")).expect("surface.pvd");
    assert_eq!(surfaces.entries().len(), frames.len());
    for ((t, file), (t_frame, _)) in surfaces.entries().iter().zip(frames.entries()) {
        assert_eq!(t, t_frame);
        let read = read_with_vtkio(&out.join(file));
        assert_eq!(read.time, *t);
        let ours = read_vtp(&out.join(file)).expect("vtp");
        let (cells, per_cell) = if dimension == 2 {
            (read.lines.clone().expect("Lines"), 2)
        } else {
            (read.polys.clone().expect("Polys"), 3)
        };
        assert!(!cells.1.is_empty(), "{file}: a surface");
        assert_eq!(cells.1.len(), ours.cells.len());
        assert_eq!(
            cells.0.len(),
            per_cell * cells.1.len(),
            "{file}: cells of {per_cell} points"
        );
        assert_eq!(cells.0, ours.cells.concat());
        let zlib_mesh = read_vtp(&zlib.join(file)).expect("zlib vtp");
        assert_eq!(zlib_mesh, ours, "{file}: base64 and zlib surfaces");
        let points: Vec<f32> = ours.points.iter().flatten().copied().collect();
        assert_eq!(bits(&points), bits(&read.points));
    }
}

fn runs_are_read_by_vtkio(dimension: usize) {
    let dir = scratch(&format!("run{dimension}d"));
    let base64 = dir.join("base64");
    let zlib = dir.join("zlib");
    run_scene(
        &dam_break(&dir, dimension, "surface = true\nencoding = \"base64\""),
        &base64,
    );
    run_scene(&dam_break(&dir, dimension, "surface = true"), &zlib);
    check_run(&base64, &zlib, dimension);

    // Fluid-only frames: the fluid particles of the full frames, with the same ids.
    let fluid = dir.join("fluid");
    run_scene(
        &dam_break(&dir, dimension, "fluid_only = true\nencoding = \"base64\""),
        &fluid,
    );
    let frames = PvdSeries::read(&fluid.join("particles.pvd")).expect("pvd");
    for (_, file) in frames.entries() {
        let only = read_with_vtkio(&fluid.join(file));
        let full = read_with_vtkio(&base64.join(file));
        assert!(u32s(&only.arrays["kind"]).iter().all(|&k| k == 0));
        let (only_at, _) = by_id(&only);
        let (full_at, _) = by_id(&full);
        let fluid_ids: Vec<u32> = u32s(&full.arrays["id"])
            .iter()
            .zip(u32s(&full.arrays["kind"]))
            .filter(|&(_, &k)| k == 0)
            .map(|(&id, _)| id)
            .collect();
        assert_eq!(
            only_at.len(),
            fluid_ids.len(),
            "{file}: every fluid particle, once"
        );
        assert!(fluid_ids.len() < full_at.len());
        for id in fluid_ids {
            assert_eq!(only_at[&id], full_at[&id], "{file}: particle {id}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn dam_break_2d_frames_and_surfaces_are_read_by_vtkio() {
    runs_are_read_by_vtkio(2);
}

#[test]
fn dam_break_3d_frames_and_surfaces_are_read_by_vtkio() {
    runs_are_read_by_vtkio(3);
}

/// `sph check` on the 2D dam break with `output` in `[output]`: (success, stderr).
fn check_scene(output: &str, name: &str) -> (bool, String) {
    let dir = scratch(name);
    let done = Command::new(BIN)
        .arg("check")
        .arg(dam_break(&dir, 2, output))
        .output()
        .expect("sph check starts");
    std::fs::remove_dir_all(&dir).ok();
    (
        done.status.success(),
        String::from_utf8_lossy(&done.stderr).into_owned(),
    )
}

#[test]
fn output_encoding_takes_zlib_base64_or_raw_and_names_them_when_wrong() {
    for encoding in Encoding::ALL {
        let (ok, err) = check_scene(&format!("encoding = \"{}\"", encoding.name()), encoding.name());
        assert!(ok, "{err}");
    }
    let (ok, err) = check_scene("encoding = \"gzip\"", "gzip");
    assert!(!ok);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    for part in ["output.encoding", "gzip", "`zlib`, `base64`, `raw`"] {
        assert!(err.contains(part), "{part} in {err}");
    }
    let (ok, err) = check_scene("fluid_only = \"yes\"", "fluid_only");
    assert!(!ok);
    assert!(err.contains("output.fluid_only"), "{err}");
}
