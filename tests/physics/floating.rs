//! Floating bodies (`solver::floating`): `scenes/floating_box_2d.toml`, a box B = 0.2 m wide
//! and H = 0.1 m tall of density ρ_b = 500 kg/m³ released 0.3 × its equilibrium draft too high
//! in a tank of still water 0.6 m wide, with either solver (`wcsph` with density diffusion as
//! shipped; `corrected` without it, [`scene_text`]).
//!
//! - Draft: Archimedes, `T = ρ_b / ρ0 · H` = 0.05 m, measured from the still-water level the
//!   fluid's area gives (`(A_fluid + B T) / W`, the tank's width `W`) to the box's bottom.
//! - Heave period: `2π sqrt((M + m_a) / (ρ0 g B))` with `M = ρ_b B H` and the 2D heave added
//!   mass of a floating rectangle `m_a = C ρ0 π B² / 8`, `C` = 0.6 for `B/T = 4` at
//!   `ω sqrt(B / 2g) ≈ 1` (Vugts 1968, "The hydrodynamic coefficients for swaying, heaving and
//!   rolling cylinders in a free surface", Int. Shipbuilding Progress 15, heave added-mass
//!   curves for rectangular sections; read off the figure, about ±0.1).

use sph::fields::FLUID;
use sph::run::simulation_from_scene;
use sph::scene::load_scene;
use std::path::Path;

/// The box: width, height [m], density [kg/m³]; the water's density [kg/m³], gravity [m/s²].
const B: f64 = 0.2;
const H: f64 = 0.1;
const RHO_B: f64 = 500.0;
const RHO: f64 = 1000.0;
const G: f64 = 9.81;
/// The tank's inner width [m].
const W: f64 = 0.6;
/// Vugts' (1968) heave added-mass coefficient for B/T = 4 near the natural frequency (module
/// doc).
const C_VUGTS: f64 = 0.6;

/// `scenes/floating_box_2d.toml` for solver `kind`: the corrected solver sets density by
/// positions, so its scene has no density diffusion.
fn scene_text(kind: &str) -> String {
    let text = std::fs::read_to_string("scenes/floating_box_2d.toml").expect("scene");
    match kind {
        "corrected" => crate::common::scene::edit(
            &crate::common::scene::edit(
                &text,
                r#"effects = ["gravity", "artificial_viscosity", "density_diffusion"]"#,
                r#"effects = ["gravity", "artificial_viscosity"]"#,
            ),
            "density_diffusion = 0.1",
            "",
        ),
        _ => text,
    }
}

#[test]
fn a_floating_box_settles_at_the_archimedes_draft_with_the_heave_period_of_its_added_mass_wcsph() {
    settles_at_the_archimedes_draft("wcsph");
}

/// The corrected solver: the box takes part in the correction as a moving wall, and the
/// correction's push on it kicks it (`solver::floating`, module doc, 3), so it neither sinks
/// into the fluid nor bounces. Measured (AMD EPYC 2-core, commit 781e462): draft 1.0 % deep,
/// period 0.654 s (4.6 % long).
#[test]
fn a_floating_box_settles_at_the_archimedes_draft_with_the_heave_period_of_its_added_mass_corrected() {
    settles_at_the_archimedes_draft("corrected");
}

/// Draft and heave period of the shipped box with solver `kind` (module doc).
fn settles_at_the_archimedes_draft(kind: &str) {
    let sets = [format!("solver.kind={kind}")];
    let sets: Vec<&str> = sets.iter().map(String::as_str).collect();
    let scene = crate::common::scene::parse_set(&scene_text(kind), &sets).expect("scene");
    let dx = scene.spacing;
    let mut sim = simulation_from_scene::<2>(&scene).expect("builds");
    let end = 3.0;
    // (t, bottom of the box) every step.
    let mut trace = Vec::new();
    while sim.clock().time < end {
        sim.step(end).expect("stable step");
        let b = sim.floating_bodies()[1].as_ref().expect("the box floats");
        trace.push((sim.clock().time, b.state.centre.y - 0.5 * H));
    }
    let f = &sim.fields;
    let fluid = (0..f.len()).filter(|&i| f.kind[i] == FLUID).count();
    let a_fluid = fluid as f64 * dx * dx;
    let draft_theory = RHO_B / RHO * H;
    let level = (a_fluid + B * draft_theory) / W;
    // The settled draft: the mean over the last second (about 1.6 periods, whose residual
    // swing averages out to a fraction of it).
    let late: Vec<f64> = trace
        .iter()
        .filter(|(t, _)| *t > end - 1.0)
        .map(|p| p.1)
        .collect();
    let bottom = late.iter().sum::<f64>() / late.len() as f64;
    let draft = level - bottom;
    println!("{kind}: draft {draft:.5} m (Archimedes {draft_theory:.5}), level {level:.5}");
    // 2 %: the issue's tolerance (1 mm, a tenth of the spacing).
    assert!(
        (draft / draft_theory - 1.0).abs() < 0.02,
        "draft {draft} m against {draft_theory} m"
    );
    let m = RHO_B * B * H;
    let added = C_VUGTS * RHO * std::f64::consts::PI * B * B / 8.0;
    let expected = 2.0 * std::f64::consts::PI * ((m + added) / (RHO * G * B)).sqrt();
    // The heave period from the up-crossings of the bottom through its settled mean; a
    // crossing within half a period of the last is the decayed swing's noise recrossing.
    let mut crossings: Vec<f64> = Vec::new();
    for w in trace.windows(2) {
        if w[0].1 < bottom && w[1].1 >= bottom {
            let t = w[0].0 + (w[1].0 - w[0].0) * (bottom - w[0].1) / (w[1].1 - w[0].1);
            if crossings.last().is_none_or(|&last| t - last > 0.5 * expected) {
                crossings.push(t);
            }
        }
    }
    assert!(crossings.len() >= 3, "too few crossings {crossings:?}");
    let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    println!("heave period {period:.4} s (theory {expected:.4} s), crossings {crossings:?}");
    // 10 %: the issue's tolerance; it covers the ±0.1 read-off of C (±5 % in the period).
    assert!(
        (period / expected - 1.0).abs() < 0.10,
        "period {period} s against {expected} s"
    );
    assert!(!fluid_inside_the_box(&sim, dx), "a fluid particle inside the box");
}

/// Whether a fluid particle of `sim` lies deeper than half a spacing `dx` [m] inside the
/// faces of the box (solid 1, B × H).
fn fluid_inside_the_box(sim: &sph::solver::Simulation<2>, dx: f64) -> bool {
    let f = &sim.fields;
    let body = sim.floating_bodies()[1].as_ref().expect("the box floats");
    let (c, q) = (body.state.centre, body.state.orientation);
    (0..f.len()).filter(|&i| f.kind[i] == FLUID).any(|i| {
        let p = nalgebra::Vector3::new(f64::from(f.position[i][0]), f64::from(f.position[i][1]), 0.0);
        let r = q.inverse() * (p - c);
        r.x.abs() < 0.5 * B - 0.5 * dx && r.y.abs() < 0.5 * H - 0.5 * dx
    })
}

/// Bad `floating` input is an error at the key: with a `motion`, with both `density` and
/// `mass`, an unknown degree of freedom, a contact out of range or of an unknown kind, and a
/// shape too thin to hold a mass.
#[test]
fn bad_floating_input_names_the_key() {
    let cases = [
        (
            "solid.1.motion={ amplitude = [0.01, 0.0], period = 1.0 }",
            "solid[1].floating",
        ),
        ("solid.1.floating.mass=10.0", "solid[1].floating.mass"),
        ("solid.1.floating.fixed=[\"rx\"]", "solid[1].floating.fixed[0]"),
        (
            "solid.1.floating.contact={ restitution = 0.0 }",
            "solid[1].floating.contact.restitution",
        ),
        (
            "solid.1.floating.contact={ kind = \"none\", friction = 0.2 }",
            "solid[1].floating.contact.kind",
        ),
        (
            "solid.1.floating.contact={ kind = \"sticky\" }",
            "solid[1].floating.contact.kind",
        ),
        (
            "solid.1.floating.contact={ friction = -1.0 }",
            "solid[1].floating.contact.friction",
        ),
        // 1 mm thick: no point of the quarter-spacing lattice its mass is sampled on.
        ("solid.1.max=[0.4, 0.266]", "too thin to float"),
        // Mean densities outside 1e-3..1e3 rho0 (a body of 1e-6 kg/m³ used to hang the run).
        ("solid.1.floating.density=1e-6", "solid[1].floating.density"),
        ("solid.1.floating={ mass = 1e-30 }", "solid[1].floating.mass"),
        ("solid.1.floating={ mass = 1e30 }", "solid[1].floating.mass"),
        (
            "solid.1.floating.fixed=[\"x\", \"x\"]",
            "solid[1].floating.fixed[1]",
        ),
        (
            "solid.1.floating.centre_of_mass=[3.0, 0.3]",
            "solid[1].floating.centre_of_mass",
        ),
        (
            "solid.1.floating.moorings=[{ anchor = [0.3, 0.0], fairlead = [0.3, 0.1], stiffness = 50.0, rest_length = 0.1 }]",
            "solid[1].floating.moorings[0].fairlead",
        ),
        // Stiffer than the body's wall contact at this spacing: 1e10 N/m used to hang the run.
        (
            "solid.1.floating.moorings=[{ anchor = [0.3, 0.0], fairlead = [0.3, 0.265], stiffness = 1e10, rest_length = 0.1 }]",
            "solid[1].floating.moorings",
        ),
    ];
    for (set, key) in cases {
        let err = load_scene(Path::new("scenes/floating_box_2d.toml"), &[set.to_string()])
            .expect_err(set)
            .to_string();
        assert!(err.contains(key), "{set}: {err}");
    }
    // The same line at a mooring's stiffness, and the bounds' ends, are accepted.
    for set in [
        "solid.1.floating.moorings=[{ anchor = [0.3, 0.0], fairlead = [0.3, 0.265], stiffness = 50.0, rest_length = 0.1 }]",
        "solid.1.floating.density=1.0",
        "solid.1.floating.density=1e6",
    ] {
        load_scene(Path::new("scenes/floating_box_2d.toml"), &[set.to_string()]).expect(set);
    }
}

/// The box of `scenes/floating_box_2d.toml` at 1.5 times the water's density sinks and comes
/// to rest on the tank's floor (`boundary::contact`), with solver `kind`: its bottom face on the
/// floor's face (y = 0), level, still, with no fluid inside it.
fn a_heavy_box_sinks_to_the_floor(kind: &str) {
    let sets = ["solid.1.floating.density=1500.0", &format!("solver.kind={kind}")];
    let scene = crate::common::scene::parse_set(&scene_text(kind), &sets).expect("scene");
    let dx = scene.spacing;
    let mut sim = simulation_from_scene::<2>(&scene).expect("builds");
    // It lands at about 1.4 s and is still from 1.6 s (both solvers).
    let end = 2.2;
    // (t, bottom of the box, speed, angle, contact pairs, centre) every step.
    let mut trace = Vec::new();
    while sim.clock().time < end {
        sim.step(end).expect("stable step");
        let b = sim.floating_bodies()[1].as_ref().expect("the box floats");
        let q = b.state.orientation.quaternion();
        trace.push((
            sim.clock().time,
            b.state.centre.y - 0.5 * H,
            b.state.velocity.norm(),
            2.0 * q.k.atan2(q.w),
            b.contact_load.pairs,
            b.state.centre,
        ));
    }
    for p in trace.iter().step_by(trace.len() / 15) {
        println!(
            "t {:.3} bottom {:+.5} speed {:.4} angle {:+.5} pairs {}",
            p.0, p.1, p.2, p.3, p.4
        );
    }
    let late: Vec<_> = trace.iter().filter(|p| p.0 > end - 0.5).collect();
    let lowest = late.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
    let highest = late.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    let rms_speed = (late.iter().map(|p| p.2 * p.2).sum::<f64>() / late.len() as f64).sqrt();
    let (first, last) = (late[0], late[late.len() - 1]);
    let drift = (last.5 - first.5).norm() / (last.0 - first.0);
    let tilt = late.iter().map(|p| p.3.abs()).fold(0.0, f64::max);
    println!(
        "{kind}, last 0.5 s: bottom {lowest:.5}..{highest:.5} m, drift {drift:.5} m/s, rms speed {rms_speed:.5} m/s, tilt ≤ {tilt:.5} rad"
    );
    // On the floor. The floor's particle rows sit half a spacing off the box's, so a pair
    // touches at a face overlap of (1 − √3/2) dx = 0.13 dx, and the springs give under the
    // box's weight and the water above it (no water below) by about 0.08 dx more: a box
    // resting on the floor has its bottom 0.2 dx below the face. A box on a trapped layer of
    // fluid would sit a spacing up; one more than 0.3 dx in means too soft a contact.
    assert!(
        lowest > -0.3 * dx && highest < 0.25 * dx,
        "bottom {lowest}..{highest} m, the floor at 0"
    );
    // At rest: over the last half second the bottom keeps within a tenth of a spacing, and the
    // centre drifts less than 2 mm/s (a fifth of a spacing over the half second; it sank at
    // 0.4 m/s). What is left is a jitter about the rest, driven by the particle pressures on
    // the box (RMS speed printed: 1–2 cm/s with wcsph, whose pressures are noisier, 0.5 cm/s
    // corrected).
    assert!(highest - lowest < 0.1 * dx, "bottom moved {} m", highest - lowest);
    assert!(drift < 0.002, "drifting at {drift} m/s");
    // Level: 0.01 rad lifts a corner 1 mm, a tenth of a spacing.
    assert!(tilt < 0.01, "tilted {tilt} rad");
    assert!(late.iter().all(|p| p.4 > 0), "lost contact with the floor");
    assert!(!fluid_inside_the_box(&sim, dx), "a fluid particle inside the box");
}

#[test]
fn a_box_heavier_than_water_sinks_and_comes_to_rest_on_the_floor_wcsph() {
    a_heavy_box_sinks_to_the_floor("wcsph");
}

#[test]
fn a_box_heavier_than_water_sinks_and_comes_to_rest_on_the_floor_corrected() {
    a_heavy_box_sinks_to_the_floor("corrected");
}
