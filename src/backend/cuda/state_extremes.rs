//! Stage `state_extremes` on the device (`kernels/state_extremes.cu`): the time step's extremes,
//! reduced by atomics, and the name of the first non-finite quantity.

use super::*;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    /// Copies particle `i`'s fields to name the first non-finite quantity, as the CPU does.
    fn non_finite_quantity(&mut self, i: usize) -> &'static str {
        let dev = &self.dev;
        let vec_at =
            |b: &K::Buf<f32>| -> Vec<f32> { dev.download_range(b, i * D..(i + 1) * D).unwrap_or_default() };
        let scalar_at = |b: &K::Buf<f32>| -> Vec<f32> { dev.download_range(b, i..i + 1).unwrap_or_default() };
        let bad = |v: Vec<f32>| v.iter().any(|c| !c.is_finite());
        if bad(vec_at(&self.f.position)) {
            "position"
        } else if bad(vec_at(&self.f.velocity)) {
            "velocity"
        } else if bad(vec_at(&self.f.acceleration)) {
            "acceleration"
        } else if bad(scalar_at(&self.f.density)) {
            "density"
        } else {
            "pressure"
        }
    }

    pub(super) fn launch_state_extremes(&mut self, params: &StepParams<D>) -> StateExtremes {
        let fallback = StateExtremes::default();
        if self.error.is_some() {
            return fallback;
        }
        let r = self.dev.write(&[DeviceExtremes::initial()], &mut self.extremes);
        if record(&mut self.error, "resetting the extremes", r).is_none() {
            return fallback;
        }
        let n = self.n as u32;
        // About 64 particles per thread (grid-stride loop), so one set of atomics per 64.
        if params.phases == Phases::Multi {
            let Some(rest) = multiphase_rest(&self.f.rest_density, &mut self.error) else {
                return fallback;
            };
            launch!(
                self,
                "reducing the extremes",
                state_extremes_multiphase(
                    n,
                    params,
                    &self.f.position,
                    &self.f.velocity,
                    &self.f.acceleration,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    rest,
                    &self.owned,
                    &mut self.extremes
                )
            );
        } else {
            launch!(
                self,
                "reducing the extremes",
                state_extremes(
                    n,
                    params,
                    &self.f.position,
                    &self.f.velocity,
                    &self.f.acceleration,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    &self.owned,
                    &mut self.extremes
                )
            );
        }
        let out = self.dev.download(&self.extremes);
        let Some(out) = record(&mut self.error, "copying the extremes", out) else {
            return fallback;
        };
        if matches!(self.partition, Partition::Whole) {
            let mut e = out[0].finish(params.rho0);
            if let Some(i) = out[0].first_non_finite() {
                e.non_finite = Some((i, self.non_finite_quantity(i)));
            }
            return e;
        }
        // One rank's share: its maxima and sums combined over ranks as `CpuBackend` does (a
        // NaN anywhere stays NaN), and a non-finite quantity named where this rank holds one.
        let (mut maxima, mut sums) = out[0].rank_parts(params.rho0);
        self.partition.max(&mut maxima);
        self.partition.sum(&mut sums);
        let mut e = StateExtremes::from_parts(maxima, sums, out[0].escaped_index());
        if !(maxima[0] + maxima[1] + maxima[2]).is_finite() {
            if let Some(i) = out[0].non_finite_index() {
                e.non_finite = Some((i, self.non_finite_quantity(i)));
            }
        }
        e
    }
}
