//! Tolerances that more than one assertion uses, each named for the quantity it bounds, with
//! where its value comes from. A tolerance used once stays at its assertion, with its reason.
//!
//! Rounding units: f32 epsilon 1.19e-7 (particle state is f32), f64 epsilon 2.2e-16 (global
//! sums, the clock, statistics).

/// An f64 result of one to three operations on values of order 0.01 to 1 (`h = ratio · dx`,
/// `end_time / 50`, a mean of three): a few ulp of 1 (2.2e-16 each); any wrong formula misses
/// by orders of magnitude more.
pub const F64_FEW_OPERATIONS: f64 = 1e-15;

/// An f64 value summed from up to a few thousand terms of order 1 or below: the clock summing
/// the steps (simulated time against the end time), a time-weighted mean over a sample
/// interval. Rounding grows by at most one ulp (1.1e-16 of the running sum) per term, so the
/// worst case stays near 1e-13; the smallest step or sample interval (1e-6 s and up) is six
/// orders of magnitude above it.
pub const F64_SUM: f64 = 1e-12;

/// A time within this of a loop's end or a sampling target counts as reached [s]: the clock
/// sums steps in f64 ([`F64_SUM`]), and no step is shorter than 1e-6 s, so this slack never
/// skips or adds a step.
pub const CLOCK_SLACK: f64 = 1e-9;

/// An f32 quantity after a few operations, relative to its size or absolute for values of
/// order 1 (positions in metres, fronts, compressions, a density against its own term): f32
/// epsilon is 1.19e-7, so this allows about 8 ulp, and a wrong term (a missing neighbour, a
/// wrong mass) is off by 1e-3 or more.
pub const F32_ROUNDING: f64 = 1e-6;

/// A quantity accumulated in f32 over about 1,000 to 2,500 steps, relative to its size: the
/// centre-of-mass velocity of a falling block against `g t`, its height against
/// `g t² / 2`, and the balance between the fluid's momentum change and the walls' impulse.
/// Each step rounds the particles' velocities at up to 6e-8 relative; rounding errors of
/// random sign add to far less than the 1.5e-4 of 2,500 worst-case steps, while a missing
/// force term or a wrong integrator offset (`g t dt / 2`, 2e-4 of the fall at t = 0.5 s) is
/// at this size or above.
pub const F32_ACCUMULATION: f64 = 1e-4;

/// The momentum of a fluid whose internal forces are pairwise antisymmetric (pressure,
/// viscosity, surface tension, the position correction without walls), as a fraction of its
/// mass times its speed scale (`M` × 1 m/s for the free block of random velocities up to
/// 0.5 m/s, `M u_capillary` for a drop, `M |u|max` for the correction's blocks): only f32
/// rounding of the pair terms changes it, over a few hundred steps (the correction's property
/// test measured at most 5.5e-8); a one-sided term shows orders of magnitude above it.
pub const PAIRWISE_MOMENTUM: f64 = 1e-5;

/// A settled column's mean floor pressure against `ρ0 g H`, relative: the shipped hydrostatic
/// tank averaged over 4–5 s, after the gravity ramp and the lattice's settling. The weakly
/// compressible column is denser at its foot by `g H / C²` = 1 % (the scene's `C` is
/// 10 sqrt(g H)), which shifts the pressure by as much; 2 % leaves room for that and still
/// fails a wrong `g`, `ρ0`, depth or wall force.
pub const HYDROSTATIC_PRESSURE: f64 = 0.02;

/// Hydrostatic pressure sampled within 2 s of the start (a slab's mean pressure against the
/// piecewise-linear profile of two layers, the floor force of a resting column against its
/// weight), relative to the bottom pressure: beside the 1 % of compressibility
/// ([`HYDROSTATIC_PRESSURE`]) the start-up's oscillation has not died out yet (the two-layer
/// tests state their measured worst slabs, 1.27–1.63 %).
pub const HYDROSTATIC_PRESSURE_EARLY: f64 = 0.03;

/// A drop's core pressure against Laplace's `σ / R` (and the ratio of two drops' jumps against
/// its exact value), relative: the surface layers are one to two spacings thick and the drops
/// are 11–23 spacings in radius, so the curvature is resolved to about `dx / R` ≈ 4–9 %.
pub const LAPLACE_JUMP: f64 = 0.10;

/// The rotating tank's free surface against the parabola of solid-body rotation, as a fraction
/// of the centre-to-wall rise `Ω² R² / (2 g)` (fitted rise, and any column's height): the
/// surface is known to about half a spacing per column (the top particle's cell), 5 mm, 5 %
/// of the 0.1 m rise at the scene's dx = 10 mm.
pub const ROTATING_SURFACE: f64 = 0.05;

/// How far a particle of one phase may stray across the two-layer interface, in spacings: the
/// lattice starts them 0.5 dx from it, and a particle a full spacing further has crossed a
/// layer of the other phase (the tests state the measured worst, 0.52 dx).
pub const INTERFACE_CROSSING_DX: f64 = 1.5;

/// Kinetic plus potential energy of a hard case may rise above its start (or its bound) by
/// this fraction of the start's magnitude: the scenes start at rest or in free flight, the
/// walls are fixed and every term dissipates or conserves, so only the time discretisation and
/// rounding can add energy; an energy source (a wall doing work, an unstable step) shows above
/// it.
pub const ENERGY_RISE: f64 = 1e-3;

/// A number `sph plan` prints as `{:.4e}` (five significant digits) read back, against the
/// run's value, relative: printing rounds at most 5e-5.
pub const PRINTED_4E: f64 = 1e-4;

/// The position correction's momentum balance in a closed box, `ΔP = Σ (M g − F_walls) dt`,
/// per axis: `(relative, absolute)`, the error within `relative` times the largest of the
/// impulses plus `absolute` times `M |u|max` (the largest speed seen). The walls' share of
/// every pair term is summed exactly, sweep by sweep, so what is left is f32 pair terms summed
/// in f64 (tests/numerics/correction.rs, module doc).
pub const CORRECTION_WALL_BALANCE: (f64, f64) = (1e-3, 1e-5);

/// The same balance for a block thrown at a wall, the correction's hardest impact (steps up
/// to the largest the validator accepts): 3 % of the largest impulse plus 1e-4 `M |u|max`.
/// Summed from the stage's final positions instead of sweep by sweep, the wall force would
/// miss the momentum change by a factor 3.
pub const THROWN_BLOCK_BALANCE: (f64, f64) = (0.03, 1e-4);
