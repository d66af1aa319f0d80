//! Rigid-body dynamics of a floating solid: the state a body carries between steps, the rate of
//! that state under the fluid's load, gravity, moorings and constraints, and its integration by
//! the run's own integrator, so that a body advances stage by stage with the fluid.
//!
//! The body is a rigid solid of mass `M` [kg] (2D: per metre of depth [kg/m]), centre of mass `c`
//! [m] and inertia tensor `I_b` [kg m²] about `c` in its reference orientation (2D: `I_zz` per
//! metre [kg m]). Its state is `c`, the velocity `v` [m/s], the orientation `q` (a unit
//! quaternion, body reference to world) and the angular velocity `ω` [rad/s] in world axes.
//! Newton–Euler equations (e.g. Goldstein, Classical Mechanics, §5.5):
//!
//! ```text
//! c' = v,                  M v' = F_fluid + M g + Σ F_mooring
//! q' = ½ (0, ω) ⊗ q,       I_w ω' = M_c − ω × (I_w ω),   I_w = R I_b Rᵀ
//! ```
//!
//! with `M_c` the moment [N m] about `c` of the fluid's load and of the moorings. 2D scenes use the
//! same equations in the plane `z = 0`: translation along x and y and rotation about z only
//! ([`Freedom::planar`]).
//!
//! Constraints ([`Freedom`]): translation and rotation can be held along any of the world axes
//! (the acceleration's component along a held axis is zero, so is the velocity's if it starts
//! at zero), or the body turns about a fixed hinge, one degree of freedom: `I_p θ'' = n · M_p`
//! with `I_p = n · (I_w + M (|r|² 1 − r rᵀ)) n` the inertia about the hinge axis `n` through the
//! hinge point `p` (parallel-axis theorem, `r = c − p`) and `M_p` the load's moment about `p`.
//!
//! A mooring ([`Mooring`]) is a taut-only linear spring from a fixed anchor to a point of the body:
//! force `k (L − L0) L̂` towards the anchor while the line is longer than its rest length `L0`,
//! none while slack.
//!
//! Units SI, evaluated in f64 (a body is a handful of numbers).

use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

/// Mass, centre of mass and inertia of a rigid body (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct MassProperties {
    /// `M` [kg] (2D: [kg/m]).
    pub mass: f64,
    /// Centre of mass [m] in the reference placement (z = 0 in 2D).
    pub centre: Vector3<f64>,
    /// `I_b` [kg m²] about the centre of mass, world axes in the reference orientation
    /// (2D: only `I_zz` [kg m] is used).
    pub inertia: Matrix3<f64>,
}

impl MassProperties {
    /// The properties of a body of uniform `density` [kg/m³] filling the cells of volume
    /// `cell_volume` [m³] (2D: area [m²]) centred at `points` [m] (a lattice sampling of its
    /// shape): `M = ρ V`, `c` the mean of the points, `I = Σ m_p (|r|² 1 − r rᵀ) + M s² (D + 2)/12`
    /// where the last term is each cell's own inertia (a cube of side `s = cell_volume^(1/D)`;
    /// `dimension` 2 or 3). Refines as the cells shrink: a box sampled by 20 cells a side is
    /// exact to rounding ([`tests`]). `None` without points.
    pub fn of_cells(
        points: &[Vector3<f64>],
        cell_volume: f64,
        density: f64,
        dimension: usize,
    ) -> Option<Self> {
        if points.is_empty() {
            return None;
        }
        let m_cell = density * cell_volume;
        let mass = m_cell * points.len() as f64;
        let centre = points.iter().sum::<Vector3<f64>>() / points.len() as f64;
        let mut inertia = Matrix3::zeros();
        for p in points {
            let r = p - centre;
            inertia += m_cell * (Matrix3::identity() * r.norm_squared() - r * r.transpose());
        }
        // A cell's own inertia about its centre: m s²/6 about each axis of a cube (3D), m s²/6
        // about z for a square (2D).
        let side = cell_volume.powf(1.0 / dimension as f64);
        inertia += Matrix3::identity() * (mass * side * side / 6.0);
        Some(Self {
            mass,
            centre,
            inertia,
        })
    }
}

/// Which motions a body may make (the scene's constraints).
#[derive(Clone, Debug, PartialEq)]
pub enum Freedom {
    /// Translation along the world axes whose flag is set, rotation about the world axes whose
    /// flag is set (a 2D body: translation x, y, rotation z).
    Axes {
        /// Free translation along x, y, z.
        translation: [bool; 3],
        /// Free rotation about x, y, z.
        rotation: [bool; 3],
    },
    /// Rotation about the fixed axis `axis` (unit) through `point` [m] only.
    Hinge {
        /// A point on the hinge axis [m].
        point: Vector3<f64>,
        /// The hinge axis (unit vector).
        axis: Vector3<f64>,
    },
}

impl Freedom {
    /// A free body in the plane (2D): translation along x and y, rotation about z.
    pub fn planar() -> Self {
        Freedom::Axes {
            translation: [true, true, false],
            rotation: [false, false, true],
        }
    }

    /// A free body in space (3D, six degrees of freedom).
    pub fn free() -> Self {
        Freedom::Axes {
            translation: [true; 3],
            rotation: [true; 3],
        }
    }
}

/// A taut-only linear mooring line (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Mooring {
    /// The fixed anchor [m].
    pub anchor: Vector3<f64>,
    /// The fairlead, the line's point on the body [m], in the reference placement.
    pub fairlead: Vector3<f64>,
    /// Stiffness `k` [N/m] (2D: [N/m per metre of depth]), >= 0.
    pub stiffness: f64,
    /// Rest length `L0` [m], >= 0.
    pub rest_length: f64,
}

/// The state of a rigid body (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyState {
    /// Centre of mass `c` [m].
    pub centre: Vector3<f64>,
    /// Velocity `v` of the centre of mass [m/s].
    pub velocity: Vector3<f64>,
    /// Orientation `q`, from the reference orientation to the world.
    pub orientation: UnitQuaternion<f64>,
    /// Angular velocity `ω` [rad/s], world axes.
    pub angular_velocity: Vector3<f64>,
}

/// The time derivative of a [`BodyState`]: `(c', v', q', ω')`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyRate {
    /// `c' = v` [m/s].
    pub velocity: Vector3<f64>,
    /// `v'` [m/s²].
    pub acceleration: Vector3<f64>,
    /// `q' = ½ (0, ω) ⊗ q` (not unit).
    pub orientation: Quaternion<f64>,
    /// `ω'` [rad/s²].
    pub angular_acceleration: Vector3<f64>,
}

/// A floating body: its mass properties, freedom, moorings and gravity.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidBody {
    /// Mass, centre and inertia in the reference placement.
    pub mass: MassProperties,
    /// What the body may do.
    pub freedom: Freedom,
    /// Mooring lines.
    pub moorings: Vec<Mooring>,
    /// Gravity `g` [m/s²] (zero without the scene's gravity).
    pub gravity: Vector3<f64>,
    /// How it meets the fixed solids (`boundary::contact`).
    pub contact: super::contact::WallContact,
}

impl RigidBody {
    /// The body at rest in its reference placement.
    pub fn initial_state(&self) -> BodyState {
        BodyState {
            centre: self.mass.centre,
            velocity: Vector3::zeros(),
            orientation: UnitQuaternion::identity(),
            angular_velocity: Vector3::zeros(),
        }
    }

    /// Where a point `x0` [m] of the reference placement is in state `s`: `c + R (x0 − c0)`.
    pub fn placed(&self, s: &BodyState, x0: &Vector3<f64>) -> Vector3<f64> {
        s.centre + s.orientation * (x0 - self.mass.centre)
    }

    /// The largest frequency `ω_m` [rad/s] at which the moorings can ring the body, `None`
    /// without moorings: `ω_m² = Σ k (1/M + |r|²/I)` over the lines (`r` the fairlead about the
    /// centre of mass, `I` the smallest principal moment, 2D: `I_zz`), an upper bound on the
    /// frequencies of the taut lines' translation and rotation modes together. The time step
    /// keeps `ω_m dt ≤ CONTACT_STEP` as for a contact (`solver::timestep`): the lines are as
    /// explicit as the contact spring.
    pub fn mooring_frequency(&self, dim: usize) -> Option<f64> {
        if self.moorings.is_empty() {
            return None;
        }
        let i = &self.mass.inertia;
        let moment = if dim == 2 {
            i[(2, 2)]
        } else {
            i[(0, 0)].min(i[(1, 1)]).min(i[(2, 2)])
        };
        let squared: f64 = self
            .moorings
            .iter()
            .map(|m| {
                let r2 = (m.fairlead - self.mass.centre).norm_squared();
                m.stiffness * (1.0 / self.mass.mass + r2 / moment)
            })
            .sum();
        Some(squared.sqrt())
    }

    /// The moorings' force [N] and moment about the centre of mass [N m] in state `s`.
    pub fn mooring_load(&self, s: &BodyState) -> (Vector3<f64>, Vector3<f64>) {
        let (mut force, mut moment) = (Vector3::zeros(), Vector3::zeros());
        for m in &self.moorings {
            let fairlead = self.placed(s, &m.fairlead);
            let line = m.anchor - fairlead;
            let length = line.norm();
            if length > m.rest_length && length > 0.0 {
                let f = line * (m.stiffness * (length - m.rest_length) / length);
                force += f;
                moment += (fairlead - s.centre).cross(&f);
            }
        }
        (force, moment)
    }

    /// The rate of state `s` under the fluid's force `force` [N] and its moment `moment` [N m]
    /// about the centre of mass, with gravity, the moorings and the body's freedom (module doc).
    pub fn rate(&self, s: &BodyState, force: &Vector3<f64>, moment: &Vector3<f64>) -> BodyRate {
        let m = self.mass.mass;
        let (mooring_force, mooring_moment) = self.mooring_load(s);
        let total_force = force + mooring_force + self.gravity * m;
        let total_moment = moment + mooring_moment;
        let rotation = s.orientation.to_rotation_matrix();
        let inertia = rotation.matrix() * self.mass.inertia * rotation.matrix().transpose();
        let w = s.angular_velocity;
        let (acceleration, angular_acceleration) = match &self.freedom {
            Freedom::Axes {
                translation,
                rotation,
            } => {
                let mut a = total_force / m;
                let gyroscopic = total_moment - w.cross(&(inertia * w));
                // Held rotation axes: solve only the free block of I_w α = M − ω × I_w ω.
                let free: Vec<usize> = (0..3).filter(|&k| rotation[k]).collect();
                let mut alpha = Vector3::zeros();
                if !free.is_empty() {
                    let n = free.len();
                    let block = nalgebra::DMatrix::from_fn(n, n, |r, c| inertia[(free[r], free[c])]);
                    let rhs = nalgebra::DVector::from_fn(n, |r, _| gyroscopic[free[r]]);
                    if let Some(x) = block.lu().solve(&rhs) {
                        for (r, &k) in free.iter().enumerate() {
                            alpha[k] = x[r];
                        }
                    }
                }
                for k in 0..3 {
                    if !translation[k] {
                        a[k] = 0.0;
                    }
                }
                (a, alpha)
            }
            Freedom::Hinge { point, axis } => {
                // One degree of freedom: the angle about the hinge axis.
                let r = s.centre - point;
                let about_point = inertia + (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * m;
                let i_axis = axis.dot(&(about_point * axis));
                let moment_about_point = total_moment + r.cross(&total_force);
                let alpha = axis * (axis.dot(&moment_about_point) / i_axis);
                // The centre turns about the hinge: a = α × r + ω × (ω × r).
                let a = alpha.cross(&r) + w.cross(&w.cross(&r));
                (a, alpha)
            }
        };
        BodyRate {
            velocity: s.velocity,
            acceleration,
            orientation: Quaternion::from_parts(0.0, w) * s.orientation.into_inner() * 0.5,
            angular_acceleration,
        }
    }

    /// One Shu–Osher stage `a y^n + b (y + dt L(y))` (`solver::Integrator::stage_weights_f64`, SSP-RK3 or
    /// with `(a, b) = (0, 1)` explicit Euler) of the body from the step's start `start` and the
    /// current stage state `current`, whose rate under the stage's load is `rate`. The orientation
    /// is combined as a quaternion and renormalised.
    pub fn stage(
        &self,
        start: &BodyState,
        current: &BodyState,
        rate: &BodyRate,
        a: f64,
        b: f64,
        dt: f64,
    ) -> BodyState {
        let mix3 = |y0: &Vector3<f64>, y: &Vector3<f64>, dy: &Vector3<f64>| y0 * a + (y + dy * dt) * b;
        let q = start.orientation.into_inner() * a
            + (current.orientation.into_inner() + rate.orientation * dt) * b;
        let orientation = UnitQuaternion::from_quaternion(q);
        let state = BodyState {
            centre: mix3(&start.centre, &current.centre, &rate.velocity),
            velocity: mix3(&start.velocity, &current.velocity, &rate.acceleration),
            orientation,
            angular_velocity: mix3(
                &start.angular_velocity,
                &current.angular_velocity,
                &rate.angular_acceleration,
            ),
        };
        self.on_hinge(state)
    }

    /// One step of the semi-implicit (symplectic) Euler integrator (`solver::Integrator::
    /// SymplecticEuler`), as the fluid takes it: velocities first, then the placement with the
    /// new velocities.
    pub fn symplectic_euler(&self, current: &BodyState, rate: &BodyRate, dt: f64) -> BodyState {
        let velocity = current.velocity + rate.acceleration * dt;
        let angular_velocity = current.angular_velocity + rate.angular_acceleration * dt;
        let spin = Quaternion::from_parts(0.0, angular_velocity) * current.orientation.into_inner() * 0.5;
        let state = BodyState {
            centre: current.centre + velocity * dt,
            velocity,
            orientation: UnitQuaternion::from_quaternion(current.orientation.into_inner() + spin * dt),
            angular_velocity,
        };
        self.on_hinge(state)
    }

    /// A hinged body's centre put back on its circle about the hinge (a combination of points on
    /// a circle lies inside it) and its velocity `ω × (c − p)`; other bodies unchanged.
    fn on_hinge(&self, mut state: BodyState) -> BodyState {
        if let Freedom::Hinge { point, .. } = &self.freedom {
            state.centre = point + state.orientation * (self.mass.centre - point);
            state.velocity = state.angular_velocity.cross(&(state.centre - point));
        }
        state
    }
}

#[cfg(test)]
#[path = "rigid_body_tests.rs"]
mod tests;
