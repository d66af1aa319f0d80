//! The hard-case suite (`scenes/hard/`), each scene with `wcsph` and `corrected`, checked after
//! every step: every field finite and every fluid particle inside the domain (the solver's own
//! guards stop the run otherwise, which fails the test), no fluid particle inside a solid's
//! volume (the surface the scene gives, half a spacing outside the centres of the solid's
//! outermost particle layer), the fluid's mass unchanged, kinetic plus
//! potential energy never above its start by more than 1e-3 of the start's magnitude (the
//! scenes start at rest or in free flight, walls are fixed and every term dissipates or
//! conserves), and for `corrected` every stage's compression below δ.

use sph::fields::FLUID;
use sph::run::AnySimulation;
use sph::scene::validate::corrected_step_bound;
use sph::scene::{Scene, SolidShape, load_scene};
use sph::smoothing::Smoothing;
use sph::solver::Simulation;
use sph::solver::timestep::TimeStepLimit;
use std::path::Path;

/// Whether `x` lies more than `margin` inside solid `k` of the scene.
fn inside_solid(scene: &Scene, x: &[f64], margin: f64) -> Option<String> {
    for s in &scene.solids {
        let (lo, hi) = (&s.region.min, &s.region.max);
        let d = x.len();
        let inside_box =
            |lo: &[f64], hi: &[f64]| (0..d).all(|k| x[k] > lo[k] + margin && x[k] < hi[k] - margin);
        let hit = match s.shape {
            SolidShape::Box => inside_box(lo, hi),
            SolidShape::Container => {
                // The walls: a shell `layers` spacings thick around the inside box.
                let t = scene.wall_layers() as f64 * scene.spacing;
                let outer_lo: Vec<f64> = lo.iter().map(|v| v - t).collect();
                let mut outer_hi: Vec<f64> = hi.iter().map(|v| v + t).collect();
                if s.open_top {
                    outer_hi[d - 1] = hi[d - 1];
                }
                let in_shell = inside_box(&outer_lo, &outer_hi);
                // The inner faces belong to the water: a particle exactly on one is 0 deep, not
                // "more than margin" inside, as the guard (`KeepOutBox::push_out`) and the box
                // case above count it (measured: jet_3d corrected, a particle at x = 1.0 exactly
                // on the far wall's face after the no-slip walls changed its path).
                let in_water = (0..d).all(|k| x[k] >= lo[k] - margin && x[k] <= hi[k] + margin);
                in_shell && !in_water
            }
        };
        if hit {
            return Some(s.name.clone());
        }
    }
    None
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

/// Fails today: the first step builds the pressure from zero at the viscous step limit
/// (10 ms): its first stage is still at 7e-4 compression after 1,000 sweeps, and kinetic plus
/// potential energy rise by 0.019 J (0.37 % of |E0|; the centre of mass rises 0.12 mm and the
/// fluid gets 0.011 J of kinetic energy), then decay (−0.03 J by 1 s). A 1 ms step converges
/// every stage (at most 89 sweeps) but the energy still rises (+0.09 J by 0.05 s): the
/// correction turns its position changes into velocity `Δx/τ`, and a smaller `τ` makes that
/// noise larger. The start-up settle (`Simulation::settle`) finds nothing to move here.
/// Also measured: starting from the hydrostatic pressure (settle, then `P = ρ0 g depth`) the
/// first step rises more (+0.034 J); symplectic Euler instead of SSP-RK3 rises as much (0.43 %
/// by step 3). Without the sweeps' momentum (β = 0) the first three steps converge, every
/// interior particle stays within 1e-4 of ρ0 and the kinetic energy near 6e-5 J, but the
/// potential energy grows 1e-3 J per step: alternate layers rise ~40 µm and sink 2–13 µm, a
/// layering the density constraint cannot see. Letting interior particles carry negative
/// pressure (down to −50…−300 Pa) made it worse (0.4–0.9 %). The stages that hit the cap stall
/// at interior particles one or two spacings from the side walls (999.3–999.5 kg/m³ with
/// P > 0), where the walls' correction increments are never negative; allowing negative wall
/// increments converges every stage and keeps the potential energy flat, but the first step
/// still gains 7.7e-3 J of kinetic energy (1.56e-3 of |E0|). That energy is sideways noise,
/// not bulk motion: in the last stage the residual falls to 1.3e-4 by sweep 60, then grows to
/// 1.8e-3 by sweep 160 (heavy-ball sweeps with the spiky gradient are not a symmetric step, and
/// a mode that shuffles particles sideways grows), leaving 0.05 m/s sideways near the floor.
/// Measured fixes that failed elsewhere: the poly6 gradient (the density kernel's) in the
/// sweeps, with walls of either sign, converges every stage here (≤ 81 sweeps, first-step
/// kinetic energy 6e-5 J, pressure at the hydrostatic value), but the spiky force stage then
/// sees pressure noise the sweeps cannot: `rest_2d` blows up by step 10 and this case passes
/// the bound only until step 8; the poly6 gradient in the force stage too is stable in 2D and
/// unstable in 3D (pairing) by step 15; β = 0.6–0.9 or restarting the momentum when the
/// residual grows leaves stages at the cap. One kernel for density and every gradient
/// (Wendland C2, support h, as DualSPHysics and DFSPH codes use) keeps `rest_2d` within its
/// bound for 1 s, but here rises 0.35 % with a steady −0.03 m/s mean vertical velocity that
/// the positions do not follow (the stages' velocity, not a motion).
/// Fifth session: summing the density (18) with the spiky kernel (times the lattice factor
/// ΣW_poly6/ΣW_spiky, 0.817 in 3D, so the lattice mass still gives ρ0), the kernel whose
/// gradient the sweeps and the force stage use, makes the sweep operator symmetric. With wall
/// increments of either sign (wall pressure kept ≥ 0) and β = 0.9 this case, `viscous_high_3d`
/// and the property tests' free block then pass (every stage ≤ 78 sweeps, kinetic energy
/// ~1e-4 J, energy never above the start). But in 2D the floor pressure then wanders with the
/// tolerance: `rest_2d`'s mean bottom pressure swings 100–6,600 Pa around the hydrostatic 2,845
/// at δ = 1e-4 and 2,300–3,600 Pa at δ = 1e-5; the sloshing tank at rest holds 8.2e-3 J/kg
/// (`sloshing_2d_corrected` fails) and the two-layer tank is 6.6 % off (limit 3 %). Walls that
/// give back only a fifth of a negative increment: this case 0.16 % at step 2, two-layer 4.0 %.
/// Wall increments clamped at zero (as now) with the spiky density: this case 0.19 % at step 2,
/// two-layer 3.6 % (1.55 % with poly6). Setting each wall to the extrapolation (with gravity) of
/// the fluid's current pressure in every sweep does not calm 2D either. The wandering is the
/// tolerance's: with the spiky density and walls of either sign at δ = 1e-5 the two-layer tank
/// is 1.75 % off (passes) and this case stays flat (kinetic energy ~3e-5 J, ≤ 87 sweeps), but
/// the sloshing test runs at the README's recommended δ = 1e-3, where the wandering is worst:
/// landing it needs a stopping rule or pressure control that bounds the drift whatever δ.
/// Sixth session: the wandering is a standing vertical wave of the whole column, not noise.
/// `rest_2d`, sampled every 50 steps (dt = 2.1 ms) over 2 s: the carried pressure rises and
/// falls by the same amount at every depth (spiky density, walls of either sign: bottom
/// 276–6,331 Pa, mid-depth 0–4,257 Pa against 2,845 and 1,471 hydrostatic) while the mean
/// vertical velocity swings ±0.016 m/s and the centre of mass barely moves. Today's code has the
/// same wave, smaller (bottom 2,480–3,544 Pa, ±5.6e-3 m/s). The loop only reacts to density
/// errors, so a carried pressure that is too high lifts the column until the floor layer
/// expands past δ, one layer per stage: the correction behaves like a fluid whose sound speed
/// is about dx/dt, and the period, ~0.2 s, matches 4H/(dx/dt). Always running at least 1 or 4
/// sweeps changes nothing. A second solve after each stage's correction, on the velocities at
/// fixed positions (the same sweeps with `ρ0 + τ dρ/dt` in place of ρ, and `Δu = τ a` without
/// moving: a divergence-free projection as in DFSPH), damps the wave: with the spiky density
/// the bottom stays within 2,443–3,353 Pa after 0.2 s (2,923–2,929 Pa from 1.1 to 1.5 s) and
/// mid-depth within 1,150–1,793 Pa, and this case stays at most 2.7e-4 |E0| above its start
/// (sampled every 5 steps). With the poly6 density that solve blows up in 3D (a
/// particle left the domain at step 107). What the carried pressure keeps of the velocity
/// solve's increments decides the rest: all of them count an impact twice (the thrown block's
/// starting residual rose from 0.02 to 0.64, 8.4 and 186 over nine steps), none let the pressure drift (bottom
/// 9,800 Pa by 1.5 s), only the decreases, `P = min(P, P_start)`, with momentum 0.9 and the
/// solve given up (velocity and pressure restored) when its residual doubles or after 200
/// sweeps, passes this case, `viscous_high_3d_corrected`, every other hard case, both sloshing
/// tanks, the two-layer tank, the free block and the thrown block at 0.25 h/|u| (CPU and CUDA
/// with shim tests: local branch `experiment/velocity-solve-full`). It fails the dam break
/// (`tests/dam_break.rs`): the front runs 11.1 % ahead of Martin & Moyce, against 4.8 % today
/// (`sph run scenes/dam_break_2d.toml --end-time 0.48`) and 5.4 % and 5.3 % for wcsph at C = 100
/// and 200 m/s (α C kept at 1.75 m/s), the incompressible limit of the same discretisation. The cause is the solve's density `ρ0 + τ dρ/dt`: a free-surface particle
/// (P = 0, density well below ρ0) that is being compressed counts as compressed and is pushed
/// apart (compression only, everywhere: 14.3 %). From its own density `ρ + τ dρ/dt` the front is
/// right (5.4 %) but the interior's pressure drains (`rest_2d` bottom 32–920 Pa over 2 s) (the solve then undoes
/// expansions within δ); from ρ0 where P > 0 and `min(ρ, ρ0)` where P = 0 the front is right
/// (5.2 %) but the wave is back (`rest_2d` bottom 1,881–3,452 Pa) and the two-layer tank is
/// 6.7 % low. Still open.
#[test]
#[ignore = "known failure: the start-up step raises KE + PE by 0.37 % of |E0| (limit 0.1 %)"]
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
// Issue 4, the remaining cases: compressed and coincident starts, thin sheets, isolated
// particles, viscosity extremes, a step too large for wcsph. Every case goes through
// `case_with` / `run_with`, which check the invariants of the module doc with the energy bound
// given per case (`case` uses `EnergyBound::Start`).

/// How `run_with` bounds the fluid's kinetic plus potential energy after every step.
#[derive(Clone, Copy, Debug, PartialEq)]
enum EnergyBound {
    /// Never above the start by more than 1e-3 of its magnitude (closed scenes
    /// whose walls are fixed and whose every term dissipates or conserves).
    Start,
    /// `wcsph` from a start above `ρ0`: never above the start plus the elastic energy of the
    /// equation of state (19) in the initial densities, `Σ m C² (ln(ρ/ρ0) + ρ0/ρ − 1)` over
    /// particles with `ρ > ρ0` (the work `∫ p/ρ² dρ` of `p = C²(ρ − ρ0)`, clamped at zero below
    /// `ρ0`), plus `ELASTIC_SLACK` of it (the pressure gradient uses the spiky kernel and the
    /// density the poly6 one, so the discrete energy is conserved only approximately), plus 1e-3
    /// of the start's magnitude.
    StartPlusElastic,
    /// No energy bound. Used only for `corrected` from a start above `ρ0`: its projection turns
    /// the compression it removes into a velocity `Δx/τ` (README, note 7), which depends on the
    /// step `τ`, not on a stored energy (an incompressible fluid has none).
    Unbounded,
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
        EnergyBound::Start => Some(e0 + 1e-3 * e0.abs().max(1e-12)),
        EnergyBound::StartPlusElastic => {
            Some(e0 + (1.0 + ELASTIC_SLACK) * elastic_energy(scene, &sim) + 1e-3 * e0.abs().max(1e-12))
        }
        EnergyBound::Unbounded => None,
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
            let x: Vec<f64> = f.position[i].iter().map(|c| f64::from(*c)).collect();
            if let Some(solid) = inside_solid(scene, &x, margin) {
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
    // The guard is a last resort: report how often it acted (README "Hard cases").
    eprintln!(
        "{name} ({solver}): {} steps, {} no-penetration pushes",
        trace.steps.len(),
        sim.stats().keep_out_pushes
    );
    if let Some(c) = sim.config().correction {
        let s = sim.stats().correction;
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

/// The energy bound of a start above `ρ0` for `solver` (see `EnergyBound`).
fn compressed_bound(solver: &str) -> EnergyBound {
    if solver == "wcsph" {
        EnergyBound::StartPlusElastic
    } else {
        EnergyBound::Unbounded
    }
}

/// Compressed start: the invariants, with the elastic energy of the start as the energy bound
/// for `wcsph` (none for `corrected`, see `EnergyBound::Unbounded`).
fn compressed(file: &str, solver: &str) {
    case_with(file, solver, &[], compressed_bound(solver));
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

/// Coincident start: the invariants without an energy bound, and at the end at most
/// `TWINS_LEFT` of the twins still closer than 0.1 dx (see `twins_separate`). No energy bound,
/// for either solver: the elastic bound of `EnergyBound::StartPlusElastic` does not hold for
/// twins under `wcsph` (measured in `coincident_2d_wcsph_energy`): a twin pair feels the spiky
/// gradient's near-peak repulsion while the poly6 density, flat at `r = 0`, hardly falls as they
/// part, so the pair gains more kinetic energy than the equation of state stored.
fn coincident(file: &str, solver: &str) {
    let trace = case_with(file, solver, &[], EnergyBound::Unbounded);
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
        trace.min_density >= trace.self_density * (1.0 - 1e-6),
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
    case("viscous_low_2d.toml", "wcsph");
}

#[test]
fn viscous_low_2d_corrected() {
    case("viscous_low_2d.toml", "corrected");
}

#[test]
fn viscous_low_3d_wcsph() {
    case("viscous_low_3d.toml", "wcsph");
}

#[test]
fn viscous_low_3d_corrected() {
    case("viscous_low_3d.toml", "corrected");
}

/// Largest share of the low-viscosity front's advance that the 10 Pa s front may reach by the
/// end time (0.25 s, before the low-viscosity front reaches the far wall). Measured with
/// `sph run` and a front probe: 0.52 (2D wcsph), 0.55 (2D corrected), 0.38 (3D wcsph), 0.44
/// (3D corrected) at 10 Pa s; at 1 Pa s 0.86, 0.89, 0.76, 0.85, so the check fails if the
/// viscous term were ten times too weak. With (17) scaled by 1/λ and no-slip walls (issue 7):
/// 0.446, 0.464, 0.283 at 10 Pa s (this test's output; 3D corrected does not get that far).
const VISCOUS_FRONT_SHARE: f64 = 0.7;

/// 10 Pa s: the invariants with energy never above its start (viscosity only dissipates), and
/// the dam-break front's advance along x by the end time below `VISCOUS_FRONT_SHARE` of the
/// same scene's at 1e-6 Pa s (run here too, same solver).
fn viscous_high(high: &str, low: &str, solver: &str) {
    let slow = case_with(high, solver, &[], EnergyBound::Start);
    let fast = case_with(low, solver, &[], EnergyBound::Start);
    let advance = |t: &Trace| {
        let (end, start) = t.front(0);
        end - start
    };
    let (slow, fast) = (advance(&slow), advance(&fast));
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

/// Fails today: kinetic plus potential energy at step 2 is 0.995857 J, 1.04e-3 above the start's
/// 0.994819 J (bound 1e-3): the corrected solver's first steps of the 10 Pa s dam break raise
/// the column (the 1e-6 Pa s case stays below the bound). The front check is not reached. (With
/// the viscosity's zero-velocity walls and no lattice scale, before issue 7's viscosity fixes,
/// the rise was 1.6e-3: 0.99643 J.)
#[test]
#[ignore = "known failure: energy 1.04e-3 above the start at step 2 (bound 1e-3)"]
fn viscous_high_3d_corrected() {
    viscous_high("viscous_high_3d.toml", "viscous_low_3d.toml", "corrected");
}

/// The scene file's fixed step, ten times the acoustic limit `cfl h / C`, is refused by the
/// validator in one line that names `solver.dt`, the value and the bound `h / C`.
fn large_dt_refused(file: &str, dt: &str, bound: &str) {
    let path = format!("{}/scenes/hard/{file}", env!("CARGO_MANIFEST_DIR"));
    let err = load_scene(Path::new(&path), &[]).expect_err("a step 10x too large is refused");
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

/// `sph run` on the scene exits non-zero with one line on stderr naming `solver.dt`, and leaves
/// no output folder.
#[test]
fn large_dt_2d_is_refused_by_sph_run() {
    let scene = format!("{}/scenes/hard/large_dt_2d.toml", env!("CARGO_MANIFEST_DIR"));
    let out = std::env::temp_dir().join(format!("sph_hard_large_dt_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_sph"))
        .args(["run", &scene, "--out"])
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
    let viscous =
        0.125 * (0.5 * scene.smoothing_length).powi(2) * scene.rho0 / scene.viscosity.expect("viscous");
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

/// The elastic bound of `EnergyBound::StartPlusElastic` on the 2D coincident start with
/// `wcsph`. Fails: kinetic plus potential energy reaches 422 J/m at step 3 against the bound
/// 339 J/m (start 20 J/m plus 1.1 times the 289 J/m of elastic energy in the twins' densities);
/// see `coincident` for why.
#[test]
#[ignore = "known failure: energy 422 J/m at step 3, above start + elastic energy (339 J/m)"]
fn coincident_2d_wcsph_energy() {
    case_with("coincident_2d.toml", "wcsph", &[], EnergyBound::StartPlusElastic);
}

/// Share of the twins allowed still closer than 0.1 dx after 10 ms in `twins_separate`.
const TWINS_LEFT: f64 = 0.1;

/// The guard at `r = 0` itself: the coincident start's first 10 ms with `wcsph`, before the
/// splash reaches a wall, with the invariants (no energy bound, see `coincident`). Twins left
/// without a direction feel bit-identical forces from every other particle and stay at
/// distance 0 forever; with `smoothing::pair_offset` at most `TWINS_LEFT` of them may still be
/// closer than 0.1 dx. Not all: a twin pair at the free surface whose summed density stays
/// below ρ0 has zero pressure (clamped, note 6) and nothing pushes it apart (measured: 0 of 56
/// pairs in 2D, 2 of 45 in 3D, both at the top surface, z ≈ 0.125 m).
fn twins_separate(file: &str) {
    let trace = case_with(file, "wcsph", &["solver.end_time=0.01"], EnergyBound::Unbounded);
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

/// Water at rest for 10 s (2D) under `wcsph`: hydrostatic stability over 5x the CI run.
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

/// The scene file's 2 ms step: above `0.0125 sqrt(h / |g|)` = 0.564 ms (h = 0.02 m).
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

/// `sph run --set solver.kind=corrected` on `large_dt_2d.toml` (its 2 ms step above the
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
