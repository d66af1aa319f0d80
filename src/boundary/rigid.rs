//! A solid's rigid motion at one time, as the stages use it (`move_solids`, `wall_pressure`):
//! a translation `d(t)` plus, where the motion turns the solid, a rotation `R(t)` about a pivot
//! `c` (the pivot's rest position; it moves with the translation). For a solid particle of
//! reference position `x0` [m]:
//!
//! ```text
//! x = c + d + R (x0 − c)                      position [m]
//! r = x − c − d                               arm from the moved pivot [m]
//! u = d' + ω × r                              velocity [m/s]
//! a = d'' + α × r + ω × (ω × r)               the wall's acceleration [m/s²] ([A12] eq. 27: g − a)
//! ```
//!
//! (rigid-body kinematics, [G80] Goldstein, *Classical Mechanics*, 2nd ed., §4.9), `ω` the angular
//! velocity [rad/s] and `α = ω'` the angular acceleration [rad/s²]. In 2D the rotation is about
//! `z` and vectors are embedded as `(x, y, 0)` (`physics::rotating_frame`'s `embed` and `cross`).
//!
//! The rotation is a value ([`Rotation`]): a pure translation (`Rotation::None`) is placed as
//! `x0 + d` with velocity `d'` and acceleration `d''`, the same f32 operations as a translation
//! always had, so translating solids move bit for bit as before. A turn stores `R − I` (computed
//! in f64, rounded once), so `x = (x0 + d) + (R − I)(x0 − c)` keeps small angles accurate in f32;
//! the matrix is general, so any rotation (a floating body's) fits, not only one about a fixed
//! axis. Both backends evaluate the same f32 operations in the same order
//! (`kernels/rigid.cuh`; kernels are compiled with `--fmad=false`).

use crate::math::{Real, Vector};
use crate::physics::rotating_frame::{cross, embed};
use nalgebra::SMatrix;

/// Displacement, velocity and acceleration of one solid at one time, and its rotation (f32,
/// `D` components; module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolidKinematics<const D: usize> {
    /// `d(t)` [m]: the translation of the solid (of its pivot, when it turns).
    pub displacement: Vector<D>,
    /// `d'(t)` [m/s]: the velocity of the pivot (of every particle without a rotation).
    pub velocity: Vector<D>,
    /// `d''(t)` [m/s²]: the acceleration of the pivot; enters the wall pressure as `g − a`
    /// ([A12] eq. 27).
    pub acceleration: Vector<D>,
    /// The rotation about the pivot, if the solid turns.
    pub rotation: Rotation<D>,
}

/// Whether and how a solid turns (module doc): the stages dispatch on this value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rotation<const D: usize> {
    /// No rotation: `R = I`, `ω = α = 0` (a pure translation).
    None,
    /// A rotation about a pivot.
    About(Turn<D>),
}

/// A rotation `R` about the pivot `c`, with its angular velocity and acceleration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Turn<const D: usize> {
    /// The pivot's rest position `c` [m] (it sits at `c + d` at the time).
    pub pivot: Vector<D>,
    /// `R − I` (dimensionless), `R` the rotation matrix (in 2D the in-plane block).
    pub offset: SMatrix<Real, D, D>,
    /// `ω` [rad/s] (in 2D only `z` is used).
    pub angular_velocity: [Real; 3],
    /// `α = ω'` [rad/s²] (in 2D only `z` is used).
    pub angular_acceleration: [Real; 3],
}

/// Floats per solid in the kernels' motion buffer ([`SolidKinematics::kernel_floats`]): the
/// rotation's tag, `d`, `d'`, `d''`, `c` (`D` each), `R − I` (`D²`, row-major), `ω`, `α` (3 each).
pub const fn motion_floats(d: usize) -> usize {
    1 + 4 * d + d * d + 6
}

impl<const D: usize> Turn<D> {
    /// The rotation by the angle `angle` [rad] about the unit axis `axis` through `pivot` [m],
    /// with the angle's rate [rad/s] and its second derivative [rad/s²] (a fixed axis: `ω = θ' n`,
    /// `α = θ'' n`). Rodrigues' formula, `R − I = sin θ [n]× + (1 − cos θ)(n nᵀ − I)` with
    /// `1 − cos θ = 2 sin²(θ/2)`, in f64 and rounded once; in 2D the axis must be `±z`.
    pub fn about_axis(pivot: &[f64], axis: [f64; 3], angle: f64, rate: f64, curvature: f64) -> Self {
        let (s, v) = (angle.sin(), 2.0 * (0.5 * angle).sin().powi(2));
        let n = axis;
        let skew = [[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]];
        let offset = SMatrix::<Real, D, D>::from_fn(|i, j| {
            let eye = if i == j { 1.0 } else { 0.0 };
            (s * skew[i][j] + v * (n[i] * n[j] - eye)) as Real
        });
        Self {
            pivot: Vector::<D>::from_fn(|k, _| pivot.get(k).copied().unwrap_or(0.0) as Real),
            offset,
            angular_velocity: n.map(|c| (c * rate) as Real),
            angular_acceleration: n.map(|c| (c * curvature) as Real),
        }
    }
}

/// The first `D` components of a 3-vector.
fn project<const D: usize>(v: [Real; 3]) -> Vector<D> {
    Vector::<D>::from_fn(|k, _| v[k])
}

impl<const D: usize> SolidKinematics<D> {
    /// A solid at rest at its reference position.
    pub fn rest() -> Self {
        Self {
            displacement: Vector::zeros(),
            velocity: Vector::zeros(),
            acceleration: Vector::zeros(),
            rotation: Rotation::None,
        }
    }

    /// The position `x = (x0 + d) + (R − I)(x0 − c)` [m] of the particle of reference position
    /// `x0` [m] (`x0 + d` without a rotation); the row sums in index order.
    pub fn position(&self, x0: &Vector<D>) -> Vector<D> {
        let mut x = x0 + self.displacement;
        if let Rotation::About(t) = &self.rotation {
            let a = x0 - t.pivot;
            for k in 0..D {
                let mut turn = t.offset[(k, 0)] * a[0];
                for j in 1..D {
                    turn += t.offset[(k, j)] * a[j];
                }
                x[k] += turn;
            }
        }
        x
    }

    /// The arm `r = (x − c) − d` [m] from the moved pivot to the point `x` [m].
    fn arm(&self, t: &Turn<D>, x: &Vector<D>) -> [Real; 3] {
        embed(&((x - t.pivot) - self.displacement))
    }

    /// The solid's velocity `u = d' + ω × r` [m/s] at the point `x` [m] (`d'` without a
    /// rotation).
    pub fn velocity_at(&self, x: &Vector<D>) -> Vector<D> {
        match &self.rotation {
            Rotation::None => self.velocity,
            Rotation::About(t) => self.velocity + project(cross(t.angular_velocity, self.arm(t, x))),
        }
    }

    /// The solid's acceleration `a = d'' + (α × r + ω × (ω × r))` [m/s²] at the point `x` [m]
    /// (`d''` without a rotation): the wall acceleration of [A12] eq. (27) at a wall particle.
    pub fn acceleration_at(&self, x: &Vector<D>) -> Vector<D> {
        match &self.rotation {
            Rotation::None => self.acceleration,
            Rotation::About(t) => {
                let r = self.arm(t, x);
                let tangential = cross(t.angular_acceleration, r);
                let centripetal = cross(t.angular_velocity, cross(t.angular_velocity, r));
                let turn = [0, 1, 2].map(|k| tangential[k] + centripetal[k]);
                self.acceleration + project(turn)
            }
        }
    }

    /// The kernels' record of this solid (`kernels/rigid.cuh`), [`motion_floats`]`(D)` floats:
    /// the tag (0: `Rotation::None`, 1: `Rotation::About`), `d`, `d'`, `d''`, then `c`, `R − I`
    /// (row-major), `ω`, `α` (zeros without a rotation).
    pub fn kernel_floats(&self) -> Vec<f32> {
        let mut out = Vec::with_capacity(motion_floats(D));
        let tag = match self.rotation {
            Rotation::None => 0.0,
            Rotation::About(_) => 1.0,
        };
        out.push(tag);
        for v in [&self.displacement, &self.velocity, &self.acceleration] {
            out.extend(v.iter());
        }
        match &self.rotation {
            Rotation::None => out.resize(motion_floats(D), 0.0),
            Rotation::About(t) => {
                out.extend(t.pivot.iter());
                for i in 0..D {
                    out.extend((0..D).map(|j| t.offset[(i, j)]));
                }
                out.extend(t.angular_velocity);
                out.extend(t.angular_acceleration);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quarter turn about z through (1, 2): (2, 2) goes to (1, 3); the velocity is ω × r and
    /// the acceleration α × r − ω² r (f32 rounding of the f64 inputs).
    #[test]
    fn quarter_turn_about_a_pivot_in_2d() {
        let turn = Turn::<2>::about_axis(
            &[1.0, 2.0],
            [0.0, 0.0, 1.0],
            std::f64::consts::FRAC_PI_2,
            3.0,
            5.0,
        );
        let k = SolidKinematics {
            displacement: Vector::<2>::new(0.5, 0.0),
            velocity: Vector::<2>::new(0.1, 0.2),
            acceleration: Vector::<2>::new(-1.0, 0.0),
            rotation: Rotation::About(turn),
        };
        let x = k.position(&Vector::<2>::new(2.0, 2.0));
        assert!((x - Vector::<2>::new(1.5, 3.0)).norm() < 1e-6, "{x}");
        // r = (0, 1): ω × r = 3 (−1, 0); α × r = 5 (−1, 0); −ω² r = (0, −9).
        let u = k.velocity_at(&x);
        assert!((u - Vector::<2>::new(0.1 - 3.0, 0.2)).norm() < 1e-5, "{u}");
        let a = k.acceleration_at(&x);
        assert!((a - Vector::<2>::new(-1.0 - 5.0, -9.0)).norm() < 1e-5, "{a}");
        assert_eq!(k.kernel_floats().len(), motion_floats(2));
    }

    /// In 3D a turn about y by θ takes (0, 0, L) above the pivot to (L sin θ, 0, L cos θ), and
    /// `R` stays orthogonal: `(R − I) + (R − I)ᵀ + (R − I)ᵀ(R − I) = 0` to f32 rounding.
    #[test]
    fn turn_about_y_in_3d_is_a_rotation() {
        let theta = 0.3f64;
        let turn = Turn::<3>::about_axis(&[0.0; 3], [0.0, 1.0, 0.0], theta, 0.0, 0.0);
        let k = SolidKinematics {
            rotation: Rotation::About(turn),
            ..SolidKinematics::<3>::rest()
        };
        let x = k.position(&Vector::<3>::new(0.0, 0.0, 2.0));
        let want = Vector::<3>::new((2.0 * theta.sin()) as f32, 0.0, (2.0 * theta.cos()) as f32);
        assert!((x - want).norm() < 1e-6, "{x}");
        let m = turn.offset;
        let residual = m + m.transpose() + m.transpose() * m;
        assert!(residual.norm() < 1e-6, "{residual}");
    }

    /// Without a rotation the particle sits at `x0 + d` with `d'` and `d''` bit for bit, and the
    /// kernel record has zeros after the translation.
    #[test]
    fn translation_is_x0_plus_d_bitwise() {
        let k = SolidKinematics {
            displacement: Vector::<2>::new(0.1, -0.3),
            velocity: Vector::<2>::new(0.7, 0.0),
            acceleration: Vector::<2>::new(2.0, 1.0),
            rotation: Rotation::None,
        };
        let x0 = Vector::<2>::new(0.37, 1.01);
        assert_eq!(k.position(&x0), x0 + k.displacement);
        assert_eq!(k.velocity_at(&x0), k.velocity);
        assert_eq!(k.acceleration_at(&x0), k.acceleration);
        let record = k.kernel_floats();
        assert_eq!(record.len(), motion_floats(2));
        assert!(record[7..].iter().all(|&v| v == 0.0));
    }
}
