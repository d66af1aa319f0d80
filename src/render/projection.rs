//! Orthographic views of particle positions: world coordinates [m] → picture plane (u to the
//! right, v up) [m] and a depth (larger = nearer the viewer) for the painter's order.
//!
//! 2D runs lie in the x–y plane and have one view. 3D runs (z up, as the paper's scenes):
//! `side` looks along +y (x–z plane, the paper's Figs. 2–3 side-on), `top` looks down −z (x–y
//! plane), `iso` is an oblique view from the front left and above.

/// Which way a 3D run is looked at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// Looking along +y: x to the right, z up.
    Side,
    /// Looking down −z: x to the right, y up.
    Top,
    /// Oblique: turned [`ISO_AZIMUTH_DEG`] about z from the side view, then tilted down by
    /// [`ISO_ELEVATION_DEG`].
    Iso,
}

/// Turn of the iso camera about the vertical axis from the side view [degrees]; negative puts
/// the camera on the −x side, so the water column of the dam-break scenes is in front.
pub const ISO_AZIMUTH_DEG: f64 = -35.0;

/// Tilt of the iso camera above the horizontal [degrees].
pub const ISO_ELEVATION_DEG: f64 = 30.0;

/// An orthographic camera: two picture axes and the direction towards the viewer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    right: [f64; 3],
    up: [f64; 3],
    toward_viewer: [f64; 3],
}

/// A point in the picture plane: `u` right and `v` up [m], `depth` towards the viewer [m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projected {
    /// Horizontal picture coordinate [m].
    pub u: f64,
    /// Vertical picture coordinate [m].
    pub v: f64,
    /// Distance along the viewing direction, larger = nearer [m].
    pub depth: f64,
}

impl Projection {
    /// The camera of a 2D run (x right, y up; all particles at one depth).
    pub fn plane() -> Self {
        Projection {
            right: [1.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            toward_viewer: [0.0, 0.0, 1.0],
        }
    }

    /// The camera of a 3D run for `view`.
    pub fn of_view(view: View) -> Self {
        match view {
            View::Side => Projection {
                right: [1.0, 0.0, 0.0],
                up: [0.0, 0.0, 1.0],
                toward_viewer: [0.0, -1.0, 0.0],
            },
            View::Top => Self::plane(),
            View::Iso => {
                let (a, e) = (ISO_AZIMUTH_DEG.to_radians(), ISO_ELEVATION_DEG.to_radians());
                // The side camera turned by `a` about z: right (cos a, sin a, 0), horizontal
                // direction to the viewer (sin a, −cos a, 0); then tilted up by `e`.
                let horizontal = [a.sin(), -a.cos(), 0.0];
                Projection {
                    right: [a.cos(), a.sin(), 0.0],
                    up: [-e.sin() * horizontal[0], -e.sin() * horizontal[1], e.cos()],
                    toward_viewer: [e.cos() * horizontal[0], e.cos() * horizontal[1], e.sin()],
                }
            }
        }
    }

    /// Projects the world point `p` [m].
    pub fn project(&self, p: [f32; 3]) -> Projected {
        let p = p.map(f64::from);
        let dot = |a: [f64; 3]| a[0] * p[0] + a[1] * p[1] + a[2] * p[2];
        Projected {
            u: dot(self.right),
            v: dot(self.up),
            depth: dot(self.toward_viewer),
        }
    }

    /// Whether a solid point `p` [m] is cut away: it lies on the viewer's side of the fluid's
    /// bounding box `fluid_min`..`fluid_max` [m] along x or y (the horizontal axes of the
    /// scenes, z up), or, in a view from straight above, above the fluid (a closed tank's
    /// lid). Without the cut the near walls of a tank would hide the water. Obstacles taller
    /// than the water keep their part up to the water's top, which the top view shows.
    pub fn cuts_away(&self, p: [f32; 3], fluid_min: [f64; 3], fluid_max: [f64; 3]) -> bool {
        // Axes nearly across the line of sight face the viewer too little to hide anything.
        const FACING: f64 = 0.1;
        // A view this close to vertical looks through the lid of a closed tank.
        const FROM_ABOVE: f64 = 0.9;
        let beside = (0..2).any(|k| {
            let (t, x) = (self.toward_viewer[k], f64::from(p[k]));
            (t < -FACING && x < fluid_min[k]) || (t > FACING && x > fluid_max[k])
        });
        beside || (self.toward_viewer[2] > FROM_ABOVE && f64::from(p[2]) > fluid_max[2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    #[test]
    fn every_camera_is_orthonormal() {
        for p in [
            Projection::plane(),
            Projection::of_view(View::Side),
            Projection::of_view(View::Top),
            Projection::of_view(View::Iso),
        ] {
            for (a, b, want) in [
                (p.right, p.right, 1.0),
                (p.up, p.up, 1.0),
                (p.toward_viewer, p.toward_viewer, 1.0),
                (p.right, p.up, 0.0),
                (p.right, p.toward_viewer, 0.0),
                (p.up, p.toward_viewer, 0.0),
            ] {
                assert!((dot(a, b) - want).abs() < 1e-12, "{p:?}");
            }
            // Right-handed: right × up = toward the viewer.
            let (r, u) = (p.right, p.up);
            let cross = [
                r[1] * u[2] - r[2] * u[1],
                r[2] * u[0] - r[0] * u[2],
                r[0] * u[1] - r[1] * u[0],
            ];
            assert!((dot(cross, p.toward_viewer) - 1.0).abs() < 1e-12, "{p:?}");
        }
    }

    #[test]
    fn side_view_puts_z_up_and_small_y_near() {
        let side = Projection::of_view(View::Side);
        let a = side.project([0.3, 0.1, 0.7]);
        assert_eq!((a.u, a.v), (f64::from(0.3f32), f64::from(0.7f32)));
        assert!(side.project([0.0, 0.0, 0.0]).depth > side.project([0.0, 0.5, 0.0]).depth);
        let iso = Projection::of_view(View::Iso);
        // Higher points are higher in the picture and nearer a camera looking down.
        assert!(iso.project([0.0, 0.0, 1.0]).v > iso.project([0.0, 0.0, 0.0]).v);
        assert!(iso.project([0.0, 0.0, 1.0]).depth > iso.project([0.0, 0.0, 0.0]).depth);
    }

    #[test]
    fn near_walls_are_cut_away_and_far_ones_kept() {
        let (lo, hi) = ([0.0, 0.0, 0.0], [1.0, 0.5, 0.5]);
        let side = Projection::of_view(View::Side);
        assert!(side.cuts_away([0.5, -0.01, 0.2], lo, hi), "front wall");
        assert!(!side.cuts_away([0.5, 0.51, 0.2], lo, hi), "back wall");
        assert!(
            !side.cuts_away([-0.01, 0.2, 0.2], lo, hi),
            "end wall seen edge-on"
        );
        let iso = Projection::of_view(View::Iso);
        assert!(iso.cuts_away([-0.01, 0.2, 0.2], lo, hi));
        assert!(iso.cuts_away([0.5, -0.01, 0.2], lo, hi));
        assert!(!iso.cuts_away([1.01, 0.51, 0.2], lo, hi));
        assert!(
            !iso.cuts_away([1.01, 0.51, 0.9], lo, hi),
            "iso keeps what rises above the water"
        );
        let top = Projection::of_view(View::Top);
        assert!(
            !top.cuts_away([0.5, -0.01, 0.2], lo, hi),
            "walls beside the water stay"
        );
        assert!(!top.cuts_away([0.5, 0.2, 0.5], lo, hi), "up to the water's top");
        assert!(
            top.cuts_away([0.5, 0.2, 0.51], lo, hi),
            "a lid above the water goes"
        );
    }
}
