//! Stages `density` and `equation_of_state`, and the velocity solve's `predicted_density`, on the
//! device (`kernels/density.cu`, `kernels/equation_of_state.cu`).

use super::*;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    pub(super) fn launch_density(&mut self, params: &StepParams<D>) {
        let Some(g) = self.grid.as_ref() else { return };
        let n = self.n as u32;
        // [HA06] number density with several phases (kernels/density.cu).
        launch!(
            self,
            "computing the density",
            density(
                params.phases as usize,
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.mass,
                &self.f.kind,
                &self.f.id,
                &mut self.f.density
            )
        );
    }

    pub(super) fn launch_equation_of_state(&mut self, params: &StepParams<D>) {
        let n = self.n as u32;
        if params.phases == Phases::Multi {
            let Some(rest) = multiphase_rest(&self.f.rest_density, &mut self.error) else {
                return;
            };
            launch!(
                self,
                "applying the equation of state",
                equation_of_state_multiphase(
                    n,
                    params,
                    &self.f.density,
                    rest,
                    &self.f.kind,
                    &mut self.f.pressure
                )
            );
            return;
        }
        launch!(
            self,
            "applying the equation of state",
            equation_of_state(n, params, &self.f.density, &self.f.kind, &mut self.f.pressure)
        );
    }

    pub(super) fn launch_predicted_density(&mut self, params: &StepParams<D>, tau: f32) {
        let Some(g) = self.grid.as_ref() else { return };
        let n = self.n as u32;
        if params.phases == Phases::Multi {
            let Some(rest) = multiphase_rest(&self.f.rest_density, &mut self.error) else {
                return;
            };
            // [HA06] each particle's own mass and rest density (kernels/density.cu).
            launch!(
                self,
                "predicting the density",
                predicted_density_multiphase(
                    n,
                    params,
                    &g.geometry,
                    &g.cell_start,
                    &g.cell_key,
                    &self.f.position,
                    &self.f.velocity,
                    &self.f.mass,
                    rest,
                    &self.f.kind,
                    &self.f.id,
                    &self.density_solve_start,
                    tau,
                    &mut self.f.density
                )
            );
            return;
        }
        launch!(
            self,
            "predicting the density",
            predicted_density(
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.velocity,
                &self.f.mass,
                &self.f.kind,
                &self.f.id,
                &self.density_solve_start,
                tau,
                &mut self.f.density
            )
        );
    }
}
