//! Closed volumes a solid occupies, and the lattice points inside them.
//!
//! A [`Volume`] is an axis-aligned box, a rotated box, a cylinder, a ball (2D: a disc) or a
//! closed triangle mesh (3D only, [`mesh`]), in scene coordinates \[m\]. Everything here is
//! `f64`; the scene code turns lattice indices into `f32` positions.
//!
//! Rotations (`rotation` in a scene): 2D, an angle θ in degrees counter-clockwise about the
//! out-of-plane axis; 3D, angles `[α, β, γ]` in degrees about the fixed x, y and z axes, applied
//! in that order, `R = R_z(γ) R_y(β) R_x(α)` (nalgebra's `Rotation3::from_euler_angles`, the
//! roll–pitch–yaw convention).

pub mod mesh;
pub mod read;

use std::fmt;
use std::sync::Arc;

use nalgebra::{Rotation3, Unit, Vector3};

pub use mesh::{Mesh, MeshError, Placement, Triangle};

/// The rotation of a scene's `rotation` key: 2D `[θ]`, 3D `[α, β, γ]`, in degrees (module doc).
pub fn rotation(degrees: &[f64]) -> Rotation3<f64> {
    let r = |k: usize| degrees.get(k).copied().unwrap_or(0.0).to_radians();
    match degrees.len() {
        1 => Rotation3::from_euler_angles(0.0, 0.0, r(0)),
        _ => Rotation3::from_euler_angles(r(0), r(1), r(2)),
    }
}

/// A closed region of space \[m\]; points on its surface count as inside.
#[derive(Debug, Clone, PartialEq)]
pub enum Volume {
    /// The box `[min, max]`, `dimension` entries each.
    Aabb {
        /// Lower corner \[m\].
        min: Vec<f64>,
        /// Upper corner \[m\].
        max: Vec<f64>,
    },
    /// A box of half-extents `half` rotated by `rotation` about its centre `centre`.
    RotatedBox {
        /// Centre \[m\] (2D: z = 0).
        centre: Vector3<f64>,
        /// Half-extents along the box's own axes \[m\] (2D: z = 0).
        half: Vector3<f64>,
        /// Rotation from the box's axes to the scene's.
        rotation: Rotation3<f64>,
    },
    /// A 3D cylinder: the points within `radius` of the segment of length `length` centred on
    /// `centre` along `axis`.
    Cylinder {
        /// Centre of the axis segment \[m\].
        centre: Vector3<f64>,
        /// Unit axis direction.
        axis: Unit<Vector3<f64>>,
        /// Radius \[m\].
        radius: f64,
        /// Length along the axis \[m\].
        length: f64,
    },
    /// A ball (3D) or disc (2D, z = 0) of `radius` about `centre`.
    Ball {
        /// Centre \[m\].
        centre: Vector3<f64>,
        /// Radius \[m\].
        radius: f64,
    },
    /// The inside of a closed mesh (3D).
    Mesh(Arc<Mesh>),
}

/// A scene point as a 3-vector (2D: z = 0).
fn point(p: &[f64]) -> Vector3<f64> {
    Vector3::from_fn(|k, _| p.get(k).copied().unwrap_or(0.0))
}

impl Volume {
    /// Whether the point `p` (`dimension` entries) is inside or on the surface.
    ///
    /// For a mesh this is the ray test of [`mesh`] over all triangles; filling uses
    /// [`Volume::lattice_inside`], which tests whole columns of the lattice at once.
    pub fn contains(&self, p: &[f64]) -> bool {
        let x = point(p);
        match self {
            Volume::Aabb { min, max } => p
                .iter()
                .zip(min.iter().zip(max))
                .all(|(c, (lo, hi))| lo <= c && c <= hi),
            Volume::RotatedBox {
                centre,
                half,
                rotation,
            } => {
                let q = rotation.inverse() * (x - centre);
                (0..p.len()).all(|k| q[k].abs() <= half[k])
            }
            Volume::Cylinder {
                centre,
                axis,
                radius,
                length,
            } => {
                let d = x - centre;
                let t = d.dot(axis);
                t.abs() <= 0.5 * length && (d - axis.as_ref() * t).norm_squared() <= radius * radius
            }
            Volume::Ball { centre, radius } => (x - centre).norm_squared() <= radius * radius,
            Volume::Mesh(m) => m.contains([x.x, x.y, x.z]),
        }
    }

    /// Axis-aligned bounding box `(min, max)` \[m\], `dim` entries each.
    pub fn bounds(&self, dim: usize) -> (Vec<f64>, Vec<f64>) {
        let (lo, hi): (Vector3<f64>, Vector3<f64>) = match self {
            Volume::Aabb { min, max } => return (min.clone(), max.clone()),
            Volume::RotatedBox {
                centre,
                half,
                rotation,
            } => {
                let m = rotation.matrix();
                let reach = Vector3::from_fn(|k, _| (0..3).map(|j| m[(k, j)].abs() * half[j]).sum::<f64>());
                (centre - reach, centre + reach)
            }
            Volume::Cylinder {
                centre,
                axis,
                radius,
                length,
            } => {
                let reach = Vector3::from_fn(|k, _| {
                    0.5 * length * axis[k].abs() + radius * (1.0 - axis[k] * axis[k]).max(0.0).sqrt()
                });
                (centre - reach, centre + reach)
            }
            Volume::Ball { centre, radius } => (centre.add_scalar(-radius), centre.add_scalar(*radius)),
            Volume::Mesh(m) => (Vector3::from(m.min()), Vector3::from(m.max())),
        };
        (
            lo.iter().take(dim).copied().collect(),
            hi.iter().take(dim).copied().collect(),
        )
    }

    /// The exact volume \[m³\] (2D: area \[m²\]) in `dim` dimensions.
    pub fn measure(&self, dim: usize) -> f64 {
        use std::f64::consts::PI;
        match self {
            Volume::Aabb { min, max } => min.iter().zip(max).map(|(a, b)| b - a).product(),
            Volume::RotatedBox { half, .. } => (0..dim).map(|k| 2.0 * half[k]).product(),
            Volume::Cylinder { radius, length, .. } => PI * radius * radius * length,
            Volume::Ball { radius, .. } => match dim {
                2 => PI * radius * radius,
                _ => 4.0 / 3.0 * PI * radius.powi(3),
            },
            Volume::Mesh(m) => m.volume(),
        }
    }

    /// Visits, axis 0 fastest, the indices `i` in `0..n` (per axis) of the lattice
    /// `x_k = min_k + (i_k + 0.5) dx` whose points are inside ([`Volume::contains`]; a mesh by
    /// the column test of [`mesh`]). `D` is 2 or 3 (a mesh: 3).
    pub fn lattice_inside<const D: usize>(
        &self,
        min: [f64; D],
        n: [i64; D],
        dx: f64,
        mut visit: impl FnMut(&[i64; D]),
    ) {
        let columns = match self {
            Volume::Mesh(m) => {
                let pad = |a: &[i64], d: i64| std::array::from_fn(|k| a.get(k).copied().unwrap_or(d));
                let corner: [f64; 3] = std::array::from_fn(|k| min.get(k).copied().unwrap_or(0.0));
                Some(m.columns(corner, pad(&n, 1), dx))
            }
            _ => None,
        };
        for_each_index([0; D], n, |idx| {
            let inside = match &columns {
                Some(c) => c.contains(std::array::from_fn(|k| idx.get(k).copied().unwrap_or(0))),
                None => {
                    let p: [f64; D] = std::array::from_fn(|k| min[k] + (idx[k] as f64 + 0.5) * dx);
                    self.contains(&p)
                }
            };
            if inside {
                visit(idx);
            }
        });
    }
}

/// Visits every lattice index in `lo..hi` (per axis) with axis 0 fastest.
pub fn for_each_index<const D: usize>(lo: [i64; D], hi: [i64; D], mut visit: impl FnMut(&[i64; D])) {
    if lo.iter().zip(&hi).any(|(l, h)| l >= h) {
        return;
    }
    let mut idx = lo;
    loop {
        visit(&idx);
        let mut k = 0;
        loop {
            let (Some(i), Some(&l), Some(&h)) = (idx.get_mut(k), lo.get(k), hi.get(k)) else {
                return;
            };
            *i += 1;
            if *i < h {
                break;
            }
            *i = l;
            k += 1;
        }
    }
}

/// Short vectors as a person reads them: `[0.5, 0.2]`.
struct Coords<'a>(&'a [f64]);

impl fmt::Display for Coords<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("[")?;
        for (i, c) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            write!(f, "{c}")?;
        }
        f.write_str("]")
    }
}

impl Volume {
    /// A one-line description for messages and `sph check` (`dim` entries per vector).
    pub fn describe(&self, dim: usize) -> String {
        let v = |x: &Vector3<f64>| Coords(&x.as_slice()[..dim]).to_string();
        match self {
            Volume::Aabb { min, max } => format!("box {} to {}", Coords(min), Coords(max)),
            Volume::RotatedBox { centre, half, .. } => {
                let size: Vec<f64> = half.iter().take(dim).map(|h| 2.0 * h).collect();
                format!("rotated box centre {} size {}", v(centre), Coords(&size))
            }
            Volume::Cylinder {
                centre,
                axis,
                radius,
                length,
            } => format!(
                "cylinder centre {} axis {} radius {radius} length {length}",
                v(centre),
                v(axis)
            ),
            Volume::Ball { centre, radius } => match dim {
                2 => format!("disc centre {} radius {radius}", v(centre)),
                _ => format!("sphere centre {} radius {radius}", v(centre)),
            },
            Volume::Mesh(m) => format!(
                "mesh of {} triangles, bounding box {} to {}",
                m.triangles().len(),
                Coords(&m.min()),
                Coords(&m.max())
            ),
        }
    }
}
