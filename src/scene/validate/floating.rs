//! A solid's `floating` table (`schema::FloatingFile`) into a [`Floating`]: exactly one of
//! `density` and `mass` (> 0), finite overrides of `dimension` entries, the held degrees of
//! freedom or a hinge (not both), and the moorings; once the shape is known
//! ([`check_body`]) the bounds the physics sets on them.

use super::{Checker, KeyPath};
use crate::boundary::contact::contact_frequency;
use crate::boundary::contact::{SpringDashpot, WallContact};
use crate::boundary::rigid_body::{Freedom, Mooring};
use crate::geometry::Volume;
use crate::scene::floating::{BodyAmount, Floating};
use crate::scene::schema::{ContactFile, FloatingFile, NumberOrVector};
use nalgebra::Vector3;

/// The degrees of freedom `fixed` may name, 3D: translation, then rotation.
const AXES: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];

/// The range of a floating body's mean density over the fluid's `rho0`: from lighter than air
/// in water (1.2e-3) to heavier than any solid in it (osmium: 22.6) by a wide margin. Outside
/// it the fluid's load per unit body mass (or gravity's against the fluid's) is out of all
/// proportion, and a body of `density = 1e-30` is thrown out of the domain at its first step.
pub const BODY_DENSITY_RATIO: [f64; 2] = [1e-3, 1e3];

/// A vector of `dim` entries embedded in 3 (z = 0 in 2D).
fn embed(v: &[f64]) -> Vector3<f64> {
    Vector3::from_fn(|k, _| v.get(k).copied().unwrap_or(0.0))
}

/// Checks `floating` at `path` in a scene of dimension `dim`.
pub(super) fn check_floating(
    c: &mut Checker,
    path: &KeyPath,
    f: &FloatingFile,
    dim: Option<usize>,
) -> Option<Floating> {
    let amount = match (f.density, f.mass) {
        (Some(_), Some(_)) => {
            c.err(path.k("mass"), "give either `density` or `mass`, not both".into());
            None
        }
        (Some(rho), None) => c.positive(path.k("density"), rho).map(BodyAmount::Density),
        (None, Some(m)) => c.positive(path.k("mass"), m).map(BodyAmount::Mass),
        (None, None) => {
            c.err(path.k("density"), "required (or give `mass`)".into());
            None
        }
    };
    let dim = dim?;
    let mut ok = true;
    let centre_of_mass = match &f.centre_of_mass {
        Some(v) => {
            let v = c.vector(path.k("centre_of_mass"), v, Some(dim));
            ok &= v.is_some();
            v.map(|v| embed(&v))
        }
        None => None,
    };
    let inertia = match (&f.inertia, dim) {
        (None, _) => None,
        (Some(NumberOrVector::Number(i)), 2) => {
            let i = c.positive(path.k("inertia"), *i);
            ok &= i.is_some();
            // 2D uses I_zz only; the other two keep the rate's block solve well posed.
            i.map(|i| Vector3::new(i, i, i))
        }
        (Some(NumberOrVector::Vector(v)), 3) if v.len() == 3 => {
            let mut all = true;
            for (k, &x) in v.iter().enumerate() {
                all &= c.positive(path.k("inertia").i(k), x).is_some();
            }
            ok &= all;
            all.then(|| Vector3::new(v[0], v[1], v[2]))
        }
        (Some(_), _) => {
            c.err(
                path.k("inertia"),
                "expected one number (2D: I_zz [kg m]) or three (3D: principal moments about x, y, z [kg m²])"
                    .into(),
            );
            ok = false;
            None
        }
    };
    let freedom = check_freedom(c, path, f, dim);
    let mut moorings = Vec::new();
    for (k, m) in f.moorings.iter().flatten().enumerate() {
        let p = path.k("moorings").i(k);
        let anchor = c.vector(p.k("anchor"), &m.anchor, Some(dim));
        let fairlead = c.vector(p.k("fairlead"), &m.fairlead, Some(dim));
        let stiffness = c.non_negative(p.k("stiffness"), m.stiffness);
        let rest_length = c.non_negative(p.k("rest_length"), m.rest_length);
        match (anchor, fairlead, stiffness, rest_length) {
            (Some(a), Some(fl), Some(k), Some(l)) => moorings.push(Mooring {
                anchor: embed(&a),
                fairlead: embed(&fl),
                stiffness: k,
                rest_length: l,
            }),
            _ => ok = false,
        }
    }
    let contact = check_contact(c, &path.k("contact"), f.contact.as_ref());
    let (amount, freedom, contact) = (amount?, freedom?, contact?);
    ok.then_some(Floating {
        amount,
        centre_of_mass,
        inertia,
        freedom,
        moorings,
        contact,
    })
}

/// The bounds on floating body `f` (at `path`) that need its shape `volume`, bounded by
/// `min`..`max` [m], in a scene of particle spacing `spacing` [m], fluid density `rho0`
/// [kg/m³] and dimension `dim`: the shape holds a point of the mass lattice; the mean density
/// is within [`BODY_DENSITY_RATIO`] of `rho0`; `centre_of_mass` lies in the body's box and
/// every fairlead within a spacing of it (a fairlead is a point of the body); and the moorings
/// ring the body no faster than its wall contact (`RigidBody::mooring_frequency` at most
/// `ω_c = sqrt(200 g0 / dx)`, `boundary::contact`): a stiffer line is a fixed point (use
/// `fixed` or `hinge`) and would cut the step below the contact's. Returns whether all hold.
#[allow(clippy::too_many_arguments)]
pub(super) fn check_body(
    c: &mut Checker,
    path: &KeyPath,
    f: &Floating,
    volume: &Volume,
    min: &[f64],
    max: &[f64],
    spacing: f64,
    rho0: Option<f64>,
    dim: usize,
) -> bool {
    let Some(shape) = Floating::shape_properties(volume, min, max, spacing, dim) else {
        c.err(
            path.clone(),
            "the solid's shape holds no point of the lattice its mass is sampled on (a quarter of the particle spacing): too thin to float".into(),
        );
        return false;
    };
    let mut ok = true;
    let density = f.mean_density(shape.mass);
    if let Some(rho0) = rho0 {
        let ratio = density / rho0;
        let [low, high] = BODY_DENSITY_RATIO;
        if ratio.is_nan() || ratio < low || ratio > high {
            let key = match f.amount {
                BodyAmount::Density(_) => "density",
                BodyAmount::Mass(_) => "mass",
            };
            c.err(
                path.k(key),
                format!(
                    "the body's mean density is {density:.3e} kg/m³ ({ratio:.3e} times the fluid's rho0 = {rho0}; \
                     its shape holds {:.4e} m{}): give {low:e} to {high:e} times rho0",
                    shape.mass,
                    if dim == 2 { "²" } else { "³" }
                ),
            );
            ok = false;
        }
    }
    let inside =
        |x: &Vector3<f64>, margin: f64| (0..dim).all(|k| x[k] >= min[k] - margin && x[k] <= max[k] + margin);
    let bounds = || format!("{:?}..{:?}", &min[..dim], &max[..dim]);
    if let Some(centre) = &f.centre_of_mass
        && !inside(centre, 0.0)
    {
        c.err(
            path.k("centre_of_mass"),
            format!(
                "lies outside the body's box {}: the centre of mass is inside the body",
                bounds()
            ),
        );
        ok = false;
    }
    for (k, m) in f.moorings.iter().enumerate() {
        if !inside(&m.fairlead, spacing) {
            c.err(
                path.k("moorings").i(k).k("fairlead"),
                format!(
                    "lies more than a particle spacing ({spacing} m) outside the body's box {}: a fairlead is a point of the body",
                    bounds()
                ),
            );
            ok = false;
        }
    }
    if ok
        && rho0.is_some()
        && let Some(w) = f.rigid_body_of(&shape).mooring_frequency(dim)
    {
        let limit = contact_frequency(spacing);
        if w.is_nan() || w > limit {
            let total: f64 = f.moorings.iter().map(|m| m.stiffness).sum();
            c.err(
                path.k("moorings"),
                format!(
                    "the lines ({total:.3e} N/m in all) would ring the body at {w:.3e} rad/s, above the {limit:.3e} rad/s \
                     of its contact with a wall at this spacing: at most {:.3e} N/m in all at these fairleads \
                     (a stiffer line is a fixed point: use `fixed` or `hinge`)",
                    total * (limit / w).powi(2)
                ),
            );
            ok = false;
        }
    }
    ok
}

/// `contact`: the spring–dashpot (default) with `restitution` in (0, 1] and `friction` ≥ 0, or
/// `kind = "none"` without them.
fn check_contact(c: &mut Checker, path: &KeyPath, f: Option<&ContactFile>) -> Option<WallContact> {
    let Some(f) = f else {
        return Some(WallContact::SpringDashpot(SpringDashpot::DEFAULT));
    };
    match f.kind.as_deref().unwrap_or("spring_dashpot") {
        "none" => {
            if f.restitution.is_some() || f.friction.is_some() {
                c.err(
                    path.k("kind"),
                    "`none` takes no `restitution` or `friction`".into(),
                );
                return None;
            }
            Some(WallContact::None)
        }
        "spring_dashpot" => {
            let d = SpringDashpot::DEFAULT;
            let restitution = match f.restitution {
                None => Some(d.restitution),
                Some(e) if e > 0.0 && e <= 1.0 => Some(e),
                Some(e) => {
                    c.err(path.k("restitution"), format!("must be in (0, 1], got {e}"));
                    None
                }
            };
            let friction = match f.friction {
                None => Some(d.friction),
                Some(m) => c.non_negative(path.k("friction"), m),
            };
            Some(WallContact::SpringDashpot(SpringDashpot {
                restitution: restitution?,
                friction: friction?,
            }))
        }
        other => {
            c.err(
                path.k("kind"),
                format!("unknown contact {other:?}: expected \"spring_dashpot\" or \"none\""),
            );
            None
        }
    }
}

/// `fixed` (names of held degrees of freedom of the dimension) or `hinge`, not both; default
/// planar (2D) or free (3D).
fn check_freedom(c: &mut Checker, path: &KeyPath, f: &FloatingFile, dim: usize) -> Option<Freedom> {
    let allowed: Vec<&str> = if dim == 2 {
        vec!["x", "y", "rz"]
    } else {
        AXES.to_vec()
    };
    match (&f.fixed, &f.hinge) {
        (Some(_), Some(_)) => {
            c.err(path.k("hinge"), "give either `fixed` or `hinge`, not both".into());
            None
        }
        (Some(names), None) => {
            let Freedom::Axes {
                mut translation,
                mut rotation,
            } = (if dim == 2 {
                Freedom::planar()
            } else {
                Freedom::free()
            })
            else {
                return None;
            };
            let mut ok = true;
            for (k, name) in names.iter().enumerate() {
                if names[..k].contains(name) {
                    c.err(path.k("fixed").i(k), format!("{name:?} is named twice"));
                    ok = false;
                    continue;
                }
                match AXES.iter().position(|a| a == name) {
                    Some(i) if allowed.contains(&name.as_str()) => {
                        if i < 3 {
                            translation[i] = false;
                        } else {
                            rotation[i - 3] = false;
                        }
                    }
                    _ => {
                        c.err(
                            path.k("fixed").i(k),
                            format!("unknown degree of freedom {name:?}: expected one of {allowed:?}"),
                        );
                        ok = false;
                    }
                }
            }
            ok.then_some(Freedom::Axes {
                translation,
                rotation,
            })
        }
        (None, Some(h)) => {
            let point = c.vector(path.k("hinge").k("point"), &h.point, Some(dim));
            let axis = match (&h.axis, dim) {
                (None, 2) => Some(Vector3::z()),
                (Some(_), 2) => {
                    c.err(
                        path.k("hinge").k("axis"),
                        "a 2D hinge turns about z: remove `axis`".into(),
                    );
                    None
                }
                (None, _) => {
                    c.err(path.k("hinge").k("axis"), "required in 3D".into());
                    None
                }
                (Some(a), _) => c.vector(path.k("hinge").k("axis"), a, Some(3)).and_then(|a| {
                    let a = embed(&a);
                    let n = a.norm();
                    if n > 0.0 {
                        Some(a / n)
                    } else {
                        c.err(path.k("hinge").k("axis"), "must not be zero".into());
                        None
                    }
                }),
            };
            Some(Freedom::Hinge {
                point: embed(&point?),
                axis: axis?,
            })
        }
        (None, None) => Some(if dim == 2 {
            Freedom::planar()
        } else {
            Freedom::free()
        }),
    }
}
