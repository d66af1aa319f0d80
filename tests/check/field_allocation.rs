//! "A field that no stage needs is not allocated" (issue 7): on every shipped scene, after one
//! step, a particle field has storage exactly when a stage or sub-stage of the scene's plan reads
//! or writes it (`solver::plan::needed_fields`), so a scene pays in memory only for its effects.
//!
//! Scenes run at twice their spacing (a coarser copy of the same set-up; the shipped spacing where
//! the coarse one is refused) with a fixed step of 1e-5 s, short enough for every solver and scene.

use crate::common::shipped_scenes;
use sph::fields::Field;
use sph::run::{plan_inputs, simulation_from_scene};
use sph::scene::{Effect, Scene, load_scene, parse_scene};
use sph::solver::plan::{needed_fields, plan};
use std::path::Path;

/// The scene at twice its spacing and a 1e-5 s step, or at its own spacing if that is refused;
/// `None` for a scene the validator refuses as shipped.
fn coarse(path: &Path) -> Option<Scene> {
    let shipped = load_scene(path, &[]).ok()?;
    let dt = "solver.dt=1e-5".to_string();
    let spacing = format!("particles.spacing={}", 2.0 * shipped.spacing);
    load_scene(path, &[spacing, dt.clone()])
        .or_else(|_| load_scene(path, &[dt]))
        .ok()
}

/// After one step of `scene`: the fields allocated against the plan's needs, as a list of
/// mismatches (`"name: allocated but not needed"` or the reverse), and the needed fields.
fn mismatches<const D: usize>(scene: &Scene) -> (Vec<String>, Vec<Field>) {
    let mut sim = simulation_from_scene::<D>(scene).expect("a valid scene builds");
    // `sph plan` builds its plan from the scene alone (`run::plan_inputs`): it must be the one
    // the simulation walks (moving solids are placed by the first step, so compared after it).
    let printed_multiphase = scene.has(Effect::Multiphase);
    sim.step(scene.end_time).expect("one short step succeeds");
    let solids = sim.fields.kind.iter().any(|&k| k != sph::fields::FLUID);
    assert_eq!(
        plan(plan_inputs(scene)).as_slice(),
        sim.plan(),
        "{:?}: sph plan prints another plan than the run walks",
        scene.name
    );
    assert_eq!(printed_multiphase, sim.multiphase(), "{:?}", scene.name);
    let needed = needed_fields(sim.plan(), solids, sim.multiphase());
    let wrong = Field::ALL
        .into_iter()
        .filter_map(|f| match (sim.fields.is_allocated(f), needed.contains(&f)) {
            (true, false) => Some(format!("{}: allocated but no stage needs it", f.name())),
            (false, true) => Some(format!("{}: needed but not allocated", f.name())),
            _ => None,
        })
        .collect();
    (wrong, needed)
}

#[test]
fn every_shipped_scene_allocates_exactly_the_fields_its_plan_needs() {
    let mut checked = 0;
    let mut optional_seen = Vec::new();
    let mut failures = Vec::new();
    for path in shipped_scenes() {
        let scene = coarse(&path).unwrap_or_else(|| panic!("{}: refused as shipped", path.display()));
        let (wrong, needed) = if scene.dimension == 2 {
            mismatches::<2>(&scene)
        } else {
            mismatches::<3>(&scene)
        };
        if !wrong.is_empty() {
            failures.push(format!("{}: {}", path.display(), wrong.join("; ")));
        }
        optional_seen.extend(needed.into_iter().filter(|f| !BASE.contains(f)));
        checked += 1;
    }
    // No shipped scene integrates the continuity equation with SSP-RK3, whose step-start
    // density only that plan needs: the resting tank with the effect, under SSP-RK3.
    let tank = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/hydrostatic_2d.toml");
    let sets = [
        r#"effects=["gravity", "viscosity", "density_diffusion"]"#,
        "fluid.density_diffusion=0.1",
        "solver.integrator=rk3",
        "solver.dt=1e-5",
    ]
    .map(String::from);
    let scene = load_scene(&tank, &sets).expect("the tank with the effect");
    let (wrong, needed) = mismatches::<2>(&scene);
    assert!(wrong.is_empty(), "{}: {}", tank.display(), wrong.join("; "));
    optional_seen.extend(needed.into_iter().filter(|f| !BASE.contains(f)));
    println!("checked {checked} scenes");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(checked >= 20, "checked only {checked} scenes");
    // The check saw every optional field needed somewhere (and allocated there).
    for f in Field::ALL.into_iter().filter(|f| !BASE.contains(f)) {
        assert!(
            optional_seen.contains(&f),
            "no shipped scene needs {}: the check never saw it allocated",
            f.name()
        );
    }
}

/// The fields every plan needs.
const BASE: [Field; 8] = [
    Field::Position,
    Field::Velocity,
    Field::Acceleration,
    Field::Density,
    Field::Pressure,
    Field::Mass,
    Field::Kind,
    Field::Id,
];

/// The base fields are needed by the smallest plan (a falling block of fluid, no solids,
/// symplectic Euler), and the optional ones are not: the list the test above compares against
/// is not simply everything.
#[test]
fn a_fluid_only_symplectic_plan_needs_only_the_base_fields() {
    let text = r#"
        name = "falling_block"
        dimension = 2
        effects = ["gravity", "viscosity"]
        [domain]
        min = [-0.1, -1.0]
        max = [0.2, 0.2]
        [particles]
        spacing = 0.01
        smoothing_ratio = 2.0
        [fluid]
        rho0 = 1000.0
        sound_speed = 20.0
        viscosity = 1.0e-3
        gravity = [0.0, -9.81]
        [[fluid_box]]
        min = [0.0, 0.0]
        max = [0.1, 0.1]
        [solver]
        kind = "wcsph"
        end_time = 0.01
    "#;
    let scene = parse_scene(text, "falling_block", &[]).expect("valid");
    let mut sim = simulation_from_scene::<2>(&scene).expect("builds");
    let needed = needed_fields(sim.plan(), false, false);
    assert_eq!(needed, BASE.to_vec(), "plan {:?}", sim.plan());
    sim.step(scene.end_time).expect("a step");
    for f in Field::ALL {
        assert_eq!(sim.fields.is_allocated(f), BASE.contains(&f), "{}", f.name());
    }
}
