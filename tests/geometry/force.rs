//! The force on a mesh solid is reported as any named solid's: a finely faceted STL cylinder in
//! a uniform stream receives the force of the `cylinder` primitive.

use sph::run::AnySimulation;
use sph::scene::{Scene, parse_scene};

use crate::common::scratch_dir;
use crate::shapes::{cylinder_y, write_stl};

/// Relative difference allowed between the two mean drag forces. The 256-gon cuts inside the
/// circle by at most r (1 − cos(π/256)) = 7.5e-5 r, far below a spacing, so the two solids
/// hold the same lattice points unless one lies in that sliver; a particle more or less in a
/// wall of hundreds changes the force by well under 1 %. 2 % is issue 26's requirement.
const FORCE: f64 = 0.02;

/// Steps run: enough for the stream's pressure to build on the cylinder's front (the first
/// steps start from a uniform density), few enough to stay cheap in a test.
const STEPS: usize = 30;

/// A box of water 0.4 x 0.2 x 0.2 m moving at 1 m/s along x, no gravity, around a cylinder of
/// radius 0.05 m across it along y, described by `cylinder` (a `[[solid]]` body's shape keys).
fn stream(cylinder: &str) -> String {
    format!(
        r#"
dimension = 3
[domain]
min = [-0.2, -0.1, -0.1]
max = [0.8, 0.3, 0.3]
[particles]
spacing = 0.02
smoothing_ratio = 2.0
[fluid]
rho0 = 1000.0
sound_speed = 20.0
[[fluid_box]]
min = [0.0, 0.0, 0.0]
max = [0.4, 0.2, 0.2]
velocity = [1.0, 0.0, 0.0]
[[solid]]
name = "cylinder"
{cylinder}
[solver]
kind = "wcsph"
end_time = 1.0
"#
    )
}

/// The mean force along x on the scene's solid over [`STEPS`] steps \[N\], and its particles.
fn mean_drag(scene: &Scene) -> (f64, usize) {
    let AnySimulation::D3(mut sim) = AnySimulation::from_scene(scene).unwrap_or_else(|e| panic!("{e}"))
    else {
        panic!("a 3D scene");
    };
    let solid = sim.fields.len()
        - sim
            .fields
            .kind
            .iter()
            .filter(|k| **k == sph::fields::FLUID)
            .count();
    let mut sum = 0.0;
    for _ in 0..STEPS {
        sim.step(f64::INFINITY).expect("step");
        sum += sim.solid_forces()[0][0];
    }
    (sum / STEPS as f64, solid)
}

#[test]
fn stl_cylinder_in_a_stream_feels_the_primitives_force() {
    let dir = scratch_dir("stream");
    let file = write_stl(&dir, "cylinder.stl", &cylinder_y(0.05, 0.2, 256), false);
    let primitive = parse_scene(
        &stream("shape = \"cylinder\"\ncentre = [0.2, 0.1, 0.1]\nradius = 0.05\nlength = 0.2\naxis = \"y\""),
        "t",
        &[],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let mesh = parse_scene(
        &stream(&format!(
            "shape = \"mesh\"\nfile = \"{file}\"\ntranslation = [0.2, 0.1, 0.1]"
        )),
        "t",
        &[],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let (f_primitive, n_primitive) = mean_drag(&primitive);
    let (f_mesh, n_mesh) = mean_drag(&mesh);
    eprintln!(
        "mean drag over {STEPS} steps: primitive {f_primitive:.4e} N ({n_primitive} particles), \
         mesh {f_mesh:.4e} N ({n_mesh} particles)"
    );
    // The stream pushes the cylinder downstream.
    assert!(f_primitive > 0.0, "drag {f_primitive} N");
    let rel = (f_mesh - f_primitive).abs() / f_primitive.abs();
    assert!(
        rel <= FORCE,
        "mesh {f_mesh} N vs primitive {f_primitive} N ({rel:.2e})"
    );
}
