//! Stage `density_rate` (the continuity equation with [F19] density diffusion) on the device
//! (`kernels/density_rate.cu`).

use super::*;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    pub(super) fn launch_density_rate(&mut self, params: &StepParams<D>) {
        if self.error.is_some() {
            return;
        }
        if self.density_rate.is_none() {
            let r = self.dev.alloc_zeros::<f32>(self.n.max(1));
            self.density_rate = record(&mut self.error, "allocating the density rate", r);
        }
        let (Some(g), Some(out)) = (self.grid.as_ref(), self.density_rate.as_mut()) else {
            return;
        };
        let n = self.n as u32;
        // SAFETY: as in `launch!`; density_rate holds n floats.
        let r = unsafe {
            self.dev.density_rate(
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.velocity,
                // Without no-slip walls a solid moves with its own velocity, as in the forces.
                self.f.wall_velocity.as_ref().unwrap_or(&self.f.velocity),
                &self.f.mass,
                &self.f.density,
                &self.f.kind,
                &self.f.id,
                out,
            )
        };
        record(&mut self.error, "computing the density rate", r);
    }
}
