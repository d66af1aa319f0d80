//! Parallel frames (`output::pvtu`): a frame split into one `.vtu` piece per rank and joined by
//! a `.pvtu` header is read by an independent reader (vtkio) as the whole frame, bit for bit.

use crate::common::scratch;
use sph::output::pvtu::{piece_name, read_pvtu_pieces, write_pvtu};
use sph::output::{Encoding, Frame, PvdSeries, write_vtu};
use std::collections::HashMap;
use vtkio::model::{Attribute, DataSet, IOBuffer, Piece};

/// The particles of a random-looking 2D frame, in pieces of unequal size (one empty, as a rank
/// whose region holds no particle), read back through vtkio from the `.pvtu` and compared by id.
#[test]
fn vtkio_reads_the_pieces_of_a_parallel_frame_as_the_whole_frame() {
    let dir = scratch("pvtu");
    let n = 900usize;
    let position: Vec<_> = (0..n)
        .map(|i| nalgebra::SVector::<f32, 2>::new((i as f32 * 0.37).sin(), i as f32 * 1e-3))
        .collect();
    let velocity: Vec<_> = position.iter().map(|x| x * -2.0).collect();
    let density: Vec<f32> = (0..n).map(|i| 1000.0 + i as f32 * 0.125).collect();
    let pressure: Vec<f32> = (0..n).map(|i| (i as f32).cos() * 1e4).collect();
    let kind: Vec<u32> = (0..n as u32).map(|i| i % 3).collect();
    let id: Vec<u32> = (0..n as u32).map(|i| (i * 389) % n as u32).collect();
    // Rank r holds [cuts[r], cuts[r + 1]); rank 2 holds nothing.
    let cuts = [0, 500, 620, 620, n];
    let mut pieces = Vec::new();
    for r in 0..4 {
        let (a, b) = (cuts[r], cuts[r + 1]);
        let frame = Frame {
            time: 0.25,
            position: &position[a..b],
            velocity: &velocity[a..b],
            density: &density[a..b],
            pressure: &pressure[a..b],
            kind: &kind[a..b],
            id: &id[a..b],
        };
        let name = piece_name("frame_000005", r);
        write_vtu(&dir.join(&name), &frame, Encoding::Base64).expect("piece written");
        pieces.push(name);
    }
    let header = dir.join("frame_000005.pvtu");
    write_pvtu(&header, &pieces).expect("header written");
    assert_eq!(read_pvtu_pieces(&header).expect("header read"), pieces);
    let mut series = PvdSeries::new();
    series.push(0.25, "frame_000005.pvtu");
    series.write(&dir.join("particles.pvd")).expect("series");

    let mut vtk = vtkio::Vtk::import(&header).expect("vtkio reads the .pvtu");
    vtk.load_all_pieces().expect("vtkio loads the pieces");
    let DataSet::UnstructuredGrid { pieces: read, .. } = vtk.data else {
        panic!("not an unstructured grid")
    };
    assert_eq!(read.len(), 4, "one piece per rank");
    let mut by_id: HashMap<u32, (Vec<u32>, Vec<u32>, u32, u32)> = HashMap::new();
    for piece in read {
        let Piece::Inline(p) = piece else {
            panic!("piece not loaded")
        };
        let IOBuffer::F32(points) = p.points else {
            panic!("Float32 points")
        };
        let mut arrays: HashMap<String, IOBuffer> = p
            .data
            .point
            .into_iter()
            .filter_map(|a| match a {
                Attribute::DataArray(d) => Some((d.name, d.data)),
                Attribute::Field { .. } => None,
            })
            .collect();
        let (Some(IOBuffer::U32(ids)), Some(IOBuffer::F32(pressures)), Some(IOBuffer::U32(kinds))) = (
            arrays.remove("id"),
            arrays.remove("pressure"),
            arrays.remove("kind"),
        ) else {
            panic!("id, pressure and kind arrays")
        };
        for (k, i) in ids.iter().enumerate() {
            let xyz = points[3 * k..3 * k + 3].iter().map(|c| c.to_bits()).collect();
            let old = by_id.insert(*i, (xyz, vec![pressures[k].to_bits()], kinds[k], k as u32));
            assert!(old.is_none(), "id {i} in two pieces");
        }
    }
    assert_eq!(by_id.len(), n);
    for k in 0..n {
        let (xyz, p, kd, _) = &by_id[&id[k]];
        assert_eq!(
            xyz,
            &vec![position[k][0].to_bits(), position[k][1].to_bits(), 0f32.to_bits()]
        );
        assert_eq!(p, &vec![pressure[k].to_bits()]);
        assert_eq!(*kd, kind[k]);
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A `.vtu` given where a `.pvtu` header is expected is an error that says so.
#[test]
fn a_frame_that_is_not_a_parallel_header_is_an_error() {
    let dir = scratch("pvtu_bad");
    let path = dir.join("frame.vtu");
    let frame = Frame::<2> {
        time: 0.0,
        position: &[],
        velocity: &[],
        density: &[],
        pressure: &[],
        kind: &[],
        id: &[],
    };
    write_vtu(&path, &frame, Encoding::Base64).expect("frame");
    let error = read_pvtu_pieces(&path).expect_err("not a header").to_string();
    assert!(error.contains("PUnstructuredGrid"), "{error}");
    std::fs::remove_dir_all(&dir).ok();
}
