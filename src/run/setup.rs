//! From a validated scene to its simulation: the particles, the solver settings, the plan's
//! inputs, the floating bodies and the no-penetration guard's boxes.

use crate::boundary::keep_out::KeepOutBox;
use crate::boundary::motion::Motion;
use crate::error::Error;
use crate::geometry::Volume;
use crate::math::{Real, Vector};
use crate::scene::initial_state::{InitialState, hydrostatic_pressure};
use crate::scene::{Effect, Scene, SolidShape, SolverKind, generate};
use crate::solver::{Correction, Integrator};
use crate::solver::{SimConfig, Simulation, SurfaceTension};

/// Builds the `D`-dimensional simulation of a validated scene.
pub fn simulation_from_scene<const D: usize>(scene: &Scene) -> Result<Simulation<D>, Error> {
    let layout = generate::<D>(scene)?;
    let config = sim_config::<D>(scene);
    let solids: Vec<(String, Vec<Vector<D>>)> =
        layout.solids.into_iter().map(|s| (s.name, s.position)).collect();
    let motions = scene.solids.iter().map(|s| s.motion.clone()).collect();
    let bodies = crate::scene::floating::rigid_bodies(scene);
    let mut sim = Simulation::new(config, &layout.fluid_position, &layout.fluid_velocity, &solids)?
        .with_solid_motion(motions)?
        .with_floating_bodies(bodies)?;
    if scene.has(Effect::Multiphase) {
        sim = sim.with_phases(&crate::scene::fluid_rest_density(scene)?)?;
    }
    if scene.initial_state == InitialState::Hydrostatic {
        // A separate pass over the generated particles (`scene::initial_state`).
        let gravity = scene.gravity.as_deref().unwrap_or(&[]);
        let pressure = hydrostatic_pressure(&layout.fluid_position, gravity, scene.rho0, scene.spacing);
        sim = sim.with_initial_pressure(&pressure)?;
    }
    sim.set_keep_out(keep_out_boxes::<D>(scene, &solids))?;
    let open = scene
        .open_boundaries
        .iter()
        .map(|b| b.boundary::<D>(scene.spacing))
        .collect();
    sim = sim.with_open_boundaries(open)?;
    Ok(sim)
}

/// The solids' volumes for the no-penetration guard (`boundary::keep_out`): an unrotated `box`
/// solid is its region, a `container` the slabs of its walls (`wall_layers` spacings thick);
/// the other shapes have none.
fn keep_out_boxes<const D: usize>(scene: &Scene, solids: &[(String, Vec<Vector<D>>)]) -> Vec<KeepOutBox<D>> {
    let vector = |v: &[f64]| Vector::<D>::from_iterator(v.iter().map(|&c| c as Real));
    let thickness = (scene.wall_layers() as f64 * scene.spacing) as Real;
    let mut boxes = Vec::new();
    for s in &scene.solids {
        let Some(index) = solids.iter().position(|(name, _)| *name == s.name) else {
            continue;
        };
        if matches!(s.motion, Some(Motion::Flap(_))) || s.floating.is_some() {
            // A turning solid leaves its axis-aligned box: the particle boundary alone holds it.
            continue;
        }
        let (min, max) = (vector(&s.region.min), vector(&s.region.max));
        match (s.shape, &s.volume) {
            (SolidShape::Box, Volume::Aabb { .. }) => boxes.push(KeepOutBox::fixed(min, max, index as u32)),
            // The guard's volumes are axis-aligned boxes: the other shapes rely on the particle
            // boundary alone (their bounding box would push fluid out of space they leave free).
            (SolidShape::Box | SolidShape::Cylinder | SolidShape::Sphere | SolidShape::Mesh, _) => {}
            (SolidShape::Container, _) => boxes.extend(KeepOutBox::container(
                min,
                max,
                thickness,
                s.open_top,
                index as u32,
            )),
        }
    }
    boxes
}

/// The solver settings of a validated scene (`scene.dimension` must be `D`).
pub fn sim_config<const D: usize>(scene: &Scene) -> SimConfig<D> {
    let vector = |v: &[f64]| Vector::<D>::from_iterator(v.iter().map(|&c| c as f32));
    SimConfig::<D> {
        spacing: scene.spacing,
        h: scene.smoothing_length,
        rho0: scene.rho0,
        sound_speed: scene.sound_speed,
        pair_terms: scene.pair_terms,
        gravity: if scene.has(Effect::Gravity) {
            scene.gravity.as_deref().map(vector)
        } else {
            None
        },
        gravity_ramp: scene.gravity_ramp,
        angular_velocity: if scene.has(Effect::RotatingFrame) {
            scene.angular_velocity
        } else {
            None
        },
        rotation_centre: vector(&scene.rotation_centre),
        surface_tension: if scene.has(Effect::SurfaceTension) {
            scene.surface_tension.map(|sigma| SurfaceTension {
                sigma,
                model: scene.surface_tension_model,
            })
        } else {
            None
        },
        artificial_viscosity_wall_factor: scene.artificial_viscosity_wall_factor,
        density_diffusion: scene.density_diffusion,
        periodic: scene.periodic,
        dt: scene.dt,
        cfl: scene.cfl,
        domain_min: vector(&scene.domain.min),
        domain_max: vector(&scene.domain.max),
        integrator: integrator(scene),
        correction: correction(scene),
        on_escape: scene.solver.on_escape,
        damping_zone: scene.damping_zone.as_ref().map(|z| z.zone()),
        gradient_moment: scene.solver.gradient_moment,
    }
}

/// What the stage plan of a validated scene depends on (`solver::plan`): the plan inputs of its
/// settings ([`sim_config`]), so a scene's plan is the one its simulation runs.
pub fn plan_inputs(scene: &Scene) -> crate::solver::plan::PlanInputs {
    let solids = !scene.solids.is_empty();
    // A floating solid moves too: its particles are placed from its state every stage.
    let moving = scene
        .solids
        .iter()
        .any(|s| s.motion.is_some() || s.floating.is_some());
    match scene.dimension {
        2 => sim_config::<2>(scene).plan_inputs(solids, moving),
        _ => sim_config::<3>(scene).plan_inputs(solids, moving),
    }
}

/// The scene's integrator.
pub fn integrator(scene: &Scene) -> Integrator {
    scene.solver.integrator
}

/// The scene's position-correction settings; `None` for `wcsph`.
pub fn correction(scene: &Scene) -> Option<Correction> {
    let s = &scene.solver;
    match s.kind {
        SolverKind::Wcsph => None,
        SolverKind::Corrected => Some(Correction {
            delta: s.delta,
            max_iterations: s.max_iterations,
            strict: s.strict,
            relaxation: s.relaxation,
            warm_start: s.warm_start,
        }),
    }
}
