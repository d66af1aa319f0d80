//! The hard-case suite (`scenes/hard/`), each scene with `wcsph` and `corrected`, checked after
//! every step: every field finite and every fluid particle inside the domain (the solver's own
//! guards stop the run otherwise, which fails the test), no fluid particle inside a solid's
//! volume (the surface the scene gives, half a spacing outside the centres of the solid's
//! outermost particle layer), the fluid's mass unchanged, kinetic plus
//! potential energy never above its start by more than 1e-3 of the start's magnitude (the
//! scenes start at rest or in free flight, walls are fixed and every term dissipates or
//! conserves), and for `corrected` every stage's compression below δ.

use crate::common::tolerance::{ENERGY_RISE, F32_ROUNDING};
use sph::fields::FLUID;
use sph::physics::lattice::lattice_gradient_moment;
use sph::run::AnySimulation;
use sph::scene::validate::corrected_step_bound;
use sph::scene::{Scene, SolidShape, load_scene};
use sph::smoothing::Smoothing;
use sph::solver::Simulation;
use sph::solver::timestep::TimeStepLimit;
use std::path::Path;
use std::sync::OnceLock;

/// A solid's volume as the invariants see it, computed once per run (the check runs for every
/// fluid particle after every step).
struct SolidVolume {
    name: String,
    /// Box: the solid's box. Container: the outer box of its wall shell.
    outer: ([f64; 3], [f64; 3]),
    /// Container: the inside box (the water's), whose faces belong to the water.
    inner: Option<([f64; 3], [f64; 3])>,
}

fn solid_volumes(scene: &Scene) -> Vec<SolidVolume> {
    let d = scene.dimension;
    let corner = |v: &[f64], shift: f64| -> [f64; 3] {
        let mut c = [0.0; 3];
        for k in 0..d {
            c[k] = v[k] + shift;
        }
        c
    };
    scene
        .solids
        .iter()
        .map(|s| {
            let (lo, hi) = (&s.region.min, &s.region.max);
            match s.shape {
                // The hard cases hold boxes and containers only; another shape's bounding box
                // would flag fluid that is outside the shape.
                SolidShape::Cylinder | SolidShape::Sphere | SolidShape::Mesh => {
                    panic!(
                        "solid {}: the penetration check knows boxes and containers only",
                        s.name
                    )
                }
                SolidShape::Box => SolidVolume {
                    name: s.name.clone(),
                    outer: (corner(lo, 0.0), corner(hi, 0.0)),
                    inner: None,
                },
                SolidShape::Container => {
                    // The walls: a shell `layers` spacings thick around the inside box.
                    let t = scene.wall_layers() as f64 * scene.spacing;
                    let mut outer_hi = corner(hi, t);
                    if s.open_top {
                        outer_hi[d - 1] = hi[d - 1];
                    }
                    SolidVolume {
                        name: s.name.clone(),
                        outer: (corner(lo, -t), outer_hi),
                        inner: Some((corner(lo, 0.0), corner(hi, 0.0))),
                    }
                }
            }
        })
        .collect()
}

/// Whether `x` lies more than `margin` inside one of the `solids`: its name.
fn inside_solid<'a>(solids: &'a [SolidVolume], x: &[f64], margin: f64) -> Option<&'a str> {
    let d = x.len();
    let inside_box =
        |(lo, hi): &([f64; 3], [f64; 3])| (0..d).all(|k| x[k] > lo[k] + margin && x[k] < hi[k] - margin);
    solids
        .iter()
        .find(|s| {
            inside_box(&s.outer)
                // The inner faces belong to the water: a particle exactly on one is 0 deep, not
                // "more than margin" inside, as the guard (`KeepOutBox::push_out`) and the box
                // case count it (measured: jet_3d corrected, a particle at x = 1.0 exactly on
                // the far wall's face after the no-slip walls changed its path).
                && !s
                    .inner
                    .is_some_and(|(lo, hi)| (0..d).all(|k| x[k] >= lo[k] - margin && x[k] <= hi[k] + margin))
        })
        .map(|s| s.name.as_str())
}

fn energy<const D: usize>(sim: &Simulation<D>, g: &[f64]) -> f64 {
    let f = &sim.fields;
    (0..f.len())
        .filter(|&i| f.kind[i] == FLUID)
        .map(|i| {
            let m = f64::from(f.mass[i]);
            let u2: f64 = f.velocity[i].iter().map(|c| f64::from(*c).powi(2)).sum();
            let pe: f64 = (0..D).map(|k| -g[k] * f64::from(f.position[i][k])).sum();
            m * (0.5 * u2 + pe)
        })
        .sum()
}

/// Runs `file` with `solver` under every invariant, energy bounded by the start (module doc).
fn case(file: &str, solver: &str) {
    case_with(file, solver, &[], EnergyBound::Start);
}

#[test]
fn rest_2d_wcsph() {
    case("rest_2d.toml", "wcsph");
}

#[test]
fn rest_2d_corrected() {
    case("rest_2d.toml", "corrected");
}

#[test]
fn rest_3d_wcsph() {
    case("rest_3d.toml", "wcsph");
}

/// Water at rest in 3D under `corrected`: the case that needs the spiky density (18), wall
/// increments of either sign and the velocity solve (docs/method.md, "The position correction").
/// With the poly6 density the sweep operator `J_poly6 · G_spiky` is not symmetric and the first
/// step's stages stall at the 1,000-sweep cap, raising KE + PE by 0.37 % of |E0|; with wall
/// increments clamped at zero, stages stall one or two spacings from the side walls; without the
/// velocity solve the carried pressure rings as a standing vertical wave of the column. The
/// energy stays below its start plus 1e-3 |E0| (measured with the CPU backend, this test's output
/// with `--nocapture`: at most 5.4e-4 |E0| above the start, at step 3, over 1 s; CI runs 0.5 s,
/// the long version 2 s).
#[test]
fn rest_3d_corrected() {
    case("rest_3d.toml", "corrected");
}

#[test]
fn jet_2d_wcsph() {
    case("jet_2d.toml", "wcsph");
}

#[test]
fn jet_2d_corrected() {
    case("jet_2d.toml", "corrected");
}

#[test]
fn jet_3d_wcsph() {
    case("jet_3d.toml", "wcsph");
}

#[test]
fn jet_3d_corrected() {
    case("jet_3d.toml", "corrected");
}

// ---------------------------------------------------------------------------------------------
// Compressed and coincident starts, thin sheets, isolated particles, viscosity extremes, a
// step too large for wcsph. Every case goes through
// `case_with` / `run_with`, which check the invariants of the module doc with the energy bound
// given per case (`case` uses `EnergyBound::Start`).

/// How `run_with` bounds the fluid's kinetic plus potential energy after every step.
#[derive(Clone, Copy, Debug, PartialEq)]
enum EnergyBound {
    /// Never above the start by more than 1e-3 of its magnitude (closed scenes
    /// whose walls are fixed and whose every term dissipates or conserves). Also `corrected`
    /// from a start above `ρ0` (compressed, coincident), from its settled state (`run_with`):
    /// measured, no step of the four cases ends above the start. The start itself is not the
    /// bound, since the projection turns the compression it removes into a velocity `Δx/τ`
    /// (PAPER.md note 7) that depends on the step `τ`, not on a stored energy.
    Start,
    /// `wcsph` from a start above `ρ0`: never above the start plus the elastic energy of the
    /// equation of state (19) in the initial densities, `Σ m C² (ln(ρ/ρ0) + ρ0/ρ − 1)` over
    /// particles with `ρ > ρ0` (the work `∫ p/ρ² dρ` of `p = C²(ρ − ρ0)`, clamped at zero below
    /// `ρ0`), plus `ELASTIC_SLACK` of it (the pressure gradient uses the spiky kernel and the
    /// density the poly6 one, so the discrete energy is conserved only approximately), plus 1e-3
    /// of the start's magnitude.
    StartPlusElastic,
    /// `wcsph` from a start with coincident particles: the start plus `twin_release_ratio` times
    /// the elastic energy of `StartPlusElastic`, plus 1e-3 of the start's magnitude. The paper's
    /// kernel pair is not energy-consistent for twins: a pair parting from `r = 0` to `h` under
    /// the factor `q = p/ρ²` feels the force `2 q m² |∇W_spiky| / κ` and so gains
    /// `2 q m² W_spiky(0) / κ` of kinetic energy, while their poly6 densities (18) fall by only
    /// `m W_poly6(0)` each, releasing `2 q m² W_poly6(0)` of elastic energy. For twins the
    /// energy released can therefore reach `W_spiky(0) / (κ W_poly6(0))` times what the equation
    /// of state stored (2.86 in 2D, 3.22 in 3D at h = 2 dx), where a consistent pair would give 1.
    /// Measured: 1.53 times in 2D, 1.45 in 3D.
    StartPlusTwinRelease,
}

/// `W_spiky(0) / (κ W_poly6(0))` for `scene`'s kernels, with κ the lattice moment that divides
/// the pressure force (`sph::physics::lattice::lattice_gradient_moment`): the most a twin pair
/// parting under a fixed `p/ρ²` gains in kinetic energy per unit of elastic energy its poly6
/// densities release (`EnergyBound::StartPlusTwinRelease`).
fn twin_release_ratio<const D: usize>(scene: &Scene) -> f64 {
    let k = Smoothing::<D>::new(scene.smoothing_length as f32).expect("2D or 3D");
    let kappa = lattice_gradient_moment(&k, scene.spacing, scene.rho0);
    f64::from(k.w_spiky(0.0)) / (kappa * f64::from(k.w(0.0)))
}

/// Share of the initial elastic energy allowed on top of it in `EnergyBound::StartPlusElastic`.
const ELASTIC_SLACK: f64 = 0.1;

/// What a run did, without its dimension.
#[derive(Debug)]
struct Trace {
    /// Kinetic plus potential fluid energy [J] (J/m in 2D) at the start and after every step.
    energy: Vec<f64>,
    /// Every step's `dt` [s] and the criterion that limited it.
    steps: Vec<(f64, TimeStepLimit)>,
    /// Smallest fluid density seen after any step [kg/m^3] (the last one the solver computed).
    min_density: f64,
    /// The smallest fluid self-term `m W(0)` [kg/m^3]: a density sum can never be below it.
    self_density: f64,
    /// Fluid positions at the end [m].
    positions: Vec<Vec<f64>>,
    /// Fluid positions at the start [m].
    start: Vec<Vec<f64>>,
}

/// Number of pairs among `x` closer than `r` [m].
fn close_pairs(x: &[Vec<f64>], r: f64) -> usize {
    (0..x.len())
        .map(|i| {
            (0..i)
                .filter(|&j| x[i].iter().zip(&x[j]).map(|(a, b)| (a - b).powi(2)).sum::<f64>() < r * r)
                .count()
        })
        .sum()
}

impl Trace {
    /// Largest fluid coordinate along `axis` at the end and at the start [m].
    fn front(&self, axis: usize) -> (f64, f64) {
        let max = |x: &[Vec<f64>]| x.iter().map(|p| p[axis]).fold(f64::NEG_INFINITY, f64::max);
        (max(&self.positions), max(&self.start))
    }
}

fn fluid_positions<const D: usize>(sim: &Simulation<D>) -> Vec<Vec<f64>> {
    let f = &sim.fields;
    (0..f.len())
        .filter(|&i| f.kind[i] == FLUID)
        .map(|i| f.position[i].iter().map(|c| f64::from(*c)).collect())
        .collect()
}

/// Elastic energy of eq. (19) in the summed densities of the current positions [J] (J/m in 2D),
/// `Σ_fluid m C² (ln(ρ/ρ0) + ρ0/ρ − 1)` for `ρ > ρ0`, by a brute-force poly6 sum over every
/// particle (walls included, as in the solver's density).
fn elastic_energy<const D: usize>(scene: &Scene, sim: &Simulation<D>) -> f64 {
    let f = &sim.fields;
    let k = Smoothing::<D>::new(scene.smoothing_length as f32).expect("2D or 3D");
    let (rho0, c2) = (scene.rho0, scene.sound_speed.powi(2));
    (0..f.len())
        .filter(|&i| f.kind[i] == FLUID)
        .map(|i| {
            let rho: f64 = (0..f.len())
                .map(|j| {
                    f64::from(f.mass[j]) * f64::from(k.w((f.position[i] - f.position[j]).norm_squared()))
                })
                .sum();
            if rho > rho0 {
                f64::from(f.mass[i]) * c2 * ((rho / rho0).ln() + rho0 / rho - 1.0)
            } else {
                0.0
            }
        })
        .sum()
}

/// Runs `scene` checking the invariants of the module doc with the energy bound `bound`,
/// recording a `Trace`.
fn run_with<const D: usize>(scene: &Scene, mut sim: Simulation<D>, bound: EnergyBound) -> Trace {
    let name = scene.name.clone().unwrap_or_default();
    let solver = scene.solver.kind.name();
    let g = scene.gravity.clone().unwrap_or_else(|| vec![0.0; D]);
    let mass = sim.fluid_mass();
    let start = fluid_positions(&sim);
    // The corrected solver's start-up settle moves particles out of the walls' reach and so
    // changes the potential energy once; the bound starts from the settled state.
    sim.settle()
        .unwrap_or_else(|e| panic!("{name} ({solver}): settle: {e}"));
    sim.sync_fields().expect("fields");
    let e0 = energy(&sim, &g);
    let allowed = match bound {
        EnergyBound::Start => Some(e0 + ENERGY_RISE * e0.abs().max(1e-12)),
        EnergyBound::StartPlusElastic => {
            Some(e0 + (1.0 + ELASTIC_SLACK) * elastic_energy(scene, &sim) + ENERGY_RISE * e0.abs().max(1e-12))
        }
        EnergyBound::StartPlusTwinRelease => Some(
            e0 + twin_release_ratio::<D>(scene) * elastic_energy(scene, &sim)
                + ENERGY_RISE * e0.abs().max(1e-12),
        ),
    };
    let kernel = Smoothing::<D>::new(scene.smoothing_length as f32).expect("2D or 3D");
    let f = &sim.fields;
    let self_density = (0..f.len())
        .filter(|&i| f.kind[i] == FLUID)
        .map(|i| f64::from(f.mass[i]) * f64::from(kernel.w(0.0)))
        .fold(f64::INFINITY, f64::min);
    let mut trace = Trace {
        energy: vec![e0],
        steps: Vec::new(),
        min_density: f64::INFINITY,
        self_density,
        positions: Vec::new(),
        start,
    };
    // No fluid particle strictly inside a solid's volume (its surface, half a spacing outside
    // the centres of its outermost particle layer).
    let margin = 0.0;
    let solids = solid_volumes(scene);
    while sim.clock().time < scene.end_time {
        let report = sim
            .step(scene.end_time)
            .unwrap_or_else(|e| panic!("{name} ({solver}): {e}"));
        trace.steps.push((report.dt, report.limit));
        let steps = trace.steps.len();
        let f = &sim.fields;
        for i in 0..f.len() {
            if f.kind[i] != FLUID {
                continue;
            }
            let mut x = [0.0f64; 3];
            for (k, c) in f.position[i].iter().enumerate() {
                x[k] = f64::from(*c);
            }
            let x = &x[..D];
            if let Some(solid) = inside_solid(&solids, x, margin) {
                panic!(
                    "{name} ({solver}): step {steps}: fluid particle {} inside solid {solid} at {x:?}",
                    f.id[i]
                );
            }
            trace.min_density = trace.min_density.min(f64::from(f.density[i]));
        }
        assert_eq!(
            sim.fluid_mass().to_bits(),
            mass.to_bits(),
            "{name} ({solver}): fluid mass changed"
        );
        let e = energy(&sim, &g);
        if let Some(allowed) = allowed {
            assert!(
                e <= allowed,
                "{name} ({solver}): step {steps}: energy {e} above the bound {allowed} (start {e0})"
            );
        }
        trace.energy.push(e);
    }
    // The guard is a last resort: report how often it acted (docs/hard-cases.md), and the
    // largest energy above the start, as a share of |E0|.
    let (peak_step, peak) = trace
        .energy
        .iter()
        .enumerate()
        .map(|(n, e)| (n, (e - e0) / e0.abs().max(1e-12)))
        .fold((0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a });
    eprintln!(
        "{name} ({solver}): {} steps, {} no-penetration pushes, energy at most {peak:.2e} |E0| above the start (step {peak_step})",
        trace.steps.len(),
        sim.stats().keep_out_pushes
    );
    if let Some(c) = sim.config().correction {
        let s = sim.stats().correction;
        eprintln!(
            "{name} ({solver}): {:.1} position sweeps per stage (max {}), {:.1} velocity sweeps per solve, {} of {} solves given up",
            s.mean_iterations(),
            s.max_iterations,
            s.mean_velocity_iterations(),
            s.velocity_solves_given_up,
            s.velocity_solves
        );
        assert_eq!(s.unconverged_stages, 0, "{name}: stages at the iteration cap");
        assert!(
            s.max_compression_after < c.delta,
            "{name}: compression {} left",
            s.max_compression_after
        );
    }
    trace.positions = fluid_positions(&sim);
    trace
}

/// `case` with extra `--set` overrides and an energy bound; returns the run's `Trace`.
fn case_with(file: &str, solver: &str, extra_sets: &[&str], bound: EnergyBound) -> Trace {
    let path = format!("{}/scenes/hard/{file}", env!("CARGO_MANIFEST_DIR"));
    let mut sets = vec![format!("solver.kind={solver}")];
    if solver == "corrected" {
        sets.push("solver.max_iterations=1000".into());
    }
    sets.extend(extra_sets.iter().map(|s| s.to_string()));
    let scene = load_scene(Path::new(&path), &sets).expect("hard scene");
    match AnySimulation::from_scene(&scene).expect("builds") {
        AnySimulation::D2(sim) => run_with(&scene, sim, bound),
        AnySimulation::D3(sim) => run_with(&scene, sim, bound),
    }
}

/// Compressed start: the invariants, with the elastic energy of the start as the energy bound
/// for `wcsph` and the start itself for `corrected` (see `EnergyBound`).
fn compressed(file: &str, solver: &str) {
    let bound = if solver == "wcsph" {
        EnergyBound::StartPlusElastic
    } else {
        EnergyBound::Start
    };
    case_with(file, solver, &[], bound);
}

#[test]
fn compressed_2d_wcsph() {
    compressed("compressed_2d.toml", "wcsph");
}

#[test]
fn compressed_2d_corrected() {
    compressed("compressed_2d.toml", "corrected");
}

#[test]
fn compressed_3d_wcsph() {
    compressed("compressed_3d.toml", "wcsph");
}

#[test]
fn compressed_3d_corrected() {
    compressed("compressed_3d.toml", "corrected");
}

/// Coincident start: the invariants, with the energy bound `EnergyBound::StartPlusTwinRelease`
/// for `wcsph` (the paper's kernel pair gives twins more kinetic energy than the equation of
/// state stored, see there) and the start itself for `corrected`, and at the end at most
/// `TWINS_LEFT` of the twins still closer than 0.1 dx (see `twins_separate`).
fn coincident(file: &str, solver: &str) {
    let bound = if solver == "wcsph" {
        EnergyBound::StartPlusTwinRelease
    } else {
        EnergyBound::Start
    };
    let trace = case_with(file, solver, &[], bound);
    twins_apart(file, &trace);
}

#[test]
fn coincident_2d_wcsph() {
    coincident("coincident_2d.toml", "wcsph");
}

#[test]
fn coincident_2d_corrected() {
    coincident("coincident_2d.toml", "corrected");
}

#[test]
fn coincident_3d_wcsph() {
    coincident("coincident_3d.toml", "wcsph");
}

#[test]
fn coincident_3d_corrected() {
    coincident("coincident_3d.toml", "corrected");
}

#[test]
fn thin_sheet_2d_wcsph() {
    case("thin_sheet_2d.toml", "wcsph");
}

#[test]
fn thin_sheet_2d_corrected() {
    case("thin_sheet_2d.toml", "corrected");
}

#[test]
fn thin_sheet_3d_wcsph() {
    case("thin_sheet_3d.toml", "wcsph");
}

#[test]
fn thin_sheet_3d_corrected() {
    case("thin_sheet_3d.toml", "corrected");
}

/// Isolated particle: the invariants with `run_case`'s energy bound, and every fluid density
/// the solver computed at least the particle's own term `m W(0)` (positive, and what a lone
/// particle's sum must give; 1e-6 relative for f32 sums).
fn isolated(file: &str, solver: &str) {
    let trace = case_with(file, solver, &[], EnergyBound::Start);
    assert!(
        trace.min_density >= trace.self_density * (1.0 - F32_ROUNDING),
        "{file} ({solver}): fluid density {} below the self term m W(0) = {}",
        trace.min_density,
        trace.self_density
    );
}

#[test]
fn isolated_2d_wcsph() {
    isolated("isolated_2d.toml", "wcsph");
}

#[test]
fn isolated_2d_corrected() {
    isolated("isolated_2d.toml", "corrected");
}

#[test]
fn isolated_3d_wcsph() {
    isolated("isolated_3d.toml", "wcsph");
}

#[test]
fn isolated_3d_corrected() {
    isolated("isolated_3d.toml", "corrected");
}

#[test]
fn viscous_low_2d_wcsph() {
    low_viscosity_run("viscous_low_2d.toml", "wcsph");
}

#[test]
fn viscous_low_2d_corrected() {
    low_viscosity_run("viscous_low_2d.toml", "corrected");
}

#[test]
fn viscous_low_3d_wcsph() {
    low_viscosity_run("viscous_low_3d.toml", "wcsph");
}

#[test]
fn viscous_low_3d_corrected() {
    low_viscosity_run("viscous_low_3d.toml", "corrected");
}

/// The 1e-6 Pa s run of `file` with `solver` under every invariant (energy bounded by the
/// start), made once per test process: `viscous_low_*` checks it and `viscous_high_*` compares
/// its front with it (under `cargo test` both share one process; the run is not repeated).
fn low_viscosity_run(file: &str, solver: &str) -> &'static Trace {
    static RUNS: [OnceLock<Trace>; 4] = [const { OnceLock::new() }; 4];
    let k = match (file, solver) {
        ("viscous_low_2d.toml", "wcsph") => 0,
        ("viscous_low_2d.toml", "corrected") => 1,
        ("viscous_low_3d.toml", "wcsph") => 2,
        ("viscous_low_3d.toml", "corrected") => 3,
        _ => panic!("no low-viscosity run {file} ({solver})"),
    };
    RUNS[k].get_or_init(|| case_with(file, solver, &[], EnergyBound::Start))
}

/// Largest share of the low-viscosity front's advance that the 10 Pa s front may reach by the
/// end time (0.25 s, before the low-viscosity front reaches the far wall). Measured (this
/// test's output): 0.446 (2D wcsph), 0.477 (2D corrected), 0.283 (3D wcsph), 0.338 (3D
/// corrected) at 10 Pa s.
const VISCOUS_FRONT_SHARE: f64 = 0.7;

/// 10 Pa s: the invariants with energy never above its start (viscosity only dissipates), and
/// the dam-break front's advance along x by the end time below `VISCOUS_FRONT_SHARE` of the
/// same scene's at 1e-6 Pa s (run here too, same solver).
fn viscous_high(high: &str, low: &str, solver: &str) {
    let slow = case_with(high, solver, &[], EnergyBound::Start);
    let fast = low_viscosity_run(low, solver);
    let advance = |t: &Trace| {
        let (end, start) = t.front(0);
        end - start
    };
    let (slow, fast) = (advance(&slow), advance(fast));
    println!(
        "{high} ({solver}): front advance {:.3} of the 1e-6 Pa s run's",
        slow / fast
    );
    assert!(
        slow < VISCOUS_FRONT_SHARE * fast,
        "{high} ({solver}): front advanced {slow} m, against {fast} m at 1e-6 Pa s"
    );
}

#[test]
fn viscous_high_2d_wcsph() {
    viscous_high("viscous_high_2d.toml", "viscous_low_2d.toml", "wcsph");
}

#[test]
fn viscous_high_2d_corrected() {
    viscous_high("viscous_high_2d.toml", "viscous_low_2d.toml", "corrected");
}

#[test]
fn viscous_high_3d_wcsph() {
    viscous_high("viscous_high_3d.toml", "viscous_low_3d.toml", "wcsph");
}

/// The 10 Pa s dam break in 3D under `corrected`. It needs the spiky density, the walls'
/// increments of either sign and the velocity solve: without them the first steps raise the
/// column, energy 1.04e-3 of |E0| above the start at step 2 (bound 1e-3).
#[test]
fn viscous_high_3d_corrected() {
    viscous_high("viscous_high_3d.toml", "viscous_low_3d.toml", "corrected");
}

/// A fixed step ten times the acoustic limit `cfl h / C` (twice the scene file's `h / C`) is
/// refused by the validator in one line that names `solver.dt`, the value and the bound `h / C`.
fn large_dt_refused(file: &str, dt: &str, bound: &str) {
    let path = format!("{}/scenes/hard/{file}", env!("CARGO_MANIFEST_DIR"));
    let shipped = load_scene(Path::new(&path), &[]).expect("the scene file's step h / C is accepted");
    let set = format!(
        "solver.dt={}",
        2.0 * shipped.smoothing_length / shipped.sound_speed
    );
    let err = load_scene(Path::new(&path), &[set]).expect_err("a step 10x too large is refused");
    let msg = err.to_string();
    assert_eq!(msg.lines().count(), 1, "{msg}");
    for part in ["solver.dt", dt, bound, "h / C"] {
        assert!(msg.contains(part), "{msg}: no {part:?}");
    }
}

#[test]
fn large_dt_2d_is_refused_by_the_validator() {
    large_dt_refused("large_dt_2d.toml", "0.002 s", "0.001");
}

#[test]
fn large_dt_3d_is_refused_by_the_validator() {
    large_dt_refused("large_dt_3d.toml", "0.004 s", "0.002");
}

/// `sph run` with ten times `cfl h / C` exits non-zero with one line on stderr naming
/// `solver.dt`, and leaves no output folder.
#[test]
fn large_dt_2d_is_refused_by_sph_run() {
    let scene = format!("{}/scenes/hard/large_dt_2d.toml", env!("CARGO_MANIFEST_DIR"));
    let out = std::env::temp_dir().join(format!("sph_hard_large_dt_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_sph"))
        .args(["run", &scene, "--set", "solver.dt=2e-3", "--out"])
        .arg(&out)
        .output()
        .expect("sph runs");
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "accepted: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("solver.dt"), "{err}");
    assert!(!out.exists(), "left {}", out.display());
}

/// At the largest allowed fixed step, `dt = h / C`, a step above the viscous limit
/// `0.125 (h/2)² ρ0 / μ` is cut to it (or to the force limit) at run time and recorded: no step
/// runs at the fixed value, none above the viscous limit, and the invariants hold with energy
/// never above its start.
fn large_dt_adapts(file: &str) {
    let path = format!("{}/scenes/hard/{file}", env!("CARGO_MANIFEST_DIR"));
    let scene = load_scene(Path::new(&path), &["solver.dt=1e-4".into()]).expect("hard scene");
    let bound = scene.smoothing_length / scene.sound_speed;
    let viscous = 0.125 * (0.5 * scene.smoothing_length).powi(2) * scene.rho0
        / scene
            .pair_terms
            .get(sph::model::pair_terms::PairTerm::Viscosity)
            .expect("viscous");
    assert!(
        viscous < bound,
        "the scene must put the viscous limit below h / C"
    );
    let trace = case_with(
        file,
        "wcsph",
        &[&format!("solver.dt={bound}")],
        EnergyBound::Start,
    );
    for (n, &(dt, limit)) in trace.steps.iter().enumerate() {
        assert!(
            dt <= viscous,
            "{file}: step {n}: dt = {dt} s above the viscous limit {viscous} s"
        );
        assert!(
            matches!(
                limit,
                TimeStepLimit::Viscosity
                    | TimeStepLimit::Force
                    | TimeStepLimit::SoundSpeed
                    | TimeStepLimit::EndTime
            ),
            "{file}: step {n}: limit {limit:?} at dt = {dt} s"
        );
    }
    assert!(trace.steps.iter().any(|s| s.1 == TimeStepLimit::Viscosity));
}

#[test]
fn large_dt_2d_at_the_bound_adapts_to_the_viscous_limit() {
    large_dt_adapts("large_dt_2d.toml");
}

#[test]
fn large_dt_3d_at_the_bound_adapts_to_the_viscous_limit() {
    large_dt_adapts("large_dt_3d.toml");
}

/// Share of the twins allowed still closer than 0.1 dx after 10 ms in `twins_separate`.
const TWINS_LEFT: f64 = 0.1;

/// The guard at `r = 0` itself: the coincident start's first 10 ms with `wcsph`, before the
/// splash reaches a wall, with the invariants and the energy bound of `coincident`. Twins left
/// without a direction feel bit-identical forces from every other particle and stay at
/// distance 0 forever; with `smoothing::pair_offset` at most `TWINS_LEFT` of them may still be
/// closer than 0.1 dx. Not all: a twin pair at the free surface whose summed density stays
/// below ρ0 has zero pressure (clamped, note 6) and nothing pushes it apart (measured: 0 of 56
/// pairs in 2D, 2 of 45 in 3D, both at the top surface, z ≈ 0.125 m).
fn twins_separate(file: &str) {
    let trace = case_with(
        file,
        "wcsph",
        &["solver.end_time=0.01"],
        EnergyBound::StartPlusTwinRelease,
    );
    twins_apart(file, &trace);
}

/// At most `TWINS_LEFT` of the start's twin pairs (pairs closer than 0.1 dx) still that close at
/// the end of `trace`.
fn twins_apart(file: &str, trace: &Trace) {
    let path = format!("{}/scenes/hard/{file}", env!("CARGO_MANIFEST_DIR"));
    let dx = load_scene(Path::new(&path), &[]).expect("hard scene").spacing;
    let twins = close_pairs(&trace.start, 0.1 * dx);
    let left = close_pairs(&trace.positions, 0.1 * dx);
    assert!(twins > 0, "{file}: no twins at the start");
    assert!(
        left as f64 <= TWINS_LEFT * twins as f64,
        "{file}: {left} of {twins} twin pairs still closer than 0.1 dx at the end"
    );
}

#[test]
fn coincident_2d_wcsph_twins_separate() {
    twins_separate("coincident_2d.toml");
}

#[test]
fn coincident_3d_wcsph_twins_separate() {
    twins_separate("coincident_3d.toml");
}

// ---------------------------------------------------------------------------------------------
// The long version (`cargo test --release -- --ignored`): the same invariants over longer runs
// and at finer spacing than CI can afford.

/// Water at rest for 10 s (2D) under `wcsph`: hydrostatic stability over 10x the CI run.
#[test]
#[ignore = "long: about 5 minutes in release on 2 cores"]
fn long_rest_2d_wcsph_10_s() {
    case_with(
        "rest_2d.toml",
        "wcsph",
        &["solver.end_time=10"],
        EnergyBound::Start,
    );
}

/// Water at rest for 10 s (2D) under `corrected`.
#[test]
#[ignore = "long: about 5 minutes in release on 2 cores"]
fn long_rest_2d_corrected_10_s() {
    case_with(
        "rest_2d.toml",
        "corrected",
        &["solver.end_time=10"],
        EnergyBound::Start,
    );
}

/// Water at rest for 2 s (3D) under both solvers: four times the CI run.
#[test]
#[ignore = "long: about 3 minutes in release on 2 cores"]
fn long_rest_3d_2_s() {
    for solver in ["wcsph", "corrected"] {
        case_with("rest_3d.toml", solver, &["solver.end_time=2"], EnergyBound::Start);
    }
}

/// The 10 m/s jet at half the spacing (5 mm, 4x the particles), both solvers.
#[test]
#[ignore = "long: about 10 minutes in release on 2 cores"]
fn long_jet_2d_at_half_the_spacing() {
    for solver in ["wcsph", "corrected"] {
        case_with(
            "jet_2d.toml",
            solver,
            &["particles.spacing=0.005"],
            EnergyBound::Start,
        );
    }
}

/// The largest fixed step validation accepts for `corrected` on the scene `file` with `sets`
/// (`sph::scene::validate::corrected_step_bound`), and a check that it is the largest: 1e-6
/// above it is refused.
fn corrected_bound(file: &str, sets: &[String]) -> f64 {
    let path = format!("{}/scenes/hard/{file}", env!("CARGO_MANIFEST_DIR"));
    let mut sets = sets.to_vec();
    sets.push("solver.kind=corrected".into());
    // A step far below any bound, in place of the scene file's own (`large_dt_*` give one).
    let small = [sets.clone(), vec!["solver.dt=1e-6".into()]].concat();
    let scene = load_scene(Path::new(&path), &small).expect("hard scene");
    let bound = corrected_step_bound(
        scene.smoothing_length,
        scene.gravity.as_deref(),
        &scene.fluid_boxes,
        &scene.solids,
    )
    .expect("gravity or an initial speed");
    sets.push(format!("solver.dt={}", bound * (1.0 + 1e-6)));
    load_scene(Path::new(&path), &sets).expect_err("a step above the bound is refused");
    bound
}

/// A fixed `corrected` step above the bound is refused by the validator in one line that names
/// `solver.dt`, the value, the bound and its formula.
fn corrected_large_dt_refused(file: &str, dt: &str, parts: &[&str]) {
    let path = format!("{}/scenes/hard/{file}", env!("CARGO_MANIFEST_DIR"));
    let sets = ["solver.kind=corrected".to_string(), format!("solver.dt={dt}")];
    let err = load_scene(Path::new(&path), &sets).expect_err("a step above the bound is refused");
    let msg = err.to_string();
    assert_eq!(msg.lines().count(), 1, "{msg}");
    for part in ["solver.dt", "corrected", "remove solver.dt"].iter().chain(parts) {
        assert!(msg.contains(part), "{msg}: no {part:?}");
    }
}

/// A 2 ms step: above `0.0125 sqrt(h / |g|)` = 0.564 ms (h = 0.02 m).
#[test]
fn large_dt_2d_corrected_is_refused_by_the_validator() {
    corrected_large_dt_refused(
        "large_dt_2d.toml",
        "0.002",
        &["0.002 s", "sqrt(h / |g|)", "0.000564"],
    );
}

/// 1 ms on the 10 m/s jet: above `0.1 h / |u|max` = 0.2 ms, below the gravity term.
#[test]
fn jet_2d_corrected_large_dt_is_refused_by_the_validator() {
    corrected_large_dt_refused(
        "jet_2d.toml",
        "0.001",
        &["0.001 s", "h / |u|max", "10 m/s", "0.0002 s", "0.000564"],
    );
}

/// `sph run --set solver.kind=corrected` on `large_dt_2d.toml` (its 1 ms step above the
/// corrected bound) exits non-zero with one line on stderr naming `solver.dt`, and leaves no
/// output folder.
#[test]
fn large_dt_2d_corrected_is_refused_by_sph_run() {
    let scene = format!("{}/scenes/hard/large_dt_2d.toml", env!("CARGO_MANIFEST_DIR"));
    let out = std::env::temp_dir().join(format!("sph_hard_large_dt_c_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_sph"))
        .args(["run", &scene, "--set", "solver.kind=corrected", "--out"])
        .arg(&out)
        .output()
        .expect("sph runs");
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "accepted: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("solver.dt") && err.contains("corrected"), "{err}");
    assert!(!out.exists(), "left {}", out.display());
}

/// `corrected` at the largest fixed step validation accepts on `file` (with `sets`): every
/// invariant of the module doc with energy never above its start, and every step at the fixed
/// value (the corrected solver keeps it; only the end time may shorten the last).
fn corrected_at_the_bound(file: &str, sets: &[&str]) {
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let bound = corrected_bound(file, &sets);
    let mut extra: Vec<&str> = sets.iter().map(|s| s.as_str()).collect();
    let dt = format!("solver.dt={bound}");
    extra.push(&dt);
    let trace = case_with(file, "corrected", &extra, EnergyBound::Start);
    for (n, &(step, limit)) in trace.steps.iter().enumerate() {
        assert!(
            (limit == TimeStepLimit::Fixed && step == bound)
                || (limit == TimeStepLimit::EndTime && step <= bound),
            "{file}: step {n}: dt = {step} s ({limit:?}), fixed {bound} s"
        );
    }
    eprintln!("{file} (corrected): fixed dt = {bound} s");
}

/// The 2D dam break at μ = 20 Pa s, `dt = 0.0125 sqrt(h / |g|)` = 0.564 ms (h = 0.02 m).
#[test]
fn large_dt_2d_corrected_at_the_bound() {
    corrected_at_the_bound("large_dt_2d.toml", &[]);
}

/// The 3D dam break at μ = 1e-6 Pa s, `dt = 0.0125 sqrt(h / |g|)` = 0.798 ms (h = 0.04 m): the
/// scene that sets the factor (it fails the energy bound at 1 ms).
#[test]
fn viscous_low_3d_corrected_at_the_bound() {
    corrected_at_the_bound("viscous_low_3d.toml", &[]);
}

/// The 10 m/s jet, `dt = 0.1 h / |u|max` = 0.2 ms, through the impact on the plate (end time
/// 0.06 s of the scene's 0.12 s, to keep the run short).
#[test]
fn jet_2d_corrected_at_the_bound() {
    corrected_at_the_bound("jet_2d.toml", &["solver.end_time=0.06"]);
}
