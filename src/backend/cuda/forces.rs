//! Stage `forces` (eqs. 15-17, 6) on the device (`kernels/forces.cu`).

use super::*;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    pub(super) fn launch_forces(&mut self, params: &StepParams<D>, terms: ForceTerms) {
        let Some(g) = self.grid.as_ref() else { return };
        let n = self.n as u32;
        let entry = terms.entry(params.phases);
        launch!(
            self,
            "computing the forces",
            forces(
                entry,
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.velocity,
                &self.f.mass,
                &self.f.density,
                &self.f.pressure,
                &self.f.kind,
                &self.f.id,
                // Without no-slip walls a solid carries its own velocity in (17).
                self.f.wall_velocity.as_ref().unwrap_or(&self.f.velocity),
                &mut self.f.acceleration
            )
        );
    }
}
