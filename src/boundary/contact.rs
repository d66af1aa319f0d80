//! Contact between a floating solid and the fixed solids: a body that sinks comes to rest on
//! the floor, one thrown against a wall bounces off it, and neither passes through.
//!
//! The fluid cannot do this alone: the particle boundary pushes fluid out of a wall, but two
//! solids' particles do not interact in SPH. Each pair of a body particle `i` and a particle
//! `j` of a fixed solid closer than the contact distance `d` (one particle spacing: the faces
//! of two solids whose outer particle layers sit half a spacing inside them touch there)
//! carries the linear spring–dashpot force of the discrete element method (Cundall & Strack
//! 1979, "A discrete numerical model for granular assemblies", Géotechnique 29(1), eqs. 1–3;
//! the particle-based rigid contact of DualSPHysics' floating bodies, Canelas et al. 2016,
//! "SPH–DCDEM model for arbitrary geometries in free surface solid–fluid flows", Comput. Phys.
//! Commun. 202, §2.3):
//!
//! - normal: `f_n = max(0, k δ − γ v_n)` along `n = (x_i − x_j)/r`, overlap `δ = d − r`,
//!   `v_n = v_i · n`, `v_i = v + ω × (x_i − c)` the body particle's velocity (the wall is
//!   fixed); never adhesive;
//! - tangential (regularised Coulomb friction, without a tangential spring):
//!   `f_t = −min(μ f_n, γ |v_t|) v_t/|v_t|`.
//!
//! The stiffness is set by the body, not by a material: `k = m_p ω_c²` with `m_p = M / N` the
//! body's mass per particle and `ω_c² = CONTACT_STIFFNESS · g0 / d` (`g0` standard gravity), so
//! that the body on all its `N` particles would ring at `ω_c`, and on the `n ≤ N` pairs of a
//! real contact at `ω_c sqrt(n/N)`, whatever its size. A body resting on the floor on `n` pairs
//! sinks into it by `δ = (N/n) g' / ω_c²`: `(N/n) d / CONTACT_STIFFNESS`, below 5 % of a
//! spacing for a body up to ten particle layers thick (`g'` its weight less its buoyancy per
//! unit mass, at most `g0`). The damping `γ = 2 ζ sqrt(k M / n)` makes the body on its `n`
//! current pairs a damped oscillator of ratio `ζ = −ln e / sqrt(π² + ln² e)`, `e` the
//! restitution coefficient (the normal velocity after a collision over the one before; the
//! clamp at zero force returns a little more: 0.55 for `e` = 0.5).
//! The time step keeps `ω_c dt ≤ CONTACT_STEP` (`solver::timestep`) over the steps in which a
//! body particle may come within the contact distance: those that start with one within that
//! distance plus how far it can move in the step (twice its speed times the step, as the speed
//! may grow within it).
//!
//! Units SI; positions and velocities f64, as the body's state.

use nalgebra::{UnitQuaternion, Vector3};
use std::collections::HashMap;

/// `ω_c² d / g0`: the contact's stiffness in units of standard gravity over the contact
/// distance (module doc).
pub const CONTACT_STIFFNESS: f64 = 200.0;

/// Standard gravity [m/s²], the stiffness's reference acceleration.
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// Largest `ω_c dt`: the spring on its `n ≤ N` pairs rings at most at `ω_c` (up to the few
/// pairs a particle may have at once, `≲ 2 ω_c`), and SSP-RK3 and symplectic Euler are stable
/// on an oscillator for `ω dt` below √3 and 2; 0.5 keeps 20 steps per contact period at `ω_c`.
pub const CONTACT_STEP: f64 = 0.5;

/// How a floating solid meets the fixed solids.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WallContact {
    /// No contact: the body passes through solids (a body held away from walls by its
    /// constraints, e.g. hinged to one).
    None,
    /// The spring–dashpot of the module doc.
    SpringDashpot(SpringDashpot),
}

/// Parameters of [`WallContact::SpringDashpot`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringDashpot {
    /// Restitution coefficient `e` in (0, 1].
    pub restitution: f64,
    /// Coulomb friction coefficient `μ` ≥ 0.
    pub friction: f64,
}

impl SpringDashpot {
    /// The scene's default: `e` = 0.5 (a moderately damped knock, about wood or concrete on
    /// concrete) and `μ` = 0.5 (the same pairs sliding).
    pub const DEFAULT: SpringDashpot = SpringDashpot {
        restitution: 0.5,
        friction: 0.5,
    };

    /// The damping ratio `ζ` of restitution `e` (module doc).
    pub fn damping_ratio(&self) -> f64 {
        let l = self.restitution.ln();
        -l / (std::f64::consts::PI * std::f64::consts::PI + l * l).sqrt()
    }
}

/// `ω_c` [rad/s] for contact distance `d` [m] (module doc).
pub fn contact_frequency(distance: f64) -> f64 {
    (CONTACT_STIFFNESS * STANDARD_GRAVITY / distance).sqrt()
}

/// The geometry of one body's contact: its particles, the fixed solids' particles in a hash
/// grid, and the spring–dashpot.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyContact {
    /// The model's parameters.
    pub law: SpringDashpot,
    /// Contact distance `d` [m].
    pub distance: f64,
    /// `x0 − c0` of each body particle [m] (reference placement about the reference centre).
    pub offsets: Vec<Vector3<f64>>,
    /// Positions of the fixed solids' particles [m].
    pub obstacles: Vec<Vector3<f64>>,
    /// Grid cell (of side `d`) → indices into `obstacles`.
    pub cells: HashMap<[i64; 3], Vec<u32>>,
    /// Body mass `M` [kg] (2D: kg/m).
    pub mass: f64,
}

/// The contact load on a body: force [N] and moment about its centre [N m], and the pairs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLoad {
    /// Total force [N].
    pub force: Vector3<f64>,
    /// Moment about the body's current centre [N m].
    pub moment: Vector3<f64>,
    /// Pairs in contact.
    pub pairs: usize,
}

impl ContactLoad {
    /// No contact.
    pub fn none() -> Self {
        Self {
            force: Vector3::zeros(),
            moment: Vector3::zeros(),
            pairs: 0,
        }
    }
}

fn cell_of(x: &Vector3<f64>, d: f64) -> [i64; 3] {
    [0, 1, 2].map(|k| (x[k] / d).floor() as i64)
}

impl BodyContact {
    /// The contact of a body of mass `mass` whose particles sit at `offsets` (`x0 − c0`) with
    /// the fixed particles `obstacles`, at distance `distance` [m].
    pub fn new(
        law: SpringDashpot,
        distance: f64,
        offsets: Vec<Vector3<f64>>,
        obstacles: Vec<Vector3<f64>>,
        mass: f64,
    ) -> Self {
        let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for (j, y) in obstacles.iter().enumerate() {
            cells.entry(cell_of(y, distance)).or_default().push(j as u32);
        }
        Self {
            law,
            distance,
            offsets,
            obstacles,
            cells,
            mass,
        }
    }

    /// Every (body particle position, offset from the centre, obstacle index, overlap, normal)
    /// within the contact distance, the body at `centre` turned by `orientation`.
    fn pairs(
        &self,
        centre: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
    ) -> Vec<(Vector3<f64>, f64, Vector3<f64>)> {
        let d = self.distance;
        let mut out = Vec::new();
        for o in &self.offsets {
            let r = orientation * o;
            let x = centre + r;
            let c = cell_of(&x, d);
            for dz in -1..=1 {
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        let Some(list) = self.cells.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                            continue;
                        };
                        for &j in list {
                            let delta = x - self.obstacles[j as usize];
                            let dist = delta.norm();
                            if dist < d && dist > 0.0 {
                                out.push((r, d - dist, delta / dist));
                            }
                        }
                    }
                }
            }
        }
        out
    }

    /// The contact load on the body at `centre` [m], turned by `orientation`, moving at
    /// `velocity` [m/s] and `angular_velocity` [rad/s] (module doc).
    pub fn load(
        &self,
        centre: &Vector3<f64>,
        orientation: &UnitQuaternion<f64>,
        velocity: &Vector3<f64>,
        angular_velocity: &Vector3<f64>,
    ) -> ContactLoad {
        let pairs = self.pairs(centre, orientation);
        if pairs.is_empty() {
            return ContactLoad::none();
        }
        let n_body = self.offsets.len() as f64;
        let omega = contact_frequency(self.distance);
        let k = self.mass / n_body * omega * omega;
        let gamma = 2.0 * self.law.damping_ratio() * (k * self.mass / pairs.len() as f64).sqrt();
        let mut load = ContactLoad::none();
        load.pairs = pairs.len();
        for (r, overlap, n) in pairs {
            let v = velocity + angular_velocity.cross(&r);
            let vn = v.dot(&n);
            let f_n = (k * overlap - gamma * vn).max(0.0);
            let vt = v - n * vn;
            let speed_t = vt.norm();
            let mut f = n * f_n;
            if speed_t > 0.0 {
                f -= vt * ((self.law.friction * f_n).min(gamma * speed_t) / speed_t);
            }
            load.force += f;
            load.moment += r.cross(&f);
        }
        load
    }

    /// Whether a body particle is within `reach` [m] of a fixed solid's particle, the body at
    /// `centre` turned by `orientation`. The cells within `reach` are scanned while they are
    /// fewer than the obstacles' non-empty cells; beyond, every obstacle is tested, so a reach
    /// of any size (a light body's speed times the step) costs at most bodies × obstacles.
    pub fn within(&self, centre: &Vector3<f64>, orientation: &UnitQuaternion<f64>, reach: f64) -> bool {
        let d = self.distance;
        let span = (reach / d).ceil();
        if !(2.0 * span + 1.0).powi(3).le(&(self.cells.len() as f64)) {
            return self.offsets.iter().any(|o| {
                let x = centre + orientation * o;
                self.obstacles.iter().any(|y| (x - y).norm() < reach)
            });
        }
        let n = span as i64;
        self.offsets.iter().any(|o| {
            let x = centre + orientation * o;
            let c = cell_of(&x, d);
            (-n..=n).any(|dz| {
                (-n..=n).any(|dy| {
                    (-n..=n).any(|dx| {
                        self.cells
                            .get(&[c[0] + dx, c[1] + dy, c[2] + dz])
                            .is_some_and(|list| {
                                list.iter()
                                    .any(|&j| (x - self.obstacles[j as usize]).norm() < reach)
                            })
                    })
                })
            })
        })
    }

    /// The largest speed [m/s] of a body particle moving at `velocity` and `angular_velocity`
    /// about `centre` turned by `orientation`.
    pub fn fastest_particle(
        &self,
        orientation: &UnitQuaternion<f64>,
        velocity: &Vector3<f64>,
        angular_velocity: &Vector3<f64>,
    ) -> f64 {
        self.offsets
            .iter()
            .map(|o| (velocity + angular_velocity.cross(&(orientation * o))).norm())
            .fold(0.0, f64::max)
    }

    /// Pairs within the contact distance at the body's reference placement.
    pub fn pairs_at_rest(&self, centre: &Vector3<f64>) -> usize {
        self.pairs(centre, &UnitQuaternion::identity()).len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A one-particle body above a one-particle floor: the spring holds its weight at the
    /// overlap `m g / k`, and a drop bounces back with about `e` times the impact's speed.
    #[test]
    fn one_pair_holds_the_weight_and_bounces_with_the_restitution() {
        let d = 0.01;
        let law = SpringDashpot {
            restitution: 0.5,
            friction: 0.0,
        };
        let c = BodyContact::new(law, d, vec![Vector3::zeros()], vec![Vector3::zeros()], 2.0);
        let k = 2.0 * contact_frequency(d).powi(2);
        let g = 9.81;
        let rest = d - 2.0 * g / k;
        let q = UnitQuaternion::identity();
        let up = c.load(
            &Vector3::new(0.0, rest, 0.0),
            &q,
            &Vector3::zeros(),
            &Vector3::zeros(),
        );
        assert!((up.force.y / (2.0 * g) - 1.0).abs() < 1e-9, "{up:?}");
        // A drop at 0.1 m/s without gravity, integrated finely: it leaves at e × 0.1 m/s.
        let (mut y, mut v) = (d, -0.1);
        let dt = 1e-3 / contact_frequency(d);
        for _ in 0..1_000_000 {
            let f = c.load(
                &Vector3::new(0.0, y, 0.0),
                &q,
                &Vector3::new(0.0, v, 0.0),
                &Vector3::zeros(),
            );
            v += f.force.y / 2.0 * dt;
            y += v * dt;
            if y > d {
                break;
            }
        }
        // The linear dashpot's restitution is e; the clamp at zero force (no pull at the end of
        // the contact, where the dashpot would hold the body back) lets it leave a little
        // faster: 0.55 here. Between e and 1.15 e.
        let e = v / 0.1;
        assert!((0.5..0.575).contains(&e), "rebound {v} m/s");
    }

    /// A body sliding along a floor feels friction opposing the slide, at most μ times the
    /// normal force.
    #[test]
    fn within_answers_for_any_reach_without_scanning_empty_space() {
        let law = SpringDashpot {
            restitution: 0.5,
            friction: 0.0,
        };
        let obstacles: Vec<Vector3<f64>> = (0..50)
            .map(|k| Vector3::new(0.01 * f64::from(k), 0.0, 0.0))
            .collect();
        let c = BodyContact::new(law, 0.01, vec![Vector3::zeros()], obstacles, 1.0);
        let q = UnitQuaternion::identity();
        let far = Vector3::new(0.0, 10.0, 0.0);
        assert!(!c.within(&far, &q, 0.05));
        // A reach of 1e12 spacings (a body of density 1e-6 at its first step) answers at once.
        assert!(c.within(&far, &q, 1e10));
        assert!(c.within(&far, &q, f64::INFINITY));
        assert!(!c.within(&far, &q, f64::NAN));
        assert!(c.within(&Vector3::new(0.2, 0.005, 0.0), &q, 0.01));
    }

    #[test]
    fn friction_opposes_sliding_and_is_bounded_by_mu_times_the_normal_force() {
        let d = 0.01;
        let law = SpringDashpot {
            restitution: 0.5,
            friction: 0.3,
        };
        let c = BodyContact::new(law, d, vec![Vector3::zeros()], vec![Vector3::zeros()], 1.0);
        let q = UnitQuaternion::identity();
        let f = c.load(
            &Vector3::new(0.0, 0.9 * d, 0.0),
            &q,
            &Vector3::new(1.0, 0.0, 0.0),
            &Vector3::zeros(),
        );
        assert!(f.force.x < 0.0 && f.force.y > 0.0, "{f:?}");
        assert!(
            (f.force.x.abs() - 0.3 * f.force.y).abs() < 1e-9 * f.force.y,
            "{f:?}"
        );
    }
}
