//! The no-penetration guard: fluid never ends a move inside a solid's volume.
//!
//! The particle boundary (module doc of `boundary`) pushes fluid back through the density sum
//! and the pressure, but only as hard as the fluid is compressed: a lone splash particle, or one
//! in a thin sheet, has too few fluid neighbours to be compressed by the wall particles it
//! approaches, and can sit among them (measured in 3D: a 10 m/s jet put a particle 0.53 dx into
//! the tank wall with `wcsph`; the correction pushed one 0.0016 dx past the innermost wall
//! layer). So after every move (an integrator stage, a correction sweep) a fluid particle found
//! inside a solid's volume is put back onto the nearest face, `margin` outside it, and the part
//! of its velocity (relative to the wall) that points into the solid is removed: a perfectly
//! inelastic, frictionless contact. Its momentum change is handed to the solid as force, so the
//! fluid's momentum balance still closes (`Simulation::step`). It acts only on particles that
//! the particle boundary let through, and every such push is counted (`RunStats::keep_out_pushes`,
//! `summary.json`), so a run shows how often the guard, not the physics, held the fluid.
//!
//! The volumes are axis-aligned boxes in the solid's frame: a `box` solid is one, a `container`
//! is the union of its wall slabs (`KeepOutBox::container`).

use crate::boundary::solid_force::cross;
use crate::math::{Real, Vector, to_xyz};

/// One axis-aligned solid volume [m] that fluid must stay out of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeepOutBox<const D: usize> {
    /// Lower corner [m].
    pub min: Vector<D>,
    /// Upper corner [m].
    pub max: Vector<D>,
    /// Velocity of the solid [m/s] (zero for fixed solids).
    pub velocity: Vector<D>,
    /// Index of the solid the box belongs to (its force receives the pushes).
    pub solid: u32,
}

/// What the guard did in one call.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct KeepOutReport {
    /// Fluid particles put back out of a solid.
    pub pushes: u64,
    /// Momentum given to the fluid by each solid [kg m/s] (2D: per unit depth).
    pub impulse: Vec<[f64; 3]>,
    /// Its angular momentum about the origin [kg m²/s] (2D: per unit depth, in the z slot):
    /// [`push_moment`] of every push, so the solid's moment balances as its force does.
    pub angular_impulse: Vec<[f64; 3]>,
}

/// The angular momentum about the origin [kg m²/s] of a push that changed the momentum along
/// `axis` by `dp` [kg m/s] and left the particle at `x` [m]: `x × dp e_axis` (2D: z = 0, the
/// moment `x dp_y − y dp_x` in the z slot).
pub fn push_moment<const D: usize>(x: &Vector<D>, axis: usize, dp: f64) -> [f64; 3] {
    let mut p = [0.0; 3];
    p[axis] = dp;
    cross(to_xyz(x), p)
}

impl KeepOutReport {
    /// No pushes, zero momentum for each of `solids` solids.
    pub fn none(solids: usize) -> Self {
        Self {
            pushes: 0,
            impulse: vec![[0.0; 3]; solids],
            angular_impulse: vec![[0.0; 3]; solids],
        }
    }
}

impl<const D: usize> KeepOutBox<D> {
    /// The wall slabs of a container whose inside is `[min, max]` [m] with walls `thickness` [m]
    /// thick; without a top wall (`open_top`, last axis vertical). The slabs overlap at the
    /// edges and corners, which changes nothing: a particle is pushed out of each in turn.
    pub fn container(
        min: Vector<D>,
        max: Vector<D>,
        thickness: Real,
        open_top: bool,
        solid: u32,
    ) -> Vec<Self> {
        let outer_min = min.add_scalar(-thickness);
        let mut outer_max = max.add_scalar(thickness);
        if open_top {
            // The side walls end at the top of the inside, as `scene::generate` lays them.
            outer_max[D - 1] = max[D - 1];
        }
        let mut slabs = Vec::with_capacity(2 * D);
        for k in 0..D {
            let (mut lo, mut hi) = (outer_min, outer_max);
            hi[k] = min[k];
            slabs.push(Self::fixed(lo, hi, solid));
            if open_top && k == D - 1 {
                continue;
            }
            (lo, hi) = (outer_min, outer_max);
            lo[k] = max[k];
            slabs.push(Self::fixed(lo, hi, solid));
        }
        slabs
    }

    /// The box as `kernels/keep_out.cu` reads it: min, max, velocity (D floats each), then the
    /// solid's index.
    pub fn kernel_floats(&self) -> impl Iterator<Item = f32> + '_ {
        self.min
            .iter()
            .chain(self.max.iter())
            .chain(self.velocity.iter())
            .copied()
            .chain(std::iter::once(self.solid as f32))
    }

    /// A fixed box.
    pub fn fixed(min: Vector<D>, max: Vector<D>, solid: u32) -> Self {
        Self {
            min,
            max,
            velocity: Vector::zeros(),
            solid,
        }
    }

    /// Puts a particle at `x` [m] with velocity `u` [m/s] that lies strictly inside the box onto
    /// the face it came in through, `margin` [m] outside, and removes the velocity component
    /// (relative to the box) that points into the box. Returns the axis it was moved along,
    /// `None` when it was not inside.
    ///
    /// The face: with `from`, a position of the particle known to be on the fluid side (its
    /// position at the step's start, `Fields::position_start`, in the SSP-RK3 stages and the
    /// correction sweeps inside them), the face where the segment from `from` to `x` enters the
    /// box ([`KeepOutBox::entry_face`]); otherwise, or when `from` is itself inside, the nearest
    /// face. The nearest face alone is wrong for a particle that crossed the middle of a thin
    /// wall slab in one move: it would be put on the far side of the wall (measured: a block
    /// thrown at a wall at 0.25 h/|u| left its box so, tests/numerics/correction.rs). With `from`, a
    /// particle outside the box whose segment from `from` passes through the box's interior
    /// went through the solid: it too goes back to the face it entered by
    /// ([`KeepOutBox::crossed_face`]).
    #[inline(always)]
    pub fn push_out(
        &self,
        x: &mut Vector<D>,
        u: &mut Vector<D>,
        margin: Real,
        from: Option<&Vector<D>>,
    ) -> Option<usize> {
        let (axis, upper) = if (0..D).all(|k| x[k] > self.min[k] && x[k] < self.max[k]) {
            from.and_then(|from| self.entry_face(x, from))
                .unwrap_or_else(|| self.nearest_face(x))
        } else {
            // Outside: back only if it went through the box since `from`.
            from.and_then(|from| self.crossed_face(x, from))?
        };
        let relative = u[axis] - self.velocity[axis];
        if upper {
            x[axis] = self.max[axis] + margin;
            if relative < 0.0 {
                u[axis] = self.velocity[axis];
            }
        } else {
            x[axis] = self.min[axis] - margin;
            if relative > 0.0 {
                u[axis] = self.velocity[axis];
            }
        }
        Some(axis)
    }

    /// The nearest face of the box to `x` (inside it): `(axis, upper)`, the axis and side with
    /// the least depth; ties go to the lower axis and the lower side, as in the kernel twin
    /// (`kernels/keep_out.cu`).
    #[inline(always)]
    pub fn nearest_face(&self, x: &Vector<D>) -> (usize, bool) {
        let (mut axis, mut upper, mut depth) = (0, false, Real::INFINITY);
        for k in 0..D {
            let below = x[k] - self.min[k];
            let above = self.max[k] - x[k];
            if below < depth {
                (axis, upper, depth) = (k, false, below);
            }
            if above < depth {
                (axis, upper, depth) = (k, true, above);
            }
        }
        (axis, upper)
    }

    /// The face where the segment from `from` to `x` (inside the box) enters the box:
    /// `(axis, upper)`, the axis whose slab the segment enters last (the largest entry
    /// parameter `t`, ties to the lower axis, as in the kernel twin); `None` when `from` is
    /// inside the box on every axis.
    #[inline(always)]
    pub fn entry_face(&self, x: &Vector<D>, from: &Vector<D>) -> Option<(usize, bool)> {
        let mut best: Option<(usize, bool, Real)> = None;
        for k in 0..D {
            // x[k] lies strictly between min and max, so each denominator is positive.
            let (upper, t) = if from[k] <= self.min[k] {
                (false, (self.min[k] - from[k]) / (x[k] - from[k]))
            } else if from[k] >= self.max[k] {
                (true, (from[k] - self.max[k]) / (from[k] - x[k]))
            } else {
                continue;
            };
            if best.is_none_or(|b| t > b.2) {
                best = Some((k, upper, t));
            }
        }
        best.map(|(k, upper, _)| (k, upper))
    }

    /// The face where the segment from `from` to `x` enters the box's interior when both ends lie
    /// outside it and the segment passes through the interior (it went through the solid):
    /// `(axis, upper)`, as [`KeepOutBox::entry_face`]; `None` when the segment misses the
    /// interior or only touches its boundary, or when `from` is inside.
    #[inline(always)]
    pub fn crossed_face(&self, x: &Vector<D>, from: &Vector<D>) -> Option<(usize, bool)> {
        let (mut enter, mut leave) = (0.0 as Real, 1.0 as Real);
        let mut face = None;
        for k in 0..D {
            let d = x[k] - from[k];
            if d == 0.0 {
                if from[k] <= self.min[k] || from[k] >= self.max[k] {
                    return None;
                }
                continue;
            }
            let (at_min, at_max) = ((self.min[k] - from[k]) / d, (self.max[k] - from[k]) / d);
            let (near, far, upper) = if d > 0.0 {
                (at_min, at_max, false)
            } else {
                (at_max, at_min, true)
            };
            if near > enter {
                (enter, face) = (near, Some((k, upper)));
            }
            leave = leave.min(far);
        }
        if enter < leave { face } else { None }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_push_moment_is_x_cross_the_momentum_change() {
        // 2D: the z moment `x dp_y − y dp_x`.
        let x = Vector::<2>::new(2.0, 3.0);
        assert_eq!(push_moment(&x, 0, 1.5), [0.0, 0.0, -4.5]);
        assert_eq!(push_moment(&x, 1, 1.5), [0.0, 0.0, 3.0]);
        // 3D: e.g. a push along z at (1, 2, 3) turns about x by y dp and about y by −x dp.
        let x = Vector::<3>::new(1.0, 2.0, 3.0);
        assert_eq!(push_moment(&x, 2, 2.0), [4.0, -2.0, 0.0]);
        assert_eq!(push_moment(&x, 0, 2.0), [0.0, 6.0, -4.0]);
    }

    #[test]
    fn a_particle_inside_lands_on_the_nearest_face_and_stops_going_in() {
        let b = KeepOutBox::<2>::fixed(Vector::<2>::new(0.0, 0.0), Vector::<2>::new(1.0, 0.1), 0);
        let mut x = Vector::<2>::new(0.5, 0.08);
        let mut u = Vector::<2>::new(0.3, -2.0);
        assert_eq!(b.push_out(&mut x, &mut u, 1e-4, None), Some(1));
        assert_eq!(x, Vector::<2>::new(0.5, 0.1 + 1e-4));
        assert_eq!(u, Vector::<2>::new(0.3, 0.0));
        // Outside (and on the face): untouched.
        let (x0, u0) = (x, u);
        assert_eq!(b.push_out(&mut x, &mut u, 1e-4, None), None);
        assert_eq!((x, u), (x0, u0));
        // Leaving already: the position is fixed, the velocity kept.
        let mut x = Vector::<2>::new(0.02, 0.05);
        let mut u = Vector::<2>::new(-1.0, 0.0);
        assert_eq!(b.push_out(&mut x, &mut u, 0.0, None), Some(0));
        assert_eq!((x[0], u[0]), (0.0, -1.0));
    }

    #[test]
    fn a_particle_past_the_middle_of_a_thin_wall_goes_back_the_way_it_came() {
        // A wall slab 2 units thick along x; the particle came from x = −1 (the fluid side) and
        // is 1.5 units in: the nearest face is the far one, the entry face the near one.
        let b = KeepOutBox::<2>::fixed(Vector::<2>::new(0.0, -5.0), Vector::<2>::new(2.0, 5.0), 0);
        let from = Vector::<2>::new(-1.0, 0.0);
        let (mut x, mut u) = (Vector::<2>::new(1.5, 0.2), Vector::<2>::new(3.0, 0.0));
        assert_eq!(b.nearest_face(&x), (0, true));
        assert_eq!(b.entry_face(&x, &from), Some((0, false)));
        assert_eq!(b.push_out(&mut x, &mut u, 0.01, Some(&from)), Some(0));
        assert_eq!((x, u), (Vector::<2>::new(-0.01, 0.2), Vector::<2>::zeros()));
        // Without the start, the nearest face: through the wall.
        let (mut x, mut u) = (Vector::<2>::new(1.5, 0.2), Vector::<2>::new(3.0, 0.0));
        assert_eq!(b.push_out(&mut x, &mut u, 0.01, None), Some(0));
        assert_eq!(x, Vector::<2>::new(2.01, 0.2));
        // Across a corner: the segment enters the slab through its top face last.
        let from = Vector::<2>::new(-1.0, 7.0);
        assert_eq!(b.entry_face(&Vector::<2>::new(1.0, 4.5), &from), Some((1, true)));
        // A start inside the box gives no entry face: the nearest one is used.
        assert_eq!(
            b.entry_face(&Vector::<2>::new(1.5, 0.0), &Vector::<2>::new(1.0, 0.0)),
            None
        );
    }

    #[test]
    fn a_particle_that_went_through_a_wall_comes_back_to_the_side_it_left() {
        let b = KeepOutBox::<2>::fixed(Vector::<2>::new(0.0, -5.0), Vector::<2>::new(2.0, 5.0), 0);
        let from = Vector::<2>::new(-1.0, 0.0);
        // Through the slab and out beyond it: back on the near face.
        let (mut x, mut u) = (Vector::<2>::new(2.5, 0.5), Vector::<2>::new(4.0, 1.0));
        assert_eq!(b.crossed_face(&x, &from), Some((0, false)));
        assert_eq!(b.push_out(&mut x, &mut u, 0.01, Some(&from)), Some(0));
        assert_eq!((x, u), (Vector::<2>::new(-0.01, 0.5), Vector::<2>::new(0.0, 1.0)));
        // Beside the slab, past its end: untouched; without a start: untouched.
        let (mut x, mut u) = (Vector::<2>::new(2.5, 7.0), Vector::<2>::new(4.0, 1.0));
        assert_eq!(
            b.push_out(&mut x, &mut u, 0.01, Some(&Vector::<2>::new(-1.0, 6.0))),
            None
        );
        let (mut x, mut u) = (Vector::<2>::new(2.5, 0.5), Vector::<2>::new(4.0, 1.0));
        assert_eq!(b.push_out(&mut x, &mut u, 0.01, None), None);
        // Along a face (touching only): not a crossing.
        assert_eq!(
            b.crossed_face(&Vector::<2>::new(3.0, 5.0), &Vector::<2>::new(-1.0, 5.0)),
            None
        );
        // Staying on the near side: not a crossing.
        assert_eq!(b.crossed_face(&Vector::<2>::new(-0.5, 3.0), &from), None);
    }

    #[test]
    fn a_moving_wall_keeps_its_velocity_for_the_particle() {
        let mut b = KeepOutBox::<2>::fixed(Vector::<2>::new(0.0, 0.0), Vector::<2>::new(1.0, 1.0), 0);
        b.velocity = Vector::<2>::new(-0.5, 0.0);
        let mut x = Vector::<2>::new(0.01, 0.5);
        let mut u = Vector::<2>::new(0.2, 0.0);
        assert_eq!(b.push_out(&mut x, &mut u, 0.0, None), Some(0));
        assert_eq!(u, Vector::<2>::new(-0.5, 0.0));
    }

    #[test]
    fn container_slabs_cover_the_walls_and_leave_the_inside_and_open_top_free() {
        let slabs = KeepOutBox::<2>::container(
            Vector::<2>::new(0.0, 0.0),
            Vector::<2>::new(1.0, 0.5),
            0.02,
            true,
            3,
        );
        assert_eq!(slabs.len(), 3);
        let inside = |p: [Real; 2]| {
            slabs.iter().any(|s| {
                let (mut x, mut u) = (Vector::<2>::new(p[0], p[1]), Vector::<2>::zeros());
                s.push_out(&mut x, &mut u, 0.0, None).is_some()
            })
        };
        assert!(inside([-0.01, 0.2]) && inside([1.01, 0.2]) && inside([0.5, -0.01]));
        assert!(inside([-0.01, -0.01]));
        assert!(!inside([0.5, 0.2]) && !inside([0.5, 0.6]) && !inside([-0.03, 0.2]));
        assert!(!inside([-0.01, 0.51]));
        assert!(slabs.iter().all(|s| s.solid == 3));
    }
}
