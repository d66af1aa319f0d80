//! The velocity solve (`solver::step::solve_velocities`): `begin_velocity_solve`,
//! `predicted_density` (both density kernels, one phase and [HA06] several),
//! `mix_velocity_pressure` (one Anderson-accelerated projected Jacobi sweep),
//! `velocity_from_pressure` (eq. 23's displacement at `τ` as a velocity) and
//! `end_velocity_solve` (kept and given up), on every backend. The sweeps run as the driver runs
//! them; each stage is checked against a reference from the state the backend reached
//! (downloaded between stages), so differences cannot build up from sweep to sweep.
//!
//! The mixing's reference keeps the window's vectors by id here and solves its least-squares
//! problem with `sph::solver::anderson::AndersonState`, the pure host module both backends use
//! (it holds no particle data; its own test solves a linear system): everything per particle and
//! every dot product is written here.

use crate::anderson_reference::Mixing;
use crate::correction_reference::{
    EPS, check_error, reference_displacements, reference_error, rest, snapshot, stiffness, two_phases,
    wall_increment,
};
use crate::setup::{DX, Rng, SUM_ORDER, Under, backends, in_id_order, neighbours, scene};
use sph::fields::{FLUID, Fields};
use sph::math::Vector;
use sph::model::params::StepParams;
use sph::physics::density::{
    DensityKernel, DensityWeight, SURFACE_DENSITY_RATIO, density_kernel_gradient, velocity_solve_base,
};
use sph::physics::lattice::lattice_spiky_scale;
use sph::physics::multiphase::Phases;
use sph::solver::anderson::WINDOW;

/// The solve's `τ` [s]: about 1 % of ρ0 from velocities of 1 m/s over dx = 1 cm.
const TAU: f32 = 1.0e-4;
/// Sweeps of the solve: past `WINDOW + 1`, so that the ring of differences wraps around.
const SWEEPS: usize = WINDOW + 3;

/// `setup::scene` for the solve: the density kernel `kernel`; the densities (18) remembered at
/// the start spread over `(0.98 ± 0.03) ρ0_i`, so that both sides of `velocity_solve_base` are
/// taken; with `Phases::Multi` two phases (`correction::two_phases`).
pub(super) fn solve_scene<const D: usize>(
    seed: u64,
    kernel: DensityKernel,
    phases: Phases,
) -> (Fields<D>, StepParams<D>) {
    let (mut f, mut p) = scene::<D>(seed);
    p.density_kernel = kernel;
    p.density_spiky_scale = density_weight(&p, kernel).spiky_scale;
    let mut rng = Rng(seed ^ 0x600d);
    for rho in &mut f.density {
        *rho = p.rho0 * (SURFACE_DENSITY_RATIO + rng.sym(0.03));
    }
    if phases == Phases::Multi {
        two_phases(&mut f, &mut p);
    }
    (f, p)
}

/// A variant of the predicted density's sum, for the checks that each part shows.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Variant {
    /// The stage's contract.
    Contract,
    /// The other particle's mass (`m_i` for one phase, `m_j` for several).
    OtherMass,
    /// Without the solid neighbours.
    NoSolids,
    /// With the other density kernel.
    OtherKernel,
}

/// The weight of (18) with `kernel`, the spiky one scaled for the lattice (`physics::lattice`).
fn density_weight<const D: usize>(p: &StepParams<D>, kernel: DensityKernel) -> DensityWeight {
    let spiky_scale = match kernel {
        DensityKernel::Poly6 => 0.0,
        DensityKernel::ScaledSpiky => lattice_spiky_scale(&p.smoothing(), f64::from(DX)) as f32,
    };
    DensityWeight { kernel, spiky_scale }
}

/// `ρ*_i = velocity_solve_base(ρ_i, ρ0_i) + τ Σ_j m (u_i − u_j)·∇W_ρ(x_i − x_j)` by brute force
/// for fluid particle `i` of `f` (id order; `density` the one remembered at the start,
/// `velocity` the current), `m = m_j`, or `m_i` with several phases; and `τ Σ|terms|`.
fn reference_predicted<const D: usize>(
    f: &Fields<D>,
    velocity: &[Vector<D>],
    p: &StepParams<D>,
    i: usize,
    variant: Variant,
) -> (f64, f64) {
    let kernel = p.smoothing();
    let multiphase = (p.phases == Phases::Multi) != (variant == Variant::OtherMass);
    let weight = match (variant, p.density_kernel) {
        (Variant::OtherKernel, DensityKernel::Poly6) => density_weight(p, DensityKernel::ScaledSpiky),
        (Variant::OtherKernel, DensityKernel::ScaledSpiky) => density_weight(p, DensityKernel::Poly6),
        _ => p.density_weight(),
    };
    let (mut rate, mut scale) = (0.0f64, 0.0f64);
    for (j, d, r) in neighbours(f, p.h, i) {
        if variant == Variant::NoSolids && f.kind[j] != FLUID {
            continue;
        }
        let grad = density_kernel_gradient(&kernel, weight, &d, r);
        let m = if multiphase { f.mass[i] } else { f.mass[j] };
        let term = f64::from(m * (velocity[i] - velocity[j]).dot(&grad));
        rate += term;
        scale += term.abs();
    }
    let rho0 = rest(f, p, i);
    let tau = f64::from(TAU);
    (
        f64::from(velocity_solve_base(f.density[i], rho0)) + tau * rate,
        tau * scale,
    )
}

/// `predicted_density` in `got` against the reference from `start` (positions, masses, the
/// remembered density) and the velocities of `current`: fluid within [`SUM_ORDER`] of the term
/// scale plus two f32 roundings of `ρ*` (of `τ Σ` and of the addition); solids keep the start's
/// density, bitwise. Returns the worst deviation against its tolerance and, per variant, the
/// largest change it makes against the tolerance.
fn check_predicted<const D: usize>(
    under: Under,
    label: &str,
    start: &Fields<D>,
    current: &Fields<D>,
    got: &Fields<D>,
    p: &StepParams<D>,
) -> (f64, [f64; 4]) {
    let (mut worst, mut effects) = (0.0f64, [0.0f64; 4]);
    for i in 0..start.len() {
        if start.kind[i] != FLUID {
            let (g, w) = (got.density[i], start.density[i]);
            assert_eq!(
                g.to_bits(),
                w.to_bits(),
                "{under:?} {label}: solid {i} keeps its density"
            );
            continue;
        }
        let (want, scale) = reference_predicted(start, &current.velocity, p, i, Variant::Contract);
        let tol = SUM_ORDER * scale + 2.0 * EPS * want.abs();
        let diff = (f64::from(got.density[i]) - want).abs();
        assert!(
            diff <= tol,
            "{under:?} {label}: fluid {i}: ρ* {} against {want} (tolerance {tol:.2e})",
            got.density[i]
        );
        worst = worst.max(diff / tol);
        let rho0 = rest(start, p, i);
        effects[0] =
            effects[0].max((want - f64::from(velocity_solve_base(start.density[i], rho0))).abs() / tol);
        for (e, variant) in
            effects[1..]
                .iter_mut()
                .zip([Variant::OtherMass, Variant::NoSolids, Variant::OtherKernel])
        {
            let (alt, _) = reference_predicted(start, &current.velocity, p, i, variant);
            *e = e.max((alt - want).abs() / tol);
        }
    }
    (worst, effects)
}

fn check_predicted_density<const D: usize>(seed: u64, kernel: DensityKernel, phases: Phases) {
    let (mut f, p) = solve_scene::<D>(seed, kernel, phases);
    // Masses ±20 %, so that `m_j` cannot pass for `m_i`.
    let mut rng = Rng(seed ^ 0xbeef);
    for m in &mut f.mass {
        *m *= 1.0 + rng.sym(0.2);
    }
    let start = in_id_order(&f);
    let fluid: Vec<usize> = (0..start.len()).filter(|&i| start.kind[i] == FLUID).collect();
    let surface = fluid
        .iter()
        .filter(|&&i| start.density[i] < SURFACE_DENSITY_RATIO * rest(&start, &p, i))
        .count();
    assert!(
        surface > 0 && surface < fluid.len(),
        "{surface} of {} at the surface",
        fluid.len()
    );
    let label = format!("{D}D {kernel:?} {phases:?}");
    for under in backends() {
        let (out, ()) = under.run(&f, &p, |b, f| {
            b.begin_velocity_solve(f, &p);
            b.predicted_density(f, &p, TAU);
        });
        let got = in_id_order(&out);
        let (worst, effects) = check_predicted(under, &label, &start, &start, &got, &p);
        for (what, e) in [
            "the velocities",
            "the mass of the phase model",
            "the solids",
            "the kernel",
        ]
        .iter()
        .zip(effects)
        {
            assert!(e > 100.0, "{label}: {what} change ρ* by only {e:.1} tolerances");
        }
        eprintln!("{under:?} {label}: predicted_density worst {worst:.2e} of the tolerance");
    }
}

#[test]
fn predicted_density_is_the_continuity_sum_for_both_kernels_and_phase_models() {
    for kernel in [DensityKernel::Poly6, DensityKernel::ScaledSpiky] {
        for phases in [Phases::Single, Phases::Multi] {
            check_predicted_density::<2>(0x2468_ace0_1357_9bdf, kernel, phases);
            check_predicted_density::<3>(0x1357_9bdf_2468_ace0, kernel, phases);
        }
    }
}

/// `velocity_from_pressure` from `mixed` to `moved`, against `start` (what
/// `begin_velocity_solve` remembered): fluid increments `P − P_start`, the walls' extrapolated
/// ([A12], as `correction_pressure`) with `P_w = max(P_start + r, 0)` within [`SUM_ORDER`] of
/// `|P_start| + Σ|δp_f| W/Σ W`; fluid `u = u_start + Δx/τ` with eq. (23)'s displacement at the
/// start's density, within [`SUM_ORDER`] of its term scale (plus four f32 roundings) over `τ`;
/// fluid pressures, positions and solids' velocities bitwise untouched. Checks that the walls'
/// terms show. Returns the worst deviations (walls' pressure, velocity) against the tolerance.
fn check_velocities<const D: usize>(
    under: Under,
    label: &str,
    start: &Fields<D>,
    mixed: &Fields<D>,
    moved: &Fields<D>,
    p: &StepParams<D>,
) -> (f64, f64) {
    let n = start.len();
    let (mut dp, mut dp_error) = (vec![0.0f32; n], vec![0.0f64; n]);
    for i in (0..n).filter(|&i| start.kind[i] == FLUID) {
        dp[i] = mixed.pressure[i] - start.pressure[i];
        assert_eq!(
            moved.pressure[i].to_bits(),
            mixed.pressure[i].to_bits(),
            "{under:?} {label}: fluid {i}"
        );
    }
    let mut worst_wall = 0.0f64;
    for w in (0..n).filter(|&i| start.kind[i] != FLUID) {
        let (r, r_abs) = wall_increment(start, p, &dp, w);
        let p0 = f64::from(start.pressure[w]);
        let want = (p0 + r).max(0.0);
        let tol = SUM_ORDER * (p0.abs() + r_abs) + f64::from(f32::MIN_POSITIVE);
        let diff = (f64::from(moved.pressure[w]) - want).abs();
        assert!(
            diff <= tol,
            "{under:?} {label}: solid {w}: pressure {} against {want}",
            moved.pressure[w]
        );
        worst_wall = worst_wall.max(diff / tol);
        dp[w] = moved.pressure[w] - start.pressure[w];
        dp_error[w] = EPS * (f64::from(moved.pressure[w]).abs() + f64::from(dp[w]).abs());
    }
    assert_eq!(
        moved.position, start.position,
        "{under:?} {label}: positions stay"
    );
    let displacements =
        |solids| reference_displacements(start, p, p.phases, &start.density, &dp, &dp_error, TAU, solids);
    let (reference, without_solids) = (displacements(true), displacements(false));
    let tau = f64::from(TAU);
    let (mut worst, mut effect) = (0.0f64, 0.0f64);
    for i in 0..n {
        if start.kind[i] != FLUID {
            assert_eq!(
                moved.velocity[i], start.velocity[i],
                "{under:?} {label}: solid {i}"
            );
            continue;
        }
        let (dx, t) = &reference[i];
        let term_tol = (SUM_ORDER * t + 4.0 * EPS * dx.amax()) / tau;
        for k in 0..D {
            let want = f64::from(start.velocity[i][k]) + dx[k] / tau;
            let tol = term_tol + 4.0 * EPS * want.abs();
            let diff = (f64::from(moved.velocity[i][k]) - want).abs();
            assert!(
                diff <= tol,
                "{under:?} {label}: fluid {i} axis {k}: u {} against {want} (tolerance {tol:.2e})",
                moved.velocity[i][k]
            );
            worst = worst.max(diff / tol);
            effect = effect.max((without_solids[i].0[k] - dx[k]).abs() / tau / tol);
        }
    }
    assert!(
        effect > 100.0,
        "{label}: the walls' terms change u by only {effect:.1} tolerances"
    );
    (worst_wall, worst)
}

/// What one sweep left: after `predicted_density`, the error, after `mix_velocity_pressure`,
/// after `velocity_from_pressure` (id order).
type SweepStates<const D: usize> = (Fields<D>, sph::backend::CorrectionError, Fields<D>, Fields<D>);

/// [`SWEEPS`] sweeps of the solve as `solver::step` runs them, then `end_velocity_solve(keep)`,
/// every stage checked per sweep (module doc), the mixing against [`Mixing`] within its
/// tolerance. Also: the window fills and wraps, the residual falls, and the accelerated pressure
/// differs from plain projected Jacobi by far more than the tolerance once differences are held.
fn check_sweeps<const D: usize>(seed: u64, phases: Phases) {
    let (f, p) = solve_scene::<D>(seed, DensityKernel::ScaledSpiky, phases);
    let k = stiffness(&p, TAU);
    let start = in_id_order(&f);
    let label = format!("{D}D {phases:?}");
    for under in backends() {
        let (out, sweeps) = under.run(&f, &p, |b, f| {
            b.begin_velocity_solve(f, &p);
            let mut sweeps: Vec<SweepStates<D>> = Vec::new();
            for _ in 0..SWEEPS {
                b.predicted_density(f, &p, TAU);
                let predicted = snapshot(b, f);
                let error = b.correction_error(f, &p);
                b.mix_velocity_pressure(f, &p, k);
                let mixed = snapshot(b, f);
                b.velocity_from_pressure(f, &p, TAU);
                sweeps.push((predicted, error, mixed, snapshot(b, f)));
            }
            b.end_velocity_solve(f, true);
            sweeps
        });
        let mut mixing = Mixing::new(start.len());
        let mut residuals = Vec::new();
        let mut worst = [0.0f64; 4];
        let (mut weakest, mut widest) = (f64::INFINITY, 0.0f64);
        let mut current = &start;
        for (s, (predicted, error, mixed, moved)) in sweeps.iter().enumerate() {
            let label = format!("{label} sweep {s}");
            let (w, _) = check_predicted(under, &label, &start, current, predicted, &p);
            worst[0] = worst[0].max(w);
            let want_error = reference_error(predicted, &p);
            check_error(under, &label, *error, want_error);
            residuals.push(want_error.residual);
            let (want, tol, jacobi) = mixing.mix(predicted, &p, k);
            let mut effect = 0.0f64;
            for i in 0..start.len() {
                if start.kind[i] != FLUID {
                    let (g, w) = (mixed.pressure[i], predicted.pressure[i]);
                    assert_eq!(
                        g.to_bits(),
                        w.to_bits(),
                        "{under:?} {label}: solid {i} keeps its pressure"
                    );
                    continue;
                }
                let diff = f64::from(mixed.pressure[i] - want[i]).abs();
                assert!(
                    diff <= tol[i],
                    "{under:?} {label}: fluid {i}: mixed pressure {} against {} (tolerance {:.2e})",
                    mixed.pressure[i],
                    want[i],
                    tol[i]
                );
                // A zero tolerance (bitwise) counts as one f32 rounding of the value.
                let scale = tol[i].max(EPS * f64::from(want[i]));
                worst[1] = worst[1].max(diff / scale);
                widest = widest.max(tol[i]);
                effect = effect.max(f64::from(jacobi[i] - want[i]).abs() / scale);
            }
            if mixing.state.held > 0 {
                assert!(
                    effect > 100.0,
                    "{label}: the mixing changes P by only {effect:.1} tolerances"
                );
                weakest = weakest.min(effect);
            }
            assert_eq!(
                mixed.velocity, predicted.velocity,
                "{under:?} {label}: mixing moves no velocity"
            );
            let (w_wall, w_u) = check_velocities(under, &label, &start, mixed, moved, &p);
            worst[2] = worst[2].max(w_wall);
            worst[3] = worst[3].max(w_u);
            current = moved;
        }
        assert_eq!(mixing.state.held, WINDOW, "{label}: the window fills");
        let (first, final_residual) = (residuals[0], residuals[SWEEPS - 1]);
        assert!(
            final_residual < 0.5 * first,
            "{label}: the solve converges ({first:.2e} -> {final_residual:.2e})"
        );
        // Kept: the released pressure, the last velocities, the start's density (18).
        let (last, out) = (&sweeps[SWEEPS - 1].3, in_id_order(&out));
        check_end(under, &label, &start, last, &out, true);
        eprintln!(
            "{under:?} {label}: worst against the tolerance: predicted_density {:.2e}, mix {:.2e}, \
             walls {:.2e}, velocities {:.2e}; residual {first:.2e} -> {final_residual:.2e}; \
             mix tolerance up to {widest:.2e} Pa, the mixing shows by at least {weakest:.1e} of it",
            worst[0], worst[1], worst[2], worst[3]
        );
    }
}

#[test]
fn velocity_solve_sweeps_are_anderson_mixed_projected_jacobi() {
    for phases in [Phases::Single, Phases::Multi] {
        check_sweeps::<2>(0x3333_cccc_5678_1234, phases);
        check_sweeps::<3>(0x9999_4444_aaaa_bbbb, phases);
    }
}

/// `end_velocity_solve` in `out` after the solve left `last`: kept, `P = min(P, P_start)` (a NaN
/// start takes the solve's, as `f32::min`), the solve's velocities and its `P` as the acting
/// pressure; given up, the start's pressure and velocity, and the start's pressure as the acting
/// one; either way the start's density and positions; all bitwise.
fn check_end<const D: usize>(
    under: Under,
    label: &str,
    start: &Fields<D>,
    last: &Fields<D>,
    out: &Fields<D>,
    keep: bool,
) {
    for i in 0..start.len() {
        let want = if keep {
            last.pressure[i].min(start.pressure[i])
        } else {
            start.pressure[i]
        };
        let got = out.pressure[i];
        assert_eq!(
            got.to_bits(),
            want.to_bits(),
            "{under:?} {label} keep {keep}: particle {i}: P {got} against {want}"
        );
        let acted = if keep { last.pressure[i] } else { start.pressure[i] };
        let got = out.acting_pressure[i];
        assert_eq!(
            got.to_bits(),
            acted.to_bits(),
            "{under:?} {label} keep {keep}: particle {i}: acting pressure {got} against {acted}"
        );
        let velocity = if keep {
            &last.velocity[i]
        } else {
            &start.velocity[i]
        };
        assert_eq!(
            &out.velocity[i], velocity,
            "{under:?} {label} keep {keep}: velocity of {i}"
        );
        let (got, want) = (out.density[i], start.density[i]);
        assert_eq!(
            got.to_bits(),
            want.to_bits(),
            "{under:?} {label} keep {keep}: density of {i}"
        );
    }
    assert_eq!(out.position, start.position, "{under:?} {label}: positions stay");
}

/// One sweep, then `end_velocity_solve` kept and given up (module doc), with a NaN start
/// pressure on a fluid particle far from all others. Checks that the solve both raised and
/// released many pressures, so that the `min` is seen both ways.
fn check_end_velocity_solve<const D: usize>(seed: u64) {
    let (mut f, p) = solve_scene::<D>(seed, DensityKernel::ScaledSpiky, Phases::Single);
    let k = stiffness(&p, TAU);
    let far = p.domain_max - Vector::<D>::repeat(DX);
    f.push(far, Vector::repeat(0.5), f.mass[0], p.rho0, FLUID);
    f.wall_velocity.push(Vector::zeros());
    *f.pressure.last_mut().expect("just pushed") = f32::NAN;
    let nan = f.len() - 1;
    let start = in_id_order(&f);
    for under in backends() {
        for keep in [true, false] {
            let (out, last) = under.run(&f, &p, |b, f| {
                b.begin_velocity_solve(f, &p);
                b.predicted_density(f, &p, TAU);
                b.mix_velocity_pressure(f, &p, k);
                b.velocity_from_pressure(f, &p, TAU);
                let last = snapshot(b, f);
                b.end_velocity_solve(f, keep);
                last
            });
            let out = in_id_order(&out);
            check_end(under, &format!("{D}D"), &start, &last, &out, keep);
            if keep {
                assert_eq!(
                    out.pressure[nan], 0.0,
                    "{under:?}: the NaN start keeps the solve's number"
                );
                let count = |up: bool| {
                    (0..start.len())
                        .filter(|&i| start.kind[i] == FLUID && i != nan)
                        .filter(|&i| {
                            (last.pressure[i] > start.pressure[i]) == up
                                && last.pressure[i] != start.pressure[i]
                        })
                        .count()
                };
                let fluid = (0..start.len()).filter(|&i| start.kind[i] == FLUID).count();
                assert!(
                    count(true) > fluid / 10 && count(false) > fluid / 10,
                    "{D}D: raised {}, released {}",
                    count(true),
                    count(false)
                );
            }
            eprintln!("{under:?} {D}D end_velocity_solve keep {keep}: bitwise");
        }
    }
}

#[test]
fn end_velocity_solve_keeps_the_released_pressure_or_restores_the_start() {
    check_end_velocity_solve::<2>(0x0123_4567_89ab_cdef);
    check_end_velocity_solve::<3>(0xfedc_ba98_7654_3210);
}

/// `record_acting_pressure`: every particle's acting pressure is its pressure, bitwise (a NaN
/// too), on every backend.
fn check_record_acting_pressure<const D: usize>(seed: u64) {
    let (mut f, p) = solve_scene::<D>(seed, DensityKernel::ScaledSpiky, Phases::Single);
    for (i, p) in f.pressure.iter_mut().enumerate() {
        *p = 100.0 + i as f32 * 0.37;
    }
    f.pressure[0] = f32::NAN;
    let start = in_id_order(&f);
    for under in backends() {
        let (out, ()) = under.run(&f, &p, |b, f| b.record_acting_pressure(f));
        let out = in_id_order(&out);
        for i in 0..start.len() {
            let want = start.pressure[i].to_bits();
            assert_eq!(
                out.acting_pressure[i].to_bits(),
                want,
                "{under:?} {D}D: particle {i}"
            );
            assert_eq!(
                out.pressure[i].to_bits(),
                want,
                "{under:?} {D}D: pressure of {i} stays"
            );
        }
    }
}

#[test]
fn record_acting_pressure_copies_the_pressure() {
    check_record_acting_pressure::<2>(0x5555_0000_1111_2222);
    check_record_acting_pressure::<3>(0x6666_7777_8888_9999);
}
