//! `[[solid]]` and `[[fluid_box]]`: each shape's keys, resolved into a [`Volume`] (and, for a
//! solid, a [`Solid`]). Both tables share the shape keys and this one check ([`check_shape`]);
//! a fluid volume takes every shape but `container`.
//!
//! Keys belong to shapes: `min`/`max` to `box` and `container`, `open_top` to `container`,
//! `rotation` to `box` and `mesh`, `centre`/`radius` to `cylinder` and `sphere`,
//! `length`/`axis` to a 3D `cylinder`, `file`/`scale`/`translation` to `mesh`. A key given to
//! a shape it does not belong to is an error (a silently ignored key would hide a mistake). A
//! mesh's file is read, placed and checked here, so that a scene that validates can be filled.

use std::path::Path;
use std::sync::Arc;

use nalgebra::{Unit, Vector3};

use super::floating::{check_body, check_floating};
use super::keys::check_name;
use super::motion::check_motion;
use super::{Checker, KeyPath, num};
use crate::boundary::motion::Motion;
use crate::geometry::{Mesh, Placement, Volume, read::read_triangles, rotation};
use crate::scene::schema::{AxisFile, FluidBoxFile, NumberOrVector, SceneFile, SolidFile, SolidShape};
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

/// The shape keys of a `[[solid]]` or a `[[fluid_box]]`, as the file gives them.
pub(super) struct ShapeKeys<'a> {
    /// The shape the table names.
    pub shape: SolidShape,
    pub min: Option<&'a [f64]>,
    pub max: Option<&'a [f64]>,
    pub open_top: Option<bool>,
    pub rotation: Option<&'a NumberOrVector>,
    pub centre: Option<&'a [f64]>,
    pub radius: Option<f64>,
    pub length: Option<f64>,
    pub axis: Option<&'a AxisFile>,
    pub file: Option<&'a str>,
    pub scale: Option<&'a NumberOrVector>,
    pub translation: Option<&'a [f64]>,
}

impl<'a> ShapeKeys<'a> {
    /// The shape keys of a `[[solid]]`.
    pub fn solid(s: &'a SolidFile) -> Self {
        ShapeKeys {
            shape: s.shape,
            min: s.min.as_deref(),
            max: s.max.as_deref(),
            open_top: s.open_top,
            rotation: s.rotation.as_ref(),
            centre: s.centre.as_deref(),
            radius: s.radius,
            length: s.length,
            axis: s.axis.as_ref(),
            file: s.file.as_deref(),
            scale: s.scale.as_ref(),
            translation: s.translation.as_deref(),
        }
    }

    /// The shape keys of a `[[fluid_box]]` (`shape` defaults to `box`).
    pub fn fluid(f: &'a FluidBoxFile) -> Self {
        ShapeKeys {
            shape: f.shape.unwrap_or(SolidShape::Box),
            min: f.min.as_deref(),
            max: f.max.as_deref(),
            open_top: None,
            rotation: f.rotation.as_ref(),
            centre: f.centre.as_deref(),
            radius: f.radius,
            length: f.length,
            axis: f.axis.as_ref(),
            file: f.file.as_deref(),
            scale: f.scale.as_ref(),
            translation: f.translation.as_deref(),
        }
    }

    /// The keys given.
    fn given(&self) -> Vec<&'static str> {
        let keys = [
            ("min", self.min.is_some()),
            ("max", self.max.is_some()),
            ("open_top", self.open_top.is_some()),
            ("rotation", self.rotation.is_some()),
            ("centre", self.centre.is_some()),
            ("radius", self.radius.is_some()),
            ("length", self.length.is_some()),
            ("axis", self.axis.is_some()),
            ("file", self.file.is_some()),
            ("scale", self.scale.is_some()),
            ("translation", self.translation.is_some()),
        ];
        keys.iter().filter(|(_, g)| *g).map(|(k, _)| *k).collect()
    }
}

/// Checks `[[solid]]` `i` of `file`; a mesh's relative path is taken from `dir`.
pub(super) fn check_solid(
    c: &mut Checker,
    file: &SceneFile,
    i: usize,
    dim: Option<usize>,
    dir: &Path,
    g: Option<f64>,
) -> Option<Solid> {
    let s = file.solid.get(i)?;
    let path = KeyPath::key("solid").i(i);
    let earlier: Vec<&str> = file.solid.iter().take(i).map(|o| o.name.as_str()).collect();
    let ok = check_name(c, path.k("name"), &s.name, &earlier, "solid");
    let motion = match &s.motion {
        None => Some(None),
        Some(m) => check_motion(c, &path.k("motion"), m, dim, g, dir).map(Some),
    };
    let floating = match (&s.floating, &s.motion, s.shape) {
        (None, ..) => Some(None),
        (Some(_), Some(_), _) => {
            c.err(
                path.k("floating"),
                "a solid either follows a `motion` or floats, not both (remove one)".into(),
            );
            None
        }
        (Some(_), None, SolidShape::Container) => {
            c.err(
                path.k("floating"),
                "a container cannot float (its volume is the space it holds): use a box".into(),
            );
            None
        }
        (Some(f), None, _) => check_floating(c, &path.k("floating"), f, dim).map(Some),
    };
    let dim = dim?;
    let volume = check_shape(c, &path, &ShapeKeys::solid(s), dim, dir);
    let open_top = match s.shape {
        SolidShape::Container => s.open_top.unwrap_or(true),
        _ => false,
    };
    let volume = volume?;
    let (min, max) = volume.bounds(dim);
    let mut motion = motion?;
    let floating = floating?;
    let spacing = Some(file.particles.spacing).filter(|s| *s > 0.0 && s.is_finite());
    let rho0 = Some(file.fluid.rho0).filter(|r| *r > 0.0 && r.is_finite());
    if let (Some(f), Some(spacing)) = (&floating, spacing)
        && !check_body(c, &path.k("floating"), f, &volume, &min, &max, spacing, rho0, dim)
    {
        return None;
    }
    if let Some(Motion::Flap(flap)) = &mut motion {
        // The flap's speed and sweep bounds need its size.
        flap.arm = flap.arm_to_box(&min, &max);
    }
    if let Some(Motion::Sea(maker)) = &mut motion {
        maker.set_arm_to_box(&min, &max);
    }
    ok.then(|| Solid {
        name: s.name.clone(),
        shape: s.shape,
        region: Aabb { min, max },
        open_top,
        motion,
        floating,
        volume,
    })
}

/// Checks the shape of `[[fluid_box]]` `fb` at `path` (a box unless `shape` says otherwise,
/// never a container) and returns the box that bounds it and its [`Volume`]. `compression` and
/// `coincident` set the lattice of an axis-aligned box only (`FluidBox::lattice_spacing`,
/// `FluidBox::has_twin`): for another shape they are an error.
pub(super) fn check_fluid_shape(
    c: &mut Checker,
    path: &KeyPath,
    fb: &FluidBoxFile,
    dim: Option<usize>,
    dir: &Path,
) -> Option<(Aabb, Volume)> {
    let keys = ShapeKeys::fluid(fb);
    if keys.shape == SolidShape::Container {
        c.err(
            path.k("shape"),
            "a fluid volume cannot be a container; its shapes are box, cylinder, sphere and mesh".into(),
        );
        return None;
    }
    let volume = check_shape(c, path, &keys, dim?, dir)?;
    if !matches!(volume, Volume::Aabb { .. }) {
        let given = [
            ("compression", fb.compression.is_some()),
            ("coincident", fb.coincident.is_some()),
        ];
        let mut ok = true;
        for (key, _) in given.iter().filter(|(_, g)| *g) {
            c.err(
                path.k(key),
                format!(
                    "only for an axis-aligned box (shape = \"box\" without rotation), not for {}",
                    volume.describe(dim?)
                ),
            );
            ok = false;
        }
        if !ok {
            return None;
        }
    }
    let (min, max) = volume.bounds(dim?);
    Some((Aabb { min, max }, volume))
}

/// Checks the shape keys `s` of the table at `path` and resolves its [`Volume`]: a key of
/// another shape, a missing or bad one is an error; a mesh's relative path is taken from `dir`.
pub(super) fn check_shape(
    c: &mut Checker,
    path: &KeyPath,
    s: &ShapeKeys<'_>,
    dim: usize,
    dir: &Path,
) -> Option<Volume> {
    let mut keys_ok = true;
    let allow = allowed(s.shape, dim);
    for key in s.given() {
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
            keys_ok = false;
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
                path,
                s.min.unwrap_or_default(),
                s.max.unwrap_or_default(),
                Some(dim),
            )?;
            match (s.rotation, s.shape) {
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
            let centre = s.centre.and_then(|v| c.vector(path.k("centre"), v, Some(dim)));
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
                let axis = s.axis.and_then(|a| cylinder_axis(c, &path.k("axis"), a));
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
            let scale = match s.scale {
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
            let rot = match s.rotation {
                None => Some(vec![0.0; 3]),
                Some(r) => angles(c, &path.k("rotation"), r, 3),
            };
            let translation = match s.translation {
                None => Some(vec![0.0; 3]),
                Some(t) => c.vector(path.k("translation"), t, Some(3)),
            };
            let (scale, rot, translation) = (scale?, rot?, translation?);
            if !fp {
                return None;
            }
            let name = s.file.unwrap_or_default();
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
    keys_ok.then_some(volume)
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
