//! What a mesh must be: closed, consistently oriented, readable, and in a 3D scene; and where
//! its file is looked for.

use sph::geometry::{Mesh, Placement, read::read_triangles};
use sph::scene::{load_scene, parse_scene};

use crate::common::scene::{problems, with_key};
use crate::common::scratch_dir;
use crate::shapes::{box_triangles, scene_2d, scene_3d, write_stl};

fn mesh_scene(file: &str) -> String {
    scene_3d(0.02, &format!("shape = \"mesh\"\nfile = \"{file}\""))
}

/// The reason given for `solid[0].file` when the scene names the mesh `triangles`.
fn reason_for(name: &str, triangles: &[sph::geometry::Triangle]) -> String {
    let dir = scratch_dir(name);
    let file = write_stl(&dir, &format!("{name}.stl"), triangles, false);
    let ps = problems(parse_scene(&mesh_scene(&file), "test.toml", &[]));
    let p = with_key(&ps, "solid[0].file");
    assert!(
        p.reason.contains(&file),
        "the reason names the file: {}",
        p.reason
    );
    p.reason.clone()
}

#[test]
fn an_open_mesh_is_refused_naming_its_boundary() {
    let mut t = box_triangles([0.1; 3], [0.3; 3]);
    t.pop();
    let reason = reason_for("open", &t);
    assert!(reason.contains("open mesh: 3 boundary edges"), "{reason}");
}

#[test]
fn a_flipped_triangle_is_refused_as_inconsistent() {
    let mut t = box_triangles([0.1; 3], [0.3; 3]);
    t[5].swap(0, 1);
    let reason = reason_for("flipped", &t);
    assert!(
        reason.contains("inconsistent orientation") && reason.contains("3 such edges"),
        "{reason}"
    );
}

#[test]
fn degenerate_empty_unreadable_and_2d_meshes_are_refused() {
    let mut t = box_triangles([0.1; 3], [0.3; 3]);
    t.push([[0.1; 3], [0.1; 3], [0.3; 3]]);
    assert!(reason_for("degenerate", &t).contains("degenerate mesh: 1 triangles"));
    let mut doubled = box_triangles([0.1; 3], [0.3; 3]);
    doubled.extend(box_triangles([0.1; 3], [0.3; 3]));
    assert!(reason_for("doubled", &doubled).contains("non-manifold mesh"));
    assert!(reason_for("empty", &[]).contains("empty mesh"));

    let dir = scratch_dir("bad_files");
    let garbage = dir.join("garbage.stl");
    std::fs::write(&garbage, b"\xff\xfe not a mesh").unwrap();
    let ps = problems(parse_scene(&mesh_scene(garbage.to_str().unwrap()), "t", &[]));
    assert!(with_key(&ps, "solid[0].file").reason.contains("not a binary STL"));
    let text = dir.join("text.stl");
    std::fs::write(&text, "a text file\n").unwrap();
    let ps = problems(parse_scene(&mesh_scene(text.to_str().unwrap()), "t", &[]));
    assert!(
        with_key(&ps, "solid[0].file")
            .reason
            .contains("an ASCII STL starts with `solid`")
    );
    let missing = dir.join("missing.stl");
    let ps = problems(parse_scene(&mesh_scene(missing.to_str().unwrap()), "t", &[]));
    assert!(
        with_key(&ps, "solid[0].file")
            .reason
            .contains("cannot read the file")
    );
    // Only a regular file is read: a folder or a link to /dev/zero is refused by what it is
    // (reading either would not end or not make sense).
    let folder = dir.join("folder.stl");
    std::fs::create_dir_all(&folder).unwrap();
    let ps = problems(parse_scene(&mesh_scene(folder.to_str().unwrap()), "t", &[]));
    assert!(
        with_key(&ps, "solid[0].file")
            .reason
            .contains("is a directory, not a regular file")
    );
    #[cfg(unix)]
    {
        let zero = dir.join("zero.obj");
        let _ = std::fs::remove_file(&zero);
        std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
        let ps = problems(parse_scene(&mesh_scene(zero.to_str().unwrap()), "t", &[]));
        let reason = &with_key(&ps, "solid[0].file").reason;
        assert!(
            reason.contains("is a character device, not a regular file"),
            "{reason}"
        );
    }
    let other = dir.join("cube.ply");
    let ps = problems(parse_scene(&mesh_scene(other.to_str().unwrap()), "t", &[]));
    assert!(
        with_key(&ps, "solid[0].file")
            .reason
            .contains("must end in .stl or .obj")
    );

    let flat = scene_2d(0.02, "shape = \"mesh\"\nfile = \"cube.stl\"");
    let ps = problems(parse_scene(&flat, "t", &[]));
    assert!(
        with_key(&ps, "solid[0].shape")
            .reason
            .contains("meshes are 3D only")
    );
}

#[test]
fn shape_keys_are_checked() {
    let ps = problems(parse_scene(
        &scene_3d(
            0.02,
            "shape = \"sphere\"\ncentre = [0.5, 0.5, 0.5]\nradius = 0.1\nmin = [0.0, 0.0, 0.0]",
        ),
        "t",
        &[],
    ));
    assert!(
        with_key(&ps, "solid[0].min")
            .reason
            .contains("not a key of shape = \"sphere\"")
    );
    let ps = problems(parse_scene(
        &scene_3d(
            0.02,
            "shape = \"cylinder\"\ncentre = [0.5, 0.5, 0.5]\nradius = 0.1\nlength = 0.2",
        ),
        "t",
        &[],
    ));
    assert!(with_key(&ps, "solid[0].axis").reason.contains("required"));
    let ps = problems(parse_scene(
        &scene_2d(
            0.02,
            "shape = \"cylinder\"\ncentre = [0.5, 0.5]\nradius = 0.1\nlength = 0.2",
        ),
        "t",
        &[],
    ));
    assert!(
        with_key(&ps, "solid[0].length")
            .reason
            .contains("2D cylinder is a disc")
    );
    let ps = problems(parse_scene(
        &scene_3d(
            0.02,
            "shape = \"sphere\"\ncentre = [0.5, 0.5, 0.5]\nradius = 0.001",
        ),
        "t",
        &[],
    ));
    assert!(
        with_key(&ps, "solid[0]")
            .reason
            .contains("holds no lattice point")
    );
}

#[test]
fn a_relative_mesh_path_is_taken_from_the_scene_files_directory() {
    let dir = scratch_dir("relative");
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    write_stl(
        &dir.join("meshes"),
        "cube.stl",
        &box_triangles([0.1; 3], [0.3; 3]),
        false,
    );
    let scene_path = dir.join("scene.toml");
    std::fs::write(&scene_path, mesh_scene("meshes/cube.stl")).unwrap();
    let scene = load_scene(&scene_path, &[]).unwrap_or_else(|e| panic!("{e}"));
    // 0.2 m / 0.02 m = 10 spacings a side.
    assert_eq!(sph::scene::count_particles(&scene).unwrap().solid[0].1, 1000);
}

#[test]
fn the_shipped_obstacle_is_the_kleefsman_box() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/meshes/obstacle_box.stl");
    let t = read_triangles(std::path::Path::new(path)).unwrap();
    assert_eq!(t.len(), 12);
    let identity = Placement {
        scale: [1.0; 3],
        rotation: nalgebra::Rotation3::identity(),
        translation: [0.0; 3],
    };
    let m = Mesh::new(&t, &identity).unwrap();
    assert_eq!(m.min(), [0.0; 3]);
    assert_eq!(m.max(), [0.161, 0.403, 0.161]);
    // The decimal corners parse to the nearest f64; their products agree to a few ulps.
    assert!((m.volume() - 0.161 * 0.403 * 0.161).abs() < 1e-15);
    // Outward as written: no flip was needed, so the first triangle is the file's.
    assert_eq!(m.triangles()[0], t[0]);
}

#[test]
fn the_parity_scene_places_the_shipped_obstacle() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/scenes/mesh_obstacle_3d.toml");
    let scene = load_scene(std::path::Path::new(path), &[]).unwrap_or_else(|e| panic!("{e}"));
    let layout = sph::scene::generate::<3>(&scene).unwrap_or_else(|e| panic!("{e}"));
    let obstacle = &layout.solids[1];
    assert_eq!(obstacle.name, "obstacle");
    // The points of the 0.04 m lattice from the box's corner inside 0.161 x 0.403 x 0.161 m.
    assert_eq!(obstacle.position.len(), 4 * 10 * 4);
    // Nothing trimmed: the obstacle stands a spacing or more from the tank's walls.
    let counts = sph::scene::count_particles(&scene).unwrap();
    let total: usize =
        layout.fluid_position.len() + layout.solids.iter().map(|s| s.position.len()).sum::<usize>();
    assert_eq!(counts.total, total as u64);
}
