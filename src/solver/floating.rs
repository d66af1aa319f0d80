//! Floating solids: rigid bodies the fluid moves (`boundary::rigid_body`), advanced stage by
//! stage with the fluid by the run's own integrator.
//!
//! Each integrator stage `k` of a step:
//! 1. `move_solids` places the body at its current stage state: `x = c0 + d + R (x0 − c0)`,
//!    `u = v + ω × r` (`boundary::rigid`, pivot `c0` the reference centre of mass, `d = c − c0`,
//!    `R` from the quaternion), with the acceleration of its last rate, which the wall pressure
//!    takes as the wall's (`[A12]` eq. 27, `g − a`).
//! 2. The force stage's reaction on the body's particles (`solid_forces`, Fig. 4, moment about
//!    the centre by `boundary::solid_force::moment_about`) is the stage's load; with gravity and
//!    the moorings it gives the rate `RigidBody::rate`, and the body takes the same Shu–Osher
//!    stage as the fluid (`RigidBody::stage`, or `RigidBody::symplectic_euler`), so body and
//!    fluid stay one system of ODEs integrated by one method (the partitioned, explicit coupling
//!    of DualSPHysics' floating bodies, Canelas et al. 2015, "SPH–DCDEM model for arbitrary
//!    geometries in free surface solid–fluid flows", Comput. Phys. Commun. 202).
//! 3. `corrected`: the body is placed at the stage's result before the position correction and
//!    held there while the correction (23)–(24) and the velocity solve push the fluid out of it;
//!    its particles carry the body's velocity `v + ω × r`, which the velocity solve takes as a
//!    moving wall's. The fluid's momentum change by the walls (`SolidForceSource::Correction`)
//!    is an impulse `J = τ F` whose reaction kicks the body at the stage's result:
//!    `Δv = J / M`, `Δω = I⁻¹ L` (within its freedom). This is the two-way coupling of Akinci et
//!    al. 2012 ("Versatile rigid-fluid coupling for incompressible and highly viscous fluids",
//!    ACM TOG 31(4), §4: the pressure force of the fluid on boundary particles, applied as the
//!    reaction to the rigid body; SPlisHSPlasH's `BoundaryModel_Akinci2012`). Why it neither
//!    sinks nor bounces: the body is a moving wall inside the correction, so the fluid under it
//!    is decompressed to `ρ0` relative to where the body stands, never to where it would be
//!    (no sinking); and the push the correction needs is returned to the body exactly as the
//!    fluid's momentum change (every pair term is antisymmetric), so the pair's momentum is
//!    conserved and no energy is injected (no bounce).
//!
//! Units SI; the body state is f64 (`boundary::rigid_body`), rounded to f32 only to place the
//! particles.

use super::{SetupError, Simulation};
use crate::backend::SolidLoad;
use crate::boundary::contact::{self, BodyContact, ContactLoad, WallContact};
use crate::boundary::rigid::{Rotation, SolidKinematics, Turn};
use crate::boundary::rigid_body::{BodyState, RigidBody};
use crate::boundary::solid_force::moment_about;
use crate::fields::FLUID;
use crate::math::{Real, Vector};
use nalgebra::{SMatrix, Vector3};

/// A floating solid: its dynamics and the state it carries between stages.
#[derive(Clone, Debug, PartialEq)]
pub struct FloatingBody {
    /// Mass properties, freedom, moorings (its `gravity` is set from the run's at each stage).
    pub body: RigidBody,
    /// The current (stage) state.
    pub state: BodyState,
    /// The state at the start of the step (the Shu–Osher `y^n`).
    pub start: BodyState,
    /// `v'` [m/s²] of the last rate: the wall's acceleration at the next placement.
    pub acceleration: Vector3<f64>,
    /// `ω'` [rad/s²] of the last rate.
    pub angular_acceleration: Vector3<f64>,
    /// The load [N, N m about the origin] of the current stage's force stage.
    pub stage_load: SolidLoad,
    /// Its contact with the fixed solids, built for [`WallContact::SpringDashpot`]
    /// (`boundary::contact`).
    pub contact: Option<BodyContact>,
    /// The contact load of the last stage.
    pub contact_load: ContactLoad,
}

impl FloatingBody {
    /// The body at rest in its reference placement.
    pub fn new(body: RigidBody) -> Self {
        let state = body.initial_state();
        Self {
            body,
            state,
            start: state,
            acceleration: Vector3::zeros(),
            angular_acceleration: Vector3::zeros(),
            stage_load: [0.0; 6],
            contact: None,
            contact_load: ContactLoad::none(),
        }
    }

    /// The kinematics that place the body's particles at its current state (module doc, 1).
    pub fn kinematics<const D: usize>(&self) -> SolidKinematics<D> {
        let c0 = self.body.mass.centre;
        let s = &self.state;
        let vector = |v: Vector3<f64>| Vector::<D>::from_fn(|k, _| v[k] as Real);
        let rotation = s.orientation.to_rotation_matrix();
        let offset = SMatrix::<Real, D, D>::from_fn(|i, j| {
            (rotation[(i, j)] - if i == j { 1.0 } else { 0.0 }) as Real
        });
        SolidKinematics {
            displacement: vector(s.centre - c0),
            velocity: vector(s.velocity),
            acceleration: vector(self.acceleration),
            rotation: Rotation::About(Turn {
                pivot: vector(c0),
                offset,
                angular_velocity: s.angular_velocity.map(|w| w as Real).into(),
                angular_acceleration: self.angular_acceleration.map(|w| w as Real).into(),
            }),
        }
    }

    /// Force [N] and moment about the current centre [N m] of `load` (force, moment about the
    /// origin).
    fn about_centre(&self, load: &SolidLoad) -> (Vector3<f64>, Vector3<f64>) {
        let c = self.state.centre;
        let m = moment_about(load, &[c.x, c.y, c.z]);
        (Vector3::new(load[0], load[1], load[2]), Vector3::from(m))
    }

    /// Shu–Osher stage `(a, b)` of the step of `dt` [s] under the stored stage load and
    /// gravity `gravity` [m/s²]; `euler`: the symplectic Euler step instead (module doc, 2).
    fn advance(&mut self, gravity: Vector3<f64>, a: f64, b: f64, dt: f64, euler: bool) {
        self.body.gravity = gravity;
        let (mut force, mut moment) = self.about_centre(&self.stage_load);
        if let Some(c) = &self.contact {
            let s = &self.state;
            self.contact_load = c.load(&s.centre, &s.orientation, &s.velocity, &s.angular_velocity);
            force += self.contact_load.force;
            moment += self.contact_load.moment;
        }
        let rate = self.body.rate(&self.state, &force, &moment);
        self.acceleration = rate.acceleration;
        self.angular_acceleration = rate.angular_acceleration;
        self.state = if euler {
            self.body.symplectic_euler(&self.state, &rate, dt)
        } else {
            self.body.stage(&self.start, &self.state, &rate, a, b, dt)
        };
    }

    /// The reaction of the correction's impulse `τ F` (`load` the force `F` [N] and its moment
    /// about the origin) on the body's stage state, within its freedom (module doc, 3): the
    /// rate of a body without gravity, moorings or spin under `τ F`.
    fn kick(&mut self, load: &SolidLoad, tau: f64) {
        let (force, moment) = self.about_centre(load);
        let still = BodyState {
            angular_velocity: Vector3::zeros(),
            ..self.state
        };
        let free = RigidBody {
            gravity: Vector3::zeros(),
            moorings: Vec::new(),
            ..self.body.clone()
        };
        let dv = free.rate(&still, &(force * tau), &(moment * tau));
        self.state.velocity += dv.acceleration;
        self.state.angular_velocity += dv.angular_acceleration;
    }
}

/// Stores each floating solid's share of a force stage's load `part` (scene order).
pub(super) fn record_stage_load(bodies: &mut [Option<FloatingBody>], part: &[SolidLoad]) {
    for (b, p) in bodies.iter_mut().zip(part) {
        if let Some(b) = b {
            b.stage_load = *p;
        }
    }
}

impl<const D: usize> Simulation<D> {
    /// The floating solids (scene order; `None`: fixed or prescribed).
    pub fn floating_bodies(&self) -> &[Option<FloatingBody>] {
        &self.floating
    }

    /// Marks the start of a step: each body's `y^n` is its current state.
    pub(super) fn begin_body_step(&mut self) {
        for b in self.floating.iter_mut().flatten() {
            b.start = b.state;
        }
    }

    /// Advances every floating body by integrator stage `k` of a step of `dt` [s] under the
    /// stage's load, with gravity `gravity` [m/s²] (module doc, 2).
    pub(super) fn advance_bodies(&mut self, k: usize, dt: f64, gravity: &Vector<D>) {
        if self.floating.iter().all(Option::is_none) {
            return;
        }
        let integrator = self.config.integrator;
        let (a, b) = integrator.stage_weights_f64()[k];
        let euler = integrator == super::Integrator::SymplecticEuler;
        let g = Vector3::from_fn(|c, _| if c < D { f64::from(gravity[c]) } else { 0.0 });
        for body in self.floating.iter_mut().flatten() {
            body.advance(g, a, b, dt, euler);
        }
        self.solids_placed_at = None;
    }

    /// Kicks every floating body by the reaction of the correction's load `load` over `tau` [s]
    /// (module doc, 3).
    pub(super) fn kick_bodies(&mut self, load: &[SolidLoad], tau: f64) {
        if self.floating.iter().all(Option::is_none) {
            return;
        }
        for (body, l) in self.floating.iter_mut().zip(load) {
            if let Some(body) = body {
                body.kick(l, tau);
            }
        }
        self.solids_placed_at = None;
    }
}

/// What a checkpoint keeps of a floating body (`solver::checkpoint`): its state and the last
/// rate's accelerations, which the next placement gives the walls; f64, exact through JSON.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BodyRecord {
    /// Centre of mass [m].
    pub centre: [f64; 3],
    /// Velocity [m/s].
    pub velocity: [f64; 3],
    /// Orientation, the unit quaternion `(w, i, j, k)`.
    pub orientation: [f64; 4],
    /// Angular velocity [rad/s].
    pub angular_velocity: [f64; 3],
    /// `v'` of the last rate [m/s²].
    pub acceleration: [f64; 3],
    /// `ω'` of the last rate [rad/s²].
    pub angular_acceleration: [f64; 3],
}

impl FloatingBody {
    /// The body's [`BodyRecord`].
    pub fn record(&self) -> BodyRecord {
        let s = &self.state;
        let q = s.orientation.quaternion();
        BodyRecord {
            centre: s.centre.into(),
            velocity: s.velocity.into(),
            orientation: [q.w, q.i, q.j, q.k],
            angular_velocity: s.angular_velocity.into(),
            acceleration: self.acceleration.into(),
            angular_acceleration: self.angular_acceleration.into(),
        }
    }

    /// The body as `r` records it (bit for bit: the quaternion is not renormalised).
    pub fn restore(&mut self, r: &BodyRecord) {
        let [w, i, j, k] = r.orientation;
        self.state = BodyState {
            centre: r.centre.into(),
            velocity: r.velocity.into(),
            orientation: nalgebra::UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(w, i, j, k)),
            angular_velocity: r.angular_velocity.into(),
        };
        self.start = self.state;
        self.acceleration = r.acceleration.into();
        self.angular_acceleration = r.angular_acceleration.into();
    }
}

impl<const D: usize> Simulation<D> {
    /// Makes solid `k` a floating body (`bodies[k]`, `None`: fixed or prescribed) that the
    /// fluid moves (`solver::floating`). Call before the first step, after
    /// [`Simulation::with_solid_motion`]; like a motion, a body adds the `move_solids` stage.
    ///
    /// # Errors
    /// [`SetupError::Invalid`] when `bodies` does not have one entry per solid, a solid has both
    /// a motion and a body, a body's mass or inertia is not finite and positive, or steps were
    /// taken.
    pub fn with_floating_bodies(mut self, bodies: Vec<Option<RigidBody>>) -> Result<Self, SetupError> {
        let invalid = |reason: String| SetupError::Invalid {
            key: "solid.floating",
            reason,
        };
        if bodies.len() != self.solid_names.len() {
            return Err(invalid(format!(
                "{} bodies for {} solids",
                bodies.len(),
                self.solid_names.len()
            )));
        }
        if self.clock.step != 0 {
            return Err(invalid(
                "floating bodies must be given before the first step".into(),
            ));
        }
        for (k, b) in bodies.iter().enumerate() {
            let Some(b) = b else { continue };
            if self.motions[k].is_some() {
                return Err(invalid(format!(
                    "solid `{}` has both a motion and a floating body",
                    self.solid_names[k]
                )));
            }
            let m = &b.mass;
            let finite = m.centre.iter().chain(m.inertia.iter()).all(|v| v.is_finite());
            let inertia_ok = (0..3).all(|c| m.inertia[(c, c)] > 0.0);
            if !(m.mass.is_finite() && m.mass > 0.0 && finite && inertia_ok) {
                return Err(invalid(format!(
                    "solid `{}`: mass properties must be finite and positive, got {m:?}",
                    self.solid_names[k]
                )));
            }
        }
        self.floating = bodies.into_iter().map(|b| b.map(FloatingBody::new)).collect();
        self.take_solid_reference();
        self.build_contacts()?;
        Ok(self)
    }

    /// Builds each floating body's contact with the fixed solids (`boundary::contact`): its
    /// particles about its centre and the particles of every solid without a motion that does
    /// not float. A body that starts within the contact distance of one would be thrown off at
    /// the first step: that is an error naming it.
    fn build_contacts(&mut self) -> Result<(), SetupError> {
        let f = &self.fields;
        let fixed = |kind: u32| {
            kind != FLUID && {
                let k = (kind - 1) as usize;
                self.motions[k].is_none() && self.floating[k].is_none()
            }
        };
        let embed = |x: &Vector<D>| Vector3::from_fn(|k, _| if k < D { f64::from(x[k]) } else { 0.0 });
        let obstacles: Vec<Vector3<f64>> = (0..f.len())
            .filter(|&i| fixed(f.kind[i]))
            .map(|i| embed(&f.position[i]))
            .collect();
        let spacing = self.config.spacing;
        let mut built = Vec::with_capacity(self.floating.len());
        for (k, b) in self.floating.iter().enumerate() {
            let Some(b) = b else {
                built.push(None);
                continue;
            };
            let WallContact::SpringDashpot(law) = b.body.contact else {
                built.push(None);
                continue;
            };
            let c0 = b.body.mass.centre;
            let offsets = (0..f.len())
                .filter(|&i| f.kind[i] == k as u32 + 1)
                .map(|i| embed(&f.position[i]) - c0)
                .collect();
            let c = BodyContact::new(law, spacing, offsets, obstacles.clone(), b.body.mass.mass);
            let touching = c.pairs_at_rest(&c0);
            if touching > 0 {
                return Err(SetupError::Invalid {
                    key: "solid.floating.contact",
                    reason: format!(
                        "solid `{}` starts within a particle spacing of a fixed solid ({touching} particle pairs): \
                         move it clear, or set `contact = {{ kind = \"none\" }}` (e.g. a body hinged to a wall)",
                        self.solid_names[k]
                    ),
                });
            }
            built.push(Some(c));
        }
        for (b, c) in self.floating.iter_mut().zip(built) {
            if let Some(b) = b {
                b.contact = c;
            }
        }
        Ok(())
    }

    /// The largest mooring frequency `ω_m` [rad/s] over the floating bodies
    /// (`RigidBody::mooring_frequency`), which bounds the step; `None` without moorings.
    pub(super) fn mooring_frequency(&self) -> Option<f64> {
        self.floating
            .iter()
            .flatten()
            .filter_map(|b| b.body.mooring_frequency(D))
            .reduce(f64::max)
    }

    /// `ω_c` [rad/s] of the stiffest contact a floating body may enter over a step of `dt` [s],
    /// which then bounds the step (`boundary::contact`, module doc); `None` when no body can
    /// reach a fixed solid within `dt`.
    pub(super) fn contact_frequency(&self, dt: f64) -> Option<f64> {
        self.floating
            .iter()
            .flatten()
            .filter_map(|b| {
                let c = b.contact.as_ref()?;
                let s = &b.state;
                let speed = c.fastest_particle(&s.orientation, &s.velocity, &s.angular_velocity);
                let reach = c.distance + 2.0 * speed * dt;
                c.within(&s.centre, &s.orientation, reach)
                    .then(|| contact::contact_frequency(c.distance))
            })
            .reduce(f64::max)
    }
}
