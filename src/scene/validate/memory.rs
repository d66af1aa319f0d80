//! The memory a scene needs: an estimate of the run's peak resident set (a base for the
//! program, a figure per particle and one per fluid particle by dimension and solver, and the
//! frame writer's share) held against the limits the process runs under
//! (`crate::memory::limit`), and the particle count against `u32` indices.

use super::*;

/// The resident memory of the process before particles \[B\]: the program, its libraries, the
/// worker threads' stacks and the allocator's arenas, 8.75 MiB. It grows with the program, and
/// it varies with the machine's load and with the threads' scheduling: the second worker
/// thread alone adds about 0.6 MiB, and `scenes/wave_flume_focused_2d.toml` (2 threads,
/// 0.003 s, AMD EPYC 2-core, commit caa8498) peaks anywhere in 9.8–10.2 MiB run to run. At
/// 8.25 MiB the small 2D scenes read 2–10 % low alone and one passed the 10 % check in CI; at
/// 8.75 MiB every shipped scene and hard case reads within -5.7 % to +5.3 % alone
/// (`tests/check/memory_estimate.rs`).
pub const BASE_BYTES: u64 = 35 << 18;

/// Estimated peak resident memory \[B\] that each particle, and each fluid particle on top,
/// adds to a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParticleBytes {
    /// Bytes per particle, fluid or solid.
    pub per_particle: u64,
    /// Further bytes per fluid particle.
    pub per_fluid: u64,
    /// Further bytes per solid particle.
    pub per_solid: u64,
}

/// Bytes per solid particle that each floating body with contact holds
/// (`boundary::contact::BodyContact`): the fixed solids' positions (24 B), their indices in
/// the hash grid (4 B) and a grid cell per particle at most (its key and list, 48 B in the
/// map, with its share of the map's control bytes and load, about 60 B, and the list's own
/// allocation, 32 B): 120 B.
pub const CONTACT_BYTES_PER_SOLID: u64 = 120;

/// The solver's state in a run in `dim` dimensions with `solver` \[B\]: the particle fields
/// (allocated to their exact size), the start-of-step copies, the grid's keys, sort pairs and
/// cell ranges and the reorder scratch per particle; for `corrected` also the correction's
/// increments, the velocity solve's saved fields and its Anderson window per particle, and per
/// fluid particle its neighbour list (`crate::neighbour_list`: `4 (D + 1)` B per pair, about 33
/// pairs in 3D at `h = 2 dx`, 13 in 2D). Generation's peak (the lattice and its trim, 32 B per particle) stays below it.
///
/// Calibrated on peak resident sets (`summary.json`'s `peak_resident_bytes`, 2 threads, Xeon
/// 2-core VM, no frames, less [`BASE_BYTES`]): 3D `wcsph` 166 B per particle on the column and
/// Yeh & Petroff (214,125 and 148,041 particles, 52 % and 43 % fluid, equal to 1 B);
/// `corrected` adds 207 and 204 B per particle there and 75 B on the 3D jet (11,124 particles,
/// 3 % fluid), which 90 B per particle and 225 B per fluid particle fit within 20 B. 2D `wcsph`
/// 143 B and `corrected` 162 B more on the 2D dam break at 0.5 mm (259,008 particles, 97 %
/// fluid), split as in 3D. The neighbour list's pair offsets, added since, count `4 D` B more per
/// pair: 400 B per fluid particle in 3D, 104 B in 2D. The grid's candidate lists
/// (`crate::grid`), added since too, hold 4 B per candidate within `1.02 h` and 4 B per
/// particle: about 36 candidates inside the fluid in 3D and 13 in 2D, fewer at walls and at the
/// free surface; counted as 120 B per particle in 3D (the column scene read +8 % at 148 B) and
/// 56 B in 2D.
pub fn particle_bytes(dim: usize, solver: crate::scene::SolverKind) -> ParticleBytes {
    use crate::scene::SolverKind;
    let (per_particle, per_fluid) = match (dim, solver) {
        (3, SolverKind::Wcsph) => (166 + 120, 0),
        (3, SolverKind::Corrected) => (166 + 120 + 90, 225 + 400),
        (_, SolverKind::Wcsph) => (143 + 56, 0),
        (_, SolverKind::Corrected) => (143 + 56 + 50, 115 + 104),
    };
    ParticleBytes {
        per_particle,
        per_fluid,
        per_solid: 0,
    }
}

/// [`particle_bytes`] for `scene`'s dimension and solver, with the continuity equation's fields
/// where the `density_diffusion` effect is on: the rate on every particle and, under SSP-RK3,
/// the step-start density (`Field::DensityRate`, `Field::DensityStart`, one `f32` each), and
/// with `corrected` the pressure that acted over the last stage (`Field::ActingPressure`, one
/// `f32`) and the velocity solves' records by particle id (`Backend::record_velocity_solve`: a
/// `u32` and an `f32` per integrator stage's slot, `VELOCITY_SOLVE_SLOTS` of them), neither in
/// the calibration above \[B\].
pub fn solver_particle_bytes(scene: &Scene) -> ParticleBytes {
    let mut bytes = particle_bytes(scene.dimension, scene.solver.kind);
    if scene.density_diffusion.is_some() {
        let copies = match scene.solver.integrator {
            crate::solver::Integrator::Rk3 => 2,
            crate::solver::Integrator::SymplecticEuler => 1,
        };
        bytes.per_particle += copies * std::mem::size_of::<crate::math::Real>() as u64;
    }
    if scene.solver.kind == crate::scene::SolverKind::Corrected {
        let records = 8 * crate::backend::VELOCITY_SOLVE_SLOTS as u64;
        bytes.per_particle += std::mem::size_of::<crate::math::Real>() as u64 + records;
    }
    let touching = scene
        .solids
        .iter()
        .filter_map(|s| s.floating.as_ref())
        .filter(|f| f.contact != crate::boundary::contact::WallContact::None)
        .count() as u64;
    bytes.per_solid += touching * CONTACT_BYTES_PER_SOLID;
    bytes
}

/// Estimated peak resident memory per particle \[B\] that writing a frame adds, by the
/// frame's `encoding`: its arrays encoded in memory (49 B per particle before encoding) while
/// one raw array at a time is made (`output::vtu::write_vtu`). Measured as for
/// [`particle_bytes`] on the 3D scenes and the 2D dam break: `zlib` 30–33 B, `raw` 46 B,
/// `base64` 63 B. Counted on every particle, also when frames hold only the fluid.
pub fn frame_bytes_per_particle(encoding: crate::output::Encoding) -> u64 {
    use crate::output::Encoding;
    match encoding {
        Encoding::Zlib => 32,
        Encoding::Raw => 46,
        Encoding::Base64 => 63,
    }
}

/// The estimated peak resident memory per particle \[B\] of `scene`'s run: the solver's
/// state and, when the scene writes frames, the frame writer's.
pub fn scene_particle_bytes(scene: &Scene) -> ParticleBytes {
    let mut bytes = solver_particle_bytes(scene);
    if scene.write_frames {
        bytes.per_particle += frame_bytes_per_particle(scene.output_encoding);
    }
    bytes
}

/// The estimated peak resident memory \[B\] of a run of `particles` particles of which
/// `fluid` are fluid, needing `bytes` ([`scene_particle_bytes`]); `None` past `u64`.
pub fn run_bytes(particles: u64, fluid: u64, bytes: ParticleBytes) -> Option<u64> {
    particles
        .checked_mul(bytes.per_particle)?
        .checked_add(fluid.checked_mul(bytes.per_fluid)?)?
        .checked_add(particles.saturating_sub(fluid).checked_mul(bytes.per_solid)?)?
        .checked_add(BASE_BYTES)
}

pub(super) fn check_counts(c: &mut Checker, scene: &Scene) {
    let dx = scene.spacing;
    let layers = scene.wall_layers();
    let mut total: Option<u64> = Some(0);
    let mut fluid: Option<u64> = Some(0);
    let mut complete = true;
    for (i, fb) in scene.fluid_boxes.iter().enumerate() {
        let path = KeyPath::key("fluid_box").i(i);
        match count::fluid_box_count(fb, dx, &path) {
            Ok(n) => {
                total = total.and_then(|t| t.checked_add(n));
                fluid = fluid.and_then(|t| t.checked_add(n));
            }
            Err(p) => {
                c.problems.push(p);
                complete = false;
            }
        }
    }
    for (i, s) in scene.solids.iter().enumerate() {
        let path = KeyPath::key("solid").i(i);
        match count::solid_count(s, dx, layers, &path) {
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
    let per = scene_particle_bytes(scene);
    let bytes = fluid.and_then(|fluid| run_bytes(total, fluid, per));
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
                "spacing {dx} m gives {total} particles needing about {bytes_txt} bytes ({} per particle, {} more per fluid particle and {BASE_BYTES} for the program), more than the {limit} bytes available ({what})",
                per.per_particle, per.per_fluid
            ),
        );
    }
}
