//! Moving walls and the no-penetration guard on the device: `move_solids` and `keep_out`
//! (`kernels/move_solids.cu`, `kernels/keep_out.cu`).

use super::*;

/// Doubles per solid in the guard's sums (`kernels/keep_out.cu`): the push count, the momentum
/// change (3) and its angular momentum about the origin (3).
const KEEP_OUT_SLOT: usize = 7;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    pub(super) fn launch_move_solids(
        &mut self,
        reference: &SolidReference<D>,
        kinematics: &[SolidKinematics<D>],
    ) {
        if self.error.is_some() {
            return;
        }
        if self.solid_reference.is_none() {
            let r = self.dev.upload(floats(&reference.position));
            self.solid_reference = record(&mut self.error, "uploading the solids' reference positions", r);
        }
        let motion: Vec<f32> = kinematics.iter().flat_map(|k| k.kernel_floats()).collect();
        if motion.len() > self.solid_motion.len() {
            self.error = Some(device_error(
                "moving solids",
                format!("{} solids, buffers for fewer", kinematics.len()),
            ));
            return;
        }
        let r = self.dev.write(&motion, &mut self.solid_motion);
        record(&mut self.error, "uploading the solids' motion", r);
        let Some(x0) = self.solid_reference.as_ref() else {
            return;
        };
        let n = self.n as u32;
        let first_id = reference.first_id;
        launch!(
            self,
            "moving solids",
            move_solids(
                n,
                &self.f.kind,
                &self.f.id,
                first_id,
                x0,
                &self.solid_motion,
                &mut self.f.position,
                &mut self.f.velocity
            )
        );
    }

    pub(super) fn launch_keep_out(
        &mut self,
        boxes: &[KeepOutBox<D>],
        solids: usize,
        margin: f32,
        from_step_start: bool,
    ) -> KeepOutReport {
        let mut report = KeepOutReport::none(solids);
        if boxes.is_empty() || self.error.is_some() {
            return report;
        }
        // Upload the boxes only when they changed (moving solids): min, max, velocity, solid.
        let host: Vec<f32> = boxes.iter().flat_map(KeepOutBox::kernel_floats).collect();
        if host != self.keep_out_host {
            let r = self.dev.upload(&host);
            match record(&mut self.error, "uploading the solid volumes", r) {
                Some(b) => self.keep_out_boxes = b,
                None => return report,
            }
            self.keep_out_host = host;
        }
        // One slot per solid a box names (the kernel writes to its box's slot unchecked), of which
        // the first `solids` give impulses, as on the CPU; pushes count in every slot.
        let slots = boxes
            .iter()
            .map(|b| b.solid as usize + 1)
            .max()
            .unwrap_or(0)
            .max(solids);
        if self.keep_out_out.len() < KEEP_OUT_SLOT * slots {
            let r = self.dev.alloc_zeros::<f64>(KEEP_OUT_SLOT * slots);
            match record(&mut self.error, "allocating the guard's sums", r) {
                Some(b) => self.keep_out_out = b,
                None => return report,
            }
        }
        let r = self.dev.zero(&mut self.keep_out_out);
        if record(&mut self.error, "clearing the guard's sums", r).is_none() {
            return report;
        }
        let (n, count) = (self.n as u32, boxes.len() as u32);
        let has_from = u32::from(from_step_start);
        launch!(
            self,
            "keeping fluid out of solids",
            keep_out(
                n,
                count,
                &self.keep_out_boxes,
                margin,
                &self.f.kind,
                &self.f.mass,
                &self.f.position_start,
                has_from,
                &self.owned,
                &mut self.f.position,
                &mut self.f.velocity,
                &mut self.keep_out_out
            )
        );
        let out = self.dev.download(&self.keep_out_out);
        if let Some(mut v) = record(&mut self.error, "copying the guard's sums", out) {
            // Over the ranks of a split run (each counts its own pushes), as on the CPU.
            v.truncate(KEEP_OUT_SLOT * slots);
            self.partition.sum(&mut v);
            let at = |s: usize| s * KEEP_OUT_SLOT;
            report.pushes = (0..slots).map(|s| v[at(s)] as u64).sum();
            for (s, slot) in report.impulse.iter_mut().enumerate() {
                slot.copy_from_slice(&v[at(s) + 1..at(s) + 4]);
            }
            for (s, slot) in report.angular_impulse.iter_mut().enumerate() {
                slot.copy_from_slice(&v[at(s) + 4..at(s) + 7]);
            }
        }
        report
    }
}
