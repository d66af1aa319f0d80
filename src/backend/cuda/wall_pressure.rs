//! Stages `wall_pressure` ([A12] eq. 27) and `wall_velocity` ([A12] eqs. 22-23) on the device
//! (`kernels/wall_pressure.cu`, `kernels/wall_velocity.cu`).

use super::*;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    pub(super) fn launch_wall_pressure(
        &mut self,
        params: &StepParams<D>,
        model: WallModel,
        kinematics: &[SolidKinematics<D>],
    ) {
        // Moving walls: their motion records (`kernels/rigid.cuh`) go up with each call (a few
        // floats); while nothing moves the buffer keeps its zeros and nothing is copied. An
        // empty list after a full one means walls at rest again (as the CPU reads it): the
        // buffer goes back to zeros.
        if kinematics.is_empty() && self.wall_motion_set && self.error.is_none() {
            let r = self.dev.zero(&mut self.wall_motion);
            record(&mut self.error, "clearing the walls' motion", r);
            self.wall_motion_set = false;
        }
        if !kinematics.is_empty() && self.error.is_none() {
            let motion: Vec<f32> = kinematics.iter().flat_map(|k| k.kernel_floats()).collect();
            if motion.len() > self.wall_motion.len() {
                self.error = Some(device_error(
                    "extrapolating the wall pressure",
                    format!("{} walls' motion, buffer for fewer", kinematics.len()),
                ));
                return;
            }
            let r = self.dev.write(&motion, &mut self.wall_motion);
            record(&mut self.error, "uploading the walls' motion", r);
            self.wall_motion_set = true;
        }
        let Some(g) = self.grid.as_ref() else { return };
        let n = self.n as u32;
        let summed = i32::from(model == WallModel::ExtrapolatedOrSummed);
        launch!(
            self,
            "extrapolating the wall pressure",
            wall_pressure(
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
                &self.wall_motion,
                summed,
                &mut self.f.pressure,
                &mut self.f.density
            )
        );
    }

    pub(super) fn launch_wall_velocity(&mut self, params: &StepParams<D>) {
        if self.error.is_some() {
            return;
        }
        if self.f.wall_velocity.is_none() {
            let r = self.dev.alloc_zeros::<f32>((self.n * D).max(1));
            self.f.wall_velocity = record(&mut self.error, "allocating the wall velocity", r);
        }
        let (Some(g), Some(out)) = (self.grid.as_ref(), self.f.wall_velocity.as_mut()) else {
            return;
        };
        let n = self.n as u32;
        // SAFETY: as in `launch!`; wall_velocity holds n D floats.
        let r = unsafe {
            self.dev.wall_velocity(
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.velocity,
                &self.f.kind,
                &self.f.id,
                out,
            )
        };
        record(&mut self.error, "extrapolating the wall velocity", r);
    }
}
