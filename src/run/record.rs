//! What a run records after each step: the `steps.csv` row, the probes, the forces on solids
//! and, at a frame time, the frame (one file, or one piece per rank of a split run).

use super::{Loop, Ranks, RunOptions, StepRow, writers};
use crate::error::Error;
use crate::scene::Scene;
use crate::solver::Simulation;

/// The outputs of the step just taken (its `steps.csv` row `row`, the probes, the forces on
/// solids and, at a frame time, a frame) and the loop's tallies of it.
pub(super) fn record_step<const D: usize>(
    sim: &mut Simulation<D>,
    scene: &Scene,
    options: &RunOptions,
    state: &mut Loop,
    row: &StepRow,
) -> Result<(), Error> {
    let end = scene.end_time;
    let clock = sim.clock();
    if let Some(w) = state.writers.as_mut() {
        w.steps.push_row(&row.values())?;
    }
    *state.limits.entry(row.limit.clone()).or_default() += 1;
    state.max_speed = state.max_speed.max(row.max_speed);
    let last = clock.time >= end;
    let frame_time = clock.time >= state.next_frame - 1e-12 * end || last;
    record_probes(sim, options, state, clock.time, row.dt, last)?;
    if let Some(w) = state.writers.as_mut() {
        if let Some(log) = w.forces.as_mut() {
            for (name, force) in sim.solid_names().iter().zip(sim.solid_forces()) {
                log.push(clock.time, name, *force)?;
            }
        }
        if let Some(log) = w.bodies.as_mut() {
            let names = sim.solid_names().iter().zip(sim.solid_forces());
            for ((name, force), body) in names.zip(sim.floating_bodies()) {
                if let Some(b) = body {
                    log.push(clock.time, name, &b.state, *force, &b.contact_load)?;
                }
            }
        }
    }
    if frame_time && options.out_dir.is_some() {
        write_frame(sim, scene, options, state)?;
        while state.next_frame <= clock.time + 1e-12 * end {
            state.next_frame += scene.output_interval;
        }
    }
    Ok(())
}

/// The probes at `time` [s] after a step of `dt` [s] (`now`: a sample is due whatever the
/// interval). Split across ranks, rank 0 decides whether they read particles; if so the
/// particles they read (`probe::reach`) of every rank are gathered there, and rank 0 records.
pub(super) fn record_probes<const D: usize>(
    sim: &mut Simulation<D>,
    options: &RunOptions,
    state: &mut Loop,
    time: f64,
    dt: f64,
    now: bool,
) -> Result<(), Error> {
    let probes = state.probes.as_mut().expect("opened by start");
    let wants = probes.wants_fields(time, now);
    let gathered = match &options.ranks {
        None => {
            if wants {
                sim.sync_fields()?;
            }
            None
        }
        Some(ranks) => {
            if ranks.root_says(f64::from(u8::from(wants)))? == 0.0 {
                None
            } else {
                let owned = sim.owned_fields()?;
                let read = ranks.gather_some(&owned, &probes.particles_read(&owned))?;
                if !ranks.is_root() {
                    return Ok(());
                }
                read
            }
        }
    };
    if !options.ranks.as_ref().is_none_or(Ranks::is_root) {
        return Ok(());
    }
    let fields = gathered.as_ref().unwrap_or(&sim.fields);
    probes.record_loads(time, dt, fields, sim.solid_forces(), sim.solid_moments(), now)?;
    Ok(())
}

/// The frame (and surface) of the state now: one file, or split across ranks one piece per
/// rank and rank 0's header, each piece claimed before any is written and the header written
/// after every piece.
pub(super) fn write_frame<const D: usize>(
    sim: &mut Simulation<D>,
    scene: &Scene,
    options: &RunOptions,
    state: &mut Loop,
) -> Result<(), Error> {
    let Some(ranks) = &options.ranks else {
        if let Some(w) = state.writers.as_mut() {
            sim.sync_fields()?;
            w.frame(sim, scene.write_frames)?;
        }
        return Ok(());
    };
    let Some(dir) = &options.out_dir else {
        return Ok(());
    };
    let time = sim.clock().time;
    let owned = sim.owned_fields()?;
    let all = if scene.write_surface {
        ranks.gather(&owned)?
    } else {
        None
    };
    if scene.write_frames {
        if let Some(w) = state.writers.as_mut() {
            w.claim_pieces(ranks.size())?;
        }
        ranks.barrier()?;
        let stem = format!("frame_{:05}", state.frames_written);
        let piece = dir
            .join("frames")
            .join(crate::output::pvtu::piece_name(&stem, ranks.rank()));
        writers::write_frame_file(&piece, time, &owned, scene.fluid_only, scene.output_encoding)?;
        ranks.barrier()?;
        state.frames_written += 1;
    }
    if let Some(w) = state.writers.as_mut() {
        w.parallel_frame(time, ranks.size(), all.as_ref(), scene.write_frames)?;
    }
    Ok(())
}
