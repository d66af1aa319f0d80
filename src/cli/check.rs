//! `sph check SCENE`: validate and report.

use crate::scene::{
    GenerationReport, ParticleCounts, Scene, count_particles, frame_bytes_per_particle, generate::describe,
    generate_reported, run_bytes, scene_particle_bytes, skipped_references, solver_particle_bytes,
};
use anyhow::Context;
use std::fmt::Write;
use std::path::Path;

/// Largest scene (particles before trimming) whose particles `check` generates to report the
/// trimming exactly; a larger one is reported by its lattice counts (about 100 bytes a particle
/// while generating, so 400 MB at this cap).
const GENERATE_CAP: u64 = 4_000_000;

/// The particles `generate` keeps and its report, if the scene is small enough to generate.
fn generated(
    scene: &Scene,
    lattice: &ParticleCounts,
) -> anyhow::Result<Option<(ParticleCounts, GenerationReport)>> {
    if lattice.total > GENERATE_CAP {
        return Ok(None);
    }
    let (fluid, solids, report) = match scene.dimension {
        2 => {
            let (l, r) = generate_reported::<2>(scene)?;
            (
                l.fluid_position.len(),
                l.solids
                    .iter()
                    .map(|s| (s.name.clone(), s.position.len()))
                    .collect::<Vec<_>>(),
                r,
            )
        }
        _ => {
            let (l, r) = generate_reported::<3>(scene)?;
            (
                l.fluid_position.len(),
                l.solids
                    .iter()
                    .map(|s| (s.name.clone(), s.position.len()))
                    .collect(),
                r,
            )
        }
    };
    let solid: Vec<(String, u64)> = solids.into_iter().map(|(n, c)| (n, c as u64)).collect();
    let total = fluid as u64 + solid.iter().map(|(_, c)| c).sum::<u64>();
    Ok(Some((
        ParticleCounts {
            fluid: fluid as u64,
            solid,
            total,
        },
        report,
    )))
}

/// What a solid is, in words: `container`, `box`, or the shape with its size
/// (`cylinder centre [..] axis [..] radius r length l`).
fn shape_words(s: &crate::scene::Solid, dim: usize) -> String {
    use crate::geometry::Volume;
    use crate::scene::SolidShape;
    match (s.shape, &s.volume) {
        (SolidShape::Container, _) | (_, Volume::Aabb { .. }) => s.shape.name().to_string(),
        (_, volume) => volume.describe(dim),
    }
}

/// Writes what generation did beyond whole-spacing boxes (the lines start with `lattice:`).
fn write_generation(out: &mut String, scene: &Scene, report: &GenerationReport) -> std::fmt::Result {
    for f in &report.fitted {
        let axis = crate::scene::count::axis_name(f.axis);
        writeln!(
            out,
            "  lattice: fluid_box[{}] is {:.3} spacings along {axis}, not a whole number: {} layer{}, {}",
            f.fluid_box,
            f.spacings,
            f.layers,
            if f.layers == 1 { "" } else { "s" },
            if f.spacings < 1.0 {
                "reaching past its max face (thinner than a spacing)"
            } else {
                "at least half a spacing inside each face"
            }
        )?;
    }
    for t in &report.trimmed {
        writeln!(
            out,
            "  lattice: trimmed {} of {} particles of {} closer than {} spacings to {}",
            t.count,
            t.of,
            describe(scene, t.removed_from),
            crate::scene::MIN_GAP,
            describe(scene, t.next_to)
        )?;
    }
    Ok(())
}

/// Validates the scene and prints counts, memory and plan ([`report`]).
pub fn check(path: &Path, sets: &[String], reference_dir: Option<&Path>) -> anyhow::Result<()> {
    let scene = super::load_located(path, sets, reference_dir, false)
        .with_context(|| format!("checking scene {}", path.display()))?;
    print!("{}", report(&scene, path)?);
    Ok(())
}

/// What `sph check` prints for the loaded `scene` read from `path`: counts, memory and plan.
/// Reads every reference file the scene's probes name that is available (a malformed one is an
/// error, as `sph run` would refuse it); one that is not is reported as `sph run` reports it.
pub fn report(scene: &Scene, path: &Path) -> anyhow::Result<String> {
    let mut text = String::new();
    let out = &mut text;
    crate::probe::check_references(scene).with_context(|| format!("checking scene {}", path.display()))?;
    let lattice = count_particles(scene)?;
    let generated =
        generated(scene, &lattice).with_context(|| format!("checking scene {}", path.display()))?;
    let counts = generated.as_ref().map_or(lattice, |(c, _)| c.clone());
    writeln!(
        out,
        "scene {}: valid ({}D, solver {}, integrator {}{})",
        path.display(),
        scene.dimension,
        scene.solver.kind.name(),
        scene.solver.integrator.name(),
        match crate::run::correction(scene) {
            Some(c) => format!(
                ", delta {:e}, max {} iterations{}, relaxation {}",
                c.delta,
                c.max_iterations,
                if c.strict { " (strict)" } else { "" },
                c.relaxation
            ),
            None => String::new(),
        }
    )?;
    writeln!(
        out,
        "  spacing {} m, support radius h {} m",
        scene.spacing, scene.smoothing_length
    )?;
    writeln!(out, "  fluid particles  {:>12}", counts.fluid)?;
    for (i, fb) in scene.fluid_boxes.iter().enumerate() {
        // A shaped fluid volume says what it is, as a shaped solid does.
        if !matches!(fb.volume, crate::geometry::Volume::Aabb { .. }) {
            writeln!(out, "    fluid_box[{i}]  {}", fb.volume.describe(scene.dimension))?;
        }
    }
    for ((name, n), s) in counts.solid.iter().zip(&scene.solids) {
        writeln!(
            out,
            "  solid {name:<10} {n:>12}  {}",
            shape_words(s, scene.dimension)
        )?;
    }
    writeln!(out, "  total particles  {:>12}", counts.total)?;
    match &generated {
        Some((_, report)) => write_generation(out, scene, report)?,
        None => writeln!(
            out,
            "  lattice: not generated (more than {GENERATE_CAP} particles): counts before trimming, which `sph run` may do"
        )?,
    }
    let per = scene_particle_bytes(scene);
    let bytes = run_bytes(counts.total, counts.fluid, per).unwrap_or(u64::MAX);
    let solver = solver_particle_bytes(scene);
    let frames = if scene.write_frames {
        format!(
            ", {} per particle for {} frames",
            frame_bytes_per_particle(scene.output_encoding),
            scene.output_encoding.name()
        )
    } else {
        String::new()
    };
    let mut fluid = if solver.per_fluid > 0 {
        format!(" and {} more per fluid particle", solver.per_fluid)
    } else {
        String::new()
    };
    if solver.per_solid > 0 {
        fluid += &format!(
            ", {} more per solid particle for floating contact",
            solver.per_solid
        );
    }
    writeln!(
        out,
        "  memory needed    {:>12.1} MiB ({} bytes per particle with {}{fluid}{frames}; {:.1} MiB for the program)",
        bytes as f64 / (1024.0 * 1024.0),
        solver.per_particle,
        scene.solver.kind.name(),
        crate::scene::BASE_BYTES as f64 / (1024.0 * 1024.0)
    )?;
    let effects: Vec<&str> = scene.effects.iter().map(|e| e.name()).collect();
    writeln!(
        out,
        "  effects          {}",
        if effects.is_empty() {
            "none".into()
        } else {
            effects.join(", ")
        }
    )?;
    if !scene.periodic.is_empty() {
        // The period of each periodic axis is the domain's extent (`crate::periodic`).
        let periods: Vec<String> = (0..scene.dimension)
            .filter(|&k| scene.periodic.contains(k))
            .map(|k| {
                let name = ["x", "y", "z"][k];
                format!("{name} (period {} m)", scene.domain.max[k] - scene.domain.min[k])
            })
            .collect();
        writeln!(out, "  periodic         {}", periods.join(", "))?;
    }
    for b in &scene.open_boundaries {
        // `boundary::open`: the plane, what crosses it, the buffer's depth.
        let axis = ["x", "y", "z"][b.axis];
        let flow = match b.kind {
            crate::scene::schema::OpenBoundaryKind::Inflow => {
                format!("inflow, velocity {:?} m/s {}", b.velocity, b.profile.name())
            }
            crate::scene::schema::OpenBoundaryKind::Outflow => "outflow".into(),
        };
        writeln!(
            out,
            "  open boundary    {axis} = {} m, {flow}, buffer {} layers",
            b.min[b.axis], b.layers
        )?;
    }
    let pair_terms: Vec<&str> = scene.pair_terms.iter().map(|(t, _)| t.label()).collect();
    let plan = crate::solver::plan::plan(crate::run::plan_inputs(scene));
    let names: Vec<&str> = plan.iter().map(|s| s.name()).collect();
    writeln!(
        out,
        "  plan             {}{}",
        names.join(" → "),
        if pair_terms.is_empty() {
            String::new()
        } else {
            format!(" (forces with {})", pair_terms.join(", "))
        }
    )?;
    let skipped = skipped_references(scene);
    for probe in scene.probes.iter().filter(|p| p.reference.is_some()) {
        match skipped.iter().find(|s| s.probe == probe.name) {
            Some(s) => writeln!(out, "  warning: {s}")?,
            None => writeln!(out, "  probe {}: reference data found and read", probe.name)?,
        }
    }
    Ok(text)
}
