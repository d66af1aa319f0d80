//! `sph check SCENE`: validate and report.

use crate::scene::{bytes_per_particle, count_particles, skipped_references};
use anyhow::Context;
use std::path::Path;

/// Validates the scene and prints counts, memory and plan.
/// Reads every reference file the scene's probes name that is available (a malformed one is an
/// error, as `sph run` would refuse it); one that is not is reported as `sph run` reports it.
pub fn check(path: &Path, sets: &[String], reference_dir: Option<&Path>) -> anyhow::Result<()> {
    let scene = super::load_located(path, sets, reference_dir, false)
        .with_context(|| format!("checking scene {}", path.display()))?;
    crate::probe::check_references(&scene).with_context(|| format!("checking scene {}", path.display()))?;
    let counts = count_particles(&scene)?;
    println!(
        "scene {}: valid ({}D, solver {}, integrator {}{})",
        path.display(),
        scene.dimension,
        scene.solver.kind.name(),
        scene.solver.integrator.name(),
        match crate::run::correction(&scene) {
            Some(c) => format!(
                ", delta {:e}, max {} iterations{}, relaxation {}",
                c.delta,
                c.max_iterations,
                if c.strict { " (strict)" } else { "" },
                c.relaxation
            ),
            None => String::new(),
        }
    );
    println!(
        "  spacing {} m, support radius h {} m",
        scene.spacing, scene.smoothing_length
    );
    println!("  fluid particles  {:>12}", counts.fluid);
    for (name, n) in &counts.solid {
        println!("  solid {name:<10} {n:>12}");
    }
    println!("  total particles  {:>12}", counts.total);
    let bytes = counts.total * bytes_per_particle(scene.dimension);
    println!(
        "  memory needed    {:>12.1} MiB ({} bytes per particle)",
        bytes as f64 / (1024.0 * 1024.0),
        bytes_per_particle(scene.dimension)
    );
    let effects: Vec<&str> = scene.effects.iter().map(|e| e.name()).collect();
    println!(
        "  effects          {}",
        if effects.is_empty() {
            "none".into()
        } else {
            effects.join(", ")
        }
    );
    let viscosity = scene.viscosity.is_some();
    let plan = crate::solver::plan::plan(crate::run::plan_inputs(&scene));
    let names: Vec<&str> = plan.iter().map(|s| s.name()).collect();
    println!(
        "  plan             {}{}",
        names.join(" → "),
        if viscosity { " (forces with viscosity)" } else { "" }
    );
    let skipped = skipped_references(&scene);
    for probe in scene.probes.iter().filter(|p| p.reference.is_some()) {
        match skipped.iter().find(|s| s.probe == probe.name) {
            Some(s) => println!("  warning: {s}"),
            None => println!("  probe {}: reference data found and read", probe.name),
        }
    }
    Ok(())
}
