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

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    /// Records an error when no `density_rate` stage allocated the rate the density stages
    /// integrate (a plan always computes it first); true when the rate is there.
    fn has_density_rate(&mut self) -> bool {
        if self.density_rate.is_none() && self.error.is_none() {
            self.error = Some(device_error(
                "integrating the density",
                "no density_rate stage ran before".to_string(),
            ));
        }
        self.density_rate.is_some()
    }

    pub(super) fn launch_integrate_density(&mut self, dt: f32) {
        if !self.has_density_rate() {
            return;
        }
        let n = self.n as u32;
        let Some(rate) = self.density_rate.as_ref() else {
            return;
        };
        // SAFETY: as in `launch!`; every buffer holds n floats.
        let r = unsafe {
            self.dev
                .integrate_density(n, dt, &self.f.kind, rate, &mut self.f.density)
        };
        record(&mut self.error, "integrating the density", r);
    }

    pub(super) fn launch_store_density_start(&mut self) {
        if self.error.is_some() {
            return;
        }
        if self.density_start.is_none() {
            let r = self.dev.alloc_zeros::<f32>(self.n.max(1));
            self.density_start = record(&mut self.error, "allocating the step-start density", r);
        }
        let Some(start) = self.density_start.as_mut() else {
            return;
        };
        let n = self.n as u32;
        // SAFETY: as in `launch!`; both buffers hold n floats.
        let r = unsafe { self.dev.store_density_start(n, &self.f.density, start) };
        record(&mut self.error, "storing the step-start density", r);
    }

    pub(super) fn launch_rk_density_stage(&mut self, dt: f32, a: f32, b: f32) {
        if !self.has_density_rate() {
            return;
        }
        let n = self.n as u32;
        let (Some(rate), Some(start)) = (self.density_rate.as_ref(), self.density_start.as_ref()) else {
            record::<()>(
                &mut self.error,
                "taking a Runge-Kutta stage of the density",
                Err("no step-start density stored".to_string().into()),
            );
            return;
        };
        // SAFETY: as in `launch!`; every buffer holds n floats.
        let r = unsafe {
            self.dev
                .rk_density_stage(n, dt, a, b, &self.f.kind, rate, start, &mut self.f.density)
        };
        record(&mut self.error, "taking a Runge-Kutta stage of the density", r);
    }
}
