//! `[[probe]]` tables: unique names, axes below `dimension`, solids that exist, reference
//! data described consistently.

use super::*;

/// Checks `probe[i]`; `has_grav` is whether the gravity effect is on.
pub(super) fn check_probe(
    c: &mut Checker,
    file: &SceneFile,
    i: usize,
    pf: &ProbeFile,
    dim: Option<usize>,
    has_grav: bool,
) -> Option<Probe> {
    let path = KeyPath::key("probe").i(i);
    let earlier: Vec<&str> = file.probe.iter().take(i).map(|o| o.name.as_str()).collect();
    let mut ok = check_name(c, path.k("name"), &pf.name, &earlier, "probe");
    let kind = pf.kind;
    // A level gauge stands along the vertical (the last axis) unless the scene says otherwise.
    let default_axis = match (kind, dim) {
        (ProbeKind::Level, Some(3)) => "z",
        (ProbeKind::Level, _) => "y",
        _ => "x",
    };
    if kind == ProbeKind::Pressure && pf.axis.is_some() {
        c.err(
            path.k("axis"),
            "not with kind = \"pressure\" (a pressure has no axis)".into(),
        );
        ok = false;
    }
    let axis_text = pf.axis.as_deref().unwrap_or(default_axis);
    let axis = match (["x", "y", "z"].iter().position(|a| *a == axis_text), dim) {
        (Some(a), Some(d)) if a < d => Some(a),
        (Some(_), None) => None,
        (found, d) => {
            let allowed = if d == Some(2) {
                "\"x\" or \"y\""
            } else {
                "\"x\", \"y\" or \"z\""
            };
            let why = match (found, d) {
                (Some(_), Some(d)) => format!(" (dimension = {d})"),
                _ => String::new(),
            };
            c.err(
                path.k("axis"),
                format!("must be {allowed}{why}, got {axis_text:?}"),
            );
            None
        }
    };
    let origin = match pf.origin {
        Some(o) => c.finite(path.k("origin"), o),
        None => Some(0.0),
    };
    let force = pf.kind == ProbeKind::Force;
    let solid = match (&pf.solid, force) {
        (None, false) => Some(None),
        (Some(_), false) => {
            c.err(path.k("solid"), "only with kind = \"force\"".into());
            None
        }
        (None, true) => {
            c.err(
                path.k("solid"),
                "required with kind = \"force\": the solid's name".into(),
            );
            None
        }
        (Some(name), true) => match file.solid.iter().position(|s| &s.name == name) {
            Some(k) => Some(Some(k)),
            None => {
                c.err(path.k("solid"), format!("no solid named {name:?}"));
                None
            }
        },
    };
    if kind != ProbeKind::Front && pf.origin.is_some() {
        c.err(path.k("origin"), "only with kind = \"front\"".into());
        ok = false;
    }
    let at_point = matches!(
        kind,
        ProbeKind::Pressure | ProbeKind::Level | ProbeKind::Velocity | ProbeKind::FlowRate
    );
    let point = match (&pf.point, at_point) {
        (None, false) => Some(None),
        (Some(_), false) => {
            c.err(
                path.k("point"),
                "only with kind = \"pressure\", \"level\", \"velocity\" or \"flow_rate\"".into(),
            );
            None
        }
        (None, true) => {
            c.err(
                path.k("point"),
                format!("required with kind = \"{}\": where it measures [m]", kind.name()),
            );
            None
        }
        (Some(v), true) => c.vector(path.k("point"), v, dim).and_then(|v| {
            let outside = (0..v.len()).find(|&k| {
                let (lo, hi) = (file.domain.min.get(k), file.domain.max.get(k));
                lo.zip(hi).is_some_and(|(lo, hi)| v[k] < *lo || v[k] > *hi)
            });
            match outside {
                Some(k) => {
                    c.err(
                        path.k("point").i(k),
                        format!(
                            "{} lies outside the domain [{}, {}]",
                            v[k], file.domain.min[k], file.domain.max[k]
                        ),
                    );
                    None
                }
                None => Some(Some(v)),
            }
        }),
    };
    let flow = kind == ProbeKind::FlowRate;
    let size = match (&pf.size, flow, dim) {
        (None, false, _) => Some(None),
        (Some(_), false, _) => {
            c.err(path.k("size"), "only with kind = \"flow_rate\"".into());
            None
        }
        (None, true, _) => {
            c.err(
                path.k("size"),
                "required with kind = \"flow_rate\": the section's extents [m] along the other axes".into(),
            );
            None
        }
        (Some(_), true, None) => None,
        (Some(v), true, Some(d)) if v.len() != d - 1 => {
            c.err(
                path.k("size"),
                format!(
                    "expected {} entries (the axes other than `axis`), found {}",
                    d - 1,
                    v.len()
                ),
            );
            None
        }
        (Some(v), true, Some(_)) => {
            let sizes: Vec<Option<f64>> = v
                .iter()
                .enumerate()
                .map(|(k, &w)| c.positive(path.k("size").i(k), w))
                .collect();
            sizes.into_iter().collect::<Option<Vec<f64>>>().map(Some)
        }
    };
    if at_point && pf.reference.is_some() {
        c.err(
            path.k("reference"),
            format!(
                "reference data are compared for front and force probes; a {} probe is written to probes.csv and plotted without one",
                kind.name()
            ),
        );
        ok = false;
    }
    let reference = match &pf.reference {
        None => Some(None),
        Some(r) => {
            let rp = path.k("reference");
            if !has_grav && kind == ProbeKind::Front {
                c.err(
                    rp.clone(),
                    "needs effect \"gravity\" (the reference time is T = t sqrt(g / a))".into(),
                );
                ok = false;
            }
            if r.file.trim().is_empty() {
                c.err(rp.k("file"), "must not be empty".into());
                ok = false;
            }
            let series = r.series.clone().unwrap_or_default();
            for (j, name) in series.iter().enumerate() {
                if name.trim().is_empty() {
                    c.err(rp.k("series").i(j), "must not be empty".into());
                    ok = false;
                } else if let Some(k) = series.iter().take(j).position(|o| o == name) {
                    c.err(
                        rp.k("series").i(j),
                        format!("duplicate series \"{name}\" (already at series[{k}])"),
                    );
                    ok = false;
                }
            }
            let length = match (r.length, force) {
                (Some(l), false) => c.positive(rp.k("length"), l),
                (None, false) => {
                    c.err(
                        rp.k("length"),
                        "required for a front: the column width a [m]".into(),
                    );
                    None
                }
                (Some(_), true) => {
                    c.err(rp.k("length"), "only for a front".into());
                    None
                }
                (None, true) => Some(0.0),
            };
            let time_range = match r.time_range.as_deref() {
                None if force => Some((0.0, file.solver.end_time)),
                None => Some(ProbeReference::DEFAULT_TIME_RANGE),
                Some(&[t0, t1]) => {
                    let t0 = c.finite(rp.k("time_range").i(0), t0);
                    let t1 = c.finite(rp.k("time_range").i(1), t1);
                    match (t0, t1) {
                        (Some(t0), Some(t1)) if t0 < t1 => Some((t0, t1)),
                        (Some(t0), Some(t1)) => {
                            c.err(
                                rp.k("time_range"),
                                format!("must be [T0, T1] with T0 < T1, got [{t0}, {t1}]"),
                            );
                            None
                        }
                        _ => None,
                    }
                }
                Some(other) => {
                    c.err(
                        rp.k("time_range"),
                        format!("expected 2 entries [T0, T1], found {}", other.len()),
                    );
                    None
                }
            };
            match (length, time_range) {
                (Some(length), Some(time_range)) => Some(Some(ProbeReference {
                    file: PathBuf::from(&r.file),
                    location: crate::scene::ReferenceLocation::Unlocated,
                    series,
                    length,
                    time_range,
                })),
                _ => None,
            }
        }
    };
    let probe = Probe {
        name: pf.name.clone(),
        kind: pf.kind,
        axis: axis?,
        origin: origin?,
        solid: solid?,
        point: point?,
        size: size?,
        reference: reference?,
    };
    ok.then_some(probe)
}
