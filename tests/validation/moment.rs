//! The `moment` probe's keys: a solid that exists, the point it is taken about, an axis that
//! exists in the scene's dimension (2D: only `"z"`), no reference data; and its column name.

use sph::probe::column_name;
use sph::scene::{Averaging, ProbeKind, parse_scene};

/// A 2D tank (solid `"tank"`) with `probes` appended, in `dimension` dimensions.
fn scene_text(dimension: usize, probes: &str) -> String {
    let (lo, hi, gravity, box_hi, tank_hi) = if dimension == 2 {
        (
            "[-0.2, -0.2]",
            "[1.0, 0.8]",
            "[0.0, -9.81]",
            "[0.4, 0.3]",
            "[0.8, 0.6]",
        )
    } else {
        (
            "[-0.2, -0.2, -0.2]",
            "[1.0, 0.5, 0.8]",
            "[0.0, 0.0, -9.81]",
            "[0.4, 0.1, 0.3]",
            "[0.8, 0.1, 0.6]",
        )
    };
    let zero = if dimension == 2 {
        "[0.0, 0.0]"
    } else {
        "[0.0, 0.0, 0.0]"
    };
    format!(
        "dimension = {dimension}\neffects = [\"gravity\"]\n[domain]\nmin = {lo}\nmax = {hi}\n\
         [particles]\nspacing = 0.05\nsmoothing_ratio = 2.0\n[fluid]\nrho0 = 1000.0\nsound_speed = 20.0\n\
         gravity = {gravity}\n[[fluid_box]]\nmin = {zero}\nmax = {box_hi}\n[[solid]]\nname = \"tank\"\n\
         shape = \"container\"\nmin = {zero}\nmax = {tank_hi}\n[output]\ninterval = 0.05\n\
         [solver]\nkind = \"wcsph\"\nend_time = 1.0\n{probes}\n"
    )
}

fn problem(dimension: usize, probe: &str) -> String {
    match parse_scene(&scene_text(dimension, probe), "moment probe keys", &[]) {
        Ok(_) => String::new(),
        Err(e) => e.to_string(),
    }
}

#[test]
fn moment_probe_keys_are_checked() {
    // A valid one in each dimension: the point may lie outside the domain; 2D about z by default.
    let ok2 = "[[probe]]\nname = \"m\"\nkind = \"moment\"\nsolid = \"tank\"\npoint = [0.0, -5.0]\n";
    assert_eq!(problem(2, ok2), "", "a valid 2D moment probe");
    let scene = parse_scene(&scene_text(2, ok2), "t", &[]).expect("valid");
    let p = &scene.probes[0];
    assert_eq!((p.kind, p.axis, p.solid), (ProbeKind::Moment, 2, Some(0)));
    assert_eq!(p.point.as_deref(), Some(&[0.0, -5.0][..]));
    assert_eq!(p.averaging, Averaging::Interval, "averaged as the force");
    assert_eq!(column_name(p, 2), "m_N_m_per_m");
    let ok3 = "[[probe]]\nname = \"m\"\nkind = \"moment\"\nsolid = \"tank\"\naxis = \"y\"\npoint = [0.0, 0.0, 0.0]\n";
    assert_eq!(problem(3, ok3), "", "a valid 3D moment probe");
    let scene = parse_scene(&scene_text(3, ok3), "t", &[]).expect("valid");
    assert_eq!(scene.probes[0].axis, 1);
    assert_eq!(column_name(&scene.probes[0], 3), "m_N_m");
    for (dimension, probe, key, says) in [
        (
            2,
            "point = [0.0, 0.0]",
            "probe[0].solid",
            "required with kind = \"moment\"",
        ),
        (
            2,
            "solid = \"lid\"\npoint = [0.0, 0.0]",
            "probe[0].solid",
            "no solid named \"lid\"",
        ),
        (
            2,
            "solid = \"tank\"",
            "probe[0].point",
            "required with kind = \"moment\"",
        ),
        (3, "solid = \"tank\"\npoint = [0.0, 0.0]", "probe[0].point", "3"),
        (
            2,
            "solid = \"tank\"\npoint = [0.0, 0.0]\naxis = \"x\"",
            "probe[0].axis",
            "must be \"z\"",
        ),
        (
            3,
            "solid = \"tank\"\npoint = [0.0, 0.0, 0.0]\naxis = \"w\"",
            "probe[0].axis",
            "\"x\", \"y\" or \"z\"",
        ),
        (
            2,
            "solid = \"tank\"\npoint = [0.0, 0.0]\n[probe.reference]\nfile = \"r.csv\"",
            "probe[0].reference",
            "moment",
        ),
    ] {
        let e = problem(
            dimension,
            &format!("[[probe]]\nname = \"m\"\nkind = \"moment\"\n{probe}\n"),
        );
        assert!(
            e.contains(key) && e.contains(says),
            "{dimension}D {probe:?}: wants {key} ({says}), got: {e}"
        );
    }
}
