//! `[[probe]]` tables: unique names, axes below `dimension`, solids that exist, reference
//! data described consistently.

use super::*;
use crate::scene::schema::ProbeReferenceFile;
use crate::scene::{Averaging, Sensor};

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
    // A moment is about z by default: in 2D the only one, the out-of-plane moment.
    let default_axis = match (kind, dim) {
        (ProbeKind::Moment, _) => "z",
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
    let moment = kind == ProbeKind::Moment;
    let axis = match (["x", "y", "z"].iter().position(|a| *a == axis_text), dim) {
        (Some(a), Some(d)) if moment && (d == 3 || a == 2) => Some(a),
        (_, Some(2)) if moment => {
            c.err(
                path.k("axis"),
                format!(
                    "must be \"z\" for a moment in 2D (only the out-of-plane moment exists), got {axis_text:?}"
                ),
            );
            None
        }
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
    let solid = match (&pf.solid, force || moment) {
        (None, false) => Some(None),
        (Some(_), false) => {
            c.err(path.k("solid"), "only with kind = \"force\" or \"moment\"".into());
            None
        }
        (None, true) => {
            c.err(
                path.k("solid"),
                format!("required with kind = \"{}\": the solid's name", kind.name()),
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
    let point = match (&pf.point, at_point || moment) {
        (None, false) => Some(None),
        (Some(_), false) => {
            c.err(
                path.k("point"),
                "only with kind = \"pressure\", \"level\", \"velocity\", \"flow_rate\" or \"moment\"".into(),
            );
            None
        }
        (None, true) if moment => {
            c.err(
                path.k("point"),
                "required with kind = \"moment\": the point the moment is taken about [m]".into(),
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
        // The moment's point may lie anywhere (a wall's foot is often on the domain's edge).
        (Some(v), true) if moment => c.vector(path.k("point"), v, dim).map(Some),
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
    if kind == ProbeKind::FlowRate && pf.reference.is_some() {
        c.err(
            path.k("reference"),
            "reference data are compared for front, force, pressure, level and velocity probes; a flow_rate probe is written to probes.csv and plotted without one".into(),
        );
        ok = false;
    }
    if moment && pf.reference.is_some() {
        c.err(
            path.k("reference"),
            "reference data are compared for front, force, pressure, level and velocity probes; a moment probe is written to probes.csv without one".into(),
        );
        ok = false;
    }
    let sensor = check_sensor(c, &path, pf, dim);
    let averaging = match (pf.sampling_rate, kind) {
        // A moment is averaged as the force it comes from.
        (None, ProbeKind::Force | ProbeKind::Moment) => Some(Averaging::Interval),
        (None, _) => Some(Averaging::Instant),
        (Some(_), ProbeKind::Front) => {
            c.err(
                path.k("sampling_rate"),
                "not with kind = \"front\" (a front is not a transducer's reading)".into(),
            );
            None
        }
        (Some(rate), _) => c
            .positive(path.k("sampling_rate"), rate)
            .map(|rate| Averaging::Window(1.0 / rate)),
    };
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
            let front = kind == ProbeKind::Front;
            let length = match (r.length, kind) {
                (Some(_), ProbeKind::Force) => {
                    c.err(
                        rp.k("length"),
                        "only for a front, pressure, level or velocity".into(),
                    );
                    None
                }
                (Some(l), _) => c.positive(rp.k("length"), l).map(Some),
                (None, ProbeKind::Front) => {
                    c.err(
                        rp.k("length"),
                        "required for a front: the column width a [m]".into(),
                    );
                    None
                }
                (None, _) => Some(None),
            };
            if !has_grav && !front && r.length.is_some() {
                c.err(
                    rp.k("length"),
                    "needs effect \"gravity\" (the reference time is T = t sqrt(g / H))".into(),
                );
                ok = false;
            }
            let columns = check_columns(c, &rp, r, at_point);
            let time_range = match r.time_range.as_deref() {
                None if force => Some((0.0, file.solver.end_time)),
                None if at_point => Some((f64::NEG_INFINITY, f64::INFINITY)),
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
            match (length, time_range, columns) {
                (Some(length), Some(time_range), Some(columns)) => Some(Some(ProbeReference {
                    file: PathBuf::from(&r.file),
                    location: crate::scene::ReferenceLocation::Unlocated,
                    series,
                    length,
                    time_range,
                    columns,
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
        sensor: sensor?,
        averaging: averaging?,
    };
    ok.then_some(probe)
}

/// The index of axis name `text` below `dim`, or an error at `key`.
fn axis_index(c: &mut Checker, key: KeyPath, text: &str, dim: Option<usize>) -> Option<usize> {
    match (["x", "y", "z"].iter().position(|a| *a == text), dim) {
        (Some(a), Some(d)) if a < d => Some(a),
        (Some(a), None) => Some(a),
        _ => {
            let allowed = if dim == Some(2) {
                "\"x\" or \"y\""
            } else {
                "\"x\", \"y\" or \"z\""
            };
            c.err(key, format!("must be {allowed}, got {text:?}"));
            None
        }
    }
}

/// A pressure sensor's face: `diameter` and `normal` together, pressure only.
fn check_sensor(c: &mut Checker, path: &KeyPath, pf: &ProbeFile, dim: Option<usize>) -> Option<Sensor> {
    let pressure = pf.kind == ProbeKind::Pressure;
    match (pf.diameter, &pf.normal) {
        (None, None) => Some(Sensor::Point),
        (Some(_), _) | (_, Some(_)) if !pressure => {
            let key = if pf.diameter.is_some() {
                "diameter"
            } else {
                "normal"
            };
            c.err(path.k(key), "only with kind = \"pressure\"".into());
            None
        }
        (Some(_), None) => {
            c.err(
                path.k("normal"),
                "required with diameter: the axis normal to the sensor's face, e.g. \"x\" on a wall x = const".into(),
            );
            None
        }
        (None, Some(_)) => {
            c.err(
                path.k("diameter"),
                "required with normal: the sensor's diameter [m]".into(),
            );
            None
        }
        (Some(d), Some(n)) => {
            let diameter = c.positive(path.k("diameter"), d);
            let normal = axis_index(c, path.k("normal"), n, dim);
            Some(Sensor::Face {
                diameter: diameter?,
                normal: normal?,
            })
        }
    }
}

/// `[probe.reference] columns`: required for the point probes' references, only there.
fn check_columns(
    c: &mut Checker,
    rp: &KeyPath,
    r: &ProbeReferenceFile,
    at_point: bool,
) -> Option<Option<(String, String)>> {
    match (r.columns.as_deref(), at_point) {
        (None, false) => Some(None),
        (Some(_), false) => {
            c.err(
                rp.k("columns"),
                "only for a pressure, level or velocity reference".into(),
            );
            None
        }
        (None, true) => {
            c.err(
                rp.k("columns"),
                "required for a pressure, level or velocity reference: [time, value], the file's column names".into(),
            );
            None
        }
        (Some([t, v]), true) if !t.trim().is_empty() && !v.trim().is_empty() && t != v => {
            Some(Some((t.clone(), v.clone())))
        }
        (Some(other), true) => {
            c.err(
                rp.k("columns"),
                format!("expected 2 different non-empty column names [time, value], got {other:?}"),
            );
            None
        }
    }
}
