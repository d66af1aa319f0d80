//! `[[solid]]`: each shape's keys, resolved into a [`Solid`] and its [`Volume`].
//!
//! Keys belong to shapes: `min`/`max` to `box` and `container`, `open_top` to `container`,
//! `rotation` to `box` and `mesh`, `centre`/`radius` to `cylinder` and `sphere`,
//! `length`/`axis` to a 3D `cylinder`, `file`/`scale`/`translation` to `mesh`. A key given to
//! a shape it does not belong to is an error (a silently ignored key would hide a mistake). A
//! mesh's file is read, placed and checked here, so that a scene that validates can be filled.

use std::path::Path;
use std::sync::Arc;

use nalgebra::{Unit, Vector3};

use super::keys::{check_motion, check_name};
use super::{Checker, KeyPath, num};
use crate::geometry::{Mesh, Placement, Volume, read::read_triangles, rotation};
use crate::scene::schema::{AxisFile, NumberOrVector, SceneFile, SolidFile, SolidShape};
use crate::scene::{Aabb, Solid};

/// Which keys each shape takes, for the "not for this shape" errors.
fn allowed(shape: SolidShape, dim: usize) -> &'static [&'static str] {
    match (shape, dim) {
        (SolidShape::Box, _) => &["min", "max", "rotation"],
        (SolidShape::Container, _) => &["min", "max", "open_top"],
        (SolidShape::Cylinder, 2) | (SolidShape::Sphere, _) => &["centre", "radius"],
        (SolidShape::Cylinder, _) => &["centre", "radius", "length", "axis"],
        (SolidShape::Mesh, _) => &["file", "scale", "rotation", "translation"],
    }
}

/// The shape keys `s` gives.
fn given(s: &SolidFile) -> Vec<&'static str> {
    let keys = [
        ("min", s.min.is_some()),
        ("max", s.max.is_some()),
        ("open_top", s.open_top.is_some()),
        ("rotation", s.rotation.is_some()),
        ("centre", s.centre.is_some()),
        ("radius", s.radius.is_some()),
        ("length", s.length.is_some()),
        ("axis", s.axis.is_some()),
        ("file", s.file.is_some()),
        ("scale", s.scale.is_some()),
        ("translation", s.translation.is_some()),
    ];
    keys.iter().filter(|(_, g)| *g).map(|(k, _)| *k).collect()
}

/// Checks `[[solid]]` `i` of `file`; a mesh's relative path is taken from `dir`.
pub(super) fn check_solid(
    c: &mut Checker,
    file: &SceneFile,
    i: usize,
    dim: Option<usize>,
    dir: &Path,
) -> Option<Solid> {
    let s = file.solid.get(i)?;
    let path = KeyPath::key("solid").i(i);
    let earlier: Vec<&str> = file.solid.iter().take(i).map(|o| o.name.as_str()).collect();
    let mut ok = check_name(c, path.k("name"), &s.name, &earlier, "solid");
    let motion = match &s.motion {
        None => Some(None),
        Some(m) => check_motion(c, &path.k("motion"), m, dim).map(Some),
    };
    let dim = dim?;
    let allow = allowed(s.shape, dim);
    for key in given(s) {
        if !allow.contains(&key) {
            let why = match (s.shape, key) {
                (SolidShape::Cylinder, "length" | "axis") => {
                    " (a 2D cylinder is a disc: centre and radius)".to_string()
                }
                _ => String::new(),
            };
            c.err(
                path.k(key),
                format!(
                    "not a key of shape = \"{}\"{why}; its keys are {}",
                    s.shape.name(),
                    allow.join(", ")
                ),
            );
            ok = false;
        }
    }
    let require = |c: &mut Checker, key: &str, present: bool| {
        if !present {
            c.err(
                path.k(key),
                format!("required for shape = \"{}\"", s.shape.name()),
            );
        }
        present
    };
    let volume = match s.shape {
        SolidShape::Box | SolidShape::Container => {
            let (min, max) = (
                require(c, "min", s.min.is_some()),
                require(c, "max", s.max.is_some()),
            );
            if !(min && max) {
                return None;
            }
            let region = c.aabb(
                &path,
                s.min.as_deref().unwrap_or_default(),
                s.max.as_deref().unwrap_or_default(),
                Some(dim),
            )?;
            match (&s.rotation, s.shape) {
                (Some(r), SolidShape::Box) => {
                    let r = angles(c, &path.k("rotation"), r, dim)?;
                    let centre = Vector3::from_fn(|k, _| {
                        0.5 * (region.min.get(k).unwrap_or(&0.0) + region.max.get(k).unwrap_or(&0.0))
                    });
                    let half = Vector3::from_fn(|k, _| {
                        0.5 * (region.max.get(k).unwrap_or(&0.0) - region.min.get(k).unwrap_or(&0.0))
                    });
                    Volume::RotatedBox {
                        centre,
                        half,
                        rotation: rotation(&r),
                    }
                }
                _ => Volume::Aabb {
                    min: region.min,
                    max: region.max,
                },
            }
        }
        SolidShape::Cylinder | SolidShape::Sphere => {
            let cp = require(c, "centre", s.centre.is_some());
            let rp = require(c, "radius", s.radius.is_some());
            let centre = s
                .centre
                .as_deref()
                .and_then(|v| c.vector(path.k("centre"), v, Some(dim)));
            let radius = s.radius.and_then(|r| c.positive(path.k("radius"), r));
            let (centre, radius) = (centre?, radius?);
            if !(cp && rp) {
                return None;
            }
            let centre = Vector3::from_fn(|k, _| centre.get(k).copied().unwrap_or(0.0));
            if s.shape == SolidShape::Sphere || dim == 2 {
                Volume::Ball { centre, radius }
            } else {
                let lp = require(c, "length", s.length.is_some());
                let ap = require(c, "axis", s.axis.is_some());
                let length = s.length.and_then(|l| c.positive(path.k("length"), l));
                let axis = s.axis.as_ref().and_then(|a| cylinder_axis(c, &path.k("axis"), a));
                if !(lp && ap) {
                    return None;
                }
                Volume::Cylinder {
                    centre,
                    axis: axis?,
                    radius,
                    length: length?,
                }
            }
        }
        SolidShape::Mesh => {
            if dim != 3 {
                c.err(
                    path.k("shape"),
                    "meshes are 3D only (dimension = 3); a 2D scene can use box, cylinder or sphere".into(),
                );
                return None;
            }
            let fp = require(c, "file", s.file.is_some());
            let scale = match &s.scale {
                None => Some([1.0; 3]),
                Some(NumberOrVector::Number(x)) => c.positive(path.k("scale"), *x).map(|x| [x; 3]),
                Some(NumberOrVector::Vector(v)) => {
                    let v = c.vector(path.k("scale"), v, Some(3))?;
                    let ok = v.iter().all(|x| *x > 0.0);
                    if !ok {
                        c.err(path.k("scale"), format!("every factor must be > 0, got {v:?}"));
                    }
                    ok.then(|| [v[0], v[1], v[2]])
                }
            };
            let rot = match &s.rotation {
                None => Some(vec![0.0; 3]),
                Some(r) => angles(c, &path.k("rotation"), r, 3),
            };
            let translation = match &s.translation {
                None => Some(vec![0.0; 3]),
                Some(t) => c.vector(path.k("translation"), t, Some(3)),
            };
            let (scale, rot, translation) = (scale?, rot?, translation?);
            if !fp {
                return None;
            }
            let name = s.file.as_deref().unwrap_or_default();
            if name.is_empty() {
                c.err(path.k("file"), "must not be empty".into());
                return None;
            }
            let full = dir.join(name);
            let placement = Placement {
                scale,
                rotation: rotation(&rot),
                translation: [translation[0], translation[1], translation[2]],
            };
            let mesh = read_triangles(&full).and_then(|t| Mesh::new(&t, &placement));
            match mesh {
                Ok(m) => Volume::Mesh(Arc::new(m)),
                Err(e) => {
                    c.err(path.k("file"), format!("mesh {}: {e}", full.display()));
                    return None;
                }
            }
        }
    };
    let open_top = match s.shape {
        SolidShape::Container => s.open_top.unwrap_or(true),
        _ => false,
    };
    let (min, max) = volume.bounds(dim);
    let motion = motion?;
    ok.then(|| Solid {
        name: s.name.clone(),
        shape: s.shape,
        region: Aabb { min, max },
        open_top,
        motion,
        volume,
    })
}

/// `rotation` as angles in degrees: 2D one number, 3D three; finite.
fn angles(c: &mut Checker, path: &KeyPath, r: &NumberOrVector, dim: usize) -> Option<Vec<f64>> {
    let v = match (r, dim) {
        (NumberOrVector::Number(x), 2) => vec![*x],
        (NumberOrVector::Vector(v), 3) => v.clone(),
        (_, 2) => {
            c.err(
                path.clone(),
                "in 2D a number: the angle in degrees, counter-clockwise".into(),
            );
            return None;
        }
        _ => {
            c.err(
                path.clone(),
                "in 3D an array [α, β, γ]: degrees about the x, y and z axes, applied in that order".into(),
            );
            return None;
        }
    };
    if v.len() != 3 && dim == 3 {
        c.err(path.clone(), format!("expected 3 entries, found {}", v.len()));
        return None;
    }
    for (k, x) in v.iter().enumerate() {
        if !x.is_finite() {
            c.err(
                path.clone(),
                format!("entry {k} must be a finite number, got {}", num(*x)),
            );
            return None;
        }
    }
    Some(v)
}

/// A 3D cylinder's axis as a unit vector.
fn cylinder_axis(c: &mut Checker, path: &KeyPath, a: &AxisFile) -> Option<Unit<Vector3<f64>>> {
    match a {
        AxisFile::Named(n) => match n.as_str() {
            "x" => Some(Vector3::x_axis()),
            "y" => Some(Vector3::y_axis()),
            "z" => Some(Vector3::z_axis()),
            _ => {
                c.err(
                    path.clone(),
                    format!("must be \"x\", \"y\", \"z\" or a vector, got \"{n}\""),
                );
                None
            }
        },
        AxisFile::Vector(v) => {
            let v = c.vector(path.clone(), v, Some(3))?;
            let d = Vector3::new(v[0], v[1], v[2]);
            let unit = Unit::try_new(d, 1e-300);
            if unit.is_none() {
                c.err(path.clone(), "must not be the zero vector".into());
            }
            unit
        }
    }
}
