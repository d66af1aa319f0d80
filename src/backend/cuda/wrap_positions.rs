//! Stage `wrap_positions` on the device (`kernels/wrap_positions.cu`).

use super::*;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    pub(super) fn launch_wrap_positions(&mut self, params: &StepParams<D>) {
        let n = self.n as u32;
        launch!(
            self,
            "wrapping positions into the period",
            wrap_positions(n, params, &self.f.kind, &mut self.f.position)
        );
    }
}
