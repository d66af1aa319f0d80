//! The position correction, eqs. (23)–(24): `correction_error` (eq. 24 with note 6),
//! `begin_correction` + `correction_pressure` (eq. 19 inside the correction, with the heavy-ball
//! momentum `physics::correction::MOMENTUM`, [A12] extrapolated to solids) and
//! `correct_positions` (eq. 23: one scale when the largest step exceeds `max_step`, the kick
//! `Δx/τ_u`), one phase and [HA06] several, on every backend. The sweeps run as the driver runs
//! them (`solver::step`: density, error, increments, displacement), with a re-sort and restarts
//! between them; each is checked against a brute-force reference from the state the backend
//! reached (downloaded between stages), so differences cannot build up from sweep to sweep.

use crate::correction_reference::*;
use crate::setup::{DX, RHO0, SUM_ORDER, Under, add_strays, backends, in_id_order, scene};
use sph::backend::{CorrectionError, Sweep};
use sph::fields::{FLUID, Fields};
use sph::model::params::StepParams;
use sph::physics::multiphase::Phases;

/// The correction's `τ` [s], the time since the step's start (section 2).
const TAU: f32 = 2.0e-3;
/// `max_step` of the scaled sweeps [m]. Small, so that the grid of the last sort still holds
/// every pair afterwards: two such sweeps close a pair by at most 4e-5 m, and a pair that comes
/// within `h` so has a spiky gradient `((4e-5 m)/(h/2))² ≈ 2e-5` of one at `r = dx`, far below
/// [`SUM_ORDER`] of a sum of ~13 or more such terms.
const SMALL_STEP: f32 = 1.0e-5;

/// The state around one sweep: after `density`, after `correction_pressure`, after
/// `correct_positions` (id order), with what the stages returned.
struct Record<const D: usize> {
    pre: Fields<D>,
    mid: Fields<D>,
    post: Fields<D>,
    error: CorrectionError,
    sweep: Sweep,
}

/// What runs before a sweep.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Before {
    /// `begin_correction` (a new stage: the momentum restarts).
    Begin,
    /// `sort_by_cell` (the driver's re-sort after drift: the momentum restarts).
    Sort,
    /// Nothing: the sweep continues the previous one, with momentum.
    Nothing,
}

/// The sweeps: what runs before each, `kick_tau` (`τ`, or infinite: the start-up settle),
/// `max_step` [m] and whether it scales the displacements. A sweep that moves by more than
/// [`SMALL_STEP`] is followed by a re-sort (the driver's `RESORT_DRIFT`); the one with momentum
/// is scaled to the driver's `MAX_SWEEP_STEP` of 0.1 dx.
const PLAN: [(Before, f32, f32, bool); 5] = [
    (Before::Begin, TAU, 1.0, false),
    (Before::Sort, f32::INFINITY, SMALL_STEP, true),
    (Before::Begin, TAU, SMALL_STEP, true),
    (Before::Nothing, TAU, 0.1 * DX, true),
    (Before::Sort, f32::INFINITY, f32::INFINITY, false),
];

/// `correction_pressure` from `pre` to `mid`: fluid `P + δp` bitwise (per-particle f32
/// arithmetic in the same order), with the momentum exactly when `previous` is given; solids
/// `max(P + r, 0)` within [`SUM_ORDER`] of `|P| + Σ|δp_f| W/Σ W` (`r` a weighted mean; the
/// roundings of the f32 additions are 1e-7 of the same scale). Also checks that the momentum
/// (or its absence, against the `stale` increments), the phases' rest densities and the walls
/// each change the result. Returns every particle's `δp` as the displacement reads it, and how
/// far the backend's may be from it: fluid exact; solids `P_mid − P_pre`, within one rounding of
/// `P_mid`.
#[allow(clippy::too_many_arguments)]
fn check_correction_pressure<const D: usize>(
    under: Under,
    label: &str,
    pre: &Fields<D>,
    mid: &Fields<D>,
    p: &StepParams<D>,
    k: f32,
    previous: Option<&[f32]>,
    stale: Option<&[f32]>,
) -> (Vec<f32>, Vec<f64>) {
    let n = pre.len();
    let fluid: Vec<usize> = (0..n).filter(|&i| pre.kind[i] == FLUID).collect();
    let increment =
        |phases, prev: Option<&[f32]>, i| fluid_increment(pre, phases, p, k, i, prev.map(|v| v[i]));
    let mut dp = vec![0.0f32; n];
    for &i in &fluid {
        dp[i] = increment(p.phases, previous, i);
        let want = pre.pressure[i] + dp[i];
        assert_eq!(
            mid.pressure[i].to_bits(),
            want.to_bits(),
            "{under:?} {label}: fluid {i}: pressure {} against {want}",
            mid.pressure[i]
        );
    }
    // Each alternative must move many fluid pressures (bitwise comparison: any change shows).
    let other_phases = if p.phases == Phases::Multi {
        Phases::Single
    } else {
        Phases::Multi
    };
    let alternatives = [
        ("the momentum", previous.map(|_| (p.phases, None))),
        ("no momentum", stale.map(|s| (p.phases, Some(s)))),
        (
            "the phases' rest densities",
            (p.phases == Phases::Multi).then_some((other_phases, previous)),
        ),
    ];
    for (what, alternative) in alternatives {
        if let Some((phases, prev)) = alternative {
            let moved = fluid
                .iter()
                .filter(|&&i| increment(phases, prev, i) != dp[i])
                .count();
            assert!(
                moved > fluid.len() / 10,
                "{label}: {what} shows in {moved} of {}",
                fluid.len()
            );
        }
    }
    let mut dp_error = vec![0.0f64; n];
    let (mut worst, mut largest_change) = (0.0f64, 0.0f64);
    for w in (0..n).filter(|&i| pre.kind[i] != FLUID) {
        let (r, r_abs) = wall_increment(pre, p, &dp, w);
        let before = f64::from(pre.pressure[w]);
        let want = (before + r).max(0.0);
        let tol = SUM_ORDER * (before.abs() + r_abs) + f64::from(f32::MIN_POSITIVE);
        let diff = (f64::from(mid.pressure[w]) - want).abs();
        assert!(
            diff <= tol,
            "{under:?} {label}: solid {w}: pressure {} against {want} (tolerance {tol:.2e})",
            mid.pressure[w]
        );
        worst = worst.max(diff / tol);
        largest_change = largest_change.max((want - before).abs() / tol);
        dp[w] = mid.pressure[w] - pre.pressure[w];
        dp_error[w] = EPS * (f64::from(mid.pressure[w]).abs() + f64::from(dp[w]).abs());
    }
    assert!(
        largest_change > 1e3,
        "{label}: the walls' increments show ({largest_change:.1e} tolerances)"
    );
    eprintln!(
        "{under:?} {label}: correction_pressure fluid bitwise, solids worst {worst:.2e} of the tolerance"
    );
    (dp, dp_error)
}

/// `correct_positions` from `mid` to `post` with the increments `dp`: the sweep's scale against
/// `max_step / largest |Δx|` of the reference (1 when it fits), then per fluid particle
/// `x + s Δx` and `u + s Δx/kick_tau` with the backend's `s`, within [`SUM_ORDER`] of the term
/// scale (times `s`, over `kick_tau` for `u`) plus four f32 roundings of the values added;
/// with an infinite `kick_tau` the velocity bitwise; solids untouched, bitwise. Returns the
/// worst deviations of `x` and `u` against their tolerances, and how far leaving out the solid neighbours' terms
/// and the other phase model move `x` against it.
#[allow(clippy::too_many_arguments)]
fn check_correct_positions<const D: usize>(
    under: Under,
    label: &str,
    mid: &Fields<D>,
    post: &Fields<D>,
    p: &StepParams<D>,
    (dp, dp_error): (&[f32], &[f64]),
    sweep: Sweep,
    kick_tau: f32,
    (max_step, scaled): (f32, bool),
) -> ([f64; 2], [f64; 2]) {
    let reference = reference_displacements(mid, p, p.phases, &mid.density, dp, dp_error, TAU, true);
    let (mut largest, mut largest_error) = (0.0f64, 0.0f64);
    for (dx, t) in &reference {
        largest = largest.max(dx.norm());
        largest_error = largest_error.max(SUM_ORDER * t + 2.0 * EPS * dx.norm());
    }
    let max_step = f64::from(max_step);
    if !scaled {
        assert!(
            largest + largest_error <= max_step,
            "{label}: max_step {max_step} below {largest}"
        );
        assert_eq!(sweep.scale, 1.0, "{under:?} {label}: unscaled");
        let diff = (sweep.largest - largest).abs();
        assert!(
            diff <= largest_error,
            "{under:?} {label}: {sweep:?} against largest {largest:e}"
        );
    } else {
        assert!(
            largest - largest_error > max_step,
            "{label}: max_step {max_step} too close to {largest}"
        );
        let want = max_step / largest;
        let tol = want * (largest_error / (largest - largest_error) + 2.0 * EPS);
        assert!(
            (sweep.scale - want).abs() <= tol && sweep.scale < 1.0,
            "{under:?} {label}: {sweep:?} against scale {want:e} (tolerance {tol:.2e})"
        );
        let diff = (sweep.largest - max_step).abs();
        assert!(
            diff <= 2.0 * EPS * max_step,
            "{under:?} {label}: {sweep:?} against {max_step:e}"
        );
    }
    let s = sweep.scale;
    let kick = f64::from(kick_tau);
    // The sum's order, then the roundings of `τ² a`, `s Δx` and the addition (and the sum's).
    let term_tol = |i: usize| SUM_ORDER * reference[i].1 * s + 4.0 * EPS * reference[i].0.amax() * s;
    let tolerance = |i: usize, k: usize| term_tol(i) + 4.0 * EPS * f64::from(mid.position[i][k]).abs();
    let (mut worst, mut moved) = ([0.0f64; 2], 0usize);
    for i in 0..mid.len() {
        if mid.kind[i] != FLUID {
            assert_eq!(
                post.position[i], mid.position[i],
                "{under:?} {label}: solid {i} stays"
            );
            assert_eq!(
                post.velocity[i], mid.velocity[i],
                "{under:?} {label}: solid {i} keeps its velocity"
            );
            continue;
        }
        let dx = &reference[i].0;
        for k in 0..D {
            let tol_x = tolerance(i, k);
            let want_x = f64::from(mid.position[i][k]) + dx[k] * s;
            let diff = (f64::from(post.position[i][k]) - want_x).abs();
            assert!(
                diff <= tol_x,
                "{under:?} {label}: particle {i} axis {k}: x {} against {want_x} (tolerance {tol_x:.2e})",
                post.position[i][k]
            );
            worst[0] = worst[0].max(diff / tol_x);
            let u = f64::from(post.velocity[i][k]);
            if kick_tau.is_infinite() {
                assert_eq!(
                    post.velocity[i][k], mid.velocity[i][k],
                    "{under:?} {label}: no kick on {i}"
                );
                continue;
            }
            let want_u = f64::from(mid.velocity[i][k]) + dx[k] * s / kick;
            let tol_u = term_tol(i) / kick + 4.0 * EPS * want_u.abs();
            assert!(
                (u - want_u).abs() <= tol_u,
                "{under:?} {label}: particle {i} axis {k}: u {u} against {want_u} (tolerance {tol_u:.2e})"
            );
            worst[1] = worst[1].max((u - want_u).abs() / tol_u);
            moved += usize::from(post.velocity[i][k] != mid.velocity[i][k]);
        }
    }
    if kick_tau.is_finite() {
        assert!(
            moved > mid.len() / 2,
            "{label}: the kick moves most velocities ({moved})"
        );
    }
    let other = if p.phases == Phases::Multi {
        Phases::Single
    } else {
        Phases::Multi
    };
    let effects = [(p.phases, false), (other, true)].map(|(phases, solids)| {
        let alt = reference_displacements(mid, p, phases, &mid.density, dp, dp_error, TAU, solids);
        (0..mid.len())
            .filter(|&i| mid.kind[i] == FLUID)
            .map(|i| (alt[i].0 - reference[i].0).amax() * s / tolerance(i, 0))
            .fold(0.0, f64::max)
    });
    (worst, effects)
}

fn check_sweeps<const D: usize>(seed: u64, phases: Phases) {
    let (mut f, mut p) = scene::<D>(seed);
    add_strays(&mut f, &p, seed ^ 0x77);
    if phases == Phases::Multi {
        two_phases(&mut f, &mut p);
    }
    let k = stiffness(&p, TAU);
    for under in backends() {
        let (_, records) = under.run(&f, &p, |b, f| {
            let mut records = Vec::new();
            for &(before, kick_tau, max_step, _) in &PLAN {
                match before {
                    Before::Begin => b.begin_correction(f),
                    Before::Sort => b.sort_by_cell(f, &p).expect("finite positions"),
                    Before::Nothing => {}
                }
                b.density(f, &p);
                let pre = snapshot(b, f);
                let error = b.correction_error(f, &p);
                b.correction_pressure(f, &p, k);
                let mid = snapshot(b, f);
                let sweep = b.correct_positions(f, &p, TAU, kick_tau, max_step);
                let post = snapshot(b, f);
                records.push(Record {
                    pre,
                    mid,
                    post,
                    error,
                    sweep,
                });
            }
            records
        });
        let mut previous: Option<Vec<f32>> = None;
        let (mut worst, mut effects) = ([0.0f64; 2], [0.0f64; 2]);
        for (s, (r, &(before, kick_tau, max_step, scaled))) in records.iter().zip(&PLAN).enumerate() {
            let label = format!("{D}D {phases:?} sweep {s} (after {before:?})");
            let stale = if before == Before::Nothing {
                None
            } else {
                previous.take()
            };
            check_error(under, &label, r.error, reference_error(&r.pre, &p));
            let (dp, dp_error) = check_correction_pressure(
                under,
                &label,
                &r.pre,
                &r.mid,
                &p,
                k,
                previous.as_deref(),
                stale.as_deref(),
            );
            let (dp, dp_error) = (&dp[..], &dp_error[..]);
            let (w, e) = check_correct_positions(
                under,
                &label,
                &r.mid,
                &r.post,
                &p,
                (dp, dp_error),
                r.sweep,
                kick_tau,
                (max_step, scaled),
            );
            eprintln!(
                "{under:?} {label}: {:?}, worst x {:.2e}, u {:.2e} of the tolerance",
                r.sweep, w[0], w[1]
            );
            worst = [0, 1].map(|k| worst[k].max(w[k]));
            effects = [0, 1].map(|k| effects[k].max(e[k]));
            let fluid = |i: usize| r.pre.kind[i] == FLUID;
            previous = Some(
                (0..dp.len())
                    .map(|i| if fluid(i) { dp[i] } else { 0.0 })
                    .collect(),
            );
        }
        // The terms under test each move x by far more than its tolerance somewhere (the two
        // pressure forms agree for equal masses: the phase model shows with two phases only).
        assert!(
            effects[0] > 100.0,
            "{D}D {phases:?}: the solids' terms show by {:.1}",
            effects[0]
        );
        if phases == Phases::Multi {
            assert!(
                effects[1] > 100.0,
                "{D}D: the phase model shows by only {:.1}",
                effects[1]
            );
        }
        eprintln!(
            "{under:?} {D}D {phases:?}: correct_positions worst x {:.2e}, u {:.2e} of the tolerance; \
             the solids' terms show by {:.1e}, the phase model by {:.1e} tolerances",
            worst[0], worst[1], effects[0], effects[1]
        );
    }
}

#[test]
fn correction_sweeps_are_eqs_19_23_24_with_momentum_scaling_and_kick() {
    for phases in [Phases::Single, Phases::Multi] {
        check_sweeps::<2>(0x1234_5678_9abc_def1, phases);
        check_sweeps::<3>(0x0fed_cba9_8765_4321, phases);
    }
}

/// `correction_error` on a given state: a pressured particle expanded beyond every compression
/// (the residual's `|e|` branch decides), a solid far above ρ0 (solids do not count), then a NaN
/// density on that pressured particle (the residual is NaN, the compression keeps its value);
/// with two phases each particle against its own ρ0.
fn check_correction_error<const D: usize>(seed: u64, phases: Phases) {
    let (mut f, mut p) = scene::<D>(seed);
    if phases == Phases::Multi {
        two_phases(&mut f, &mut p);
    }
    let expanded = (0..f.len())
        .find(|&i| f.kind[i] == FLUID && f.pressure[i] > 0.0)
        .expect("a pressured fluid particle");
    f.density[expanded] *= 0.97;
    let solid = (0..f.len()).find(|&i| f.kind[i] != FLUID).expect("a solid");
    f.density[solid] = 2.0 * RHO0;
    for case in ["expanded", "NaN"] {
        let want = reference_error(&in_id_order(&f), &p);
        assert!(
            want.compression > 0.0 && want.compression < 0.02,
            "{case}: {want:?}"
        );
        if case == "expanded" {
            assert!(
                want.residual > 0.02,
                "the expansion of pressured particles counts: {want:?}"
            );
        } else {
            assert!(want.residual.is_nan(), "a NaN density never reads as converged");
        }
        if phases == Phases::Multi && case == "expanded" {
            // The lighter phase's pressured particles read 20 % expanded against the one ρ0.
            let single = reference_error(
                &in_id_order(&f),
                &StepParams {
                    phases: Phases::Single,
                    ..p
                },
            );
            assert!(
                single.residual > 0.1,
                "the phases' rest densities show: {single:?}"
            );
        }
        for under in backends() {
            let (_, got) = under.run(&f, &p, |b, f| b.correction_error(f, &p));
            check_error(under, &format!("{D}D {phases:?} {case}"), got, want);
            eprintln!("{under:?} {D}D {phases:?} {case}: correction_error {got:?}, bitwise");
        }
        f.density[expanded] = f32::NAN;
    }
}

#[test]
fn correction_error_is_eq_24_with_note_6_and_the_residual() {
    for phases in [Phases::Single, Phases::Multi] {
        check_correction_error::<2>(0x1111_2222_3333_4444, phases);
        check_correction_error::<3>(0x5555_6666_7777_8888, phases);
    }
}
