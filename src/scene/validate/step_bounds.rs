//! Bounds on a fixed `solver.dt`: the acoustic bound of `wcsph` and the gravity and flow
//! bounds of `corrected` (`solver::timestep` applies the same bounds at run time).

use super::*;

/// A fixed `solver.dt` \[s\] for `wcsph` must not exceed the acoustic bound `h / C` (support
/// radius over sound speed, CFL number 1): beyond it a pressure wave crosses more than a kernel
/// support per step, which no explicit scheme follows (the CFL condition; the adaptive step
/// uses a fifth of it by default). Adaptive steps and `corrected`
/// (no acoustic wave, eq. (19) unused) are not limited here; at run time a fixed step is also
/// cut to the force and viscous limits (`solver::timestep::choose`).
pub(super) fn check_acoustic_step(
    c: &mut Checker,
    sp: &KeyPath,
    dt: f64,
    kind: SolverKind,
    h: f64,
    sound: f64,
) {
    let bound = h / sound;
    if kind == SolverKind::Wcsph && dt > bound {
        c.err(
            sp.k("dt"),
            format!(
                "{} s is above the acoustic stability bound h / C = {} m / {} m/s = {} s of solver.kind = \"wcsph\" (CFL number 1); use solver.dt <= {}, or remove solver.dt for an adaptive step",
                num(dt),
                num(h),
                num(sound),
                num(bound),
                num(bound)
            ),
        );
    }
}

/// Factor `k_g` of the gravity bound `k_g sqrt(h / |g|)` on a fixed `corrected` step. Measured
/// (docs/hard-cases.md) as the largest fixed step that keeps every hard-case invariant, over
/// `sqrt(h/|g|)`: `viscous_low_3d.toml` passes at 0.85 ms and fails the energy bound at 1 ms
/// (h = 0.04 m: 0.0133 and 0.0157); `large_dt_3d.toml` 2.5 ms (0.039), `large_dt_2d.toml`
/// 2.5 ms (h = 0.02 m: 0.055), `rest_2d.toml` 3.5 ms (0.078), `viscous_low_2d.toml` at least
/// 6 ms (0.13). 0.0125 stays below the smallest (`rest_3d.toml` fails at every step tried,
/// adaptive included: a known failure).
pub const CORRECTED_GRAVITY_FACTOR: f64 = 0.0125;

/// Factor `k_u` of the flow bound `k_u h / |u|max` on a fixed `corrected` step, `|u|max` the
/// largest initial fluid speed or moving-wall speed. Measured on `jet_2d.toml` (10 m/s, h =
/// 0.02 m): 0.25 h / |u| = 0.5 ms keeps every invariant, 0.3 h / |u| (0.6 ms) raises the energy
/// at the impact; `jet_3d.toml` (h = 0.04 m) passes at 0.25 and 0.3 h / |u|. A 12 × 12 lattice
/// block thrown at 1 m/s at a wall (h = 0.02 m, no gravity, with the no-penetration guard;
/// tests/numerics/correction.rs) stays in its box for 0.3 s at 0.05, 0.075, 0.1 and 0.15 h / |u|; at
/// 0.125, 0.2 and 0.25 the impact is violent enough that a particle went through the wall (steps
/// 25, 7 and 7) until the guard took each particle's step start into account, and since then the
/// correction stops unconverged (steps 28, 10 and 9). 0.1 is the largest factor below which every
/// measured step passed.
pub const CORRECTED_FLOW_FACTOR: f64 = 0.1;

/// The largest fixed `solver.dt` [s] that validation accepts for `solver.kind = "corrected"`:
/// `min(k_g sqrt(h / |g|), k_u h / |u|max)` over the terms that apply (gravity given and
/// non-zero; a fluid box or moving wall with a non-zero speed), `None` when neither applies.
/// `h` is the support radius [m], `gravity` [m/s²], the speeds from the fluid boxes' initial
/// velocities and the solids' `Motion::max_speed` [m/s]. The corrected solver has no acoustic
/// limit (its pressure does not come from eq. (19)); these are the measured limits of its
/// start-up and of impacts (`CORRECTED_GRAVITY_FACTOR`, `CORRECTED_FLOW_FACTOR`).
pub fn corrected_step_bound(
    h: f64,
    gravity: Option<&[f64]>,
    fluid_boxes: &[FluidBox],
    solids: &[Solid],
) -> Option<f64> {
    corrected_step_terms(h, gravity, fluid_boxes, solids)
        .map(|t| t.gravity.min(t.flow))
        .filter(|b| b.is_finite())
}

/// The two terms of [`corrected_step_bound`] with their inputs (infinite where absent).
pub(super) struct CorrectedStepTerms {
    g: f64,
    gravity: f64,
    speed: f64,
    flow: f64,
}

pub(super) fn corrected_step_terms(
    h: f64,
    gravity: Option<&[f64]>,
    fluid_boxes: &[FluidBox],
    solids: &[Solid],
) -> Option<CorrectedStepTerms> {
    let norm = |v: &[f64]| v.iter().map(|c| c * c).sum::<f64>().sqrt();
    let g = gravity.map(norm).unwrap_or(0.0);
    let speed = fluid_boxes
        .iter()
        .map(|b| norm(&b.velocity))
        .chain(
            solids
                .iter()
                .filter_map(|s| s.motion.as_ref())
                .map(Motion::max_speed),
        )
        .fold(0.0, f64::max);
    if !(g.is_finite() && speed.is_finite()) {
        return None;
    }
    let gravity = if g > 0.0 {
        CORRECTED_GRAVITY_FACTOR * (h / g).sqrt()
    } else {
        f64::INFINITY
    };
    let flow = if speed > 0.0 {
        CORRECTED_FLOW_FACTOR * h / speed
    } else {
        f64::INFINITY
    };
    Some(CorrectedStepTerms {
        g,
        gravity,
        speed,
        flow,
    })
}

/// A fixed `solver.dt` \[s\] for `corrected` must not exceed [`corrected_step_bound`]; the
/// error names the value, the bound, the terms it is made of and the fix.
pub(super) fn check_corrected_step(
    c: &mut Checker,
    sp: &KeyPath,
    dt: f64,
    h: f64,
    gravity: Option<&[f64]>,
    fluid_boxes: &[FluidBox],
    solids: &[Solid],
) {
    let Some(t) = corrected_step_terms(h, gravity, fluid_boxes, solids) else {
        return;
    };
    let bound = t.gravity.min(t.flow);
    if dt <= bound {
        return;
    }
    // Six significant digits, rounded down so that the value shown is itself accepted; the
    // whole problem stays one readable line.
    let shown = |v: f64| {
        let scale = 10f64.powi(5 - v.log10().floor() as i32);
        num((v * scale).floor() / scale)
    };
    let mut terms = Vec::new();
    let mut inputs = vec![format!("h = {} m", num(h))];
    if t.gravity.is_finite() {
        terms.push(format!(
            "{CORRECTED_GRAVITY_FACTOR} sqrt(h / |g|) = {} s",
            shown(t.gravity)
        ));
        inputs.push(format!("|g| = {} m/s^2", num(t.g)));
    }
    if t.flow.is_finite() {
        terms.push(format!(
            "{CORRECTED_FLOW_FACTOR} h / |u|max = {} s",
            shown(t.flow)
        ));
        inputs.push(format!("|u|max = {} m/s", num(t.speed)));
    }
    let how = match terms.as_slice() {
        [one] => one.clone(),
        _ => format!("min({})", terms.join(", ")),
    };
    c.err(
        sp.k("dt"),
        format!(
            "{} s is above the largest fixed step of solver.kind = \"corrected\", {how} ({}); use a smaller solver.dt, or remove solver.dt for an adaptive step",
            num(dt),
            inputs.join(", ")
        ),
    );
}
