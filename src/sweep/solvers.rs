//! The solver comparison sweep (`sph sweep SCENE --solvers wcsph=C1,C2 --solvers
//! corrected=D1,D2`): `wcsph` over sound speeds and `corrected` over tolerances on one scene, and
//! its Pareto figure `pareto.png`, error against wall time per simulated second with one line
//! per solver. The answer to "which solver should I use" for a scene: the lower-left line wins.

use super::{Sweep, SweepError, Variant, VariantResult, split_values};
use crate::output::plot::{Figure, Series, SeriesStyle};

/// The key each solver is swept over: `wcsph` by its sound speed C [m/s] (its stiffness and time
/// step), `corrected` by its tolerance δ on the compression (eq. 24).
pub const SOLVER_KEYS: [(&str, &str); 2] = [("wcsph", "fluid.sound_speed"), ("corrected", "solver.delta")];

impl Sweep {
    /// The variants of `solvers` (each `KIND=V1,V2,...`, KIND `wcsph` with sound speeds or
    /// `corrected` with tolerances, see [`SOLVER_KEYS`]), each with every override of `sets`
    /// (which may not sweep: one value per key). Swept keys: `solver.kind` and the two keys of
    /// [`SOLVER_KEYS`]; a variant leaves the other solver's key empty.
    ///
    /// # Errors
    /// A malformed `--solvers` or `--set`, an unknown solver kind, a kind given twice, or a
    /// `--set` with several values.
    pub fn solvers(solvers: &[String], sets: &[String]) -> Result<Self, SweepError> {
        let base = Sweep::from_sets(sets)?;
        if let Some(key) = base.keys.first() {
            return Err(SweepError::SweptWithSolvers { key: key.clone() });
        }
        let base_sets = base.variants.first().map(|v| v.sets.clone()).unwrap_or_default();
        let mut keys = vec!["solver.kind".to_string()];
        keys.extend(SOLVER_KEYS.iter().map(|(_, k)| k.to_string()));
        let mut variants = Vec::new();
        let mut seen: Vec<&str> = Vec::new();
        for given in solvers {
            let bad = |reason: &str| SweepError::BadSolvers {
                given: given.clone(),
                reason: reason.into(),
            };
            let (kind, list) = given
                .split_once('=')
                .ok_or_else(|| bad("expected KIND=V1,V2,..."))?;
            let kind = kind.trim();
            let slot = SOLVER_KEYS
                .iter()
                .position(|(k, _)| *k == kind)
                .ok_or_else(|| bad("KIND is wcsph (sound speeds) or corrected (tolerances)"))?;
            if seen.contains(&kind) {
                return Err(bad("each solver kind may be given once"));
            }
            seen.push(SOLVER_KEYS[slot].0);
            let values = split_values(list);
            if values.is_empty() || values.iter().any(String::is_empty) {
                return Err(bad("empty value (expected KIND=V1,V2,...)"));
            }
            let key = SOLVER_KEYS[slot].1;
            for v in values {
                let mut row = vec![kind.to_string(), String::new(), String::new()];
                row[1 + slot] = v.clone();
                let mut sets = base_sets.clone();
                sets.push(format!("solver.kind={kind}"));
                sets.push(format!("{key}={v}"));
                variants.push(Variant {
                    name: format!("solver.kind={kind} {key}={v}"),
                    values: row,
                    sets,
                });
            }
        }
        if variants.is_empty() {
            return Err(SweepError::BadSolvers {
                given: String::new(),
                reason: "no solver given".into(),
            });
        }
        Ok(Sweep { keys, variants })
    }
}

/// Wall time per simulated second [s/s] of a finished variant.
pub(super) fn wall_per_simulated_second(r: &VariantResult) -> Option<f64> {
    let s = r.summary.as_ref()?;
    (s.simulated_time > 0.0).then(|| s.wall_seconds / s.simulated_time)
}

/// `pareto.png`: per solver kind, its variants at (wall time per simulated second, error), joined
/// in order of cost, log-log. The error is the mean relative error of `probe` when any variant
/// has one, else the largest compression. `None` when no variant finished.
pub(super) fn pareto_figure(
    scene: &str,
    results: &[VariantResult],
    probe: Option<&String>,
) -> Option<Figure> {
    let probe_error = |r: &VariantResult| probe.and_then(|p| r.probe_error(p, "error_mean"));
    let use_probe = results.iter().any(|r| probe_error(r).is_some_and(f64::is_finite));
    let y_label = match probe {
        Some(p) if use_probe => format!("{p}: mean relative error against reference [-]"),
        _ => "max compression max(rho - rho0, 0)/rho0 [-]".into(),
    };
    let mut series: Vec<Series> = Vec::new();
    for r in results.iter().filter(|r| r.status == "completed") {
        let Some(s) = r.summary.as_ref() else { continue };
        let y = if use_probe {
            probe_error(r)
        } else {
            r.max_compression()
        };
        let (Some(x), Some(y)) = (wall_per_simulated_second(r), y) else {
            continue;
        };
        if !(x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite()) {
            continue;
        }
        match series.iter_mut().find(|c| c.label == s.solver) {
            Some(c) => c.points.push((x, y)),
            None => series.push(Series {
                label: s.solver.clone(),
                points: vec![(x, y)],
                style: SeriesStyle::LineMarkers,
            }),
        }
    }
    for c in &mut series {
        c.points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    (!series.is_empty()).then(|| Figure {
        title: format!("{scene}: error against cost, per solver"),
        x_label: "wall time per simulated second [s/s]".into(),
        y_label,
        log_x: true,
        log_y: true,
        series,
        vertical_lines: Vec::new(),
    })
}
