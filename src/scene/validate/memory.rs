//! The memory a scene needs: an estimate of the run's peak resident set (a base for the
//! program and a figure per particle by dimension and solver) held against the limits the
//! process runs under (`crate::memory::limit`), and the particle count against `u32` indices.

use super::*;

/// The resident memory of the process before particles \[B\]: the program, its libraries, the
/// worker threads' stacks and the allocator's arenas. Measured peak resident sets of the
/// smallest shipped scenes (a few hundred particles, `/usr/bin/time -f %M`): 6.6–8.4 MiB.
pub const BASE_BYTES: u64 = 7 << 20;

/// Estimated peak resident memory per particle \[B\] of a run in `dim` dimensions with
/// `solver`: the particle fields, SSP-RK3's start-of-step copies, the grid's keys, sort pairs
/// and cell ranges, the reorder scratch, and for `corrected` the correction's increments, the
/// velocity solve's saved fields, its Anderson window and its neighbour list (4 B per pair,
/// about 33 pairs per fluid particle in 3D at `h = 2 dx`).
///
/// Calibrated on peak resident sets (`/usr/bin/time -f %M`, Xeon 2-core VM, 3 ms of every
/// shipped scene, less [`BASE_BYTES`]): 3D `wcsph` 195–222 B (214,125 and 148,041
/// particles), 3D `corrected` 400–466 B, 2D `wcsph` about 160 B and `corrected` about 330 B
/// (scenes of 3–4 thousand particles, where the base dominates). The per-particle figure
/// varies by scene with the growth of the arrays built particle by particle.
pub fn bytes_per_particle(dim: usize, solver: crate::scene::SolverKind) -> u64 {
    use crate::scene::SolverKind;
    match (dim, solver) {
        (3, SolverKind::Wcsph) => 205,
        (3, SolverKind::Corrected) => 432,
        (_, SolverKind::Wcsph) => 170,
        (_, SolverKind::Corrected) => 340,
    }
}

/// The estimated peak resident memory \[B\] of a run of `particles` particles.
pub fn run_bytes(particles: u64, dim: usize, solver: crate::scene::SolverKind) -> Option<u64> {
    particles
        .checked_mul(bytes_per_particle(dim, solver))?
        .checked_add(BASE_BYTES)
}

pub(super) fn check_counts(c: &mut Checker, scene: &Scene) {
    let dx = scene.spacing;
    let layers = scene.wall_layers();
    let mut total: Option<u64> = Some(0);
    let mut complete = true;
    for (i, fb) in scene.fluid_boxes.iter().enumerate() {
        let path = KeyPath::key("fluid_box").i(i);
        match generate::fluid_box_count(fb, dx, &path) {
            Ok(n) => total = total.and_then(|t| t.checked_add(n)),
            Err(p) => {
                c.problems.push(p);
                complete = false;
            }
        }
    }
    for (i, s) in scene.solids.iter().enumerate() {
        let path = KeyPath::key("solid").i(i);
        match generate::solid_count(s, dx, layers, &path) {
            Ok(n) => total = total.and_then(|t| t.checked_add(n)),
            Err(p) => {
                c.problems.push(p);
                complete = false;
            }
        }
    }
    if !complete {
        return;
    }
    let key = KeyPath::key("particles").k("spacing");
    let Some(total) = total else {
        c.err(
            key,
            format!("particle count overflows a 64-bit integer at spacing {dx} m"),
        );
        return;
    };
    let per = bytes_per_particle(scene.dimension, scene.solver.kind);
    let bytes = run_bytes(total, scene.dimension, scene.solver.kind);
    let bytes_txt = bytes.map_or_else(|| "more than 2^64".to_string(), |b| format!("{b}"));
    if total > u64::from(u32::MAX) {
        c.err(
            key,
            format!(
                "spacing {dx} m gives {total} particles (about {bytes_txt} bytes), more than the {} that u32 particle indices allow",
                u32::MAX
            ),
        );
        return;
    }
    let (limit, what) =
        crate::memory::limit().unwrap_or((isize::MAX as u64, "isize::MAX (no limit readable)"));
    if bytes.is_none_or(|b| b > limit) {
        c.err(
            key,
            format!(
                "spacing {dx} m gives {total} particles needing about {bytes_txt} bytes ({per} per particle and {BASE_BYTES} for the program), more than the {limit} bytes available ({what})"
            ),
        );
    }
}
