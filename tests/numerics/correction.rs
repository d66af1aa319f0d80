//! Property tests of the position correction, eqs. (23)–(24) (PAPER.md section 2, notes 5–8), on
//! random fluid blocks in 2D and 3D, built directly from `SimConfig` and particle positions.
//!
//! Each random case is a block of 10–16 (2D) or 6–8 (3D) particles per axis on a lattice of
//! spacing `dx ∈ [0.005, 0.05)` m (`h = 2 dx`), every coordinate jittered by up to 0.3 `dx`, with
//! velocities of up to 0.5–1 m/s (a random bulk part plus a random per-particle part), a fixed
//! step log-uniform over three decades below `dx / speed` (the largest moves a particle by one
//! spacing), gravity on or off, with or without a closed container of `ceil(h/dx)` wall layers one
//! empty lattice row away from the block, `δ = 1e-4` (or `1e-3` in a quarter of the cases), SSP-RK3
//! (symplectic Euler in a quarter of the cases), `strict`, a 2000-iteration cap, `ω = 0.5`.
//! After each of 1–3 steps:
//!
//! 1. The step returns `Ok` (strict: a stage that does not converge is an error) and the
//!    compression `max((ρ_i − ρ0)/ρ0, 0)` of every fluid particle is below `δ` + 2e-6, with `ρ_i`
//!    from a brute-force O(N²) sum of (18) over all particles in f64 (not the solver's density),
//!    with the corrected solver's density kernel (`sph::physics::density`).
//!    The slack covers the solver's f32 sum: each of its ≤ 60 terms rounds by at most
//!    `2^-24 ρ`, so it may differ from the f64 sum by up to ~4e-6 ρ0 in the worst case and by
//!    `√n 2^-24 ≈ 5e-7` typically; measured: at most 2.8e-7.
//! 2. Positions and velocities are finite, the particle count is unchanged, every id is present
//!    exactly once.
//! 3. With the container, every fluid particle lies strictly inside the box spanned by the centres
//!    of the innermost wall layer.
//! 4. Momentum without walls: `P(t) − P(0) = M g t`. Every pair term is antisymmetric, so this
//!    holds to f32 rounding: 1e-5 of `M |u|max` (`|u|max` the largest speed seen; measured
//!    ≤ 5.5e-8).
//!
//! With walls, `P(t) − P(0) = Σ_steps (M g − Σ_solids F_solid) dt`: the walls' share of every
//! pair term is summed exactly (the correction's sweep by sweep), so this holds to 1e-3 of the
//! largest impulse plus 1e-5 `M |u|max` (f32 pair terms summed in f64).
//!
//! The largest random step is one spacing per step at the block's speed and, with gravity, the
//! solver's own force limit `0.25 sqrt(h/g)`: beyond it gravity alone carries the bottom layer
//! through both wall layers in one step, which no position correction can undo.
//!
//! One ignored test reproduces a defect these properties found that is still open (robustness
//! issue; run it with `-- --ignored`, its doc says what happens): a block at rest on a floor
//! with no dissipation at all and a step nine times what validation accepts does not quite stay
//! at rest. Two more inputs they found (a block thrown at a wall at 0.25 h/|u|, and a free block
//! at one spacing per step, both beyond the accepted step) are kept as named tests and pass
//! (docs/method.md, "The position correction"). The solver gets no solid volumes here, so the
//! no-penetration guard (`boundary::keep_out`) does not act: these properties test the
//! correction and the particle boundary alone. One deterministic test gives it the guard, as a
//! scene run has: the thrown block at the largest step validation accepts.

use crate::common::tolerance::{CORRECTION_WALL_BALANCE, PAIRWISE_MOMENTUM, THROWN_BLOCK_BALANCE};
use proptest::prelude::*;
use sph::boundary::keep_out::KeepOutBox;
use sph::fields::FLUID;
use sph::math::{Real, Vector};
use sph::physics::lattice::lattice_spiky_scale;
use sph::scene::wall_layers;
use sph::smoothing::Smoothing;
use sph::solver::{Correction, Integrator, SimConfig, Simulation};

/// Rest density [kg/m³].
const RHO0: f64 = 1000.0;
/// Gravity [m/s²], along minus the last axis.
const G: f64 = 9.81;
/// Largest jitter of a fluid particle off its lattice site, per coordinate, in units of `dx`.
const JITTER: f64 = 0.3;
/// Empty lattice rows between the fluid block and the container's innermost wall layer.
const GAP: i64 = 1;
/// Allowance on the brute-force compression for the solver's f32 density sum (module doc, 1).
const COMPRESSION_SLACK: f64 = 2e-6;

/// A small deterministic generator (splitmix64), seeded by proptest.
struct SplitMix(u64);

impl SplitMix {
    /// Uniform in `[0, 1)`.
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[-1, 1)`.
    fn symmetric(&mut self) -> f64 {
        2.0 * self.unit() - 1.0
    }
}

/// One random scenario.
#[derive(Clone, Debug)]
struct Case {
    /// Lattice spacing [m]; `h = 2 dx`.
    dx: f64,
    /// Fluid particles per axis (the first `D` entries are used).
    block: [i64; 3],
    /// Largest initial particle speed [m/s].
    speed: f64,
    /// Fixed time step [s].
    dt: f64,
    /// Gravity along minus the last axis.
    gravity: bool,
    /// A closed container around the block.
    walls: bool,
    /// Tolerance `δ` of (24).
    delta: f64,
    /// Steps to take.
    steps: usize,
    /// Time integrator.
    integrator: Integrator,
    /// Seed of the jitter and the velocities.
    seed: u64,
}

/// Random cases in dimension `dim` (module doc).
fn cases(dim: usize) -> impl Strategy<Value = Case> {
    let (lo, hi) = if dim == 2 { (10i64, 16i64) } else { (6, 8) };
    (
        0.005f64..0.05,
        [lo..=hi, lo..=hi, lo..=hi],
        0.5f64..1.0,
        0.0f64..3.0,
        any::<bool>(),
        any::<bool>(),
        prop::bool::weighted(0.25),
        1usize..=3,
        prop::bool::weighted(0.25),
        any::<u64>(),
    )
        .prop_map(
            |(dx, block, speed, decades, gravity, walls, loose, steps, euler, seed)| Case {
                dx,
                block,
                speed,
                // Largest step: one spacing per step at the block's speed, and with gravity the
                // solver's own force limit 0.25 sqrt(h/g) (h = 2 dx; beyond it gravity alone moves
                // the bottom layer through the two wall layers in one step).
                dt: if gravity {
                    (dx / speed).min(0.25 * (2.0 * dx / G).sqrt())
                } else {
                    dx / speed
                } * 10f64.powf(-decades),
                gravity,
                walls,
                delta: if loose { 1e-3 } else { 1e-4 },
                steps,
                integrator: if euler {
                    Integrator::SymplecticEuler
                } else {
                    Integrator::Rk3
                },
                seed,
            },
        )
}

/// Lattice site `(idx + 1/2) dx` [m].
fn site<const D: usize>(idx: &[i64; D], dx: f64) -> Vector<D> {
    Vector::<D>::from_fn(|k, _| ((idx[k] as f64 + 0.5) * dx) as Real)
}

/// Calls `f` for every lattice index in `[lo, hi)` (per axis).
fn for_each_index<const D: usize>(lo: [i64; D], hi: [i64; D], mut f: impl FnMut(&[i64; D])) {
    if (0..D).any(|k| lo[k] >= hi[k]) {
        return;
    }
    let mut idx = lo;
    loop {
        f(&idx);
        let mut axis = 0;
        loop {
            if axis == D {
                return;
            }
            idx[axis] += 1;
            if idx[axis] < hi[axis] {
                break;
            }
            idx[axis] = lo[axis];
            axis += 1;
        }
    }
}

/// Wall particles of a container whose inside is the lattice index box `[lo, hi)`:
/// `ceil(h/dx)` layers on every side, as `scene::generate` lays them out; no top when
/// `open_top` (last axis = vertical).
fn container<const D: usize>(lo: [i64; D], hi: [i64; D], dx: f64, h: f64, open_top: bool) -> Vec<Vector<D>> {
    let layers = wall_layers(h, dx) as i64;
    let mut outer_hi = hi.map(|v| v + layers);
    if open_top {
        outer_hi[D - 1] = hi[D - 1];
    }
    let mut walls = Vec::new();
    for_each_index(lo.map(|v| v - layers), outer_hi, |idx| {
        if (0..D).any(|k| idx[k] < lo[k] || idx[k] >= hi[k]) {
            walls.push(site(idx, dx));
        }
    });
    walls
}

/// The corrected solver's settings: `h = 2 dx`, fixed step `dt`, strict, 2000 iterations.
fn config<const D: usize>(
    dx: f64,
    dt: f64,
    gravity: bool,
    delta: f64,
    integrator: Integrator,
) -> SimConfig<D> {
    SimConfig::<D> {
        spacing: dx,
        h: 2.0 * dx,
        rho0: RHO0,
        // The corrected solver does not use (19): a real sound speed adds no stiffness (note 5).
        sound_speed: 1500.0,
        pair_terms: sph::model::pair_terms::PairTermSettings::none(),
        gravity: gravity.then(|| {
            let mut g = Vector::<D>::zeros();
            g[D - 1] = -G as Real;
            g
        }),
        gravity_ramp: 0.0,
        angular_velocity: None,
        rotation_centre: Vector::zeros(),
        surface_tension: None,
        artificial_viscosity_wall_factor: 1.0,
        density_diffusion: None,
        periodic: sph::periodic::PeriodicAxes::NONE,
        dt: Some(dt),
        cfl: 0.2,
        domain_min: Vector::<D>::repeat(-100.0),
        domain_max: Vector::<D>::repeat(100.0),
        integrator,
        correction: Some(Correction {
            delta,
            max_iterations: 2000,
            strict: true,
            relaxation: 0.5,
            warm_start: false,
        }),
        on_escape: Default::default(),
        damping_zone: None,
        gradient_moment: sph::model::GradientMoment::Measured,
    }
}

/// Lower and upper corners [m] of the box spanned by the centres of a container's innermost
/// wall layer.
type InnerBox<const D: usize> = ([f64; D], [f64; D]);

/// A case ready to run: the simulation and, with a container, its inner box.
fn setup<const D: usize>(case: &Case) -> (Simulation<D>, Option<InnerBox<D>>) {
    let mut rng = SplitMix(case.seed);
    let dx = case.dx;
    let n: [i64; D] = std::array::from_fn(|k| case.block[k]);
    // Each component in [-1, 1) times size/√D, so the magnitude stays below `size`.
    let random_vector = |rng: &mut SplitMix, size: f64| {
        Vector::<D>::from_fn(|_, _| rng.symmetric() as Real) * (size / (D as f64).sqrt()) as Real
    };
    let bulk = random_vector(&mut rng, 0.5 * case.speed);
    let (mut x, mut u) = (Vec::new(), Vec::new());
    for_each_index([0; D], n, |idx| {
        let jitter = Vector::<D>::from_fn(|_, _| (JITTER * dx * rng.symmetric()) as Real);
        x.push(site(idx, dx) + jitter);
        u.push(bulk + random_vector(&mut rng, 0.5 * case.speed));
    });
    let config = config::<D>(dx, case.dt, case.gravity, case.delta, case.integrator);
    let (solids, inner) = if case.walls {
        let (lo, hi) = ([-GAP; D], n.map(|v| v + GAP));
        let walls = container(lo, hi, dx, config.h, false);
        let inner = (
            std::array::from_fn(|k| (lo[k] as f64 - 0.5) * dx),
            std::array::from_fn(|k| (hi[k] as f64 + 0.5) * dx),
        );
        (vec![("container".to_string(), walls)], Some(inner))
    } else {
        (Vec::new(), None)
    };
    let sim = Simulation::new(config, &x, &u, &solids).expect("valid setup");
    (sim, inner)
}

/// Largest compression `max((ρ_i − ρ0)/ρ0, 0)` over fluid particles and that particle's id, with
/// `ρ_i` from a brute-force O(N²) sum of eq. (18) over all particles (fluid and solid), in f64,
/// with the corrected solver's kernel (`sph::physics::density`: the spiky kernel (21) times the
/// lattice factor that makes a lattice particle sum `ρ0`) and each particle's own mass:
/// independent of the solver's grid and of its density field.
fn max_compression_naive<const D: usize>(sim: &Simulation<D>) -> (f64, u32) {
    let f = &sim.fields;
    let kernel = Smoothing::<D>::new(sim.config().h as Real).expect("2D or 3D");
    let scale = lattice_spiky_scale(&kernel, sim.config().spacing);
    let mut worst = (0.0, u32::MAX);
    for i in (0..f.len()).filter(|&i| f.kind[i] == FLUID) {
        let rho: f64 = (0..f.len())
            .map(|j| {
                let r = (f.position[i] - f.position[j]).norm();
                f64::from(f.mass[j]) * scale * f64::from(kernel.w_spiky(r))
            })
            .sum();
        let compression = ((rho - RHO0) / RHO0).max(0.0);
        if compression > worst.0 {
            worst = (compression, f.id[i]);
        }
    }
    worst
}

/// Largest fluid speed [m/s].
fn max_speed<const D: usize>(sim: &Simulation<D>) -> f64 {
    let f = &sim.fields;
    (0..f.len())
        .filter(|&i| f.kind[i] == FLUID)
        .map(|i| f64::from(f.velocity[i].norm()))
        .fold(0.0, f64::max)
}

/// Properties 1–3 of the module doc for the state after step `step`.
fn check_state<const D: usize>(
    sim: &Simulation<D>,
    step: usize,
    delta: f64,
    count: usize,
    inner: Option<InnerBox<D>>,
) -> Result<(), TestCaseError> {
    // 1: eq. (24) with note 6, measured independently of the solver.
    let (compression, id) = max_compression_naive(sim);
    prop_assert!(
        compression < delta + COMPRESSION_SLACK,
        "step {step}: particle {id} compressed by {compression:.4e}, delta {delta:e}"
    );
    prop_assert_eq!(sim.stats().correction.unconverged_stages, 0);

    // 2: a finite state, nothing lost or duplicated.
    let f = &sim.fields;
    prop_assert_eq!(f.len(), count);
    prop_assert_eq!(f.kind.iter().filter(|&&k| k == FLUID).count(), sim.fluid_count());
    for i in 0..f.len() {
        prop_assert!(
            f.position[i]
                .iter()
                .chain(f.velocity[i].iter())
                .all(|c| c.is_finite()),
            "step {step}: particle {} has a non-finite state",
            f.id[i]
        );
    }
    let mut ids = f.id.clone();
    ids.sort_unstable();
    prop_assert!(
        ids.iter().copied().eq(0..count as u32),
        "step {step}: ids are not a permutation"
    );

    // 3: no fluid on or beyond the innermost wall layer.
    if let Some((lo, hi)) = inner {
        for i in (0..f.len()).filter(|&i| f.kind[i] == FLUID) {
            let x = &f.position[i];
            prop_assert!(
                (0..D).all(|k| f64::from(x[k]) > lo[k] && f64::from(x[k]) < hi[k]),
                "step {step}: fluid particle {} at {:?} is outside the container's inside {:?}..{:?}",
                f.id[i],
                x.as_slice(),
                lo,
                hi
            );
        }
    }
    Ok(())
}

/// Runs `case`, checking properties 1–3 after every step and 4 at the end. With a container the
/// momentum balance (module doc) is checked only when `wall_tolerance = Some((r, a))`, to `r`
/// times the largest impulse plus `a` times `M |u|max`.
fn check_case<const D: usize>(case: &Case, wall_tolerance: Option<(f64, f64)>) -> Result<(), TestCaseError> {
    let (mut sim, inner) = setup::<D>(case);
    let count = sim.fields.len();
    let mass = sim.fluid_mass();
    let p0 = sim.fluid_momentum();
    let mut gravity_impulse = [0.0f64; 3];
    let mut wall_impulse = [0.0f64; 3];
    let mut speed = max_speed(&sim);
    for step in 0..case.steps {
        let report = sim.step(f64::INFINITY);
        prop_assert!(report.is_ok(), "step {step}: {:?}", report.err());
        let dt = report.map(|r| r.dt).unwrap_or_default();
        prop_assert_eq!(dt, case.dt);
        if case.gravity {
            gravity_impulse[D - 1] -= mass * G * dt;
        }
        for force in sim.solid_forces() {
            for k in 0..3 {
                wall_impulse[k] += force[k] * dt;
            }
        }
        speed = speed.max(max_speed(&sim));
        check_state(&sim, step, case.delta, count, inner)?;
    }

    // 4: ΔP = Σ (M g − F_walls) dt.
    let p1 = sim.fluid_momentum();
    let largest = largest_impulse::<D>(p0, p1, gravity_impulse, wall_impulse);
    let tolerance = match (case.walls, wall_tolerance) {
        (false, _) => PAIRWISE_MOMENTUM * mass * speed,
        (true, Some((relative, floor))) => relative * largest + floor * mass * speed,
        (true, None) => return Ok(()),
    };
    check_balance::<D>(p0, p1, gravity_impulse, wall_impulse, tolerance, "")
}

/// The largest of the gravity impulse, the wall impulse and the fluid momentum change
/// `p1 − p0` on any axis: the scale of property 4's tolerance.
fn largest_impulse<const D: usize>(p0: [f64; 3], p1: [f64; 3], gravity: [f64; 3], wall: [f64; 3]) -> f64 {
    (0..D)
        .map(|k| gravity[k].abs().max(wall[k].abs()).max((p1[k] - p0[k]).abs()))
        .fold(0.0, f64::max)
}

/// Property 4 on each axis: the fluid momentum change `p1 − p0` is the gravity impulse minus
/// the wall impulse to `tolerance`; `what` leads the message.
fn check_balance<const D: usize>(
    p0: [f64; 3],
    p1: [f64; 3],
    gravity: [f64; 3],
    wall: [f64; 3],
    tolerance: f64,
    what: &str,
) -> Result<(), TestCaseError> {
    for k in 0..D {
        let change = p1[k] - p0[k];
        let error = (change - (gravity[k] - wall[k])).abs();
        prop_assert!(
            error <= tolerance,
            "{what}axis {k}: fluid momentum change {change:.6e}, gravity impulse {:.6e}, wall \
             impulse {:.6e}: error {error:.3e} > tolerance {tolerance:.3e}",
            gravity[k],
            wall[k]
        );
    }
    Ok(())
}

/// A lattice block (no jitter) of `n` particles per axis with spacing `dx`, from the origin.
fn lattice_block<const D: usize>(n: [i64; D], dx: f64) -> Vec<Vector<D>> {
    let mut x = Vec::new();
    for_each_index([0; D], n, |idx| x.push(site::<D>(idx, dx)));
    x
}

/// Steps `sim` `steps` times: each step succeeds (`what` leads the message) and leaves
/// properties 1–3 (3 in `inner`).
fn run_checked<const D: usize>(
    sim: &mut Simulation<D>,
    steps: usize,
    delta: f64,
    inner: Option<InnerBox<D>>,
    what: &str,
) {
    let count = sim.fields.len();
    for step in 0..steps {
        let report = sim.step(f64::INFINITY);
        assert!(report.is_ok(), "{what}step {step}: {:?}", report.err());
        expect_ok(check_state(sim, step, delta, count, inner));
    }
}

proptest! {
    // Random cases each local run (CI fixes the seed, `.ci/run`): failures found are kept as
    // named tests (`block_against_walls_in_3d_stays_off_the_wall_layer`,
    // `large_step_with_gravity_in_2d_converges`,
    // `free_block_at_one_spacing_per_step_in_2d_converges`).
    #![proptest_config(ProptestConfig { cases: 192, ..ProptestConfig::default() })]

    #[test]
    fn corrected_steps_leave_no_compression_and_balance_momentum_in_2d(case in cases(2)) {
        check_case::<2>(&case, Some(CORRECTION_WALL_BALANCE))?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn corrected_steps_leave_no_compression_and_balance_momentum_in_3d(case in cases(3)) {
        check_case::<3>(&case, Some(CORRECTION_WALL_BALANCE))?;
    }
}

/// A 3D property-test input: a 7 x 8 x 6 block at up to 0.5 m/s in a closed box. The jitter
/// compresses the block by up to 12 %; corrected inside the first stage, that overlap would
/// become velocity `Δx/τ` (20 m/s) and a fluid particle would pass the innermost wall layer by
/// 8 µm (0.0016 dx) at step 2. The start-up settle (`Simulation::settle`) removes it first. These property tests give the solver no solid volumes, so the
/// no-penetration guard (`boundary::keep_out`) does not act: they test the correction alone.
#[test]
fn block_against_walls_in_3d_stays_off_the_wall_layer() {
    let case = Case {
        dx: 0.005,
        block: [7, 8, 6],
        speed: 0.5,
        dt: 0.000_215_564_455_589_222_9,
        gravity: false,
        walls: true,
        delta: 1e-4,
        steps: 3,
        integrator: Integrator::Rk3,
        seed: 3_074_884_354_973_246_187,
    };
    expect_ok(check_case::<3>(&case, Some(CORRECTION_WALL_BALANCE)));
}

/// Turns a failed property into a panic, for the deterministic tests.
fn expect_ok(result: Result<(), TestCaseError>) {
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// A 20 × 20 block (H = 0.2 m) at rest on the floor of a tank as wide as the block, gravity
/// on from t = 0, corrected SSP-RK3 with the large fixed step dt = 5e-3 s (dx = 0.01 m,
/// h = 0.02 m; a wcsph step with C = 20 m/s would be 2e-4 s), run for 0.5 s: every step
/// converges, the compression stays below δ after every step, and the water is at rest at the
/// end (largest speed below 5 % of sqrt(g H) = 0.07 m/s).
///
/// Fails (no viscosity and no artificial viscosity at all here): every step converges, but the
/// largest speed after 0.5 s is 0.11 m/s. A scene cannot ask for this
/// step: 5e-3 s is nine times the largest fixed step validation accepts for `corrected` with
/// gravity here, `0.0125 sqrt(h/g)` = 0.56 ms (`sph::scene::validate::CORRECTED_GRAVITY_FACTOR`).
#[test]
#[ignore = "defect beyond the accepted step: a resting block reaches 0.11 m/s, limit 0.07 (see doc)"]
fn resting_block_with_large_step_stays_uncompressed_and_at_rest() {
    let (dx, dt, steps, delta) = (0.01, 5e-3, 100, 1e-4);
    let (width, height) = (20i64, 20i64);
    let x = lattice_block([width, height], dx);
    let u = vec![Vector::<2>::zeros(); x.len()];
    let config = config::<2>(dx, dt, true, delta, Integrator::Rk3);
    let walls = container([0, 0], [width, height + 5], dx, config.h, true);
    let inner = ([-0.5 * dx, -0.5 * dx], [(width as f64 + 0.5) * dx, 100.0]);
    let mut sim = Simulation::new(config, &x, &u, &[("tank".to_string(), walls)]).expect("valid setup");
    run_checked(&mut sim, steps, delta, Some(inner), "");
    let speed = max_speed(&sim);
    let limit = 0.05 * (G * height as f64 * dx).sqrt();
    assert!(
        speed < limit,
        "largest speed {speed:.4} m/s after 0.5 s, limit {limit:.4}"
    );
}

/// A 12 × 12 lattice block (no jitter) moving at 1 m/s towards a wall one empty row away,
/// dx = 0.01 m, dt = 5e-3 s (half a spacing per step), SSP-RK3, δ = 1e-4, 12 steps: the
/// correction must stop the block at the wall.
///
/// It needs the spiky density, the walls' increments of either sign and the velocity solve with
/// momentum 0.9 (at 0.95 the correction stops unconverged). 5e-3 s is `0.25 h / |u|`, beyond
/// the largest step validation accepts, `0.1 h / |u|` = 2e-3 s here
/// (`sph::scene::validate::CORRECTED_FLOW_FACTOR`,
/// [`block_thrown_at_a_wall_at_the_largest_accepted_step_stays_inside_with_the_guard`]).
#[test]
fn block_thrown_at_a_wall_stays_inside_the_container() {
    let (dx, dt, steps, delta) = (0.01, 5e-3, 12, 1e-4);
    let n = [12i64, 12];
    let x = lattice_block(n, dx);
    let u = vec![Vector::<2>::new(1.0, 0.0); x.len()];
    let config = config::<2>(dx, dt, false, delta, Integrator::Rk3);
    let walls = container([-GAP; 2], n.map(|v| v + GAP), dx, config.h, false);
    let inner = ([-1.5 * dx; 2], [13.5 * dx; 2]);
    let mut sim = Simulation::new(config, &x, &u, &[("box".to_string(), walls)]).expect("valid setup");
    run_checked(&mut sim, steps, delta, Some(inner), "");
}

/// A block thrown at a wall as above, at the largest fixed step validation accepts for it,
/// `CORRECTED_FLOW_FACTOR h / |u|` = 2e-3 s (h = 0.02 m, |u| = 1 m/s, no gravity), and with
/// the no-penetration guard a scene run has (`boundary::keep_out`, the container's wall slabs):
/// every step converges and no fluid particle leaves the container's inside (plus half a
/// spacing) over 0.3 s, through the impact and the splash along the walls.
#[test]
fn block_thrown_at_a_wall_at_the_largest_accepted_step_stays_inside_with_the_guard() {
    let (dx, speed, delta) = (0.01, 1.0, 1e-4);
    let h = 2.0 * dx;
    let dt = sph::scene::validate::CORRECTED_FLOW_FACTOR * h / speed;
    let steps = (0.3 / dt).round() as usize;
    let n = [12i64, 12];
    let x = lattice_block(n, dx);
    let u = vec![Vector::<2>::new(speed as Real, 0.0); x.len()];
    let config = config::<2>(dx, dt, false, delta, Integrator::Rk3);
    let walls = container([-GAP; 2], n.map(|v| v + GAP), dx, config.h, false);
    let thickness = (wall_layers(config.h, dx) as f64 * dx) as Real;
    let (lo, hi) = (-GAP as f64 * dx, (n[0] + GAP) as f64 * dx);
    let inner = ([lo - 0.5 * dx; 2], [hi + 0.5 * dx; 2]);
    let mut sim = Simulation::new(config, &x, &u, &[("box".to_string(), walls)]).expect("valid setup");
    sim.set_keep_out(KeepOutBox::container(
        Vector::<2>::repeat(lo as Real),
        Vector::<2>::repeat(hi as Real),
        thickness,
        false,
        0,
    ))
    .expect("the box's walls");
    run_checked(&mut sim, steps, delta, Some(inner), &format!("dt = {dt} s, "));
}

/// The momentum balance with walls (module doc) at 3 % of the largest impulse plus 1e-4
/// `M |u|max`, on a case the 2D property test shrank to: dx = 5 mm, a jittered 14 × 12 block
/// thrown at up to 0.5 m/s into a closed box, dt = 3.58e-3 s, SSP-RK3, 3 steps.
///
/// The correction's share of the wall force is summed sweep by sweep at each sweep's own
/// positions (`solver::step`); evaluated from the stage's accumulated pressure at its final
/// positions it would miss the fluid's momentum change by a factor 3.
#[test]
fn wall_impulse_balances_fluid_momentum_to_three_percent() {
    let case = Case {
        dx: 0.005,
        block: [14, 12, 10],
        speed: 0.5,
        dt: 0.003582898151039542,
        gravity: false,
        walls: true,
        delta: 1e-4,
        steps: 3,
        integrator: Integrator::Rk3,
        seed: 4066443804933428726,
    };
    expect_ok(check_case::<2>(&case, Some(THROWN_BLOCK_BALANCE)));
}

/// A lattice block of `size` particles per axis (no jitter) moving at 1 m/s along x towards a
/// wall of a closed box one empty row away (dx = 0.01 m, δ = 1e-4, gravity on), `steps` steps
/// of `dt`: properties 1, 2 (and 3 when `inside`) after every step, and property 4 over the
/// impact at 3 % of the largest impulse plus 1e-4 `M |u|max`.
fn check_thrown_block<const D: usize>(
    size: i64,
    dt: f64,
    steps: usize,
    integrator: Integrator,
    inside: bool,
) {
    let (dx, delta) = (0.01, 1e-4);
    let n = [size; D];
    let x = lattice_block(n, dx);
    let mut u = Vector::<D>::zeros();
    u[0] = 1.0;
    let u = vec![u; x.len()];
    let config = config::<D>(dx, dt, true, delta, integrator);
    let walls = container([-GAP; D], n.map(|v| v + GAP), dx, config.h, false);
    let inner = (
        [(-GAP as f64 - 0.5) * dx; D],
        [((size + GAP) as f64 + 0.5) * dx; D],
    );
    let mut sim = Simulation::new(config, &x, &u, &[("box".to_string(), walls)]).expect("valid setup");
    let count = sim.fields.len();
    let mass = sim.fluid_mass();
    let p0 = sim.fluid_momentum();
    let (mut gravity_impulse, mut wall_impulse) = ([0.0f64; 3], [0.0f64; 3]);
    let mut speed: f64 = 1.0;
    for step in 0..steps {
        let report = sim.step(f64::INFINITY);
        assert!(report.is_ok(), "{D}D step {step}: {:?}", report.err());
        expect_ok(check_state(&sim, step, delta, count, inside.then_some(inner)));
        gravity_impulse[D - 1] -= mass * G * dt;
        for k in 0..3 {
            wall_impulse[k] += sim.solid_forces()[0][k] * dt;
        }
        speed = speed.max(max_speed(&sim));
    }
    let p1 = sim.fluid_momentum();
    let largest = largest_impulse::<D>(p0, p1, gravity_impulse, wall_impulse);
    let (relative, floor) = THROWN_BLOCK_BALANCE;
    let tolerance = relative * largest + floor * mass * speed;
    assert!(
        wall_impulse[0].abs() > 0.5 * p0[0].abs(),
        "{D}D: the block hit the wall (wall impulse {wall_impulse:?}, initial momentum {p0:?})"
    );
    let what = format!("{D}D {integrator:?} ");
    expect_ok(check_balance::<D>(
        p0,
        p1,
        gravity_impulse,
        wall_impulse,
        tolerance,
        &what,
    ));
}

/// Property 4 with walls and gravity, deterministically, over an impact where the correction's
/// wall impulse matters (0.06 s; the block reaches the wall at 0.02 s). Measured: errors up to
/// 1.6 % of the largest impulse (2D, symplectic Euler; 0.52 of the bound), 0.5 % (2D) and 0.9 %
/// (3D) with SSP-RK3.
#[test]
fn thrown_block_momentum_balances_gravity_and_wall_impulse() {
    check_thrown_block::<2>(12, 2e-3, 30, Integrator::Rk3, true);
    check_thrown_block::<2>(12, 1e-3, 60, Integrator::SymplecticEuler, true);
    check_thrown_block::<3>(8, 2e-3, 30, Integrator::Rk3, true);
}

/// Property 3 on the 3D run of `thrown_block_momentum_balances_gravity_and_wall_impulse`
/// (8 × 8 × 8 block, dt = 2e-3 s, SSP-RK3): the splash runs along the ceiling and the walls and
/// must stay off the innermost wall layer.
///
/// With the loop stopping on compression alone, particles of a thin sheet sliding along the
/// ceiling would get up to 0.024 dx past the layer (uncompressed, so never pushed out); the loop
/// also removes the excess pressure of expanded particles (`physics::correction::residual`), so
/// the sheet stays off the wall.
#[test]
fn splash_along_a_3d_wall_stays_off_the_wall_layer() {
    check_thrown_block::<3>(8, 2e-3, 30, Integrator::Rk3, true);
}

/// A 2D property-test input (seed 0x5eed0002): a free 14 x 10 block under gravity at up to
/// 0.69 m/s with a 23.6 ms step, a large step with pressure still building. Without the start-up
/// settle the third stage of step 2 does not converge in 2,000 sweeps (3.5e-4 left); the settle
/// removes the jitter's compression before the first step.
#[test]
fn large_step_with_gravity_in_2d_converges() {
    let case = Case {
        dx: 0.047_345_166_746_955_03,
        block: [14, 10, 10],
        speed: 0.689_462_242_855_428,
        dt: 0.023_573_152_726_866_206,
        gravity: true,
        walls: false,
        delta: 1e-4,
        steps: 3,
        integrator: Integrator::Rk3,
        seed: 500_988_943_488_858_139,
    };
    expect_ok(check_case::<2>(&case, Some(CORRECTION_WALL_BALANCE)));
}

/// A 2D property-test input: a free 13 x 14 block, no gravity, no walls, moving at up to
/// 0.64 m/s with the largest random step, one spacing per step (dt = 65 ms at dx = 42 mm). It
/// converges because the correction sums (18) with the spiky kernel its sweeps move along (with
/// the poly6 sum the second stage of the first step leaves 4.1e-4 against δ = 1e-4 after 2,000
/// sweeps; docs/method.md, "Kernels, density, pressure"). That step is five times the largest
/// that validation accepts for such a scene, `0.1 h / |u|max` (`CORRECTED_FLOW_FACTOR`), so a
/// scene cannot ask for it; the property test still draws steps up to one spacing to find the
/// correction's limits. CI runs the property tests with a fixed seed (`PROPTEST_RNG_SEED` in
/// `.ci/run`), local runs draw new cases.
#[test]
fn free_block_at_one_spacing_per_step_in_2d_converges() {
    let case = Case {
        dx: 0.041_845_009_707_578_186,
        block: [13, 14, 10],
        speed: 0.641_536_092_738_92,
        dt: 0.065_226_275_156_131_33,
        gravity: false,
        walls: false,
        delta: 1e-4,
        steps: 1,
        integrator: Integrator::Rk3,
        seed: 13_904_500_518_979_752_299,
    };
    expect_ok(check_case::<2>(&case, Some(CORRECTION_WALL_BALANCE)));
}
