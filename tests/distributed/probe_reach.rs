//! The particles a probe reads (`probe::reach`), which a split run gathers on rank 0 instead of
//! every particle: the readings from them alone are the readings from all, bit for bit.

use sph::probe::reach::particles_read;
use sph::probe::{ProbeSpace, measure_loads};
use sph::run::simulation_from_scene;

/// Every probe kind that reads particles, appended to a scene: a velocity, a flow rate, a
/// pressure inside the fluid and a front (`D` = 2).
const MORE_2D: &str = r#"
[[probe]]
name = "flux"
kind = "flow_rate"
point = [0.4, 0.05]
axis = "x"
size = [0.1]

[[probe]]
name = "u_low"
kind = "velocity"
axis = "y"
point = [0.2, 0.1]

[[probe]]
name = "p_inside"
kind = "pressure"
point = [0.1, 0.05]

[[probe]]
name = "front"
kind = "front"
axis = "x"
"#;

/// `scene` (with `more` appended and `sets`) stepped to `end` [s]: every probe's reading from
/// the particles `particles_read` picks equals its reading from all of them, bit for bit; the
/// pick is under `fraction` of the particles and at least `finite` readings are nonzero.
fn readings_agree<const D: usize>(
    scene: &str,
    more: &str,
    sets: &[&str],
    end: f64,
    fraction: f64,
    finite: usize,
) {
    let path = format!("{}/{scene}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("shipped scene") + more;
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    // Parsed in the file's folder, so that its meshes are found beside it.
    let dir = std::path::Path::new(&path).parent().expect("a folder");
    let scene = sph::scene::parse_scene_in(&text, &path, &sets, dir).expect("valid");
    let mut sim = simulation_from_scene::<D>(&scene).expect("builds");
    while sim.clock().time < end {
        sim.step(end).expect("stable step");
    }
    sim.sync_fields().expect("fields");
    let space = ProbeSpace::of(&scene);
    let read = particles_read(&scene.probes, &space, &sim.fields);
    assert!(
        (read.len() as f64) < fraction * sim.fields.len() as f64,
        "{} of {} particles read",
        read.len(),
        sim.fields.len()
    );
    let mut some = sim.fields.clone();
    some.keep(&read);
    let mut nonzero = 0;
    for probe in &scene.probes {
        let (forces, moments) = (sim.solid_forces(), sim.solid_moments());
        let all = measure_loads(probe, &space, &sim.fields, forces, moments);
        let picked = measure_loads(probe, &space, &some, forces, moments);
        eprintln!(
            "{}: {all} from all, {picked} from {} particles",
            probe.name,
            read.len()
        );
        assert_eq!(
            all.to_bits(),
            picked.to_bits(),
            "{}: {all} against {picked}",
            probe.name
        );
        nonzero += usize::from(all.is_finite() && all != 0.0);
    }
    assert!(nonzero >= finite, "{nonzero} nonzero readings");
}

/// The 2D dam break against a wall with its sensors (point and face) and gauges, and a flow
/// rate, a velocity, a pressure in the fluid and a front, at t = 0.7 s (the surge on the wall).
#[test]
fn the_particles_a_2d_probe_reads_give_its_reading() {
    let sets = ["particles.spacing=0.01"];
    readings_agree::<2>("scenes/dam_break_wall_2d.toml", MORE_2D, &sets, 0.7, 0.2, 12);
}

/// More probes in the 3D column (`D` = 3): a velocity, a flow rate across it, a pressure.
const MORE_3D: &str = r#"
[[probe]]
name = "u_column"
kind = "velocity"
axis = "x"
point = [2.3, 0.5, 0.2]

[[probe]]
name = "flux_column"
kind = "flow_rate"
point = [1.8, 0.5, 0.1]
axis = "x"
size = [0.6, 0.2]

[[probe]]
name = "p_column"
kind = "pressure"
point = [2.6, 0.5, 0.1]
"#;

/// The 3D dam break on an obstacle from an STL mesh, with its pressure sensors, gauges, force
/// and moment, and a velocity, a flow rate and a pressure in the fluid, at t = 0.15 s.
#[test]
fn the_particles_a_3d_probe_reads_give_its_reading() {
    let sets = ["particles.spacing=0.04"];
    readings_agree::<3>("scenes/dam_break_obstacle_3d.toml", MORE_3D, &sets, 0.15, 0.2, 4);
}
