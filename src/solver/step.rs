//! The step driver, the only one: walks the plan once per integrator stage and calls the
//! backend, stage by stage, in the order of the paper's algorithm (sections 1 and 2).
//!
//! Decisions for the `corrected` solver (PAPER.md notes 5–8, docs/method.md, "The position correction"):
//! - Integrator: SSP-RK3 in Shu–Osher form; the correction (23)–(24) runs after every stage, on
//!   the stage's state, which lies at `t^n + τ` with `τ = dt, dt/2, dt`.
//! - Eq. (23) with `dt → τ`, and the velocity follows the move as in a pressure projection:
//!   `Δu = Δx/τ` (note 7). The pair terms of (16) are antisymmetric, so the fluid's momentum
//!   changes only by the walls' share; that share is reported as force on the solids.
//! - Pressure: the correction's pressure `P` is carried from stage to stage and drives the force
//!   stage (incremental pressure correction); eq. (19) with the scene's `C` is not used, so a real
//!   `C = 1500 m/s` adds no stiffness (note 5) and the time step follows the flow speed.
//! - Step scale: `δp = ω K/τ² (ρ − ρ0)` (`physics::lattice::correction_stiffness`), the same
//!   displacement for any `τ`; each sweep's displacements are scaled down together when the
//!   largest exceeds `MAX_SWEEP_STEP · dx`.
//! - Neighbours: the grid is rebuilt inside the loop once the summed largest displacement since
//!   the last sort exceeds `RESORT_DRIFT · h`, so a pair within `h` can only be missed when the
//!   kernels there are below `(4 · RESORT_DRIFT)³ ≈ 1e-5` of their peak.

use super::floating;
use super::stage::{SolidsAt, Stage};
use super::timestep::TimeStepLimit;
use super::{Correction, Integrator, Simulation, StepError, StepReport};
use crate::backend::{SolidForceSource, SolidLoad, StateExtremes};
use crate::boundary::keep_out::{KeepOutBox, KeepOutReport};
use crate::model::params::StepParams;

/// Largest displacement of one correction sweep, in units of the particle spacing.
pub const MAX_SWEEP_STEP: f64 = 0.1;

/// Distance outside a solid's face, in units of the spacing, where the no-penetration guard
/// puts a particle it finds inside (`boundary::keep_out`): on the face itself f32 rounding
/// could leave it inside.
pub const KEEP_OUT_MARGIN: f64 = 1e-3;

/// `τ` [s] of the start-up settle. Any value gives the same sweeps: the stiffness scales with
/// `1/τ²` and the displacement with `τ²` (`physics::lattice::correction_stiffness`).
pub const SETTLE_TAU: f64 = 1.0;

/// Most sweeps of one velocity solve (`Simulation::solve_velocities`), or the run's
/// `max_iterations` if lower. Why: where fluid hits a wall the solve converges slowly (a block
/// thrown at 1 m/s against a wall, dx = 10 mm, dt = 2 ms: 192 of 690 solves were still above
/// δ after 200 sweeps, at 1e-3 to 4e-3 from 2e-2 to 4e-2); it is given up there, and the
/// position correction of the next stage still holds the density.
pub const VELOCITY_SOLVE_CAP: u32 = 200;

/// The velocity solve's tolerance with SSP-RK3, in units of `δ`: it stops when its residual is
/// below `VELOCITY_TOLERANCE · δ` (or, at the cap, keeps a result below `δ`). Why tighter than the
/// positions: a divergence left in the velocities compresses the fluid over the next stage,
/// which the position loop then removes with pushes that reach the walls. Measured on
/// `scenes/hard/rest_2d.toml` (corrected, δ = 1e-4), the floor force's standard deviation over
/// 1.5–2 s: 160 N/m at 1, 16 at 0.2, 4.9 at 0.1, 0.3 at 0.05 (hydrostatic 1,160 N/m), with the
/// position sweeps per stage falling from 8 to 1.1; on the 2D dam break the solve takes 15, 29
/// and 35 iterations at 1, 0.1 and 0.05. docs/method.md, "The velocity solve".
pub const VELOCITY_TOLERANCE: f64 = 0.05;

/// The velocity solve's tolerance with symplectic Euler, in units of `δ`. Why tighter than with
/// SSP-RK3: one solve per step instead of three, and the divergence it leaves compresses the
/// fluid over a whole step, so the position loop pushes about every `1/tolerance` steps and the
/// column rings at that period. Measured on `scenes/hard/rest_2d.toml` (corrected, δ = 1e-4, the
/// same statistic as [`VELOCITY_TOLERANCE`]): 5.8 N/m at 0.05, 3.2 at 0.03, 1.5 at 0.02, 0.35 at
/// 0.01 (`tests/hard_cases/standing_wave.rs` holds 2 N/m for both integrators).
pub const VELOCITY_TOLERANCE_SYMPLECTIC_EULER: f64 = 0.01;

/// The velocity solve's tolerance in units of `δ` for `integrator`.
pub fn velocity_tolerance(integrator: Integrator) -> f64 {
    match integrator {
        Integrator::Rk3 => VELOCITY_TOLERANCE,
        Integrator::SymplecticEuler => VELOCITY_TOLERANCE_SYMPLECTIC_EULER,
    }
}

/// Summed displacement since the last sort, in units of `h`, that triggers a re-sort.
pub const RESORT_DRIFT: f64 = 0.005;

// Two particles drift apart by at most `2 RESORT_DRIFT h` between sorts; the grid's candidate
// lists cover `CANDIDATE_SKIN h` (`crate::grid`), so every pair within `h` is listed.
const _: () = assert!(2.0 * RESORT_DRIFT <= crate::grid::CANDIDATE_SKIN as f64);

impl<const D: usize> Simulation<D> {
    /// Advances the simulation by one step, ending no later than `end_time` [s].
    pub fn step(&mut self, end_time: f64) -> Result<StepReport, StepError> {
        let step = self.clock.step;
        let time = self.clock.time;
        let integrator = self.config.integrator;
        let mut report = StepReport {
            dt: 0.0,
            limit: TimeStepLimit::Fixed,
            extremes: StateExtremes::default(),
            removed: 0,
            created: 0,
            outflow: 0,
        };
        // Open boundaries: buffer particles set, created and removed (`solver::open`).
        let open = self.update_open_boundaries()?;
        let solids = self.solid_names.len();
        // Until this step stores its start (SSP-RK3), the guard has no start to go by.
        self.step_start_stored = false;
        self.settle()?;
        self.begin_body_step();
        let mut solid_force = vec![[0.0f64; 6]; solids];
        // Force and moment (`SolidLoad`), or a force alone (the guard's impulse: its first three).
        let add_force = |total: &mut Vec<SolidLoad>, part: &[[f64; 6]], weight: f64| {
            for (t, p) in total.iter_mut().zip(part) {
                for k in 0..6 {
                    t[k] += weight * p[k];
                }
            }
        };
        for (k, &(a, b, tau_frac, t_frac)) in integrator.stages().iter().enumerate() {
            let mut params = self.params_at(time + t_frac * report.dt);
            for s in 0..self.plan.len() {
                let stage = self.plan[s];
                let started = self.stage_seconds.is_some().then(std::time::Instant::now);
                let (bk, f) = (&mut self.backend, &mut self.fields);
                match stage {
                    Stage::MoveSolids(at) => {
                        // boundary::motion: x0 + d(t), d'(t) at the stage's start or result.
                        let t = match at {
                            SolidsAt::StageStart => time + t_frac * report.dt,
                            SolidsAt::StageResult => time + tau_frac * report.dt,
                        };
                        if self.place_solids(t) {
                            self.moved();
                        }
                    }
                    Stage::SortByCell => {
                        if !self.grid_fresh {
                            bk.sort_by_cell(f, &params)
                                .map_err(|source| StepError::Grid { step, source })?; // section 3
                            self.grid_fresh = true;
                        }
                    }
                    Stage::Density => {
                        if !self.density_fresh {
                            bk.density(f, &params); // eq. (18)
                            self.density_fresh = true;
                        }
                    }
                    Stage::DensityRate => bk.density_rate(f, &params), // continuity, [F19]
                    Stage::EquationOfState => bk.equation_of_state(f, &params), // eq. (19)
                    Stage::WallPressure(model) => {
                        bk.wall_pressure(f, &params, model, &self.solid_kinematics); // [A12] eq. (27)
                    }
                    Stage::WallVelocity => bk.wall_velocity(f, &params), // [A12] eqs. (22)-(23)
                    Stage::GradientMoment => {
                        // physics::gradient_moment: the rest of the stage divides by it; without
                        // a fully supported particle the last one holds.
                        if let Some(kappa) = bk.gradient_moment(f, &params).kappa() {
                            self.pressure_gradient_scale = (1.0 / kappa) as crate::math::Real;
                            params.pressure_gradient_scale = self.pressure_gradient_scale;
                            self.correction_stiffness = self.stiffness_per_kappa * kappa;
                        }
                    }
                    Stage::Forces(terms) => bk.forces(f, &params, terms), // eqs. (15)-(17), (6)
                    // The plan's model is the one the backends evaluate.
                    Stage::SurfaceNormals(model) => {
                        let params = StepParams {
                            surface_tension_model: model,
                            ..params
                        };
                        bk.surface_normals(f, &params) // [AAT13] eq. (3)
                    }
                    Stage::SurfaceTension(model) => {
                        let params = StepParams {
                            surface_tension_model: model,
                            ..params
                        };
                        bk.surface_tension(f, &params) // surface stress or [AAT13]
                    }
                    Stage::SolidForces(terms) => {
                        let source = SolidForceSource::Forces(terms);
                        let part = bk.solid_forces(f, &params, solids, source); // Fig. 4
                        add_force(&mut solid_force, &part, integrator.force_weights()[k]);
                        floating::record_stage_load(&mut self.floating, &part);
                    }
                    Stage::TimeStep => {
                        if k == 0 {
                            report = self.choose_time_step(&params, end_time)?;
                            report.created = open.created;
                            report.outflow = open.removed;
                        }
                    }
                    Stage::Integrate | Stage::RkStage => {
                        if stage == Stage::Integrate {
                            bk.integrate(f, report.dt as f32); // eq. (15), symplectic Euler
                        } else {
                            if k == 0 {
                                bk.store_step_start(f);
                                self.step_start_stored = true;
                            }
                            bk.rk_stage(f, report.dt as f32, a, b); // PAPER.md note 8
                        }
                        self.moved();
                        // The guard's momentum change, weighted as the stage's own changes.
                        let guard = self.keep_out();
                        let weight = -integrator.correction_weights()[k] / report.dt.max(f64::MIN_POSITIVE);
                        add_guard_force(&mut solid_force, &guard, weight);
                        // Floating bodies take the same stage (`solver::floating`).
                        self.advance_bodies(k, report.dt, &params.gravity);
                    }
                    Stage::IntegrateDensity => match integrator {
                        // The last step's motion (`solver::plan`): rho^n = rho^(n-1) + dt R(x^n, u^n).
                        Integrator::SymplecticEuler => bk.integrate_density(f, self.clock.last_dt as f32),
                        Integrator::Rk3 => {
                            if k == 0 {
                                bk.store_density_start(f);
                            }
                            bk.rk_density_stage(f, report.dt as f32, a, b); // note 8
                        }
                    },
                    Stage::Correction => {
                        let tau = tau_frac * report.dt;
                        let impulse_force = self.correct(k, tau, tau, &params)?;
                        self.kick_bodies(&impulse_force, tau);
                        // Impulse τ F, weighted by how much of this stage reaches y^{n+1}.
                        let w = integrator.correction_weights()[k] * tau / report.dt.max(f64::MIN_POSITIVE);
                        add_force(&mut solid_force, &impulse_force, w);
                    }
                    Stage::WrapPositions(_) => {
                        // Once a step, after every stage that moved particles (`crate::periodic`).
                        if k + 1 == integrator.stages().len() {
                            bk.wrap_positions(f, &params);
                            self.moved();
                        }
                    }
                    Stage::DampingZone => {
                        // Once a step, on u^{n+1} ([AEA17]); the plan has it only with a zone.
                        if let (true, Some(zone)) =
                            (k + 1 == integrator.stages().len(), &self.config.damping_zone)
                        {
                            bk.damping_zone(f, zone, report.dt as f32);
                        }
                    }
                }
                if let Some(t0) = started {
                    self.backend.synchronize();
                    // The correction stage's velocity solve is timed on its own
                    // (`velocity_solve`), so that `correct_positions` holds the position sweeps.
                    let velocity = std::mem::take(&mut self.velocity_solve_seconds);
                    let elapsed = t0.elapsed().as_secs_f64() - velocity;
                    if let Some(times) = self.stage_seconds.as_mut() {
                        for (name, seconds) in [(stage.name(), elapsed), ("velocity_solve", velocity)] {
                            if name == "velocity_solve" && seconds == 0.0 {
                                continue;
                            }
                            match times.iter_mut().find(|(n, _)| *n == name) {
                                Some((_, total)) => *total += seconds,
                                None => times.push((name, seconds)),
                            }
                        }
                    }
                }
            }
        }
        self.fields_stale = self.backend.holds_state();
        if let Some(source) = self.backend.take_error() {
            return Err(StepError::Backend { step, source });
        }
        if solids > 0 {
            self.solid_force = solid_force.iter().map(|l| [l[0], l[1], l[2]]).collect();
            self.solid_moment = solid_force.iter().map(|l| [l[3], l[4], l[5]]).collect();
        }
        let e = &report.extremes;
        let s = &mut self.stats;
        s.max_compression = s.max_compression.max(e.max_compression);
        s.sum_mean_compression += e.mean_compression;
        s.max_surface_deficit = s.max_surface_deficit.max(e.max_surface_deficit);
        s.sum_mean_surface_deficit += e.mean_surface_deficit;
        self.clock.time += report.dt;
        self.clock.last_dt = report.dt;
        self.clock.step += 1;
        // Every step starts from a fresh sort and density, so a step depends only on the fields
        // and a restart from a checkpoint is bit-identical (`solver::checkpoint`). The
        // `corrected` solver pays one sort and one density pass per step for it (of ~200 sweeps).
        self.moved();
        Ok(report)
    }

    /// The `corrected` solver's start-up settle, run by the first [`Simulation::step`] if not
    /// called before (a no-op for `wcsph` and once done): the correction (23)–(24) removes the
    /// initial compression (a lattice cut by walls, a jittered or compressed start) by moving
    /// particles without giving them velocity. Why: corrected inside the first stage, the same
    /// overlap becomes velocity `Δx/τ` (note 7); measured, a block jittered by 0.3 dx (12%
    /// compression) left its first step at 20 m/s instead of 0.5 m/s and drove particles into
    /// the walls. Counted in the correction statistics as one stage.
    pub fn settle(&mut self) -> Result<(), StepError> {
        if self.settled || self.config.correction.is_none() {
            return Ok(());
        }
        let params = self.params_at(self.clock.time);
        self.correct(0, SETTLE_TAU, f64::INFINITY, &params)?;
        self.settled = true;
        self.fields_stale = self.backend.holds_state();
        Ok(())
    }

    /// The no-penetration guard after a move (`boundary::keep_out`): each solid's momentum
    /// change of the fluid [kg m/s] and the pushes, which it also counts.
    fn keep_out(&mut self) -> KeepOutReport {
        let solids = self.solid_names.len();
        if self.keep_out.is_empty() {
            return KeepOutReport::none(solids);
        }
        let margin = (KEEP_OUT_MARGIN * self.config.spacing) as f32;
        // Moving solids: their volumes where the solids were last placed, at their velocity.
        let moved: Vec<KeepOutBox<D>>;
        let boxes = if self.solid_kinematics.is_empty() {
            &self.keep_out
        } else {
            moved = self
                .keep_out
                .iter()
                .map(|b| {
                    let k = &self.solid_kinematics[b.solid as usize];
                    KeepOutBox {
                        min: b.min + k.displacement,
                        max: b.max + k.displacement,
                        velocity: k.velocity,
                        solid: b.solid,
                    }
                })
                .collect();
            &moved
        };
        let report = self
            .backend
            .keep_out(&mut self.fields, boxes, solids, margin, self.step_start_stored);
        self.stats.keep_out_pushes += report.pushes;
        report
    }

    /// [`StepError::NonFinite`] for the first particle with a non-finite field
    /// (`Backend::state_extremes`), if any.
    fn non_finite_error(&mut self, params: &StepParams<D>) -> Result<Option<StepError>, StepError> {
        let (step, time) = (self.clock.step, self.clock.time);
        let Some((i, quantity)) = self.backend.state_extremes(&self.fields, params).non_finite else {
            return Ok(None);
        };
        // Name the particle from the backend's own state (device order for CUDA).
        self.fields_stale = self.backend.holds_state();
        self.sync_fields()
            .map_err(|source| StepError::Backend { step, source })?;
        Ok(Some(StepError::NonFinite {
            step,
            time,
            particle: self.fields.id[i],
            quantity,
        }))
    }

    /// Positions changed: the grid and the density are stale.
    fn moved(&mut self) {
        self.grid_fresh = false;
        self.density_fresh = false;
    }

    /// The velocity solve after a stage's position correction: at fixed positions, the pressure
    /// `P ≥ 0` whose force makes the density `ρ* = base + τ dρ/dt` the velocities would give `τ`
    /// later meet the residual of (24) (`base`: ρ0 inside the fluid, the particle's own density
    /// (18) at the free surface, `physics::density::velocity_solve_base`), with
    /// `u = u_start + τ a^press(P − P_start)` (a divergence-free projection, as DFSPH's). Each
    /// iteration is a projected Jacobi sweep `max(P + k (ρ* − ρ0), 0)` mixed with the last
    /// iterates by Anderson acceleration (`solver::anderson`), until the residual is below
    /// [`velocity_tolerance`]` · δ`; with `Correction::warm_start`, started from the increments
    /// `P − P_start` that stage `slot`'s solve of the last step ended with
    /// (`Backend::warm_start_velocity_solve`). The pressure keeps only what the solve released. Given up, with
    /// velocity and pressure restored, when the residual doubles, or at `VELOCITY_SOLVE_CAP`
    /// iterations above `δ`. Adds the walls' share to `solid_force` [N], as the position sweeps
    /// do. docs/method.md, "The velocity solve", says why each choice.
    #[allow(clippy::too_many_arguments)]
    fn solve_velocities(
        &mut self,
        slot: usize,
        tau: f64,
        params: &StepParams<D>,
        stiffness: f32,
        delta: f64,
        max_iterations: u32,
        drift: &mut f64,
        solid_force: &mut [SolidLoad],
    ) -> Result<(), StepError> {
        let h = f64::from(params.h);
        let solids = self.solid_names.len();
        let (bk, f) = (&mut self.backend, &mut self.fields);
        if *drift > RESORT_DRIFT * h {
            bk.sort_by_cell(f, params).map_err(|source| StepError::Grid {
                step: self.clock.step,
                source,
            })?;
            *drift = 0.0;
        }
        bk.begin_velocity_solve(f, params);
        let warm = self.config.correction.is_some_and(|c| c.warm_start);
        if warm {
            // The same stage's solve of the last step: its increments are most of this one's.
            bk.warm_start_velocity_solve(f, slot);
            bk.velocity_from_pressure(f, params, tau as f32);
        }
        let cap = VELOCITY_SOLVE_CAP.min(max_iterations);
        let tolerance = velocity_tolerance(self.config.integrator) * delta;
        let mut first = None;
        let mut iterations = 0u32;
        let (interrupt, step) = (&mut self.interrupt, self.clock.step);
        let time = self.clock.time;
        let keep = loop {
            super::interrupt::due(interrupt, step, time)?;
            bk.predicted_density(f, params, tau as f32);
            let residual = bk.correction_error(f, params).residual;
            let start = *first.get_or_insert(residual);
            if residual < tolerance {
                break true;
            }
            if !residual.is_finite() || residual > 2.0 * start {
                break false;
            }
            if iterations >= cap {
                break residual < delta;
            }
            bk.mix_velocity_pressure(f, params, stiffness);
            bk.velocity_from_pressure(f, params, tau as f32);
            iterations += 1;
        };
        if warm {
            bk.record_velocity_solve(f, slot, keep);
        }
        bk.end_velocity_solve(f, keep);
        // The solve's push on the solids from its total increments (the map is linear in them),
        // with the sum (18) back in `density`.
        // The increments are the warm start's where no iteration ran.
        if keep && solids > 0 && (iterations > 0 || warm) {
            let part = bk.solid_forces(f, params, solids, SolidForceSource::Correction);
            for (total, p) in solid_force.iter_mut().zip(&part) {
                for c in 0..6 {
                    total[c] += p[c];
                }
            }
        }
        let s = &mut self.stats.correction;
        s.velocity_solves += 1;
        s.velocity_iterations += u64::from(iterations);
        s.velocity_solves_given_up += u64::from(!keep);
        Ok(())
    }

    /// Eqs. (23)–(24) for integrator stage `stage` (0-based), whose state lies `tau` [s] after
    /// the step's start: density, pressure increments, displacement, until the residual
    /// (compression, and the expansion of particles that carry pressure) is below `δ` or the cap
    /// is hit. Velocities change by `Δx / kick_tau` (`kick_tau = tau` in a stage, infinite for
    /// the start-up settle). Returns the correction's force on each solid over the stage [N].
    fn correct(
        &mut self,
        stage: usize,
        tau: f64,
        kick_tau: f64,
        params: &StepParams<D>,
    ) -> Result<Vec<SolidLoad>, StepError> {
        let Correction {
            delta,
            max_iterations,
            strict,
            relaxation,
            ..
        } = self.config.correction.unwrap_or_default();
        let h = f64::from(params.h);
        let max_step = (MAX_SWEEP_STEP * self.config.spacing) as f32;
        let stiffness = (relaxation * self.correction_stiffness / (tau * tau)) as f32;
        self.backend.begin_correction(&mut self.fields);
        let solids = self.solid_names.len();
        // The sweeps' pushes on the solids, each at the positions it starts from: the exact
        // counterpart of the fluid's momentum change (every pair term is antisymmetric).
        let mut solid_force = vec![[0.0f64; 6]; solids];
        let mut drift = if self.grid_fresh { 0.0 } else { f64::INFINITY };
        let mut iterations = 0u32;
        let error = loop {
            self.check_interrupt()?;
            let (bk, f) = (&mut self.backend, &mut self.fields);
            if drift > RESORT_DRIFT * h {
                bk.sort_by_cell(f, params).map_err(|source| StepError::Grid {
                    step: self.clock.step,
                    source,
                })?;
                drift = 0.0;
            }
            bk.density(f, params); // eq. (18)
            let error = bk.correction_error(f, params); // eq. (24), note 6
            if error.residual < delta || iterations >= max_iterations || !error.residual.is_finite() {
                break error;
            }
            bk.correction_pressure(f, params, stiffness); // eq. (19), note 5
            let part = if solids > 0 {
                bk.solid_forces(f, params, solids, SolidForceSource::Correction)
            } else {
                Vec::new()
            };
            let sweep = bk.correct_positions(f, params, tau as f32, kick_tau as f32, max_step); // eq. (23)
            for (total, p) in solid_force.iter_mut().zip(&part) {
                for c in 0..6 {
                    total[c] += sweep.scale * p[c];
                }
            }
            drift += sweep.largest;
            iterations += 1;
            // The guard's momentum change as a force over the stage (the caller multiplies by τ);
            // a particle it moved may have left its cell, so the grid is rebuilt.
            let guard = self.keep_out();
            if guard.pushes > 0 {
                drift = f64::INFINITY;
            }
            add_guard_force(&mut solid_force, &guard, -1.0 / tau);
        };
        // The velocity solve, only after a stage whose positions converged (the start-up settle
        // gives no velocity).
        if kick_tau.is_finite() && error.residual < delta {
            let started = self.stage_seconds.is_some().then(std::time::Instant::now);
            self.solve_velocities(
                stage,
                tau,
                params,
                stiffness,
                delta,
                max_iterations,
                &mut drift,
                &mut solid_force,
            )?;
            if let Some(t0) = started {
                self.backend.synchronize();
                self.velocity_solve_seconds += t0.elapsed().as_secs_f64();
            }
        } else {
            self.backend.record_acting_pressure(&mut self.fields);
        }
        self.grid_fresh = drift <= RESORT_DRIFT * h;
        self.density_fresh = true;
        let s = &mut self.stats.correction;
        s.stages += 1;
        s.iterations += u64::from(iterations);
        s.max_iterations = s.max_iterations.max(iterations);
        s.last_iterations = iterations;
        s.max_compression_after = s.max_compression_after.max(error.compression);
        s.max_residual_after = s.max_residual_after.max(error.residual);
        if error.residual < delta {
            return Ok(solid_force);
        }
        s.unconverged_stages += 1;
        let residual = error.residual;
        if residual.is_nan() {
            // A state that is not a number (`physics::correction::residual`): name the particle,
            // as the state guards would.
            if let Some(e) = self.non_finite_error(params)? {
                return Err(e);
            }
        }
        if strict || !residual.is_finite() {
            return Err(StepError::Unconverged {
                step: self.clock.step,
                time: self.clock.time,
                stage: stage + 1,
                iterations,
                residual,
                delta,
            });
        }
        Ok(solid_force)
    }
}

/// Adds `weight` times the no-penetration guard's impulse on each solid [N s]
/// (`boundary::keep_out`) to the force slots of `total`, and its angular impulse about the
/// origin (at the pushed particles) to the moment slots.
fn add_guard_force(total: &mut [SolidLoad], guard: &KeepOutReport, weight: f64) {
    for ((t, j), l) in total.iter_mut().zip(&guard.impulse).zip(&guard.angular_impulse) {
        for c in 0..3 {
            t[c] += weight * j[c];
            t[3 + c] += weight * l[c];
        }
    }
}
