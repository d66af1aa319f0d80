//! The fictitious body forces of a frame rotating at the constant angular velocity `Ω`
//! (effect `rotating_frame`): Coriolis and centrifugal accelerations, added to gravity (eq. 6)
//! in the momentum equation (15).
//!
//! In a frame rotating steadily at `Ω` [rad/s] about an axis through `x_c` [m], the momentum
//! equation per unit mass gains (Batchelor 1967, *An Introduction to Fluid Dynamics*, §3.2;
//! Kundu & Cohen, *Fluid Mechanics*, 4th ed., §4.12)
//!
//! `a = −2 Ω × u − Ω × (Ω × (x − x_c)) = −Ω × (2 u + Ω × (x − x_c))`  [m/s²],
//!
//! `u` [m/s] the velocity relative to the rotating frame. The Coriolis part `−2 Ω × u` is
//! perpendicular to `u` and does no work; the centrifugal part is `Ω² r_⊥`, pointing away from
//! the axis, `r_⊥` the part of `x − x_c` perpendicular to `Ω`.
//!
//! Dimensions. `Ω` is always a 3-vector. In 3D positions and velocities are used as they are.
//! In 2D they are embedded as `(x, y, 0)` and the result's third component is dropped:
//! - `Ω = (0, 0, Ω_z)` (the scene gives a scalar): rotation about the out-of-plane axis, e.g. a
//!   plan view of a rotating basin; Coriolis and centrifugal forces both lie in the plane, and the
//!   2D model is exact for plane motion.
//! - `Ω = (Ω_x, Ω_y, 0)` (the scene gives 2 entries): rotation about an axis in the plane, e.g.
//!   the vertical axis of a rotating tank seen in a vertical slice through the axis. The
//!   centrifugal force lies in the plane; the Coriolis force of plane motion points out of the
//!   plane and is dropped, so the slice is exact only for motion without out-of-plane (azimuthal)
//!   velocity, such as the tank at rest in the rotating frame (its free surface is the parabola
//!   `z = z0 + Ω² x²/(2g)`, the slice of the 3D paraboloid).
//!
//! References: [B67] G. K. Batchelor, An Introduction to Fluid Dynamics, CUP 1967, §3.2;
//! [KC08] P. K. Kundu, I. M. Cohen, Fluid Mechanics, 4th ed., Academic Press 2008, §4.12.

use crate::math::{Real, Vector};

/// A `D`-vector (D = 2 or 3) as a 3-vector, `(x, y, 0)` in 2D.
pub(crate) fn embed<const D: usize>(v: &Vector<D>) -> [Real; 3] {
    [v[0], v[1], if D > 2 { v[2] } else { 0.0 }]
}

/// The cross product `a × b`.
pub(crate) fn cross(a: [Real; 3], b: [Real; 3]) -> [Real; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// [B67] §3.2: Coriolis plus centrifugal acceleration in a frame rotating at `omega` [rad/s]
/// about the axis through `centre` [m], of a particle at `x` [m] moving at `u` [m/s] relative to
/// the frame.
///
/// `a = −Ω × (2 u + Ω × (x − x_c))` [m/s²]: the first `D` components of the 3D formula on the
/// embedded vectors (module doc for 2D). `kernels/forces.cu` `rotating_frame_acceleration` is the
/// twin, with the same operations in the same order.
pub fn rotating_frame_acceleration<const D: usize>(
    omega: &[Real; 3],
    centre: &Vector<D>,
    x: &Vector<D>,
    u: &Vector<D>,
) -> Vector<D> {
    let r = embed(&(x - centre));
    let u = embed(u);
    let w_r = cross(*omega, r);
    let s = [2.0 * u[0] + w_r[0], 2.0 * u[1] + w_r[1], 2.0 * u[2] + w_r[2]];
    let a = cross(*omega, s);
    Vector::<D>::from_fn(|k, _| -a[k])
}

/// [B67] §3.2: the Coriolis part alone, `−2 Ω × u` [m/s²] (2D: module doc).
pub fn coriolis_acceleration<const D: usize>(omega: &[Real; 3], u: &Vector<D>) -> Vector<D> {
    let a = cross(*omega, embed(u));
    Vector::<D>::from_fn(|k, _| -2.0 * a[k])
}

/// [B67] §3.2: the centrifugal part alone, `−Ω × (Ω × (x − x_c))` [m/s²] (2D: module doc).
pub fn centrifugal_acceleration<const D: usize>(
    omega: &[Real; 3],
    centre: &Vector<D>,
    x: &Vector<D>,
) -> Vector<D> {
    let a = cross(*omega, cross(*omega, embed(&(x - centre))));
    Vector::<D>::from_fn(|k, _| -a[k])
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Vector2, Vector3};

    /// f32 arithmetic on O(1) inputs: a few ulps.
    const TOL: Real = 1.0e-5;

    #[test]
    fn a_particle_at_rest_feels_omega_squared_r_outward_in_3d() {
        let omega = [0.0, 0.0, 2.0];
        let centre = Vector3::new(1.0, 1.0, 0.0);
        let x = Vector3::new(1.3, 1.4, 0.7); // r_⊥ = (0.3, 0.4), |r_⊥| = 0.5
        let a = rotating_frame_acceleration(&omega, &centre, &x, &Vector3::zeros());
        let expected = Vector3::new(0.3, 0.4, 0.0) * 4.0; // Ω² r_⊥, no axial part
        assert!((a - expected).norm() < TOL, "{a:?} vs {expected:?}");
        assert!((a.norm() - 4.0 * 0.5).abs() < TOL);
    }

    #[test]
    fn a_vertical_slice_sees_the_centrifugal_force_of_the_vertical_axis_in_2d() {
        // Ω along y (the vertical of a 2D scene), axis through x = 0.5.
        let omega = [0.0, 3.0, 0.0];
        let centre = Vector2::new(0.5, 0.0);
        let x = Vector2::new(0.7, 0.25);
        let a = rotating_frame_acceleration(&omega, &centre, &x, &Vector2::zeros());
        assert!((a - Vector2::new(9.0 * 0.2, 0.0)).norm() < TOL, "{a:?}");
        // Plane motion in the slice: the Coriolis force is out of the plane and dropped.
        let u = Vector2::new(0.4, -0.1);
        assert!(coriolis_acceleration(&omega, &u).norm() < TOL);
    }

    #[test]
    fn coriolis_is_perpendicular_to_the_velocity_and_does_no_work() {
        let omega = [0.3, -0.7, 1.1];
        for u in [
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.2, -0.5, 0.9),
            Vector3::new(-3.0, 2.0, 1.0),
        ] {
            let a = coriolis_acceleration(&omega, &u);
            assert!(a.dot(&u).abs() < TOL * a.norm() * u.norm(), "power {}", a.dot(&u));
            // |−2 Ω × u| = 2 |Ω| |u| sin θ.
            let w = Vector3::from(omega);
            let sin = w.cross(&u).norm() / (w.norm() * u.norm());
            assert!((a.norm() - 2.0 * w.norm() * u.norm() * sin).abs() < TOL * a.norm());
        }
        // About the out-of-plane axis in 2D: a = 2 Ω (u_y, −u_x), perpendicular to u.
        let u = Vector2::new(0.6, 0.8);
        let a = coriolis_acceleration(&[0.0, 0.0, 1.5], &u);
        assert!((a - Vector2::new(2.0 * 1.5 * 0.8, -2.0 * 1.5 * 0.6)).norm() < TOL);
    }

    #[test]
    fn the_total_is_coriolis_plus_centrifugal() {
        let omega = [0.3, -0.7, 1.1];
        let centre = Vector3::new(0.1, 0.2, 0.3);
        let x = Vector3::new(-0.4, 0.9, 0.5);
        let u = Vector3::new(0.2, -0.5, 0.9);
        let total = rotating_frame_acceleration(&omega, &centre, &x, &u);
        let parts = coriolis_acceleration(&omega, &u) + centrifugal_acceleration(&omega, &centre, &x);
        assert!((total - parts).norm() < TOL, "{total:?} vs {parts:?}");
        // The centrifugal force is perpendicular to the axis.
        assert!(
            centrifugal_acceleration(&omega, &centre, &x)
                .dot(&Vector3::from(omega))
                .abs()
                < TOL
        );
    }
}
