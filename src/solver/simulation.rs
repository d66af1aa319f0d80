//! The [`Simulation`]: its state, its set-up, its accessors and its stage parameters.

use super::floating::FloatingBody;
use super::plan;
use super::stage::Stage;
use super::{Clock, RunStats, SetupError, SimConfig, SurfaceTension};
use crate::backend::Backend;
use crate::backend::cpu::CpuBackend;
use crate::boundary::keep_out::KeepOutBox;
use crate::boundary::motion::{Motion, SolidKinematics, SolidReference};
use crate::fields::{FLUID, Fields};
use crate::math::{Real, Vector, sum_in_order};
use crate::model::SurfaceTensionModel;
use crate::model::pair_terms::PairTerm;
use crate::model::params::StepParams;
use crate::physics::density::DensityWeight;
use crate::physics::gravity::gravity_at;
use crate::physics::lattice::{
    correction_stiffness, lattice_gradient_moment, lattice_laplacian_moment, lattice_mass,
    lattice_spiky_scale,
};
use crate::physics::multiphase::Phases;
use crate::physics::surface_stress::calibrated_stress;
use crate::physics::surface_tension::gamma_for_surface_tension;
use crate::smoothing::Smoothing;

/// A running simulation in dimension `D` (2 or 3).
pub struct Simulation<const D: usize> {
    /// Particle fields (cell-sorted after the first step).
    pub fields: Fields<D>,
    pub(super) backend: Box<dyn Backend<D> + Send>,
    /// Wall seconds per stage name since [`Simulation::time_stages`] turned timing on.
    pub(super) stage_seconds: Option<Vec<(&'static str, f64)>>,
    /// Seconds the velocity solves of the current correction stage took, while stages are
    /// timed; moved into `stage_seconds` as `velocity_solve` when the stage ends.
    pub(super) velocity_solve_seconds: f64,
    /// `fields` lags the backend's state (a device-resident backend ran stages since the last
    /// [`Simulation::sync_fields`]).
    pub(super) fields_stale: bool,
    pub(super) plan: Vec<Stage>,
    pub(super) config: SimConfig<D>,
    pub(super) solid_names: Vec<String>,
    /// `1/κ` of the pressure gradient (see `physics::lattice`).
    pub(super) pressure_gradient_scale: Real,
    /// The kernel of eq. (18): poly6 for `wcsph`, the spiky kernel times its lattice factor for
    /// `corrected` (`physics::density`).
    pub(super) density_weight: DensityWeight,
    /// `1/λ` of the viscous force (17) (`physics::lattice::lattice_laplacian_moment`); 1 when
    /// the scene has no viscosity.
    pub(super) viscosity_scale: Real,
    /// [AAT13]'s `γ` for the scene's `σ`, calibrated on the lattice at set-up
    /// (`physics::surface_tension::gamma_for_surface_tension`); 0 without surface tension.
    pub(super) surface_tension_gamma: Real,
    /// `σ'` of the surface stress, calibrated on the lattice at set-up
    /// (`physics::surface_stress::calibrated_stress`); 0 unless that is the model.
    pub(super) surface_tension_sigma: Real,
    pub(super) clock: Clock,
    pub(super) stats: RunStats,
    /// Force of the fluid on each named solid at the last step [N] (2D: [N/m]).
    pub(super) solid_force: Vec<[f64; 3]>,
    /// Moment of that force about the origin at the last step [N m] (2D: [N m/m], z only;
    /// `backend::SolidLoad`).
    pub(super) solid_moment: Vec<[f64; 3]>,
    pub(super) fluid_count: usize,
    /// `K` of the correction's step scale [m²] (`physics::lattice::correction_stiffness`), for
    /// the `κ` the pressure force divides by now.
    pub(super) correction_stiffness: f64,
    /// `K/κ` [m²]: `K` is proportional to the `κ` of the pressure gradient it moves particles
    /// along, so a measured `κ` (`Stage::GradientMoment`) sets `K = κ K/κ` and the sweeps'
    /// displacements stay those of the lattice's `κ`; only the pressure that makes them scales.
    pub(super) stiffness_per_kappa: f64,
    /// The grid matches the positions (no move since the last sort beyond `RESORT_DRIFT`).
    pub(super) grid_fresh: bool,
    /// The density field matches the positions.
    pub(super) density_fresh: bool,
    /// The start-up settle ran ([`Simulation::settle`]).
    pub(super) settled: bool,
    /// The stop request polled inside a step (`solver::interrupt`), if the run set one.
    pub(super) interrupt: Option<super::interrupt::Interrupt>,
    /// The current step stored its start positions (`Backend::store_step_start`, SSP-RK3): the
    /// no-penetration guard can tell from them which side a particle came from.
    pub(super) step_start_stored: bool,
    /// The solids' volumes for the no-penetration guard (`boundary::keep_out`); empty: no guard.
    pub(super) keep_out: Vec<KeepOutBox<D>>,
    /// Prescribed motion of each solid (`None`: fixed), in scene order.
    pub(super) motions: Vec<Option<Motion>>,
    /// The floating solids (`solver::floating`), in scene order; `None`: fixed or prescribed.
    pub(super) floating: Vec<Option<FloatingBody>>,
    /// `x0` of the solid particles by id; empty unless a solid moves.
    pub(super) solid_reference: SolidReference<D>,
    /// Kinematics of each solid at its last placement; empty unless a solid moves.
    pub(super) solid_kinematics: Vec<SolidKinematics<D>>,
    /// Time [s] the moving solids were last placed at, if they were since the fields were set.
    pub(super) solids_placed_at: Option<f64>,
    /// Bound of the moving solids' speed [m/s] (`Motion::max_speed`), a flow speed for the time
    /// step; 0 when nothing moves.
    pub(super) wall_speed: f64,
    /// The smallest rest density of any phase [kg/m³] (`config.rho0` unless
    /// [`Simulation::with_phases`] gave a lighter one): the viscous time-step limit uses the
    /// largest kinematic viscosity `μ/ρ0`.
    pub(super) lightest_rho0: f64,
    /// One fluid phase, or several from [`Simulation::with_phases`] (`StepParams::phases`).
    pub(super) phases: Phases,
    /// Open boundaries (`solver::open`); `None`: the particle count only falls (escapes).
    pub(super) open: Option<super::open::OpenBoundaries<D>>,
}

impl<const D: usize> Simulation<D> {
    /// Builds a simulation from fluid particles (positions [m], velocities [m/s]) and named
    /// solids. Every particle gets the lattice mass (see `physics::lattice::lattice_mass`).
    pub fn new(
        config: SimConfig<D>,
        fluid_position: &[Vector<D>],
        fluid_velocity: &[Vector<D>],
        solids: &[(String, Vec<Vector<D>>)],
    ) -> Result<Self, SetupError> {
        let positive = |key: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(SetupError::Invalid {
                    key,
                    reason: format!("must be positive and finite, got {v}"),
                })
            }
        };
        positive("particles.spacing", config.spacing)?;
        positive("particles.smoothing_length", config.h)?;
        positive("fluid.rho0", config.rho0)?;
        positive("fluid.sound_speed", config.sound_speed)?;
        positive("solver.cfl", config.cfl)?;
        if let Some(st) = config.surface_tension {
            positive("fluid.surface_tension", st.sigma)?;
        }
        if fluid_position.len() != fluid_velocity.len() {
            return Err(SetupError::Invalid {
                key: "fluid_box",
                reason: "positions and velocities differ in length".into(),
            });
        }
        let kernel = Smoothing::<D>::new(config.h as Real)?;
        let mass = lattice_mass(&kernel, config.spacing, config.rho0) as Real;
        let kappa = lattice_gradient_moment(&kernel, config.spacing, config.rho0);
        // The corrected solver sums the kernel whose gradient its correction moves particles
        // along (`physics::density`); wcsph keeps the paper's poly6.
        let density_weight = if config.correction.is_some() {
            DensityWeight::spiky(lattice_spiky_scale(&kernel, config.spacing) as Real)
        } else {
            DensityWeight::POLY6
        };
        let stiffness = correction_stiffness(&kernel, config.spacing, config.rho0, kappa, density_weight);
        let viscosity_scale = if config.pair_terms.get(PairTerm::Viscosity).is_some() {
            (1.0 / lattice_laplacian_moment(&kernel, config.spacing, config.rho0)) as Real
        } else {
            1.0
        };
        let (dx, m) = (config.spacing, f64::from(mass));
        let (surface_tension_gamma, surface_tension_sigma) = match config.surface_tension {
            None => (0.0, 0.0),
            Some(SurfaceTension {
                sigma,
                model: SurfaceTensionModel::Akinci,
            }) => (
                gamma_for_surface_tension(&kernel, dx, config.rho0, m, sigma) as Real,
                0.0,
            ),
            Some(SurfaceTension {
                sigma,
                model: SurfaceTensionModel::SurfaceStress,
            }) => (
                0.0,
                calibrated_stress(&kernel, dx, m, config.rho0, 1.0 / kappa, sigma) as Real,
            ),
        };
        if let Some(c) = &config.correction {
            positive("solver.delta", c.delta)?;
            positive("solver.relaxation", c.relaxation)?;
            if c.max_iterations == 0 {
                return Err(SetupError::Invalid {
                    key: "solver.max_iterations",
                    reason: "must be at least 1".into(),
                });
            }
        }
        let rho0 = config.rho0 as Real;
        let n = fluid_position.len() + solids.iter().map(|(_, xs)| xs.len()).sum::<usize>();
        let mut fields = Fields::with_capacity(n);
        for (x, u) in fluid_position.iter().zip(fluid_velocity) {
            fields.push(*x, *u, mass, rho0, FLUID);
        }
        for (k, (_, xs)) in solids.iter().enumerate() {
            for x in xs {
                fields.push(*x, Vector::zeros(), mass, rho0, k as u32 + 1);
            }
        }
        let plan = plan::plan(config.plan_inputs(!solids.is_empty(), false));
        if plan.contains(&Stage::WallVelocity) {
            // [A12] no-slip walls: the viscous velocity of solids, only where it is used.
            fields.wall_velocity = vec![Vector::zeros(); fields.len()];
        }
        if plan.contains(&Stage::Correction) {
            // What the probes read before the first stage has acted: the carried pressure.
            fields.acting_pressure.clone_from(&fields.pressure);
        }
        Ok(Self {
            fields,
            backend: Box::new(CpuBackend::new()),
            stage_seconds: None,
            velocity_solve_seconds: 0.0,
            fields_stale: false,
            plan,
            solid_names: solids.iter().map(|(n, _)| n.clone()).collect(),
            pressure_gradient_scale: (1.0 / kappa) as Real,
            density_weight,
            viscosity_scale,
            surface_tension_gamma,
            surface_tension_sigma,
            clock: Clock::default(),
            stats: RunStats::default(),
            solid_force: vec![[0.0; 3]; solids.len()],
            solid_moment: vec![[0.0; 3]; solids.len()],
            fluid_count: fluid_position.len(),
            correction_stiffness: stiffness,
            stiffness_per_kappa: stiffness / kappa,
            grid_fresh: false,
            density_fresh: false,
            settled: false,
            interrupt: None,
            step_start_stored: false,
            keep_out: Vec::new(),
            motions: vec![None; solids.len()],
            floating: vec![None; solids.len()],
            solid_reference: SolidReference::default(),
            solid_kinematics: Vec::new(),
            solids_placed_at: None,
            wall_speed: 0.0,
            lightest_rho0: config.rho0,
            phases: Phases::Single,
            open: None,
            config,
        })
    }

    /// Gives the solids their prescribed motions (`motions[k]` for solid `k`, `None`: fixed), as
    /// the scene's `[[solid]] motion` does. Call before the first step. When some solid moves,
    /// the plan gains the `move_solids` stage and the solid particles' current positions become
    /// their reference positions `x0`; when none does, nothing changes (no stage, no cost).
    ///
    /// # Errors
    /// [`SetupError::Invalid`] when `motions` does not have one entry per solid, a motion is not
    /// finite (period ≤ 0, negative ramp, non-finite or missing amplitude), or steps were taken.
    pub fn with_solid_motion(mut self, motions: Vec<Option<Motion>>) -> Result<Self, SetupError> {
        let invalid = |reason: String| SetupError::Invalid {
            key: "solid.motion",
            reason,
        };
        if motions.len() != self.solid_names.len() {
            return Err(invalid(format!(
                "{} motions for {} solids",
                motions.len(),
                self.solid_names.len()
            )));
        }
        if self.clock.step != 0 {
            return Err(invalid("motions must be given before the first step".into()));
        }
        for motion in motions.iter().flatten() {
            let piston_ok = match motion {
                Motion::Sway(_) => true,
                Motion::Piston(p) => [p.wave_height, p.depth, p.gravity]
                    .iter()
                    .all(|v| v.is_finite() && *v > 0.0),
                // `DisplacementSeries::new` checked its samples.
                Motion::Series(s) => s.direction.len() == D && s.direction.iter().all(|n| n.is_finite()),
                Motion::Flap(f) => f.is_valid_in(D),
                Motion::Sea(s) => s.is_valid_in(D),
            };
            let ok = piston_ok
                && motion.sway().is_none_or(|m| {
                    m.period.is_finite()
                        && m.period > 0.0
                        && m.ramp.is_finite()
                        && m.ramp >= 0.0
                        && m.amplitude.len() == D
                        && m.amplitude.iter().all(|a| a.is_finite())
                });
            if !ok {
                return Err(invalid(format!("not a valid motion: {motion:?}")));
            }
        }
        self.wall_speed = motions
            .iter()
            .flatten()
            .map(Motion::max_speed)
            .fold(0.0, f64::max);
        self.motions = motions;
        self.take_solid_reference();
        Ok(self)
    }

    /// Plans `move_solids` and records the solid particles' current positions as their
    /// reference `x0` when a solid moves (a motion or a floating body); otherwise drops both.
    pub(super) fn take_solid_reference(&mut self) {
        let moving = self.motions.iter().any(Option::is_some) || self.floating.iter().any(Option::is_some);
        self.plan = plan::plan(self.config.plan_inputs(!self.solid_names.is_empty(), moving));
        self.solids_placed_at = None;
        if !moving {
            self.solid_reference = SolidReference::default();
            self.solid_kinematics.clear();
            return;
        }
        // Solids are appended after the fluid: ids fluid_count.. in any current order.
        let f = &self.fields;
        let first_id = self.fluid_count as u32;
        let mut position = vec![Vector::zeros(); f.len() - self.fluid_count];
        for i in 0..f.len() {
            if f.kind[i] != FLUID {
                position[(f.id[i] - first_id) as usize] = f.position[i];
            }
        }
        self.solid_reference = SolidReference { first_id, position };
        self.solid_kinematics = vec![SolidKinematics::rest(); self.solid_names.len()];
    }

    /// Gives each fluid particle (in the order given to [`Simulation::new`]) the rest density
    /// `rest_density[k]` [kg/m³] of its phase: the `multiphase` effect (`physics::multiphase`).
    /// Each phase gets the lattice mass of its own `ρ0` (`physics::lattice::lattice_mass`), so it
    /// starts at its rest density; solids keep the scene's `ρ0` and mass. Allocates
    /// `Fields::rest_density` and sets the run's [`Phases::Multi`], on which the backends run the
    /// multiphase variants of density, equation of state, forces, wall pressure, correction and
    /// state extremes. Call
    /// before the first step. All phases share the sound speed `C` (see `physics::multiphase`).
    ///
    /// # Errors
    /// [`SetupError::Invalid`] when the count differs from the fluid particles', a density is not
    /// finite and positive, steps were taken, or a device backend already holds the fields.
    pub fn with_phases(mut self, rest_density: &[f64]) -> Result<Self, SetupError> {
        let invalid = |reason: String| SetupError::Invalid {
            key: "fluid_box.rho0",
            reason,
        };
        if rest_density.len() != self.fluid_count {
            return Err(invalid(format!(
                "{} rest densities for {} fluid particles",
                rest_density.len(),
                self.fluid_count
            )));
        }
        if self.clock.step != 0 || self.settled {
            return Err(invalid("phases must be given before the first step".into()));
        }
        if self.backend.holds_state() {
            // A device backend took its copy of the fields without the rest densities.
            return Err(invalid("phases must be given before `use_backend`".into()));
        }
        if let Some(bad) = rest_density.iter().find(|r| !(r.is_finite() && **r > 0.0)) {
            return Err(invalid(format!("must be positive and finite, got {bad}")));
        }
        let kernel = Smoothing::<D>::new(self.config.h as Real)?;
        let mut masses: Vec<(f64, Real)> = Vec::new();
        let f = &mut self.fields;
        f.rest_density = vec![self.config.rho0 as Real; f.len()];
        for i in 0..f.len() {
            if f.kind[i] != FLUID {
                continue;
            }
            // Before the first step particle i has id i (`Fields::push`).
            let rho0 = rest_density[f.id[i] as usize];
            let mass = match masses.iter().find(|(r, _)| *r == rho0) {
                Some(&(_, m)) => m,
                None => {
                    let m = lattice_mass(&kernel, self.config.spacing, rho0) as Real;
                    masses.push((rho0, m));
                    m
                }
            };
            f.mass[i] = mass;
            f.density[i] = rho0 as Real;
            f.rest_density[i] = rho0 as Real;
        }
        self.lightest_rho0 = rest_density.iter().fold(self.config.rho0, |a, &b| a.min(b));
        self.phases = Phases::Multi;
        self.fields_stale = false;
        self.grid_fresh = false;
        self.density_fresh = false;
        Ok(self)
    }

    /// Whether the fluid has phases of their own rest densities (`Simulation::with_phases`).
    pub fn multiphase(&self) -> bool {
        self.phases == Phases::Multi
    }

    /// The prescribed motion of each solid (`None`: fixed), in scene order.
    pub fn solid_motions(&self) -> &[Option<Motion>] {
        &self.motions
    }

    /// The reference positions `x0` of the solid particles, by id (empty unless a solid moves).
    pub fn solid_reference(&self) -> &SolidReference<D> {
        &self.solid_reference
    }

    /// Displacement `d`, velocity `d'` and acceleration `d''` of each solid (scene order) at the
    /// time it was last placed (`Stage::MoveSolids`; [`Simulation::solids_placed_at`]); empty
    /// unless a solid moves. A fixed solid in a scene with moving ones has zero kinematics.
    pub fn solid_kinematics(&self) -> &[SolidKinematics<D>] {
        &self.solid_kinematics
    }

    /// The time [s] the moving solids were last placed at (`None` before the first placement and
    /// after a restore, or when nothing moves).
    pub fn solids_placed_at(&self) -> Option<f64> {
        self.solids_placed_at
    }

    /// Places every moving solid at time `time` [s] (stage `move_solids`): kinematics from the
    /// motions, then the backend moves the particles. Returns whether anything was done (not
    /// when the solids already stand at `time`).
    pub(super) fn place_solids(&mut self, time: f64) -> bool {
        if self.solids_placed_at == Some(time) {
            return false;
        }
        for (k, (m, b)) in self.motions.iter().zip(&self.floating).enumerate() {
            self.solid_kinematics[k] = match (m, b) {
                (_, Some(b)) => b.kinematics::<D>(),
                (Some(m), None) => m.kinematics::<D>(time),
                (None, None) => SolidKinematics::rest(),
            };
        }
        self.backend
            .move_solids(&mut self.fields, &self.solid_reference, &self.solid_kinematics);
        self.solids_placed_at = Some(time);
        true
    }

    /// The plan each step walks.
    pub fn plan(&self) -> &[Stage] {
        &self.plan
    }

    /// [AAT13]'s `γ` the run uses for the scene's `σ` (`physics::surface_tension`); 0 without
    /// surface tension.
    pub fn surface_tension_gamma(&self) -> Real {
        self.surface_tension_gamma
    }

    /// The surface stress's `σ'` the run uses for the scene's `σ` (`physics::surface_stress`); 0
    /// unless the scene's surface-tension model is `surface_stress`.
    pub fn surface_stress_sigma(&self) -> Real {
        self.surface_tension_sigma
    }

    /// The settings of the run.
    pub fn config(&self) -> &SimConfig<D> {
        &self.config
    }

    /// Simulated time and step count.
    pub fn clock(&self) -> Clock {
        self.clock
    }

    /// Density-error statistics so far.
    pub fn stats(&self) -> RunStats {
        self.stats
    }

    /// Names of the solids, in scene order (solid `k` has `kind == k + 1`).
    pub fn solid_names(&self) -> &[String] {
        &self.solid_names
    }

    /// Force of the fluid on each solid during the last step [N] (per unit depth in 2D).
    pub fn solid_forces(&self) -> &[[f64; 3]] {
        &self.solid_force
    }

    /// Moment about the origin of the fluid's force on each solid during the last step [N m]
    /// (2D: [N m/m], the out-of-plane moment in the z slot): `Σ_s x_s × f_s` over the solid's
    /// particles (`backend::SolidLoad`). About a point `P`:
    /// `boundary::solid_force::moment_about`.
    pub fn solid_moments(&self) -> &[[f64; 3]] {
        &self.solid_moment
    }

    /// Number of fluid particles.
    pub fn fluid_count(&self) -> usize {
        self.fluid_count
    }

    /// Gives the solids' volumes to the no-penetration guard (`boundary::keep_out`), which then
    /// runs after every move; each box's `solid` indexes the solids given to [`Simulation::new`].
    /// Without it (the default) only the particle boundary keeps fluid out of solids.
    ///
    /// # Errors
    /// [`SetupError::Invalid`] when a box names a solid that does not exist or is not a box.
    pub fn set_keep_out(&mut self, boxes: Vec<KeepOutBox<D>>) -> Result<(), SetupError> {
        for b in &boxes {
            let finite = b
                .min
                .iter()
                .chain(b.max.iter())
                .chain(b.velocity.iter())
                .all(|c| c.is_finite());
            if b.solid as usize >= self.solid_names.len() || !finite || (0..D).any(|k| b.min[k] > b.max[k]) {
                return Err(SetupError::Invalid {
                    key: "solid",
                    reason: format!(
                        "a solid volume {b:?} is not a finite box of one of the {} solids",
                        self.solid_names.len()
                    ),
                });
            }
        }
        self.keep_out = boxes;
        Ok(())
    }

    /// Parameters for the stages at the current time.
    pub fn step_params(&self) -> StepParams<D> {
        self.params_at(self.clock.time)
    }

    /// Parameters for the stages at time `time` [s] (gravity is ramped in time).
    pub fn params_at(&self, time: f64) -> StepParams<D> {
        let c = &self.config;
        let g = c
            .gravity
            .map(|g| gravity_at(&g, time, c.gravity_ramp))
            .unwrap_or_else(Vector::zeros);
        StepParams {
            h: c.h as Real,
            rho0: c.rho0 as Real,
            c2: (c.sound_speed * c.sound_speed) as Real,
            pair: c.pair_terms.coefficients(),
            c: c.sound_speed as Real,
            pressure_gradient_scale: self.pressure_gradient_scale,
            gravity: g,
            domain_min: c.domain_min,
            domain_max: c.domain_max,
            angular_velocity: c.angular_velocity.map_or([0.0; 3], |w| w.map(|x| x as Real)),
            rotation_centre: if c.angular_velocity.is_some() {
                c.rotation_centre
            } else {
                Vector::zeros()
            },
            viscosity_scale: self.viscosity_scale,
            surface_tension_gamma: self.surface_tension_gamma,
            surface_tension_sigma: self.surface_tension_sigma,
            spacing: c.spacing as Real,
            density_spiky_scale: self.density_weight.spiky_scale,
            density_kernel: self.density_weight.kernel,
            surface_tension_model: c
                .surface_tension
                .as_ref()
                .map_or(SurfaceTensionModel::default(), |t| t.model),
            rotating_frame: u32::from(c.angular_velocity.is_some()),
            phases: self.phases,
            density_diffusion: c.density_diffusion.unwrap_or(0.0) as Real,
            artificial_viscosity_wall_factor: c.artificial_viscosity_wall_factor as Real,
            periodic: c.periodic,
        }
    }

    /// `1/λ`, the scale of the viscous force (17) on this scene's lattice
    /// (`physics::lattice::lattice_laplacian_moment`); 1 without viscosity.
    pub fn viscosity_scale(&self) -> Real {
        self.viscosity_scale
    }

    /// Total fluid mass [kg] (per unit depth in 2D), summed in f64.
    pub fn fluid_mass(&self) -> f64 {
        let f = &self.fields;
        sum_in_order(f.len(), |i| {
            [if f.kind[i] == FLUID {
                f64::from(f.mass[i])
            } else {
                0.0
            }]
        })[0]
    }

    /// Total fluid momentum [kg m/s] (per unit depth in 2D), summed in f64.
    pub fn fluid_momentum(&self) -> [f64; 3] {
        let f = &self.fields;
        sum_in_order(f.len(), |i| {
            if f.kind[i] != FLUID {
                return [0.0; 3];
            }
            let m = f64::from(f.mass[i]);
            let u = crate::math::to_xyz(&f.velocity[i]);
            [m * u[0], m * u[1], m * u[2]]
        })
    }
}
