//! The stages of [`RankBackend`]: each runs on the wrapped backend, after a ghost refresh when
//! it sums over neighbours, and names the fields it writes (what the next refresh sends).

use super::{Decomposition, HaloTraffic, RankBackend};
use crate::backend::partition::Partition;
use crate::backend::{
    Backend, BackendError, BackendKind, CorrectionError, ForceTerms, MomentSums, SolidForceSource, SolidLoad,
    StateExtremes, Sweep, WallModel,
};
use crate::boundary::keep_out::{KeepOutBox, KeepOutReport};
use crate::boundary::motion::{SolidKinematics, SolidReference};
use crate::fields::{Field, Fields};
use crate::grid::GridError;
use crate::model::params::StepParams;
use crate::physics::damping_zone::DampingZone;

impl<const D: usize> Backend<D> for RankBackend<D> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn kind(&self) -> BackendKind {
        self.inner.kind()
    }

    fn heap_bytes(&self) -> usize {
        self.inner.heap_bytes()
    }

    fn device(&self) -> Option<String> {
        self.inner.device()
    }

    fn holds_state(&self) -> bool {
        self.inner.holds_state()
    }

    fn download(&mut self, fields: &mut Fields<D>) -> Result<(), BackendError> {
        self.inner.download(fields)
    }

    fn reload(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> Result<(), BackendError> {
        // The host changed the particles (escapes removed, open boundaries' particles created
        // and removed): the halo's indices no longer hold; its ghost ids still name the ghosts
        // to drop at the next rebuild, and the reductions until then count the others.
        self.inner.reload(fields, params)?;
        if let Some(halo) = self.halo.as_mut() {
            halo.anchor.clear();
            halo.send_index.clear();
            halo.recv_index.clear();
            let owned = fields.id.iter().map(|id| !halo.ghosts.contains_key(id)).collect();
            self.inner.set_partition(Partition::Rank {
                owned,
                comm: self.comm.clone(),
                error: None,
            })?;
        }
        Ok(())
    }

    fn synchronize(&mut self) {
        self.inner.synchronize();
    }

    fn take_error(&mut self) -> Option<BackendError> {
        self.error.take().or_else(|| self.inner.take_error())
    }

    fn sort_by_cell(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) -> Result<(), GridError> {
        self.rebuild(fields, params)
    }

    fn density(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        self.summing(fields, "density", &[Field::Density], |b, f| b.density(f, params));
    }

    fn density_rate(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        self.summing(fields, "density_rate", &[Field::DensityRate], |b, f| {
            b.density_rate(f, params)
        });
    }

    fn integrate_density(&mut self, fields: &mut Fields<D>, dt: f32) {
        self.local(fields, &[Field::Density], |b, f| b.integrate_density(f, dt));
    }

    fn store_density_start(&mut self, fields: &mut Fields<D>) {
        self.local(fields, &[Field::DensityStart], |b, f| b.store_density_start(f));
    }

    fn rk_density_stage(&mut self, fields: &mut Fields<D>, dt: f32, a: f32, b: f32) {
        self.local(fields, &[Field::Density], |bk, f| {
            bk.rk_density_stage(f, dt, a, b)
        });
    }

    fn damping_zone(&mut self, fields: &mut Fields<D>, zone: &DampingZone<D>, dt: f32) {
        self.local(fields, &[Field::Velocity], |b, f| b.damping_zone(f, zone, dt));
    }

    fn wrap_positions(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        self.local(fields, &[Field::Position], |b, f| b.wrap_positions(f, params));
    }

    fn equation_of_state(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        self.local(fields, &[Field::Pressure], |b, f| b.equation_of_state(f, params));
    }

    fn move_solids(
        &mut self,
        fields: &mut Fields<D>,
        reference: &SolidReference<D>,
        kinematics: &[SolidKinematics<D>],
    ) {
        self.local(fields, &[Field::Position, Field::Velocity], |b, f| {
            b.move_solids(f, reference, kinematics)
        });
    }

    fn wall_pressure(
        &mut self,
        fields: &mut Fields<D>,
        params: &StepParams<D>,
        model: WallModel,
        kinematics: &[SolidKinematics<D>],
    ) {
        self.summing(
            fields,
            "wall_pressure",
            &[Field::Pressure, Field::Density],
            |b, f| b.wall_pressure(f, params, model, kinematics),
        );
    }

    fn wall_velocity(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        self.summing(fields, "wall_velocity", &[Field::WallVelocity], |b, f| {
            b.wall_velocity(f, params)
        });
    }

    fn gradient_moment(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) -> MomentSums {
        self.summing(fields, "gradient_moment", &[], |b, f| {
            b.gradient_moment(f, params)
        })
    }

    fn forces(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, terms: ForceTerms) {
        self.summing(fields, "forces", &[Field::Acceleration], |b, f| {
            b.forces(f, params, terms)
        });
    }

    fn surface_normals(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        self.summing(fields, "surface_normals", &[Field::Normal], |b, f| {
            b.surface_normals(f, params)
        });
    }

    fn surface_tension(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        self.summing(fields, "surface_tension", &[Field::Acceleration], |b, f| {
            b.surface_tension(f, params)
        });
    }

    fn solid_forces(
        &mut self,
        fields: &Fields<D>,
        params: &StepParams<D>,
        solids: usize,
        source: SolidForceSource,
    ) -> Vec<SolidLoad> {
        // Reads neighbours, but through `&Fields`: the stage before it (the force stage, or
        // the correction's pressure) already refreshed what it reads.
        self.inner.solid_forces(fields, params, solids, source)
    }

    fn state_extremes(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> StateExtremes {
        self.inner.state_extremes(fields, params)
    }

    fn integrate(&mut self, fields: &mut Fields<D>, dt: f32) {
        self.local(fields, &[Field::Position, Field::Velocity], |b, f| {
            b.integrate(f, dt)
        });
    }

    fn store_step_start(&mut self, fields: &mut Fields<D>) {
        self.local(fields, &[Field::PositionStart, Field::VelocityStart], |b, f| {
            b.store_step_start(f)
        });
    }

    fn rk_stage(&mut self, fields: &mut Fields<D>, dt: f32, a: f32, b: f32) {
        self.local(fields, &[Field::Position, Field::Velocity], |bk, f| {
            bk.rk_stage(f, dt, a, b)
        });
    }

    fn correction_error(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> CorrectionError {
        self.inner.correction_error(fields, params)
    }

    fn begin_correction(&mut self, fields: &mut Fields<D>) {
        self.inner.begin_correction(fields);
    }

    fn correction_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, k: f32) {
        self.summing(fields, "correction_pressure", &[Field::Pressure], |b, f| {
            b.correction_pressure(f, params, k)
        });
    }

    fn correct_positions(
        &mut self,
        fields: &mut Fields<D>,
        params: &StepParams<D>,
        tau: f32,
        kick_tau: f32,
        max_step: f32,
    ) -> Sweep {
        self.summing(
            fields,
            "correct_positions",
            &[Field::Position, Field::Velocity],
            |b, f| b.correct_positions(f, params, tau, kick_tau, max_step),
        )
    }

    fn begin_velocity_solve(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        self.refresh(fields, "begin_velocity_solve");
        self.inner.begin_velocity_solve(fields, params);
    }

    fn warm_start_velocity_solve(&mut self, _fields: &mut Fields<D>, _slot: usize) {
        // A split run starts every velocity solve from `P_start`: records kept by id on one
        // rank go stale as particles change ranks, and a split checkpoint's pieces hold none.
    }

    fn predicted_density(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, tau: f32) {
        self.summing(fields, "predicted_density", &[Field::Density], |b, f| {
            b.predicted_density(f, params, tau)
        });
    }

    fn mix_velocity_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, k: f32) {
        self.local(fields, &[Field::Pressure], |b, f| {
            b.mix_velocity_pressure(f, params, k)
        });
    }

    fn velocity_from_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, tau: f32) {
        self.summing(
            fields,
            "velocity_from_pressure",
            &[Field::Velocity, Field::Pressure],
            |b, f| b.velocity_from_pressure(f, params, tau),
        );
    }

    fn record_velocity_solve(&mut self, _fields: &mut Fields<D>, _slot: usize, _keep: bool) {
        // None kept (`warm_start_velocity_solve`).
    }

    fn velocity_solve_records(
        &mut self,
        ids: &[u32],
    ) -> Result<Vec<crate::backend::SolveRecord>, BackendError> {
        Ok(vec![Default::default(); ids.len()])
    }

    fn restore_velocity_solve_records(
        &mut self,
        _ids: &[u32],
        _records: &[crate::backend::SolveRecord],
    ) -> Result<(), BackendError> {
        Ok(())
    }

    fn end_velocity_solve(&mut self, fields: &mut Fields<D>, keep: bool) {
        self.local(
            fields,
            &[
                Field::ActingPressure,
                Field::Pressure,
                Field::Velocity,
                Field::Density,
            ],
            |b, f| b.end_velocity_solve(f, keep),
        );
    }

    fn record_acting_pressure(&mut self, fields: &mut Fields<D>) {
        self.local(fields, &[Field::ActingPressure], |b, f| {
            b.record_acting_pressure(f)
        });
    }

    fn keep_out(
        &mut self,
        fields: &mut Fields<D>,
        boxes: &[KeepOutBox<D>],
        solids: usize,
        margin: f32,
        from_step_start: bool,
    ) -> KeepOutReport {
        self.local(fields, &[Field::Position, Field::Velocity], |b, f| {
            b.keep_out(f, boxes, solids, margin, from_step_start)
        })
    }

    fn partition(&self) -> &Partition {
        self.inner.partition()
    }

    fn partition_mut(&mut self) -> Option<&mut Partition> {
        self.inner.partition_mut()
    }

    fn verify_halo(&mut self) {
        self.verify = true;
    }

    fn decomposition(&self) -> Option<Decomposition<D>> {
        Some(self.decomposition.clone())
    }

    fn halo_traffic(&self) -> Option<HaloTraffic> {
        Some(self.traffic)
    }

    fn set_partition(&mut self, partition: Partition) -> Result<(), BackendError> {
        self.inner.set_partition(partition)
    }
}
