//! Stage `gradient_moment` on the device (`kernels/gradient_moment.cu`): the pressure gradient's
//! first moment over the fluid with full support (`physics::gradient_moment`).

use super::*;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    pub(super) fn launch_gradient_moment(&mut self, params: &StepParams<D>) -> MomentSums {
        let none = MomentSums::default();
        if self.error.is_some() {
            return none;
        }
        let Some(g) = self.grid.as_ref() else { return none };
        let r = self.dev.zero(&mut self.moment_out);
        if record(&mut self.error, "clearing the gradient moment", r).is_none() {
            return none;
        }
        let n = self.n as u32;
        // SAFETY: as in `launch!`; moment_out holds 2 doubles.
        let r = unsafe {
            self.dev.gradient_moment(
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.mass,
                &self.f.density,
                &self.f.kind,
                &self.f.id,
                &self.owned,
                &mut self.moment_out,
            )
        };
        if record(&mut self.error, "summing the gradient moment", r).is_none() {
            return none;
        }
        let out = self.dev.download(&self.moment_out);
        let Some(mut v) = record(&mut self.error, "copying the gradient moment", out) else {
            return none;
        };
        // Summed over the ranks of a split run, as on the CPU.
        v.truncate(2);
        self.partition.sum(&mut v);
        MomentSums {
            moment: v[0],
            count: v[1],
        }
    }
}
