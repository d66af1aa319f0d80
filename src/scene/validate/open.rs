//! `[[open_boundary]]` (`boundary::open`): the section's corners and a normal along a
//! coordinate axis, a buffer of at least one kernel support, an inflow velocity that points into
//! the fluid; then, on the resolved scene, a buffer inside the domain and clear of every solid
//! and of the other boundaries' sections and buffers, and a solver that can run it (`wcsph`, one phase, the normal's axis not periodic).

use super::*;
use crate::boundary::open::Profile;
use crate::scene::OpenBoundarySpec;
use crate::scene::schema::{OpenBoundaryFile, OpenBoundaryKind};

/// The validated entry `i`; `None` after reporting a problem.
pub(super) fn check_open_boundary(
    c: &mut Checker,
    i: usize,
    b: &OpenBoundaryFile,
    dim: Option<usize>,
    spacing: Option<f64>,
    h: Option<f64>,
) -> Option<OpenBoundarySpec> {
    let path = KeyPath::key("open_boundary").i(i);
    let min = c.vector(path.k("min"), &b.min, dim);
    let max = c.vector(path.k("max"), &b.max, dim);
    let normal = c.vector(path.k("normal"), &b.normal, dim);
    let inflow = b.kind == OpenBoundaryKind::Inflow;
    let velocity = match (&b.velocity, inflow) {
        (Some(v), true) => c.vector(path.k("velocity"), v, dim),
        (None, true) => {
            c.err(
                path.k("velocity"),
                "an inflow needs its mean velocity [m/s]".into(),
            );
            None
        }
        (Some(_), false) => {
            c.err(
                path.k("velocity"),
                "an outflow is a free exit: its particles move with the fluid; drop velocity".into(),
            );
            None
        }
        (None, false) => dim.map(|d| vec![0.0; d]),
    };
    let ramp = match b.ramp {
        Some(t) if inflow => c.positive(path.k("ramp"), t).map(Some),
        _ => Some(None),
    };
    for (given, key) in [
        (b.profile.is_some(), "profile"),
        (b.level.is_some(), "level"),
        (b.ramp.is_some(), "ramp"),
    ] {
        if given && !inflow {
            c.err(path.k(key), format!("only an inflow has a {key}"));
        }
    }
    let (min, max, normal, velocity, ramp, dim) = (min?, max?, normal?, velocity?, ramp?, dim?);
    // The normal: not zero, along one axis.
    let along: Vec<usize> = (0..dim).filter(|&k| normal[k] != 0.0).collect();
    let axis = match along[..] {
        [] => {
            c.err(
                path.k("normal"),
                "has zero length; give the direction into the fluid".into(),
            );
            return None;
        }
        [k] => k,
        _ => {
            c.err(
                path.k("normal"),
                "must point along a coordinate axis (such as [1, 0] or [0, -1]): the buffer's columns follow the lattice".into(),
            );
            return None;
        }
    };
    let inward = normal[axis].signum();
    let mut ok = true;
    if min[axis] != max[axis] {
        c.err(
            path.k("max"),
            format!(
                "must equal min along the normal's axis {} (the section lies in the plane {} = {}), got {}",
                axis_name(axis),
                axis_name(axis),
                num(min[axis]),
                num(max[axis])
            ),
        );
        ok = false;
    }
    for k in (0..dim).filter(|&k| k != axis) {
        if min[k] >= max[k] {
            c.err(
                path.k("max"),
                format!(
                    "the section needs a width across the normal: on axis {} max = {} <= min = {}",
                    axis_name(k),
                    num(max[k]),
                    num(min[k])
                ),
            );
            ok = false;
        }
    }
    if inflow && velocity[axis] * inward <= 0.0 {
        c.err(
            path.k("velocity"),
            format!(
                "points out of the fluid (its {} component {} against the normal {}): an inflow's velocity has a positive component along the normal",
                axis_name(axis),
                num(velocity[axis]),
                num(normal[axis])
            ),
        );
        ok = false;
    }
    let level = match b.level {
        Some(l) if inflow => {
            let up = dim - 1;
            let l = c.finite(path.k("level"), l)?;
            if axis == up {
                c.err(
                    path.k("level"),
                    format!(
                        "an inflow through a plane of constant {} has no level",
                        axis_name(up)
                    ),
                );
                ok = false;
            } else if l <= min[up] {
                c.err(
                    path.k("level"),
                    format!(
                        "is at or below the section's bottom {} = {}: no fluid would enter",
                        axis_name(up),
                        num(min[up])
                    ),
                );
                ok = false;
            }
            Some(l)
        }
        _ => None,
    };
    let (dx, h) = (spacing?, h?);
    let least = (h / dx - 1e-9).ceil().max(1.0);
    let layers = match b.layers {
        None => (2.0 * h / dx - 1e-9).ceil() as u32 + 1,
        Some(n) if (n as f64) >= least && n <= 1000 => n as u32,
        Some(n) => {
            c.err(
                path.k("layers"),
                format!(
                    "must be in [{least}, 1000], got {n}: the buffer must hold a kernel support (h = {} m) of particles behind the plane",
                    num(h)
                ),
            );
            return None;
        }
    };
    ok.then_some(OpenBoundarySpec {
        kind: b.kind,
        axis,
        inward,
        min,
        max,
        layers,
        velocity,
        profile: b.profile.unwrap_or(Profile::Uniform),
        level,
        ramp,
    })
}

/// The buffer box of `b` at spacing `dx` \[m\].
fn buffer_box(b: &OpenBoundarySpec, dx: f64) -> Aabb {
    let depth = f64::from(b.layers) * dx;
    let mut region = Aabb {
        min: b.min.clone(),
        max: b.max.clone(),
    };
    let plane = b.min[b.axis];
    let back = plane - b.inward * depth;
    region.min[b.axis] = plane.min(back);
    region.max[b.axis] = plane.max(back);
    region
}

/// Boundary `b` (at `path`) apart from the earlier boundary `j`, `other`: their sections do not
/// share a plane over a positive area (an outflow on an inflow's section drains what the inflow
/// brings), and their buffers do not overlap (a buffer particle belongs to one boundary).
fn check_apart(
    c: &mut Checker,
    path: &KeyPath,
    b: &OpenBoundarySpec,
    (j, other): (usize, &OpenBoundarySpec),
    dx: f64,
) {
    let tol = 1e-6 * dx;
    let dim = b.min.len();
    let same_plane = other.axis == b.axis && (other.min[b.axis] - b.min[b.axis]).abs() <= tol;
    let sections_meet = same_plane
        && (0..dim)
            .filter(|&k| k != b.axis)
            .all(|k| b.max[k].min(other.max[k]) - b.min[k].max(other.min[k]) > tol);
    let (mine, theirs) = (buffer_box(b, dx), buffer_box(other, dx));
    if sections_meet {
        c.err(
            path.clone(),
            format!(
                "its section {} lies on open_boundary[{j}]'s section {} (the plane {} = {}): give each section a plane of its own",
                fmt_box(&Aabb { min: b.min.clone(), max: b.max.clone() }),
                fmt_box(&Aabb { min: other.min.clone(), max: other.max.clone() }),
                axis_name(b.axis),
                b.min[b.axis]
            ),
        );
    } else if intersection(&mine, &theirs, tol).is_some() {
        c.err(
            path.clone(),
            format!(
                "its buffer {} overlaps open_boundary[{j}]'s buffer {}: a buffer particle belongs to one boundary",
                fmt_box(&mine),
                fmt_box(&theirs)
            ),
        );
    }
}

/// On the resolved scene: each buffer inside the domain and clear of the solids; the solver
/// and effects that open boundaries run with.
pub(super) fn check_open_geometry(c: &mut Checker, scene: &Scene) {
    let dx = scene.spacing;
    let tol = 1e-6 * dx;
    for (i, b) in scene.open_boundaries.iter().enumerate() {
        let path = KeyPath::key("open_boundary").i(i);
        let buffer = buffer_box(b, dx);
        if let Some(k) = outside_axis(&buffer, &scene.domain, tol) {
            c.err(
                path.clone(),
                format!(
                    "its section and buffer {} ({} layers behind the plane) extend outside the domain {} on axis {}",
                    fmt_box(&buffer),
                    b.layers,
                    fmt_box(&scene.domain),
                    axis_name(k)
                ),
            );
        }
        for (j, other) in scene.open_boundaries[..i].iter().enumerate() {
            check_apart(c, &path, b, (j, other), dx);
        }
        for s in &scene.solids {
            let extent = solid_extent(s, dx, scene.wall_layers());
            let inside_container = s.shape == SolidShape::Container
                && (0..buffer.min.len()).all(|k| {
                    buffer.min[k] >= s.region.min[k] - tol && buffer.max[k] <= s.region.max[k] + tol
                });
            if !inside_container && intersection(&buffer, &extent, tol).is_some() {
                c.err(
                    path.clone(),
                    format!(
                        "its buffer {} overlaps solid \"{}\": the buffer holds fluid particles only",
                        fmt_box(&buffer),
                        s.name
                    ),
                );
            }
        }
        if scene.solver.kind != SolverKind::Wcsph {
            c.err(
                path.clone(),
                "needs solver.kind = \"wcsph\": the corrected solver's position correction moves the buffer particles whose columns the inflow follows".into(),
            );
        }
        if scene.has(Effect::Multiphase) {
            c.err(
                path.clone(),
                "cannot be combined with the multiphase effect: a created particle has no phase".into(),
            );
        }
        if scene.periodic.contains(b.axis) {
            c.err(
                path,
                format!(
                    "its normal's axis {} is periodic: the flow would wrap round instead of leaving",
                    axis_name(b.axis)
                ),
            );
        }
    }
}
