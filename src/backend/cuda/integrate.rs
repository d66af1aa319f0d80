//! Stages `integrate`, `store_step_start` and `rk_stage` on the device (`kernels/integrate.cu`).

use super::*;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    pub(super) fn launch_integrate(&mut self, dt: f32) {
        let n = self.n as u32;
        launch!(
            self,
            "integrating",
            integrate(
                n,
                dt,
                &self.f.kind,
                &self.f.acceleration,
                &mut self.f.velocity,
                &mut self.f.position
            )
        );
    }

    pub(super) fn launch_store_step_start(&mut self) {
        let n = self.n as u32;
        launch!(
            self,
            "storing the step start",
            store_step_start(
                n,
                &self.f.position,
                &self.f.velocity,
                &mut self.f.position_start,
                &mut self.f.velocity_start
            )
        );
    }

    pub(super) fn launch_rk_stage(&mut self, dt: f32, a: f32, b: f32) {
        let n = self.n as u32;
        launch!(
            self,
            "taking a Runge-Kutta stage",
            rk_stage(
                n,
                dt,
                a,
                b,
                &self.f.kind,
                &self.f.acceleration,
                &self.f.position_start,
                &self.f.velocity_start,
                &mut self.f.position,
                &mut self.f.velocity
            )
        );
    }
}
