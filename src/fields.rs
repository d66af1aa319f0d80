//! Struct-of-arrays particle fields and the registry every reorder goes through.
//!
//! Fluid and solid particles live in the same arrays (sorted together by cell, section 3 of the
//! paper); `kind` tells them apart. Every per-particle quantity is a field of [`Fields`], and
//! [`Fields::permute`] reorders all of them: adding a field means adding it there too
//! (`tests/numerics/grid.rs` checks that a reorder permutes every field).

use crate::math::{Real, Vector};
use rayon::prelude::*;

/// `kind` value of a fluid particle; solid particles carry `1 + index of their solid`.
pub const FLUID: u32 = 0;

/// Per-particle state, struct of arrays, all in the same (cell-sorted) order.
#[derive(Debug, Clone, Default)]
pub struct Fields<const D: usize> {
    /// Position `x` [m].
    pub position: Vec<Vector<D>>,
    /// Velocity `u` [m/s]; zero for fixed solids.
    pub velocity: Vec<Vector<D>>,
    /// Acceleration `dV/dt` of eq. (15) [m/s²]; zero for solids.
    pub acceleration: Vec<Vector<D>>,
    /// Density `ρ` [kg/m³]: eq. (18) for fluid (with the `density_diffusion` effect integrated
    /// by the continuity equation instead), the boundary model's value for solids.
    pub density: Vec<Real>,
    /// Pressure `p` [Pa]: eq. (19) for fluid, the boundary model's value for solids.
    pub pressure: Vec<Real>,
    /// Mass `m` [kg] (per unit depth [kg/m] in 2D).
    pub mass: Vec<Real>,
    /// [`FLUID`], or `1 + k` for a particle of the k-th named solid.
    pub kind: Vec<u32>,
    /// Index of the particle in the initial layout (stable across reorders).
    pub id: Vec<u32>,
    /// Position at the start of the step [m] (SSP-RK3 only; empty otherwise).
    pub position_start: Vec<Vector<D>>,
    /// Velocity at the start of the step [m/s] (SSP-RK3 only; empty otherwise).
    pub velocity_start: Vec<Vector<D>>,
    /// Velocity [m/s] a solid particle carries in the viscous force (17): the no-slip
    /// extrapolation `2 u_wall − ũ` of [A12] eqs. (22)–(23) (`boundary::wall_velocity`); unused
    /// for fluid particles. Allocated only in scenes with the `viscosity` effect and solids
    /// (empty otherwise: solids then carry their own velocity).
    pub wall_velocity: Vec<Vector<D>>,
    /// Surface normal `n = h Σ_j (m_j/ρ_j) ∇W` of [AAT13] eq. (3), dimensionless, pointing into
    /// the fluid (`physics::surface_tension`), or with the surface stress the colour gradient
    /// `h ∇c` with rest volumes `m_j/ρ0_j` (`physics::surface_stress`); allocated by the
    /// `surface_normals` stage, so empty unless the scene has the `surface_tension` effect.
    pub normal: Vec<Vector<D>>,
    /// Rest density `ρ0` of the particle's phase [kg/m³] (the `multiphase` effect only; empty
    /// otherwise). Solids carry the scene's `fluid.rho0`. Read by the multiphase variants of the
    /// stages, which the run's `Phases` selects (`physics::multiphase`).
    pub rest_density: Vec<Real>,
    /// `dρ/dt` [kg/(m³ s)] of fluid particles: the continuity equation with [F19] density
    /// diffusion (`physics::density_diffusion`), written by the `density_rate` stage (the
    /// `density_diffusion` effect only; empty otherwise).
    pub density_rate: Vec<Real>,
    /// Density at the start of the step [kg/m³] (SSP-RK3 with the `density_diffusion` effect
    /// only; empty otherwise).
    pub density_start: Vec<Real>,
    /// The pressure that acted on the fluid over the last integrator stage [Pa] (the
    /// `corrected` solver only; empty otherwise): the velocity solve's `P` before it releases
    /// to `min(P, P_start)`, or the carried pressure where no velocity solve ran. Pressure
    /// probes read it (`probe::PressureReading::Acting`): the carried pressure forgets what
    /// stopped a sheet at a wall (docs/method.md, "Impact pressure").
    pub acting_pressure: Vec<Real>,
}

/// A field of [`Fields`] by name, for what a stage reads and writes (`Stage::reads`,
/// `Stage::writes`, printed by `sph plan`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    /// [`Fields::position`].
    Position,
    /// [`Fields::velocity`].
    Velocity,
    /// [`Fields::acceleration`].
    Acceleration,
    /// [`Fields::density`].
    Density,
    /// [`Fields::pressure`].
    Pressure,
    /// [`Fields::mass`].
    Mass,
    /// [`Fields::kind`].
    Kind,
    /// [`Fields::id`].
    Id,
    /// [`Fields::position_start`].
    PositionStart,
    /// [`Fields::velocity_start`].
    VelocityStart,
    /// [`Fields::wall_velocity`].
    WallVelocity,
    /// [`Fields::normal`].
    Normal,
    /// [`Fields::rest_density`].
    RestDensity,
    /// [`Fields::density_rate`].
    DensityRate,
    /// [`Fields::density_start`].
    DensityStart,
    /// [`Fields::acting_pressure`].
    ActingPressure,
}

impl Field {
    /// Every field, in the order of [`Fields`] (what a reorder writes).
    pub const ALL: [Field; 16] = [
        Field::Position,
        Field::Velocity,
        Field::Acceleration,
        Field::Density,
        Field::Pressure,
        Field::Mass,
        Field::Kind,
        Field::Id,
        Field::PositionStart,
        Field::VelocityStart,
        Field::WallVelocity,
        Field::Normal,
        Field::RestDensity,
        Field::DensityRate,
        Field::DensityStart,
        Field::ActingPressure,
    ];

    /// The field's name in [`Fields`].
    pub fn name(self) -> &'static str {
        match self {
            Field::Position => "position",
            Field::Velocity => "velocity",
            Field::Acceleration => "acceleration",
            Field::Density => "density",
            Field::Pressure => "pressure",
            Field::Mass => "mass",
            Field::Kind => "kind",
            Field::Id => "id",
            Field::PositionStart => "position_start",
            Field::VelocityStart => "velocity_start",
            Field::WallVelocity => "wall_velocity",
            Field::Normal => "normal",
            Field::RestDensity => "rest_density",
            Field::DensityRate => "density_rate",
            Field::DensityStart => "density_start",
            Field::ActingPressure => "acting_pressure",
        }
    }
}

/// Scratch buffers reused by [`Fields::permute`], so reordering does not allocate per step.
#[derive(Debug, Clone, Default)]
pub struct PermuteScratch<const D: usize> {
    vector: Vec<Vector<D>>,
    real: Vec<Real>,
    index: Vec<u32>,
}

/// Gathers `field[perm[i]]` into `scratch`, then swaps it in.
fn gather<T: Copy + Send + Sync>(field: &mut Vec<T>, perm: &[u32], scratch: &mut Vec<T>) {
    scratch.clear();
    scratch.par_extend(perm.par_iter().map(|&p| field[p as usize]));
    std::mem::swap(field, scratch);
}

impl<const D: usize> Fields<D> {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Empty fields with room for exactly `n` particles in the fields every run holds, so that
    /// filling them by [`Fields::push`] leaves no growth slack (up to 2× a field's size, held for
    /// the whole run and uneven between scenes).
    pub fn with_capacity(n: usize) -> Self {
        Self {
            position: Vec::with_capacity(n),
            velocity: Vec::with_capacity(n),
            acceleration: Vec::with_capacity(n),
            density: Vec::with_capacity(n),
            pressure: Vec::with_capacity(n),
            mass: Vec::with_capacity(n),
            kind: Vec::with_capacity(n),
            id: Vec::with_capacity(n),
            ..Self::default()
        }
    }

    /// Appends one particle with zero acceleration, density `rho` and zero pressure.
    pub fn push(&mut self, position: Vector<D>, velocity: Vector<D>, mass: Real, rho: Real, kind: u32) {
        self.id.push(self.position.len() as u32);
        self.position.push(position);
        self.velocity.push(velocity);
        self.acceleration.push(Vector::zeros());
        self.density.push(rho);
        self.pressure.push(0.0);
        self.mass.push(mass);
        self.kind.push(kind);
    }

    /// Appends one fluid particle created during a run (`boundary::open`) with id `id`, zero
    /// acceleration, and an entry in every allocated optional field: the step-start copies of
    /// its position, velocity and density, the rest density `rho0`, the acting pressure
    /// `pressure`, zero for the rest (recomputed by their stages before use).
    #[allow(clippy::too_many_arguments)]
    pub fn push_created(
        &mut self,
        position: Vector<D>,
        velocity: Vector<D>,
        mass: Real,
        density: Real,
        pressure: Real,
        id: u32,
        rho0: Real,
    ) {
        let n = self.len();
        let has = |len: usize| n > 0 && len == n;
        if has(self.position_start.len()) {
            self.position_start.push(position);
        }
        if has(self.velocity_start.len()) {
            self.velocity_start.push(velocity);
        }
        if has(self.wall_velocity.len()) {
            self.wall_velocity.push(Vector::zeros());
        }
        if has(self.normal.len()) {
            self.normal.push(Vector::zeros());
        }
        if has(self.rest_density.len()) {
            self.rest_density.push(rho0);
        }
        if has(self.density_rate.len()) {
            self.density_rate.push(0.0);
        }
        if has(self.density_start.len()) {
            self.density_start.push(density);
        }
        if has(self.acting_pressure.len()) {
            self.acting_pressure.push(pressure);
        }
        self.position.push(position);
        self.velocity.push(velocity);
        self.acceleration.push(Vector::zeros());
        self.density.push(density);
        self.pressure.push(pressure);
        self.mass.push(mass);
        self.kind.push(FLUID);
        self.id.push(id);
    }

    /// Reorders every field by `perm` (new index → old index). The one place fields are permuted.
    pub fn permute(&mut self, perm: &[u32], scratch: &mut PermuteScratch<D>) {
        debug_assert_eq!(perm.len(), self.len());
        self.permute_into(perm, scratch);
    }

    /// Gathers every field by `perm` (new index → old index), which may be shorter than the
    /// fields (a subset).
    fn permute_into(&mut self, perm: &[u32], scratch: &mut PermuteScratch<D>) {
        gather(&mut self.position, perm, &mut scratch.vector);
        gather(&mut self.velocity, perm, &mut scratch.vector);
        gather(&mut self.acceleration, perm, &mut scratch.vector);
        gather(&mut self.density, perm, &mut scratch.real);
        gather(&mut self.pressure, perm, &mut scratch.real);
        gather(&mut self.mass, perm, &mut scratch.real);
        gather(&mut self.kind, perm, &mut scratch.index);
        gather(&mut self.id, perm, &mut scratch.index);
        // Optional fields: allocated only by the schemes that use them.
        if !self.position_start.is_empty() {
            gather(&mut self.position_start, perm, &mut scratch.vector);
            gather(&mut self.velocity_start, perm, &mut scratch.vector);
        }
        if !self.wall_velocity.is_empty() {
            gather(&mut self.wall_velocity, perm, &mut scratch.vector);
        }
        if !self.normal.is_empty() {
            gather(&mut self.normal, perm, &mut scratch.vector);
        }
        if !self.rest_density.is_empty() {
            gather(&mut self.rest_density, perm, &mut scratch.real);
        }
        if !self.density_rate.is_empty() {
            gather(&mut self.density_rate, perm, &mut scratch.real);
        }
        if !self.density_start.is_empty() {
            gather(&mut self.density_start, perm, &mut scratch.real);
        }
        if !self.acting_pressure.is_empty() {
            gather(&mut self.acting_pressure, perm, &mut scratch.real);
        }
    }

    /// Keeps only the particles `kept` (indices in increasing order) in every field, in that
    /// order: removes the others (`solver::escape`). Optional fields stay unallocated.
    pub fn keep(&mut self, kept: &[u32]) {
        debug_assert!(kept.windows(2).all(|w| w[0] < w[1]));
        let mut scratch = PermuteScratch::default();
        self.permute_into(kept, &mut scratch);
    }

    /// Whether `field` has storage (one entry per particle). The optional fields are allocated
    /// only when a stage of the plan needs them (`solver::plan::needed_fields`, checked on
    /// every shipped scene by `tests/check/field_allocation.rs`).
    pub fn is_allocated(&self, field: Field) -> bool {
        let n = self.len();
        n > 0
            && match field {
                Field::Position => self.position.len() == n,
                Field::Velocity => self.velocity.len() == n,
                Field::Acceleration => self.acceleration.len() == n,
                Field::Density => self.density.len() == n,
                Field::Pressure => self.pressure.len() == n,
                Field::Mass => self.mass.len() == n,
                Field::Kind => self.kind.len() == n,
                Field::Id => self.id.len() == n,
                Field::PositionStart => self.position_start.len() == n,
                Field::VelocityStart => self.velocity_start.len() == n,
                Field::WallVelocity => self.wall_velocity.len() == n,
                Field::Normal => self.normal.len() == n,
                Field::RestDensity => self.rest_density.len() == n,
                Field::DensityRate => self.density_rate.len() == n,
                Field::DensityStart => self.density_start.len() == n,
                Field::ActingPressure => self.acting_pressure.len() == n,
            }
    }

    /// Bytes per particle held by the always-present fields (for memory reports and scene
    /// validation); SSP-RK3 adds `2 D · 4`, no-slip walls (viscosity with solids) `D · 4`,
    /// surface tension `D · 4`, the `multiphase` effect 4, the `density_diffusion` effect 4
    /// (and 4 more with SSP-RK3), the `corrected` solver 4 (the acting pressure).
    pub const BYTES_PER_PARTICLE: usize = 3 * D * 4 + 3 * 4 + 2 * 4;

    /// Bytes held by the fields' arrays.
    pub fn heap_bytes(&self) -> usize {
        (self.position.capacity() * 3
            + self.position_start.capacity()
            + self.velocity_start.capacity()
            + self.wall_velocity.capacity()
            + self.normal.capacity())
            * D
            * 4
            + (self.density.capacity() * 3
                + self.kind.capacity() * 2
                + self.rest_density.capacity()
                + self.density_rate.capacity()
                + self.density_start.capacity()
                + self.acting_pressure.capacity())
                * 4
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn field_names_are_the_members_of_fields_in_order() {
        // The Debug form lists the struct's members: `Fields { position: [], velocity: [], … }`.
        let debug = format!("{:?}", Fields::<2>::default());
        let members: Vec<&str> = debug
            .trim_start_matches("Fields {")
            .split(", ")
            .filter_map(|m| m.trim().split(':').next())
            .collect();
        let names: Vec<&str> = Field::ALL.iter().map(|f| f.name()).collect();
        assert_eq!(members, names);
    }
}
