//! Single-table rules: names of solids and probes, the `[solver]`
//! settings and the rotating frame's keys.

use super::*;

/// Checks a solid or probe name: non-empty, `[A-Za-z0-9_-]` only, not among `earlier`
/// (the names of the preceding `what` tables). Reports at `path`; returns whether it is fine.
pub(super) fn check_name(c: &mut Checker, path: KeyPath, name: &str, earlier: &[&str], what: &str) -> bool {
    if name.is_empty() {
        c.err(path, "must not be empty".into());
    } else if let Some(bad) = name
        .chars()
        .find(|ch| !(ch.is_ascii_alphanumeric() || *ch == '_' || *ch == '-'))
    {
        c.err(
            path,
            format!("may only contain A-Z, a-z, 0-9, '_' and '-', found {bad:?}"),
        );
    } else if let Some(j) = earlier.iter().position(|o| *o == name) {
        c.err(
            path,
            format!("duplicate {what} name \"{name}\" (already used by {what}[{j}])"),
        );
    } else {
        return true;
    }
    false
}

/// The `[solver]` scheme settings; `corrected`-only keys are an error with `wcsph`.
pub(super) fn check_solver(c: &mut Checker, sp: &KeyPath, sv: &SolverFile) -> Option<SolverSettings> {
    let mut settings = SolverSettings::defaults(sv.kind);
    if let Some(integrator) = sv.integrator {
        settings.integrator = integrator;
    }
    let corrected = sv.kind == SolverKind::Corrected;
    let mut ok = true;
    let given = [
        ("delta", sv.delta.is_some()),
        ("max_iterations", sv.max_iterations.is_some()),
        ("strict", sv.strict.is_some()),
        ("relaxation", sv.relaxation.is_some()),
        ("warm_start", sv.warm_start.is_some()),
    ];
    for (key, present) in given {
        if present && !corrected {
            c.err(
                sp.k(key),
                format!(
                    "only with solver.kind = \"corrected\" (solver.kind is \"{}\")",
                    sv.kind.name()
                ),
            );
            ok = false;
        }
    }
    if !ok {
        return None;
    }
    if let Some(d) = sv.delta {
        match in_range(c, sp.k("delta"), d, 0.0, 0.1, true) {
            Some(d) => settings.delta = d,
            None => ok = false,
        }
    }
    if let Some(n) = sv.max_iterations {
        match u32::try_from(n) {
            Ok(m) if (1..=100_000).contains(&m) => settings.max_iterations = m,
            _ => {
                c.err(
                    sp.k("max_iterations"),
                    format!("must be an integer in [1, 100000], got {n}"),
                );
                ok = false;
            }
        }
    }
    if let Some(strict) = sv.strict {
        settings.strict = strict;
    }
    if let Some(warm) = sv.warm_start {
        settings.warm_start = warm;
    }
    if let Some(moment) = sv.gradient_moment {
        settings.gradient_moment = moment;
    }
    if let Some(policy) = sv.on_escape {
        settings.on_escape = policy;
    }
    if let Some(w) = sv.relaxation {
        match in_range(c, sp.k("relaxation"), w, 0.0, 1.0, true) {
            Some(w) => settings.relaxation = w,
            None => ok = false,
        }
    }
    ok.then_some(settings)
}

/// `fluid.angular_velocity` as 3 components and `fluid.rotation_centre` (default the origin):
/// required / allowed iff the `rotating_frame` effect is on (`schema::FluidFile`).
pub(super) fn rotating_frame(
    c: &mut Checker,
    fp: &KeyPath,
    f: &crate::scene::schema::FluidFile,
    on: bool,
    dim: Option<usize>,
) -> (Option<[f64; 3]>, Option<Vec<f64>>) {
    use crate::scene::schema::AngularVelocityFile;
    let key = fp.k("angular_velocity");
    let omega = match (&f.angular_velocity, on, dim) {
        (Some(_), false, _) => {
            c.err(
                key,
                "given but effect \"rotating_frame\" is not enabled (add it to `effects` or remove this key)"
                    .into(),
            );
            None
        }
        (None, true, _) => {
            c.err(
                key,
                "required because effect \"rotating_frame\" is enabled".into(),
            );
            None
        }
        (None, false, _) | (Some(_), true, None) => None,
        (Some(AngularVelocityFile::Scalar(w)), true, Some(2)) => c.finite(key, *w).map(|w| [0.0, 0.0, w]),
        (Some(AngularVelocityFile::Scalar(_)), true, Some(d)) => {
            c.err(
                key,
                format!(
                    "expected {d} entries (dimension = {d}); a single number (about the out-of-plane axis) is for 2D only"
                ),
            );
            None
        }
        (Some(AngularVelocityFile::Vector(v)), true, Some(d)) => c
            .vector(key, v, Some(d))
            .map(|v| [v[0], v[1], if d > 2 { v[2] } else { 0.0 }]),
    };
    let centre = match (&f.rotation_centre, on) {
        (Some(_), false) => {
            c.err(
                fp.k("rotation_centre"),
                "given but effect \"rotating_frame\" is not enabled".into(),
            );
            None
        }
        (Some(x), true) => c.vector(fp.k("rotation_centre"), x, dim),
        (None, _) => dim.map(|d| vec![0.0; d]),
    };
    (omega, centre)
}

/// `fluid.initial_state` (default uniform). Hydrostatic needs the `gravity` effect (a column
/// without weight is uniform), no `gravity_ramp` (the ramp starts without weight, which a
/// hydrostatic column is not in) and no `multiphase` (a column of several densities is not
/// `ρ0 g (H − z)`); `gravity_ramp` is the validated ramp.
pub(super) fn initial_state(
    c: &mut Checker,
    fp: &KeyPath,
    f: &crate::scene::schema::FluidFile,
    effects: &[Effect],
    gravity_ramp: Option<f64>,
) -> crate::scene::initial_state::InitialState {
    use crate::scene::initial_state::InitialState;
    let state = f.initial_state.unwrap_or_default();
    if state == InitialState::Hydrostatic {
        let key = fp.k("initial_state");
        if !effects.contains(&Effect::Gravity) {
            c.err(
                key,
                "\"hydrostatic\" needs effect \"gravity\": without weight a column at rest is uniform".into(),
            );
        } else if gravity_ramp.is_some_and(|r| r > 0.0) {
            c.err(
                key,
                "\"hydrostatic\" starts with the column's full weight, but `fluid.gravity_ramp` starts without \
                 gravity: remove one of the two"
                    .into(),
            );
        }
        if effects.contains(&Effect::Multiphase) {
            c.err(
                fp.k("initial_state"),
                "\"hydrostatic\" with effect \"multiphase\" is not supported: a column of several densities \
                 does not carry ρ0 g (H − z)"
                    .into(),
            );
        }
    }
    state
}

/// `fluid.artificial_viscosity_wall_factor` (default 1): ≥ 0, allowed only with the
/// `artificial_viscosity` effect, which it qualifies.
pub(super) fn artificial_viscosity_wall_factor(
    c: &mut Checker,
    fp: &KeyPath,
    f: &crate::scene::schema::FluidFile,
    effects: &[Effect],
) -> Option<f64> {
    use crate::model::pair_terms::PairTerm;
    use crate::physics::artificial_viscosity::DEFAULT_WALL_FACTOR;
    let key = fp.k("artificial_viscosity_wall_factor");
    match f.artificial_viscosity_wall_factor {
        Some(_) if !effects.contains(&Effect::Pair(PairTerm::ArtificialViscosity)) => {
            c.err(
                key,
                "given but effect \"artificial_viscosity\" is not enabled (add it to `effects` or remove this key)"
                    .into(),
            );
            Some(DEFAULT_WALL_FACTOR)
        }
        Some(factor) => c.non_negative(key, factor),
        None => Some(DEFAULT_WALL_FACTOR),
    }
}

/// `fluid.density_diffusion`: δ ≥ 0, required / allowed iff the `density_diffusion` effect is
/// on; the effect with `multiphase` is refused ([F19]'s hydrostatic part and the continuity
/// sum are written for one rest density).
pub(super) fn density_diffusion(
    c: &mut Checker,
    fp: &KeyPath,
    f: &crate::scene::schema::FluidFile,
    effects: &[Effect],
) -> Option<f64> {
    let key = fp.k("density_diffusion");
    let on = effects.contains(&Effect::DensityDiffusion);
    if on && effects.contains(&Effect::Multiphase) {
        c.err(
            key.clone(),
            "effect \"density_diffusion\" is not supported with \"multiphase\" (its hydrostatic part assumes one rest density)".into(),
        );
    }
    match (f.density_diffusion, on) {
        (Some(delta), true) => c.non_negative(key, delta),
        (None, true) => {
            c.err(
                key,
                "required because effect \"density_diffusion\" is enabled".into(),
            );
            None
        }
        (Some(_), false) => {
            c.err(
                key,
                "given but effect \"density_diffusion\" is not enabled (add it to `effects` or remove this key)"
                    .into(),
            );
            None
        }
        (None, false) => None,
    }
}
