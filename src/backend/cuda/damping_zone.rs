//! Stage `damping_zone` on the device (`kernels/damping_zone.cu`).

use super::*;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    pub(super) fn launch_damping_zone(&mut self, zone: &DampingZone<D>, dt: f32) {
        let n = self.n as u32;
        // x0 and n/L as three components each (the third unused in 2D).
        let (o, a) = (zone.start, zone.gradient);
        let c = |v: &Vector<D>, k: usize| if k < D { v[k] } else { 0.0 };
        launch!(
            self,
            "damping the zone's velocities",
            damping_zone(
                n,
                dt,
                zone.strength,
                c(&o, 0),
                c(&o, 1),
                c(&o, 2),
                c(&a, 0),
                c(&a, 1),
                c(&a, 2),
                &self.f.kind,
                &self.f.position,
                &mut self.f.velocity
            )
        );
    }
}
