//! The point probes (`pressure`, `level`, `velocity`, `flow_rate`, `probe::interpolate`) on
//! states whose readings are known: a tank at rest, in 2D and 3D. (The flow rate of a developing
//! Poiseuille flow against its series is checked in `poiseuille`.)
//!
//! `point_probes_read_a_prescribed_hydrostatic_state` sets the particles of a freshly generated
//! tank to the exact hydrostatic pressure and a uniform velocity, so the readings are checked
//! without a solver's own error; `basics::hydrostatic_tank_settles_to_rho_g_h_and_stays_at_rest`
//! reads the same probes on the solver's own resting tank, through `ProbeLog` as a run records
//! them.

use sph::fields::FLUID;
use sph::probe::{ProbeSpace, measure};
use sph::run::simulation_from_scene;
use sph::scene::{Scene, parse_scene};

const G: f64 = 9.81;
const RHO0: f64 = 1000.0;

/// A tank of water `depth` [m] deep, `width` [m] along x (and y in 3D), walls of the container
/// shape, spacing `dx`; `probes` is appended as `[[probe]]` tables, `extra` as more tables.
fn tank(dimension: usize, dx: f64, width: f64, depth: f64, probes: &str, extra: &str) -> Scene {
    let v = |horizontal: f64, vertical: f64| -> String {
        if dimension == 2 {
            format!("[{horizontal}, {vertical}]")
        } else {
            format!("[{horizontal}, {horizontal}, {vertical}]")
        }
    };
    let gravity = if dimension == 2 {
        "[0.0, -9.81]"
    } else {
        "[0.0, 0.0, -9.81]"
    };
    let text = format!(
        r#"
        dimension = {dimension}
        effects = ["gravity"]
        [domain]
        min = {lo}
        max = {hi}
        [particles]
        spacing = {dx}
        smoothing_ratio = 2.0
        [fluid]
        rho0 = {RHO0}
        sound_speed = 20.0
        gravity = {gravity}
        [[fluid_box]]
        min = {box_lo}
        max = {box_hi}
        [[solid]]
        name = "tank"
        shape = "container"
        min = {box_lo}
        max = {tank_hi}
        [solver]
        kind = "wcsph"
        end_time = 1.0
        {extra}
        {probes}
        "#,
        lo = v(-0.2, -0.2),
        hi = v(width + 0.2, 2.0 * depth + 0.2),
        box_lo = v(0.0, 0.0),
        box_hi = v(width, depth),
        tank_hi = v(width, 2.0 * depth),
    );
    parse_scene(&text, "gauges test", &[]).unwrap_or_else(|e| panic!("test scene: {e}"))
}

/// A point `[x, (y,) z]` with `z` the vertical.
fn point(dimension: usize, horizontal: f64, vertical: f64) -> String {
    if dimension == 2 {
        format!("[{horizontal}, {vertical}]")
    } else {
        format!("[{horizontal}, {horizontal}, {vertical}]")
    }
}

fn check_prescribed<const D: usize>(dx: f64) {
    let (width, depth) = (0.4, 0.3);
    let heights = [0.05, 0.15, 0.25];
    let mut probes = String::new();
    for (k, z) in heights.iter().enumerate() {
        // On the left wall's face (x = 0), and in the middle of the water.
        probes += &format!(
            "[[probe]]\nname = \"wall{k}\"\nkind = \"pressure\"\npoint = {}\n",
            point(D, 0.0, *z)
        );
        probes += &format!(
            "[[probe]]\nname = \"inside{k}\"\nkind = \"pressure\"\npoint = {}\n",
            point(D, width / 2.0, *z)
        );
    }
    // A sensor's face on the left wall, 0.1 m across (z from 0.10 to 0.20, all under water;
    // in 3D centred across the wall, away from the corners).
    let centre = if D == 2 {
        format!("[0.0, {}]", heights[1])
    } else {
        format!("[0.0, {}, {}]", width / 2.0, heights[1])
    };
    probes += &format!(
        "[[probe]]\nname = \"face\"\nkind = \"pressure\"\npoint = {centre}\ndiameter = 0.1\nnormal = \"x\"\n"
    );
    probes += &format!(
        "[[probe]]\nname = \"gauge\"\nkind = \"level\"\npoint = {}\n",
        point(D, width / 2.0, 0.0)
    );
    probes += &format!(
        "[[probe]]\nname = \"current\"\nkind = \"velocity\"\naxis = \"x\"\npoint = {}\n",
        point(D, width / 2.0, depth / 2.0)
    );
    // Across the whole tank normal to x, from the floor to twice the water's depth: only the
    // water counts.
    let section = if D == 2 {
        format!("[{}]", 2.0 * depth)
    } else {
        format!("[{width}, {}]", 2.0 * depth)
    };
    probes += &format!(
        "[[probe]]\nname = \"flux\"\nkind = \"flow_rate\"\naxis = \"x\"\npoint = {}\nsize = {section}\n",
        point(D, width / 2.0, depth)
    );
    probes += &format!(
        "[[probe]]\nname = \"dry\"\nkind = \"pressure\"\npoint = {}\n",
        point(D, width / 2.0, depth + 2.0 * dx * 2.0)
    );
    // A droplet of one particle well above the gauge.
    let lift = depth + 0.1;
    let droplet = format!(
        "[[fluid_box]]\nmin = {}\nmax = {}\n",
        point(D, width / 2.0 - dx / 2.0, lift),
        point(D, width / 2.0 + dx / 2.0, lift + dx)
    );
    let scene = tank(D, dx, width, depth, &probes, &droplet);
    let mut sim = simulation_from_scene::<D>(&scene).expect("builds");
    let f = &mut sim.fields;
    let vertical = D - 1;
    let speed = 0.3;
    let mut drops = 0;
    for i in 0..f.len() {
        let z = f64::from(f.position[i][vertical]);
        f.density[i] = RHO0 as f32;
        f.pressure[i] = (RHO0 * G * (depth - z)).max(0.0) as f32;
        if f.kind[i] == FLUID {
            f.velocity[i][0] = speed;
            drops += usize::from(z > depth + 0.05);
        }
    }
    assert_eq!(drops, 1, "{D}D: one droplet particle above the water");
    let space = ProbeSpace::of(&scene);
    let read = |name: &str| {
        let probe = scene.probes.iter().find(|p| p.name == name).expect("probe");
        measure(probe, &space, &sim.fields, &[])
    };
    for (k, z) in heights.iter().enumerate() {
        let want = RHO0 * G * (depth - z);
        for name in [format!("wall{k}"), format!("inside{k}")] {
            let got = read(&name);
            // The particles' pressures are exact; the interpolation of a linear field with the
            // Shepard normalisation is exact up to the lattice's asymmetry about the point
            // (none across a vertical wall) and f32 storage: 0.5 % of rho0 g H.
            assert!(
                (got - want).abs() <= 0.005 * RHO0 * G * depth,
                "{D}D {name} at z = {z}: {got:.1} Pa, want {want:.1}"
            );
        }
    }
    // The hydrostatic pressure is linear across the face, so its mean is the centre's value;
    // each point of the face is read with the point sensors' 0.5 % error.
    let face = read("face");
    let want = RHO0 * G * (depth - heights[1]);
    assert!(
        (face - want).abs() <= 0.005 * RHO0 * G * depth,
        "{D}D face sensor {face:.1} Pa, want {want:.1}"
    );
    let level = read("gauge");
    assert!(
        (level - depth).abs() <= dx / 2.0,
        "{D}D level {level:.4} m, water {depth} m deep (the droplet is at {lift} m)"
    );
    let highest = (0..sim.fields.len())
        .filter(|&i| sim.fields.kind[i] == FLUID)
        .map(|i| f64::from(sim.fields.position[i][vertical]))
        .fold(f64::MIN, f64::max);
    assert!(
        highest > depth + 0.05,
        "the highest particle would read the droplet"
    );
    let current = read("current");
    assert!(
        (current - f64::from(speed)).abs() < 1e-5,
        "{D}D velocity {current}"
    );
    assert_eq!(read("dry"), 0.0, "{D}D: a sensor in the air reads 0");
    // The flux of the uniform stream through the wet part of the section (`width` deep in 3D):
    // within 2 %, the free surface's half-step and the lattice's kernel sum.
    let wet_area = if D == 2 { depth } else { width * depth };
    let want = f64::from(speed) * wet_area;
    let flux = read("flux");
    assert!(
        (flux / want - 1.0).abs() < 0.02,
        "{D}D flux {flux:.5}, want {want:.5}"
    );
}

#[test]
fn point_probes_read_a_prescribed_hydrostatic_state() {
    check_prescribed::<2>(0.01);
    check_prescribed::<3>(0.02);
}

/// The point probes' keys: `point` required, inside the domain, with `dimension` entries, and
/// only for them; a pressure has no axis; a flow rate has no reference data. Each error
/// names the key.
#[test]
fn point_probe_keys_are_checked() {
    let problem = |probe: &str| -> String {
        let text = format!(
            "dimension = 2\neffects = [\"gravity\"]\n[domain]\nmin = [-0.2, -0.2]\nmax = [0.6, 0.8]\n\
             [particles]\nspacing = 0.02\nsmoothing_ratio = 2.0\n[fluid]\nrho0 = 1000.0\nsound_speed = 20.0\n\
             gravity = [0.0, -9.81]\n[[fluid_box]]\nmin = [0.0, 0.0]\nmax = [0.4, 0.3]\n[[solid]]\nname = \"tank\"\n\
             shape = \"container\"\nmin = [0.0, 0.0]\nmax = [0.4, 0.6]\n[solver]\nkind = \"wcsph\"\nend_time = 1.0\n\
             [[probe]]\nname = \"p\"\n{probe}\n"
        );
        match parse_scene(&text, "probe keys", &[]) {
            Ok(_) => String::new(),
            Err(e) => e.to_string(),
        }
    };
    let ok = problem("kind = \"pressure\"\npoint = [0.0, 0.1]");
    assert_eq!(ok, "", "a valid pressure probe");
    for (probe, key, says) in [
        ("kind = \"pressure\"", "probe[0].point", "required"),
        (
            "kind = \"flow_rate\"\npoint = [0.2, 0.1]",
            "probe[0].size",
            "required",
        ),
        (
            "kind = \"flow_rate\"\npoint = [0.2, 0.1]\nsize = [0.1, 0.1]",
            "probe[0].size",
            "expected 1 entries",
        ),
        (
            "kind = \"flow_rate\"\npoint = [0.2, 0.1]\nsize = [-0.1]",
            "probe[0].size[0]",
            "",
        ),
        (
            "kind = \"level\"\npoint = [0.2, 0.1]\nsize = [0.1]",
            "probe[0].size",
            "only with",
        ),
        (
            "kind = \"level\"\npoint = [0.2]",
            "probe[0].point",
            "expected 2 entries",
        ),
        (
            "kind = \"velocity\"\npoint = [0.2, 5.0]",
            "probe[0].point[1]",
            "outside the domain",
        ),
        (
            "kind = \"pressure\"\naxis = \"y\"\npoint = [0.0, 0.1]",
            "probe[0].axis",
            "no axis",
        ),
        (
            "kind = \"front\"\npoint = [0.0, 0.1]",
            "probe[0].point",
            "only with",
        ),
        (
            "kind = \"level\"\npoint = [0.2, 0.0]\norigin = 0.1",
            "probe[0].origin",
            "only with",
        ),
        (
            "kind = \"flow_rate\"\npoint = [0.2, 0.1]\nsize = [0.1]\n[probe.reference]\nfile = \"x.csv\"",
            "probe[0].reference",
            "a flow_rate probe",
        ),
    ] {
        let e = problem(probe);
        assert!(
            e.contains(key) && e.contains(says),
            "{probe:?}: wants {key} ({says}), got: {e}"
        );
    }
}
