//! No-slip walls for the viscous force (17): the velocity a solid particle carries in the
//! viscous term, extrapolated from the fluid ([A12] eqs. 22–23).
//!
//! A solid particle that carries its own (wall) velocity in (17) is not a no-slip condition at
//! the wall face: the fluid next to the wall sees a neighbour moving with the wall half a
//! spacing or more beyond the face, and slips (measured in `tests/physics/poiseuille.rs`: slip length
//! ≈ h/4). Adami, Hu & Adams give each solid particle `w` instead the velocity
//! `2 u_w − ũ_w`, with `ũ_w` the Shepard interpolation of the fluid velocity around it
//! (eq. 22), so that the velocity interpolated at the wall face is the wall's own (eq. 23).
//! Only the viscous term uses it; pressure, artificial viscosity and the no-penetration guard
//! keep the wall's velocity.
//!
//! References: [A12] S. Adami, X. Y. Hu, N. A. Adams, "A generalized wall boundary condition for
//! smoothed particle hydrodynamics", J. Comput. Phys. 231, 7057–7075 (2012), eqs. (22)–(23).

use crate::math::{Real, Vector};

/// Running Shepard sums over the fluid neighbours `f` of one solid particle (eq. 22).
#[derive(Clone, Copy, Debug)]
pub struct WallVelocitySums<const D: usize> {
    /// `Σ_f W_wf` [1/m^D].
    pub weight: Real,
    /// `Σ_f u_f W_wf` [m/s /m^D].
    pub velocity: Vector<D>,
}

impl<const D: usize> Default for WallVelocitySums<D> {
    fn default() -> Self {
        Self {
            weight: 0.0,
            velocity: Vector::zeros(),
        }
    }
}

impl<const D: usize> WallVelocitySums<D> {
    /// Adds fluid neighbour `f` with velocity `u_f` [m/s] and poly6 weight `w` (eq. 20).
    #[inline(always)]
    pub fn add(&mut self, u_f: &Vector<D>, w: Real) {
        self.weight += w;
        self.velocity += u_f * w;
    }

    /// [A12] eqs. (22)–(23): the velocity [m/s] of the solid particle in the viscous term,
    /// `2 u_wall − ũ` with `ũ = Σ_f u_f W_wf / Σ_f W_wf`; `u_wall` [m/s] is the particle's own
    /// velocity (zero for a fixed wall, `d'(t)` for a moving one, `boundary::motion`). Without
    /// fluid neighbours (`Σ W = 0`) the particle keeps `u_wall`.
    #[inline(always)]
    pub fn viscous_velocity(&self, u_wall: &Vector<D>) -> Vector<D> {
        if self.weight <= 0.0 {
            return *u_wall;
        }
        u_wall * 2.0 - self.velocity / self.weight
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_linear_shear_is_mirrored_about_the_wall_velocity() {
        // Fluid moving at 1 and 3 m/s with equal weights: ũ = 2, so a wall at rest gets −2 and
        // a wall moving at 0.5 gets −1; without fluid it keeps its own velocity.
        let mut s = WallVelocitySums::<2>::default();
        s.add(&Vector::<2>::new(1.0, 0.0), 0.5);
        s.add(&Vector::<2>::new(3.0, 0.0), 0.5);
        assert_eq!(s.viscous_velocity(&Vector::zeros()), Vector::<2>::new(-2.0, 0.0));
        assert_eq!(
            s.viscous_velocity(&Vector::<2>::new(0.5, 0.0)),
            Vector::<2>::new(-1.0, 0.0)
        );
        let dry = WallVelocitySums::<2>::default();
        let u = Vector::<2>::new(0.3, -0.1);
        assert_eq!(dry.viscous_velocity(&u), u);
    }
}
