//! The rayon-parallel CPU backend: the reference implementation of every stage.
//!
//! Every loop is a gather (particle `i` writes only its own slots), and every global sum goes
//! through `math::sum_in_order`, so results are bitwise identical for any thread count.
//!
//! One file per stage group, named as its twin in `kernels/`; the `Backend` impl here hands
//! each stage to the inherent method of the same name.

use super::params::StepParams;
use super::partition::Partition;
use super::{
    Backend, BackendError, CorrectionError, ForceTerms, SolidForceSource, SolidLoad, StateExtremes, Sweep,
    WallModel,
};
use crate::boundary::keep_out::{KeepOutBox, KeepOutReport};
use crate::boundary::motion::{SolidKinematics, SolidReference};
use crate::fields::{Fields, PermuteScratch};
use crate::grid::{Grid, GridError};
use crate::math::{Real, Vector};
use crate::neighbour_list::{NeighbourList, WetSolidPairs};
use crate::physics::damping_zone::DampingZone;
use crate::physics::gradient_moment::MomentSums;
use anderson::AndersonBuffers;
use warm_start::VelocitySolveRecords;

mod anderson;
mod correction;
mod damping_zone;
mod density;
mod density_rate;
mod forces;
mod gradient_moment;
mod integrate;
mod move_solids;
mod solid_forces;
mod sort_by_cell;
mod state_extremes;
mod surface_tension;
mod wall_pressure;
mod warm_start;
mod wrap_positions;

/// CPU backend state: the neighbour grid and reusable scratch buffers.
#[derive(Debug, Default)]
pub struct CpuBackend<const D: usize> {
    /// The neighbour grid of the last `sort_by_cell`.
    pub grid: Grid<D>,
    scratch: PermuteScratch<D>,
    wall: Vec<(Real, Real)>,
    /// Pressure increments `δp` of the current correction sweep [Pa].
    delta_p: Vec<Real>,
    /// Displacements `Δx` of the current correction sweep [m].
    displacement: Vec<Vector<D>>,
    /// Pressure increments of the previous sweep (heavy-ball momentum), empty after a sort.
    delta_p_previous: Vec<Real>,
    /// Per particle since the last sort: a solid with no fluid particle among its neighbour
    /// candidates (`Grid::neighbour_ranges`). Its wall pressure, correction increment and
    /// force on its solid are exactly zero until the next sort, so the solid loops skip it
    /// (the tank walls far from the water: half the particles of the 3D column scene). Empty
    /// before the first sort: nothing is skipped (the correction finds them on first use).
    dry: Vec<bool>,
    /// The other solids (indices, ascending), whose correction increments are summed.
    wet: Vec<u32>,
    /// The correction increments of the `wet` solids [Pa], before they are scattered.
    wet_increments: Vec<Real>,
    /// Velocities [m/s] at the start of the velocity solve (`begin_velocity_solve`).
    velocity_solve_start: Vec<Vector<D>>,
    /// Pressures [Pa] at the start of the velocity solve.
    pressure_solve_start: Vec<Real>,
    /// Densities (18) [kg/m³] at the start of the velocity solve, for its base density
    /// (`physics::density::velocity_solve_base`).
    density_solve_start: Vec<Real>,
    /// `p/ρ²` per particle (`physics::pressure::pressure_term`) of the current pressure loop.
    pressure_terms: Vec<Real>,
    /// Scratch of `find_dry_solids`: fluid particles before each sorted index.
    fluid_before: Vec<u32>,
    /// The fluid's pairs and their spiky gradients at the velocity solve's fixed positions, built by
    /// `begin_velocity_solve` and cleared by `end_velocity_solve` (`crate::neighbour_list`).
    /// Non-empty exactly while a solve runs.
    velocity_neighbours: NeighbourList<D>,
    /// The `wet` solids' fluid pairs over the same solve (`crate::neighbour_list`).
    wet_pairs: WetSolidPairs<D>,
    /// The velocity solve's Anderson acceleration (`anderson.rs`).
    anderson: AndersonBuffers,
    /// Each stage's last velocity solve, its warm start (`warm_start.rs`).
    solve_records: VelocitySolveRecords,
    /// The whole simulation, or one rank's share (`backend::partition`): which particles the
    /// reductions count and how they add across ranks.
    partition: Partition,
}

impl<const D: usize> CpuBackend<D> {
    /// A backend with empty buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// Bytes held by the grid and scratch buffers.
    pub fn heap_bytes(&self) -> usize {
        self.grid.heap_bytes()
            + self.wall.capacity() * 8
            + self.delta_p.capacity() * 4
            + self.delta_p_previous.capacity() * 4
            + self.velocity_solve_start.capacity() * D * 4
            + self.pressure_solve_start.capacity() * 4
            + self.density_solve_start.capacity() * 4
            + self.displacement.capacity() * D * 4
            + self.dry.capacity()
            + self.wet.capacity() * 4
            + self.wet_increments.capacity() * 4
            + self.pressure_terms.capacity() * 4
            + self.fluid_before.capacity() * 4
            + self.velocity_neighbours.heap_bytes()
            + self.wet_pairs.heap_bytes()
            + self.anderson.heap_bytes()
            + self.solve_records.heap_bytes()
    }
}

impl<const D: usize> Backend<D> for CpuBackend<D> {
    fn name(&self) -> &'static str {
        "cpu"
    }

    fn kind(&self) -> super::BackendKind {
        super::BackendKind::Cpu
    }

    fn reload(&mut self, _fields: &Fields<D>, _params: &StepParams<D>) -> Result<(), BackendError> {
        // A rank's share stays one: its owned particles are set again after the next sort.
        // The velocity solves' records are by id, which a reload keeps.
        let partition = std::mem::take(&mut self.partition);
        let records = std::mem::take(&mut self.solve_records);
        *self = Self::new();
        self.partition = partition;
        self.solve_records = records;
        Ok(())
    }

    fn take_error(&mut self) -> Option<BackendError> {
        self.partition.take_error().map(BackendError::Ranks)
    }

    fn partition(&self) -> &Partition {
        &self.partition
    }

    fn partition_mut(&mut self) -> Option<&mut Partition> {
        Some(&mut self.partition)
    }

    fn set_partition(&mut self, partition: Partition) -> Result<(), BackendError> {
        self.partition = partition;
        Ok(())
    }

    fn heap_bytes(&self) -> usize {
        CpuBackend::heap_bytes(self)
    }

    fn sort_by_cell(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) -> Result<(), GridError> {
        CpuBackend::sort_by_cell(self, fields, params)
    }

    fn density(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        CpuBackend::density(self, fields, params)
    }

    fn equation_of_state(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        CpuBackend::equation_of_state(self, fields, params)
    }

    fn density_rate(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        CpuBackend::density_rate(self, fields, params)
    }

    fn damping_zone(&mut self, fields: &mut Fields<D>, zone: &DampingZone<D>, dt: f32) {
        CpuBackend::damping_zone(self, fields, zone, dt)
    }

    fn wrap_positions(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        CpuBackend::wrap_positions(self, fields, params)
    }

    fn integrate_density(&mut self, fields: &mut Fields<D>, dt: f32) {
        CpuBackend::integrate_density(self, fields, dt)
    }

    fn store_density_start(&mut self, fields: &mut Fields<D>) {
        CpuBackend::store_density_start(self, fields)
    }

    fn rk_density_stage(&mut self, fields: &mut Fields<D>, dt: f32, a: f32, b: f32) {
        CpuBackend::rk_density_stage(self, fields, dt, a, b)
    }

    fn move_solids(
        &mut self,
        fields: &mut Fields<D>,
        reference: &SolidReference<D>,
        kinematics: &[SolidKinematics<D>],
    ) {
        CpuBackend::move_solids(self, fields, reference, kinematics)
    }

    fn wall_pressure(
        &mut self,
        fields: &mut Fields<D>,
        params: &StepParams<D>,
        model: WallModel,
        kinematics: &[SolidKinematics<D>],
    ) {
        CpuBackend::wall_pressure(self, fields, params, model, kinematics)
    }

    fn wall_velocity(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        CpuBackend::wall_velocity(self, fields, params)
    }

    fn forces(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, terms: ForceTerms) {
        CpuBackend::forces(self, fields, params, terms)
    }

    fn gradient_moment(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) -> MomentSums {
        CpuBackend::gradient_moment(self, fields, params)
    }

    fn surface_normals(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        CpuBackend::surface_normals(self, fields, params)
    }

    fn surface_tension(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        CpuBackend::surface_tension(self, fields, params)
    }

    fn solid_forces(
        &mut self,
        fields: &Fields<D>,
        params: &StepParams<D>,
        solids: usize,
        source: SolidForceSource,
    ) -> Vec<SolidLoad> {
        CpuBackend::solid_forces(self, fields, params, solids, source)
    }

    fn state_extremes(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> StateExtremes {
        CpuBackend::state_extremes(self, fields, params)
    }

    fn integrate(&mut self, fields: &mut Fields<D>, dt: f32) {
        CpuBackend::integrate(self, fields, dt)
    }

    fn store_step_start(&mut self, fields: &mut Fields<D>) {
        CpuBackend::store_step_start(self, fields)
    }

    fn rk_stage(&mut self, fields: &mut Fields<D>, dt: f32, a: f32, b: f32) {
        CpuBackend::rk_stage(self, fields, dt, a, b)
    }

    fn correction_error(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> CorrectionError {
        CpuBackend::correction_error(self, fields, params)
    }

    fn begin_correction(&mut self, fields: &mut Fields<D>) {
        CpuBackend::begin_correction(self, fields)
    }

    fn correction_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, k: f32) {
        CpuBackend::correction_pressure(self, fields, params, k)
    }

    fn correct_positions(
        &mut self,
        fields: &mut Fields<D>,
        params: &StepParams<D>,
        tau: f32,
        kick_tau: f32,
        max_step: f32,
    ) -> Sweep {
        CpuBackend::correct_positions(self, fields, params, tau, kick_tau, max_step)
    }

    fn begin_velocity_solve(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        CpuBackend::begin_velocity_solve(self, fields, params)
    }

    fn predicted_density(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, tau: f32) {
        CpuBackend::predicted_density(self, fields, params, tau)
    }

    fn mix_velocity_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, k: f32) {
        CpuBackend::mix_velocity_pressure(self, fields, params, k)
    }

    fn velocity_from_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, tau: f32) {
        CpuBackend::velocity_from_pressure(self, fields, params, tau)
    }

    fn warm_start_velocity_solve(&mut self, fields: &mut Fields<D>, slot: usize) {
        CpuBackend::warm_start_velocity_solve(self, fields, slot)
    }

    fn record_velocity_solve(&mut self, fields: &mut Fields<D>, slot: usize, keep: bool) {
        CpuBackend::record_velocity_solve(self, fields, slot, keep)
    }

    fn velocity_solve_records(&mut self, ids: &[u32]) -> Result<Vec<super::SolveRecord>, BackendError> {
        Ok(CpuBackend::velocity_solve_records(self, ids))
    }

    fn restore_velocity_solve_records(
        &mut self,
        ids: &[u32],
        records: &[super::SolveRecord],
    ) -> Result<(), BackendError> {
        CpuBackend::restore_velocity_solve_records(self, ids, records);
        Ok(())
    }

    fn end_velocity_solve(&mut self, fields: &mut Fields<D>, keep: bool) {
        CpuBackend::end_velocity_solve(self, fields, keep)
    }

    fn record_acting_pressure(&mut self, fields: &mut Fields<D>) {
        fields.acting_pressure.clone_from(&fields.pressure);
    }

    fn keep_out(
        &mut self,
        fields: &mut Fields<D>,
        boxes: &[KeepOutBox<D>],
        solids: usize,
        margin: f32,
        from_step_start: bool,
    ) -> KeepOutReport {
        CpuBackend::keep_out(self, fields, boxes, solids, margin, from_step_start)
    }
}
