//! Backends: the memory and the loops. One method per stage of the solver's plan
//! (`solver::stage::Stage`); the driver (`solver::step`) walks the plan and calls them, so the
//! CPU and CUDA backends cannot diverge in the order of stages.

/// Velocity-solve guesses a backend keeps (`Backend::record_velocity_solve`): one per
/// integrator stage (SSP-RK3 has three).
pub const VELOCITY_SOLVE_SLOTS: usize = 3;

/// One particle's velocity-solve records (`Backend::record_velocity_solve`): per slot the
/// increment `P − P_start` [Pa] that the slot's last solve recorded, `None` where it recorded
/// none for the particle. A checkpoint keeps them (`solver::checkpoint`).
pub type SolveRecord = [Option<crate::math::Real>; VELOCITY_SOLVE_SLOTS];

pub mod cpu;
pub mod partition;
/// The step's parameters, at their home `model::params` (re-exported for the backends' users).
pub use crate::model::params;
pub use crate::model::{ForceTerms, SurfaceTensionModel, WallModel};

use crate::boundary::keep_out::{KeepOutBox, KeepOutReport};
use crate::boundary::motion::{SolidKinematics, SolidReference};
use crate::fields::{Field, Fields};
use crate::grid::GridError;
use crate::model::pair_terms::PairTerms;
use crate::physics::damping_zone::DampingZone;
pub use crate::physics::gradient_moment::MomentSums;
use params::StepParams;
use partition::Partition;

/// What `Backend::solid_forces` gives per solid: the fluid's force `F = Σ_s f_s` [N] (slots
/// 0–2, z = 0 in 2D) and its moment about the origin `M_O = Σ_s x_s × f_s` [N m] (slots 3–5),
/// summed over the solid's particles `s` at positions `x_s`. In 2D (per metre of depth, [N/m] and
/// [N m/m]) only the out-of-plane moment `x f_y − y f_x` exists, in slot 5; slots 3–4 are 0.
/// The moment about a point `P` is `M_O − P × F` (`boundary::solid_force::moment_about`).
pub type SolidLoad = [f64; 6];

/// Which forces on solids `Backend::solid_forces` sums.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolidForceSource {
    /// Pressure (16) and the force stage's optional pair terms (`ForceTerms::pair`).
    Forces(PairTerms),
    /// The pressure increments `δp` of the current correction sweep (eqs. 23–24), at the
    /// positions the sweep starts from: the sweep's impulse on the solids is this force times
    /// `τ` and the sweep's `scale` (`Backend::correct_positions`).
    Correction,
}

impl SolidForceSource {
    /// The pair terms the force on solids is summed with: the correction moves particles by
    /// pressure alone, so its source has none.
    pub fn pair_terms(self) -> PairTerms {
        match self {
            SolidForceSource::Forces(terms) => terms,
            SolidForceSource::Correction => PairTerms::NONE,
        }
    }
}

/// How far the state is from the correction's goal (`Backend::correction_error`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CorrectionError {
    /// Eq. (24) with note 6: largest `max(ρ − ρ0, 0)/ρ0` over fluid particles.
    pub compression: f64,
    /// Largest `physics::correction::residual`: the compression, and the expansion of particles
    /// that still carry pressure. The loop runs until it is below `δ`. NaN when a fluid
    /// particle's density or pressure is NaN, so such a state ends the loop with an error.
    pub residual: f64,
}

/// What one correction sweep did (`Backend::correct_positions`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sweep {
    /// Largest displacement applied [m].
    pub largest: f64,
    /// The factor (≤ 1) all displacements were scaled by.
    pub scale: f64,
}

/// Extremes of the fluid state needed by the time-step choice and the state guards.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StateExtremes {
    /// Largest fluid speed [m/s].
    pub max_speed: f64,
    /// Largest fluid acceleration magnitude [m/s²].
    pub max_acceleration: f64,
    /// Largest `|ρ − ρ0|/ρ0` over fluid particles.
    pub max_abs_density_error: f64,
    /// Mean `|ρ − ρ0|/ρ0` over fluid particles.
    pub mean_abs_density_error: f64,
    /// Largest compression `max(ρ − ρ0, 0)/ρ0` over fluid particles (PAPER.md note 6).
    pub max_compression: f64,
    /// Mean compression over fluid particles.
    pub mean_compression: f64,
    /// Largest free-surface deficit `max(ρ0 − ρ, 0)/ρ0` over fluid particles: a particle near
    /// the free surface lacks neighbours on one side, so its summed density (eq. 18) is below
    /// `ρ0` while the fluid is not expanded.
    pub max_surface_deficit: f64,
    /// Mean deficit over fluid particles, as `mean |ρ − ρ0|/ρ0 − mean compression` (equal to
    /// the mean of `max(ρ0 − ρ, 0)/ρ0` but for rounding; both backends form it so).
    pub mean_surface_deficit: f64,
    /// When a fluid particle's speed, acceleration or density error is not finite (the cheap
    /// trigger both backends test): the first particle (current order, fluid or solid) with a
    /// non-finite position, velocity, acceleration, density or pressure, and that field's name.
    /// A non-finite pressure or position alone does not trigger it: pressure comes from the
    /// density (19) or the correction, and the next sort refuses a non-finite position.
    pub non_finite: Option<(usize, &'static str)>,
    /// First fluid particle (current order) outside the domain box.
    pub escaped: Option<usize>,
}

impl StateExtremes {
    /// The extremes from their parts, as both backends combine them over the ranks of a split
    /// run: `maxima` the largest fluid speed [m/s], acceleration [m/s²], `|ρ − ρ0|/ρ0`,
    /// compression and deficit (a NaN reads 0, as `f64::max`), `sums` the fluid count and the
    /// sums of `|ρ − ρ0|/ρ0` and of the compression; `escaped` as the field says, and no
    /// non-finite particle named.
    pub fn from_parts(maxima: [f64; 5], sums: [f64; 3], escaped: Option<usize>) -> Self {
        let [max_speed, max_acceleration, max_abs, max_comp, max_deficit] = maxima;
        let [count, abs_sum, comp_sum] = sums;
        let mean = |s: f64| if count > 0.0 { s / count } else { 0.0 };
        StateExtremes {
            max_speed: max_speed.max(0.0),
            max_acceleration: max_acceleration.max(0.0),
            max_abs_density_error: max_abs.max(0.0),
            mean_abs_density_error: mean(abs_sum),
            max_compression: max_comp.max(0.0),
            mean_compression: mean(comp_sum),
            max_surface_deficit: max_deficit.max(0.0),
            mean_surface_deficit: mean(abs_sum - comp_sum),
            non_finite: None,
            escaped,
        }
    }
}

/// The stages a backend runs. Each method is one `Stage` of the plan.
pub trait Backend<const D: usize> {
    /// Short name for reports (`"cpu"`, `"cuda"`).
    fn name(&self) -> &'static str;
    /// Which backend this is.
    fn kind(&self) -> BackendKind;
    /// Bytes the backend holds beside `Fields` (grid, scratch; device buffers for CUDA).
    fn heap_bytes(&self) -> usize;
    /// The device the stages run on, for reports (`None`: the host's CPUs).
    fn device(&self) -> Option<String> {
        None
    }
    /// Whether the state lives in the backend (device memory) rather than in `Fields`, so that
    /// `Fields` is stale after a stage until [`Backend::download`].
    fn holds_state(&self) -> bool {
        false
    }
    /// Copies the backend's state into `fields`: every field, in the backend's current order,
    /// but the step-start copies of SSP-RK3 (`position_start`, `velocity_start`), which a
    /// device keeps as its own scratch (they come back empty). Nothing to do for a backend
    /// that works on `fields` itself.
    fn download(&mut self, _fields: &mut Fields<D>) -> Result<(), BackendError> {
        Ok(())
    }
    /// Copies the fields `which` from the backend's state into `fields`, the step-start copies
    /// included, in the backend's current order: how a split run stages a device rank's
    /// particles through the host (`distributed::RankBackend`). Nothing to do for a backend
    /// that works on `fields` itself.
    ///
    /// # Errors
    /// [`BackendError::Device`] when a copy fails.
    fn download_some(&mut self, fields: &mut Fields<D>, which: &[Field]) -> Result<(), BackendError> {
        let _ = (fields, which);
        Ok(())
    }
    /// Writes the fields `which` of `fields` (the backend's particles in its current order)
    /// over the backend's state: a split run's ghost refresh on a device rank, after the host
    /// replaced the ghosts' rows. Nothing to do for a backend that works on `fields` itself.
    ///
    /// # Errors
    /// [`BackendError::Device`] when the particle count differs or a copy fails.
    fn upload_some(&mut self, fields: &Fields<D>, which: &[Field]) -> Result<(), BackendError> {
        let _ = (fields, which);
        Ok(())
    }
    /// Starts again from `fields`, which the host changed (`Simulation::reload_backend`: a
    /// particle count changed, `solver::escape` and `solver::open`): the same kind of backend on
    /// the same device, with every buffer sized and filled from `fields` as at its creation.
    ///
    /// # Errors
    /// [`BackendError::Device`] when an allocation or the upload fails.
    fn reload(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> Result<(), BackendError>;
    /// Waits until every stage launched so far has finished (for timings; a no-op on the CPU,
    /// whose stages return when done).
    fn synchronize(&mut self) {}
    /// The first device failure since the last call, if any. Stage methods cannot return errors
    /// (the CPU's cannot fail); a backend whose stages can fail records the first failure, skips
    /// the stages after it, and the step driver reports it here at the end of the step.
    fn take_error(&mut self) -> Option<BackendError> {
        None
    }
    /// Section 3: hash particles to cells of size `params.h` (stretched to divide the period
    /// along `params.periodic` axes, `crate::periodic`), sort, reorder every field.
    fn sort_by_cell(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) -> Result<(), GridError>;
    /// Eq. (18): density of fluid particles by summation.
    fn density(&mut self, fields: &mut Fields<D>, params: &StepParams<D>);
    /// The continuity equation with [F19] density diffusion (`physics::density_diffusion`):
    /// `Fields::density_rate` (allocated here on first use) of fluid particles,
    /// `Σ_j m_j (u_i − u_j)·∇W_ρ` over every neighbour (a solid with its
    /// `Fields::wall_velocity` where that field is allocated, its own velocity otherwise, as in
    /// the force stage) plus the diffusion `D_i` of strength `params.density_diffusion` over
    /// fluid neighbours; zero for solids.
    fn density_rate(&mut self, fields: &mut Fields<D>, params: &StepParams<D>);
    /// Symplectic Euler for the density: `ρ += dt dρ/dt`, fluid only; `dt` [s].
    fn integrate_density(&mut self, fields: &mut Fields<D>, dt: f32);
    /// SSP-RK3: remembers `ρ^n` (in `Fields::density_start` on the CPU, allocated here; in
    /// device memory on CUDA, as the other step-start copies).
    fn store_density_start(&mut self, fields: &mut Fields<D>);
    /// One Shu–Osher stage of the density, fluid only: `ρ ← a ρ^n + b (ρ + dt dρ/dt)`; `dt` [s].
    fn rk_density_stage(&mut self, fields: &mut Fields<D>, dt: f32, a: f32, b: f32);
    /// The damping zone ([AEA17], `physics::damping_zone`): the velocity of every fluid particle
    /// at `x` is multiplied by `zone.velocity_factor(x, dt)`; `dt` [s] the step. Solids are
    /// untouched.
    fn damping_zone(&mut self, fields: &mut Fields<D>, zone: &DampingZone<D>, dt: f32);
    /// Periodic boundaries (`crate::periodic`): every fluid particle's position goes through
    /// `params.periodic().wrap` (one period back along each periodic axis it left the domain
    /// on); mass, velocity and solids are untouched.
    fn wrap_positions(&mut self, fields: &mut Fields<D>, params: &StepParams<D>);
    /// Eq. (19): pressure of fluid particles.
    fn equation_of_state(&mut self, fields: &mut Fields<D>, params: &StepParams<D>);
    /// Moving solids (`boundary::motion`, `boundary::rigid`): every solid particle of id
    /// `reference.first_id + k` and kind `1 + s` moves to
    /// `kinematics[s].position(reference.position[k])` [m] (`x0 + d`, turned about the pivot when
    /// the solid rotates) and takes the velocity `kinematics[s].velocity_at(x)` [m/s] (`d' + ω × r`;
    /// fixed solids in the same scene get zero kinematics and stay where they are). Fluid
    /// particles are untouched.
    fn move_solids(
        &mut self,
        fields: &mut Fields<D>,
        reference: &SolidReference<D>,
        kinematics: &[SolidKinematics<D>],
    );
    /// Boundary: pressure and density of solid particles ([A12] eq. 27). `kinematics` holds
    /// each solid's motion (index `kind − 1`); the wall's acceleration at each solid particle,
    /// `kinematics[s].acceleration_at(x)` [m/s²] (`d'' + α × r + ω × (ω × r)`), enters as
    /// `g − a_w`; empty when no solid moves. With a rotating frame (`params.angular_velocity` not zero) the
    /// centrifugal acceleration at the wall particle is added (`physics::rotating_frame`).
    fn wall_pressure(
        &mut self,
        fields: &mut Fields<D>,
        params: &StepParams<D>,
        model: WallModel,
        kinematics: &[SolidKinematics<D>],
    );
    /// Boundary, no-slip walls ([A12] eqs. 22–23, `boundary::wall_velocity`): every solid
    /// particle's `Fields::wall_velocity` becomes `2 u_wall − ũ`, `ũ` the Shepard average (poly6
    /// weights) of its fluid neighbours' velocities and `u_wall` its own velocity; a solid
    /// without fluid neighbours gets its own velocity. Fluid entries are left as they are. Only
    /// in scenes with the `viscosity` effect and solids (the field is allocated there).
    fn wall_velocity(&mut self, fields: &mut Fields<D>, params: &StepParams<D>);
    /// Eqs. (15)–(17) and (6): acceleration of fluid particles. With viscosity, a solid
    /// neighbour carries its `Fields::wall_velocity` in (17) when that field is allocated (its
    /// own velocity otherwise), and (17) is scaled by `params.viscosity_scale`.
    fn forces(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, terms: ForceTerms);
    /// The first moment of the spiky gradient over the owned fluid particles with full support
    /// (`physics::gradient_moment`), summed over the ranks of a split run.
    fn gradient_moment(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) -> MomentSums;
    /// [AAT13] eq. (3): the surface normal `n_i = h Σ_j (m_j/ρ_j) ∇W(x_ij)` of fluid particles
    /// over fluid neighbours (`physics::surface_tension`), into `Fields::normal` (allocated here
    /// on first use: only scenes with the `surface_tension` effect run this stage); zero for
    /// solids. With the surface stress (`params.surface_tension_model`) each neighbour's rest
    /// volume `m_j/ρ0_j` replaces `m_j/ρ_j`: the colour gradient `h ∇c`
    /// (`physics::surface_stress`).
    fn surface_normals(&mut self, fields: &mut Fields<D>, params: &StepParams<D>);
    /// Adds the surface tension of the fluid neighbours to the acceleration of fluid particles,
    /// from the normals of the `surface_normals` stage. Runs after `forces`. The model is
    /// `params.surface_tension_model`: the surface stress, the pair force of the capillary
    /// stresses (`physics::surface_stress`), or [AAT13] eqs. (1)–(5), the cohesion and curvature
    /// forces with `γ = params.surface_tension_gamma`.
    fn surface_tension(&mut self, fields: &mut Fields<D>, params: &StepParams<D>);
    /// Fig. 4: total force [N] (per unit depth in 2D) of the fluid on each of `solids` solids,
    /// and its moment about the origin [N m] ([`SolidLoad`]).
    fn solid_forces(
        &mut self,
        fields: &Fields<D>,
        params: &StepParams<D>,
        solids: usize,
        source: SolidForceSource,
    ) -> Vec<SolidLoad>;
    /// Extremes of speed, acceleration and density error, and the first non-finite value.
    fn state_extremes(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> StateExtremes;
    /// Semi-implicit (symplectic) Euler: `u += a dt`, then `x += u dt`, fluid only; `dt` [s].
    fn integrate(&mut self, fields: &mut Fields<D>, dt: f32);
    /// SSP-RK3: remembers `x^n`, `u^n` (in `Fields::position_start`, `velocity_start` on the
    /// CPU; in device memory on CUDA, see [`Backend::download`]).
    fn store_step_start(&mut self, fields: &mut Fields<D>);
    /// One Shu–Osher stage, fluid only: `x ← a x^n + b (x + dt u)`, `u ← a u^n + b (u + dt a)`
    /// with the acceleration of the force stage; `dt` [s].
    fn rk_stage(&mut self, fields: &mut Fields<D>, dt: f32, a: f32, b: f32);
    /// Eq. (24) with note 6: the largest compression `max(ρ − ρ0, 0)/ρ0` over fluid particles,
    /// and the loop's residual (`physics::correction::residual`); `ρ0` is each particle's own
    /// with [`Phases::Multi`](crate::physics::multiphase::Phases).
    fn correction_error(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> CorrectionError;
    /// Starts a stage's position correction (forgets the previous sweep's increments).
    fn begin_correction(&mut self, fields: &mut Fields<D>);
    /// Eq. (19) inside the correction: pressure increments `δp` from the density for fluid
    /// (`physics::correction::pressure_increment`, stiffness `k` [m²/s²]), extrapolated to solids
    /// ([A12] without gravity); added to `pressure`.
    fn correction_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, k: f32);
    /// Eq. (23): `Δx = τ² a^press(δp)` for fluid, scaled down uniformly (so momentum stays
    /// conserved) when the largest exceeds `max_step` [m]; `x += Δx`, `u += Δx/τ_u` with
    /// `τ_u = kick_tau` [s]: `τ` inside a stage, infinite for the start-up settle, which moves
    /// particles without giving them velocity (`Simulation::step`).
    fn correct_positions(
        &mut self,
        fields: &mut Fields<D>,
        params: &StepParams<D>,
        tau: f32,
        kick_tau: f32,
        max_step: f32,
    ) -> Sweep;
    /// Starts a stage's velocity solve (`solver::step`, after the position correction):
    /// remembers every particle's velocity, pressure and density (18) and forgets the previous
    /// sweep's increments. Positions stay fixed until `end_velocity_solve`: the CPU backend
    /// lists the fluid's pairs and their spiky gradients here once (`crate::neighbour_list`,
    /// same sums bitwise); the CUDA backend keeps searching the grid.
    fn begin_velocity_solve(&mut self, fields: &mut Fields<D>, params: &StepParams<D>);
    /// The velocity solve's warm start, right after `begin_velocity_solve`: each fluid particle's
    /// pressure becomes `max(P_start + ΔP, 0)`, with `ΔP` [Pa] the increment that the last solve of
    /// the same `slot` (the integrator stage, below [`VELOCITY_SOLVE_SLOTS`]) recorded for the
    /// particle's id (`record_velocity_solve`); a particle without one keeps `P_start`. The
    /// caller then sets the velocities with `velocity_from_pressure`. docs/method.md, "The
    /// velocity solve", says why the guess comes from the same stage.
    fn warm_start_velocity_solve(&mut self, fields: &mut Fields<D>, slot: usize);
    /// The velocity solve's density: `ρ* = base_i + τ Σ_j m_j (u_i − u_j)·∇W_ρ(x_i − x_j)`
    /// [kg/m³] for fluid particles into `density`, `base_i` from the density remembered by
    /// `begin_velocity_solve` (`physics::density::velocity_solve_base`: ρ0_i inside the fluid,
    /// the density itself at the free surface): the sum (18) that the current velocities give
    /// `τ` [s] later, to first order, with the surface's missing neighbours discounted; `∇W_ρ` the gradient of the kernel of (18),
    /// `physics::density::density_kernel_gradient`; with the multiphase effect `m_i` in place of
    /// `m_j`, as in `physics::multiphase::density`). Solids move with their own velocity.
    fn predicted_density(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, tau: f32);
    /// The velocity solve's next pressure: one Anderson-accelerated projected Jacobi sweep
    /// (`solver::anderson`) on the fluid pressure `P` [Pa] from the predicted density in
    /// `density`, `g(P) = max(P + k (ρ* − ρ0), 0)` with stiffness `k` [m²/s²]; `P ≥ 0` (note 6).
    fn mix_velocity_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, k: f32);
    /// The velocity solve's velocities for the current pressure: `u = u_start + τ a^press(P −
    /// P_start)` for fluid (the increments extrapolated to the wet solids as
    /// `correction_pressure` does, the solids' pressure kept ≥ 0, the pressure terms with the
    /// sum (18) remembered by `begin_velocity_solve`); leaves the increments where
    /// `solid_forces` (`SolidForceSource::Correction`) reads them.
    fn velocity_from_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, tau: f32);
    /// Records each fluid particle's increment `P − P_start` [Pa] of the solve about to end, by
    /// particle id, as `slot`'s guess for its next solve (`warm_start_velocity_solve`) when the
    /// solve is kept (`keep`); either way the slot's older records stop counting. Call before
    /// `end_velocity_solve`.
    fn record_velocity_solve(&mut self, fields: &mut Fields<D>, slot: usize, keep: bool);
    /// The records that count (`warm_start_velocity_solve` would use them) of the particles
    /// `ids`, one per id, for a checkpoint.
    ///
    /// # Errors
    /// [`BackendError::Device`] when the device copy fails.
    fn velocity_solve_records(&mut self, ids: &[u32]) -> Result<Vec<SolveRecord>, BackendError>;
    /// Replaces every record with `records` of the particles `ids` (from
    /// `velocity_solve_records`), as a run resumed from a checkpoint.
    ///
    /// # Errors
    /// [`BackendError::Device`] when the device copy fails.
    fn restore_velocity_solve_records(
        &mut self,
        ids: &[u32],
        records: &[SolveRecord],
    ) -> Result<(), BackendError>;
    /// Ends the velocity solve. `keep`: the velocities stay, `acting_pressure` gets the
    /// solve's pressure `P` (what acted over the stage), and every particle's pressure keeps
    /// only what the solve released, `P = min(P, P_start)`. Otherwise velocity and pressure go
    /// back to what `begin_velocity_solve` remembered, and `acting_pressure` gets that pressure.
    /// Either way `density` gets back the sum (18) remembered there (positions did not move),
    /// in place of the predicted density, without a neighbour pass.
    fn end_velocity_solve(&mut self, fields: &mut Fields<D>, keep: bool);
    /// `acting_pressure = pressure` for every particle: what acted over a `corrected` stage
    /// without a velocity solve (the start-up settle, a stage whose positions did not
    /// converge): the carried pressure with the correction's increments.
    fn record_acting_pressure(&mut self, fields: &mut Fields<D>);
    /// The no-penetration guard (`boundary::keep_out`): every fluid particle inside one of
    /// `boxes` is put `margin` [m] outside the face it came in through and loses the velocity
    /// that points into it, box after box in order (`KeepOutBox::push_out`). With
    /// `from_step_start` the step's start positions stored by `store_step_start` tell the face
    /// (the segment from there enters the box through it); without, the nearest face. Returns
    /// the pushes and each of the `solids` solids' momentum change of the fluid [kg m/s].
    fn keep_out(
        &mut self,
        fields: &mut Fields<D>,
        boxes: &[KeepOutBox<D>],
        solids: usize,
        margin: f32,
        from_step_start: bool,
    ) -> KeepOutReport;
    /// Which particles this backend's reductions count (`Partition::Whole` unless set by
    /// [`Backend::set_partition`]); its owned mask follows the order of the last sort.
    fn partition(&self) -> &Partition {
        &partition::WHOLE
    }
    /// The partition itself, where this backend keeps one ([`Backend::set_partition`]), for
    /// the reductions over ranks; `None` for a backend that always holds the whole simulation.
    fn partition_mut(&mut self) -> Option<&mut Partition> {
        None
    }
    /// Replaces each of `values` by its sum over the ranks of a split run (`backend::partition`;
    /// unchanged for a backend that holds the whole simulation). Every rank must call it.
    fn sum_over_ranks(&mut self, values: &mut [f64]) {
        if let Some(partition) = self.partition_mut() {
            partition.sum(values);
        }
    }
    /// Replaces each of `values` by its largest over the ranks of a split run (as
    /// [`Backend::sum_over_ranks`]). Every rank must call it.
    fn max_over_ranks(&mut self, values: &mut [f64]) {
        if let Some(partition) = self.partition_mut() {
            partition.max(values);
        }
    }
    /// From now on, check after every ghost refresh that every field of every ghost is its
    /// owner's (a split run's stages' write lists, `distributed::RankBackend`); nothing for a
    /// backend that holds the whole simulation.
    fn verify_halo(&mut self) {}
    /// The regions of a split run now (`distributed::RankBackend`); `None` for a backend that
    /// holds the whole simulation.
    fn decomposition(&self) -> Option<crate::distributed::Decomposition<D>> {
        None
    }
    /// What a rank's share did and sent so far (`distributed::RankBackend`); `None` for a
    /// backend that holds the whole simulation.
    fn halo_traffic(&self) -> Option<crate::distributed::HaloTraffic> {
        None
    }
    /// Makes this backend one rank's share of a run split across ranks (`backend::partition`):
    /// from now on its reductions count the particles `partition` owns and add across ranks.
    /// The rank's ghost exchange (`distributed::rank_backend`) sets it after every sort.
    ///
    /// # Errors
    /// [`BackendError::Unavailable`] for a backend that cannot run a rank's share.
    fn set_partition(&mut self, partition: Partition) -> Result<(), BackendError> {
        drop(partition);
        Err(BackendError::Unavailable {
            backend: self.name(),
            reason: "this backend cannot run one rank's share of a split run".into(),
        })
    }
}

pub mod cuda;

/// Which backend runs the stages.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BackendKind {
    /// The rayon CPU reference backend.
    #[default]
    Cpu,
    /// The CUDA backend (`--features cuda`, NVIDIA GPU).
    Cuda,
}

/// Errors of backend selection, setup and device transfers.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BackendError {
    /// The backend cannot run here; the reason says why.
    #[error("backend {backend} is unavailable: {reason}")]
    Unavailable {
        /// Backend name.
        backend: &'static str,
        /// Why it cannot run.
        reason: String,
    },
    /// A collective between ranks failed (a lost rank, a bad packet).
    #[error("exchange between ranks failed: {0}")]
    Ranks(#[from] crate::distributed::DistributedError),
    /// The device failed during the run (a launch, a copy, an allocation).
    #[error("backend {backend} failed while {during}: {reason}")]
    Device {
        /// Backend name.
        backend: &'static str,
        /// What it was doing.
        during: String,
        /// The driver's message.
        reason: String,
    },
}
