//! Geometry: boxes with `min < max`, fluid boxes and solids inside the domain, fluid boxes
//! overlapping neither each other nor a solid (the inside of a container is fine).

use super::*;
use crate::boundary::sea_maker::SeaMaker;
use crate::geometry::Volume;
use crate::physics::sea_state::Sea;

pub(super) fn check_box(c: &mut Checker, path: &KeyPath, b: &BoxFile, dim: Option<usize>) -> Option<Aabb> {
    c.aabb(path, &b.min, &b.max, dim)
}

/// Domain containment, overlaps and particle-count / memory limits.
pub(super) fn check_geometry(c: &mut Checker, scene: &Scene) {
    let dx = scene.spacing;
    let tol = 1e-6 * dx;
    let layers = scene.wall_layers();
    let domain = &scene.domain;
    for (i, fb) in scene.fluid_boxes.iter().enumerate() {
        if let Some(k) = outside_axis(&fb.region, domain, tol) {
            c.err(
                KeyPath::key("fluid_box").i(i),
                format!(
                    "fluid box {} extends outside the domain {} on axis {}",
                    fmt_box(&fb.region),
                    fmt_box(domain),
                    axis_name(k)
                ),
            );
        }
    }
    let extents: Vec<Aabb> = scene.solids.iter().map(|s| solid_extent(s, dx, layers)).collect();
    for (i, (s, ext)) in scene.solids.iter().zip(&extents).enumerate() {
        if let Some(m) = &s.motion {
            // The box the moving solid sweeps: |d_k(t)| <= reach_k (a sine: |A_k|, |r sin| <= 1).
            let reach = m.reach();
            let swept = Aabb {
                min: ext.min.iter().zip(&reach).map(|(x, a)| x - a).collect(),
                max: ext.max.iter().zip(&reach).map(|(x, a)| x + a).collect(),
            };
            // The key that sets how far it moves.
            let key = match m {
                Motion::Sway(_) => "amplitude",
                Motion::Piston(_) => "wave_height",
                Motion::Series(_) => "file",
                Motion::Flap(_) => "hinge",
                Motion::Sea(_) => "sea",
            };
            if let Motion::Sea(maker) = m
                && let Some(reason) = focus_outside(maker, ext, domain)
            {
                c.err(
                    KeyPath::key("solid")
                        .i(i)
                        .k("motion")
                        .k("sea")
                        .k("focus_position"),
                    format!("solid \"{}\": {reason}", s.name),
                );
            }
            if let Some(k) = outside_axis(&swept, domain, tol) {
                // A wave maker's stroke comes from the wave: say from which values.
                let cause = match m {
                    Motion::Piston(p) => format!(
                        " (the stroke {} m that makes waves {} m high of period {} s on {} m of water)",
                        num(p.stroke()),
                        num(p.wave_height),
                        num(p.period),
                        num(p.depth)
                    ),
                    _ => String::new(),
                };
                c.err(
                    KeyPath::key("solid").i(i).k("motion").k(key),
                    format!(
                        "solid \"{}\" sweeps {} while moving by ±{} m on axis {}, outside the domain {}{cause}",
                        s.name,
                        fmt_box(&swept),
                        num(reach[k]),
                        axis_name(k),
                        fmt_box(domain)
                    ),
                );
                continue;
            }
        }
        if let Some(k) = outside_axis(ext, domain, tol) {
            let walls = match s.shape {
                SolidShape::Box | SolidShape::Cylinder | SolidShape::Sphere | SolidShape::Mesh => {
                    String::new()
                }
                SolidShape::Container => format!(" (including walls of {layers} layers x {dx} m)"),
            };
            c.err(
                KeyPath::key("solid").i(i),
                format!(
                    "solid \"{}\" occupies {}{walls}, outside the domain {} on axis {}",
                    s.name,
                    fmt_box(ext),
                    fmt_box(domain),
                    axis_name(k)
                ),
            );
        }
    }
    for (i, fb) in scene.fluid_boxes.iter().enumerate() {
        let path = KeyPath::key("fluid_box").i(i);
        for (s, ext) in scene.solids.iter().zip(&extents) {
            let Some(cut) = intersection(&fb.region, ext, tol) else {
                continue;
            };
            match (s.shape, &s.volume) {
                // A shape that is not an axis-aligned box displaces the fluid it overlaps
                // (`generate`'s module doc): its lattice is not the fluid's, so only trimming
                // can say which fluid particles it takes.
                (SolidShape::Box, Volume::RotatedBox { .. })
                | (SolidShape::Cylinder | SolidShape::Sphere | SolidShape::Mesh, _) => {}
                (SolidShape::Box, _) => c.err(
                    path.clone(),
                    format!(
                        "fluid box {} overlaps solid box \"{}\" {}",
                        fmt_box(&fb.region),
                        s.name,
                        fmt_box(&s.region)
                    ),
                ),
                (SolidShape::Container, _) => {
                    if outside_axis(&cut, &s.region, tol).is_some() {
                        c.err(
                            path.clone(),
                            format!(
                                "fluid box {} overlaps the walls of container \"{}\" (walls occupy {} minus the inside {})",
                                fmt_box(&fb.region),
                                s.name,
                                fmt_box(ext),
                                fmt_box(&s.region)
                            ),
                        );
                    }
                }
            }
        }
        for (j, other) in scene.fluid_boxes.iter().enumerate().take(i) {
            // A shaped volume's region is its bounding box, which may overlap another's while
            // the shapes do not: as for shaped solids, the lattices meet in trimming, where the
            // later volume yields and the removal is reported (`trim`).
            let shaped = |b: &FluidBox| !matches!(b.volume, Volume::Aabb { .. });
            if shaped(fb) || shaped(other) {
                continue;
            }
            if intersection(&fb.region, &other.region, tol).is_some() {
                c.err(path.clone(), format!("fluid box overlaps fluid_box[{j}]"));
            }
        }
    }
    check_counts(c, scene);
}

/// Why a focused sea's focus lies outside `domain`, if it does: the focus is `x_f` past the
/// paddle's face at rest (the box `ext`'s farthest extent along the waves' direction `n`), so
/// its plane `n·x = max_box(n·x) + x_f` must not pass the domain's `max_domain(n·x)`.
fn focus_outside(maker: &SeaMaker, ext: &Aabb, domain: &Aabb) -> Option<String> {
    let Sea::Focused { focus_position, .. } = &maker.sea else {
        return None;
    };
    let n = maker.wave_direction();
    let farthest = |b: &Aabb| -> f64 {
        n.iter()
            .enumerate()
            .map(|(k, c)| (c * b.min[k]).max(c * b.max[k]))
            .sum()
    };
    let (face, end) = (farthest(ext), farthest(domain));
    (face + focus_position > end).then(|| {
        format!(
            "the focus, {} m past the paddle's face at {} m along the waves' direction, lies at {} m, beyond the domain's end at {} m",
            num(*focus_position),
            num(face),
            num(face + focus_position),
            num(end)
        )
    })
}
