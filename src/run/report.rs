//! The run's `summary.json`: the `running` one written at the start and the final one written
//! on every way out of the time loop (completed, failed, interrupted).

use super::folder::RunIdentity;
use super::{Ending, Loop, RunOptions};
use crate::error::Error;
use crate::output::Summary;
use crate::probe::{compare, write_figures};
use crate::scene::{Scene, SolverKind};
use crate::solver::Simulation;

/// Largest compression `max(ρ − ρ0, 0)/ρ0` a `wcsph` run reports without a warning. The
/// usual rule, a sound speed of 10 times the largest flow speed (Monaghan 1994), keeps the
/// *mean* density variation near 1 %; the largest over every particle and step, which is what
/// the summary reports, reaches 6 % on the shipped 2D dam break at that sound speed
/// (docs/validation.md). Beyond 10 % the sound speed is too low for the flow: pressures,
/// forces and the front lose accuracy.
pub const WCSPH_COMPRESSION_WARNING: f64 = 0.10;

/// The summary of a run about to start (status `running`).
pub(super) fn initial<const D: usize>(
    sim: &Simulation<D>,
    scene: &Scene,
    options: &RunOptions,
    identity: Option<&RunIdentity>,
) -> Summary {
    let scene_run = options.restart.scene.as_ref();
    Summary {
        scene: options.scene_name.clone(),
        scene_file: scene_run.map(|(file, _)| file.clone()),
        scene_overrides: scene_run.map(|(_, sets)| sets.clone()).unwrap_or_default(),
        run_id: identity.map(|i| i.run_id.clone()).unwrap_or_default(),
        scene_hash: identity.map(|i| i.scene_hash.clone()).unwrap_or_default(),
        dimension: D,
        solver: scene.solver.kind.name().into(),
        backend: sim.backend_name().into(),
        threads: options.threads,
        particles: sim.fields.len() as u64,
        fluid_particles: sim.fluid_count() as u64,
        status: "running".into(),
        ..Summary::default()
    }
}

/// Fills in the statistics of the run, the status `ending` gives, the probes' comparisons and
/// figures, and writes `summary.json`. On a failure the summary is written as far as it can
/// be and the original error returned.
pub(super) fn finish<const D: usize>(
    sim: &mut Simulation<D>,
    scene: &Scene,
    options: &RunOptions,
    summary: &mut Summary,
    state: &mut Loop,
    ending: Ending,
) -> Result<Summary, Error> {
    // Split across ranks: the whole run's totals, a collective every rank reaches unless the
    // run failed (a failed rank may be gone); only rank 0 writes.
    let mut totals = None;
    let mut ending = ending;
    if options.ranks.is_some() && !matches!(ending, Ending::Failed(_)) {
        totals = Some(sim.totals_over_ranks());
        if let Some(e) = sim.synchronize().err() {
            ending = Ending::Failed(e.into());
        }
    }
    if !options.ranks.as_ref().is_none_or(super::Ranks::is_root) {
        return match ending {
            Ending::Completed => Ok(summary.clone()),
            Ending::Failed(e) => Err(e),
            Ending::Interrupted(signal, inside_step) => Err(Error::Interrupted { signal, inside_step }),
        };
    }
    let ending = match statistics(sim, scene, summary, state, totals) {
        Ok(()) => ending,
        Err(e) => match ending {
            Ending::Completed => Ending::Failed(e),
            other => other,
        },
    };
    summary.status = match &ending {
        Ending::Completed => "completed".into(),
        Ending::Failed(e) => format!("failed: {e}"),
        Ending::Interrupted(signal, None) => format!("interrupted (signal {signal})"),
        Ending::Interrupted(signal, Some(step)) => {
            format!("interrupted (signal {signal}) inside step {step}, which was not written")
        }
    };
    let written = match state.writers.as_mut() {
        Some(w) => w.summary(summary),
        None => Ok(()),
    };
    match (ending, written) {
        (Ending::Completed, Ok(())) => Ok(summary.clone()),
        (Ending::Completed, Err(e)) => Err(e),
        (Ending::Failed(e), _) => Err(e),
        (Ending::Interrupted(signal, inside_step), _) => Err(Error::Interrupted { signal, inside_step }),
    }
}

/// The run's statistics, comparisons and figures into `summary`.
fn statistics<const D: usize>(
    sim: &mut Simulation<D>,
    scene: &Scene,
    summary: &mut Summary,
    state: &mut Loop,
    totals: Option<(u64, f64)>,
) -> Result<(), Error> {
    sim.sync_fields()?;
    // Particles and fluid mass of the whole run (summed over ranks when split).
    let (particles, fluid_mass) = totals.unwrap_or((sim.fields.len() as u64, sim.fluid_mass()));
    let clock = sim.clock();
    let stats = sim.stats();
    let wall = state.wall_before + state.start.elapsed().as_secs_f64();
    let steps = clock.step.max(1) as f64;
    summary.steps = clock.step;
    summary.simulated_time = clock.time;
    summary.wall_seconds = wall;
    summary.particle_steps_per_second = clock.step as f64 * particles as f64 / wall.max(1e-9);
    summary.max_compression = stats.max_compression;
    summary.mean_compression = stats.sum_mean_compression / steps;
    summary.max_surface_deficit = stats.max_surface_deficit;
    summary.mean_surface_deficit = stats.sum_mean_surface_deficit / steps;
    summary.output_frames = state.writers.as_ref().map_or(0, |w| w.frames().len() as u64);
    if scene.solver.kind == SolverKind::Wcsph && stats.max_compression > WCSPH_COMPRESSION_WARNING {
        summary.warnings.push(format!(
            "the fluid was compressed by up to {:.1} % (more than {} %): fluid.sound_speed is too low for this flow; raise it to about 10 times the largest flow speed ({:.2} m/s here) or use solver.kind = \"corrected\"",
            100.0 * stats.max_compression,
            100.0 * WCSPH_COMPRESSION_WARNING,
            10.0 * state.max_speed
        ));
    }
    if stats.removed_particles > 0 {
        summary.warnings.push(format!(
            "{} fluid particles left the domain and were removed (steps.csv: removed_particles); enlarge the domain or close the tank if the fluid must be conserved (solver.on_escape = \"stop\" ends the run instead)",
            stats.removed_particles
        ));
    }
    let extra = &mut summary.extra;
    extra.insert("removed_particles".into(), stats.removed_particles.into());
    extra.insert("created_particles".into(), stats.created_particles.into());
    extra.insert("outflow_particles".into(), stats.outflow_particles.into());
    extra.insert("fluid_mass".into(), fluid_mass.into());
    extra.insert("memory_bytes".into(), (sim.heap_bytes() as u64).into());
    // The process's peak resident set (Linux), what `sph check`'s estimate is held to.
    if let Some(peak) = crate::memory::peak_resident_bytes() {
        extra.insert("peak_resident_bytes".into(), peak.into());
    }
    extra.insert(
        "memory_bytes_per_particle".into(),
        (sim.heap_bytes() as f64 / sim.fields.len().max(1) as f64).into(), // this rank's
    );
    extra.insert("smoothing_length".into(), scene.smoothing_length.into());
    extra.insert("spacing".into(), scene.spacing.into());
    extra.insert(
        "time_step_limits".into(),
        serde_json::Value::Object(
            state
                .limits
                .iter()
                .map(|(k, v)| (k.clone(), (*v).into()))
                .collect(),
        ),
    );
    extra.insert(
        "plan".into(),
        sim.plan().iter().map(|s| s.name()).collect::<Vec<_>>().into(),
    );
    extra.insert("integrator".into(), scene.solver.integrator.name().into());
    // How often the no-penetration guard, not the particle boundary, held the fluid.
    extra.insert("keep_out_pushes".into(), stats.keep_out_pushes.into());
    if let Some(c) = sim.config().correction {
        let cs = stats.correction;
        extra.insert("delta".into(), c.delta.into());
        extra.insert("correction_iterations_mean".into(), cs.mean_iterations().into());
        extra.insert("correction_iterations_max".into(), cs.max_iterations.into());
        extra.insert("corrected_stages".into(), cs.stages.into());
        extra.insert("unconverged_stages".into(), cs.unconverged_stages.into());
        extra.insert("velocity_solves".into(), cs.velocity_solves.into());
        extra.insert(
            "velocity_iterations_mean".into(),
            cs.mean_velocity_iterations().into(),
        );
        extra.insert(
            "operator_applications_per_stage".into(),
            cs.mean_operator_applications().into(),
        );
        extra.insert(
            "velocity_solves_given_up".into(),
            cs.velocity_solves_given_up.into(),
        );
        extra.insert(
            "max_compression_after_correction".into(),
            cs.max_compression_after.into(),
        );
    }
    let Some(probes) = state.probes.as_ref() else {
        return Ok(());
    };
    let comparisons = compare(scene, probes)?;
    let mut probe_errors = serde_json::Map::new();
    for c in &comparisons {
        let value = match (&c.error, &c.peak) {
            _ if c.signal.is_some() => crate::probe::signal::summary_json(c),
            (Some(e), _) => serde_json::json!({"error_max": e.max, "error_mean": e.mean, "points": e.count}),
            (None, Some(peak)) => {
                let (sim, reference) = (peak.simulated, peak.reference);
                serde_json::json!({
                    "peak_time_s": sim.0,
                    "peak_N": sim.1,
                    "reference_peak_time_s": reference.0,
                    "reference_peak_N": reference.1,
                    "peak_error": (sim.1 - reference.1) / reference.1,
                    "peak_time_error_s": sim.0 - reference.0,
                    "onset_time_s": peak.onset.map(|o| o.0),
                    "reference_onset_time_s": peak.onset.map(|o| o.1),
                    "rise_time_error_s": peak.rise_time_error(),
                })
            }
            (None, None) => serde_json::Value::Null,
        };
        probe_errors.insert(c.name.clone(), value);
    }
    // A probe whose reference file is not available was sampled but not compared.
    for skipped in crate::scene::skipped_references(scene) {
        let value = serde_json::json!({
            "status": "skipped",
            "reference_file": skipped.file.display().to_string(),
            "reason": skipped.reason.to_string(),
        });
        probe_errors.insert(skipped.probe, value);
    }
    if !probe_errors.is_empty() {
        extra.insert("probe_errors".into(), probe_errors.into());
    }
    if let Some(w) = state.writers.as_mut() {
        for c in &comparisons {
            w.folder.claim(&format!("{}.png", c.name))?;
        }
        // A figure is a picture of numbers already in the summary: failing to draw one (an axis
        // range a plot cannot hold, say) is a warning, never the run's failure.
        if let Err(e) = write_figures(w.dir(), scene.solver.kind.name(), &comparisons) {
            summary.warnings.push(format!(
                "the probes' comparison figures were not drawn: {e}; the errors are in summary.json"
            ));
        }
    }
    Ok(())
}
