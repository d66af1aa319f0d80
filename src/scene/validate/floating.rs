//! A solid's `floating` table (`schema::FloatingFile`) into a [`Floating`]: exactly one of
//! `density` and `mass` (> 0), finite overrides of `dimension` entries, the held degrees of
//! freedom or a hinge (not both), and the moorings.

use super::{Checker, KeyPath};
use crate::boundary::contact::{SpringDashpot, WallContact};
use crate::boundary::rigid_body::{Freedom, Mooring};
use crate::scene::floating::{BodyAmount, Floating};
use crate::scene::schema::{ContactFile, FloatingFile, NumberOrVector};
use nalgebra::Vector3;

/// The degrees of freedom `fixed` may name, 3D: translation, then rotation.
const AXES: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];

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
