//! Stage `solid_forces` on the device (`kernels/solid_forces.cu`): the fluid's force on each solid
//! and its moment about the origin (`backend::SolidLoad`).

use super::*;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    pub(super) fn launch_solid_forces(
        &mut self,
        params: &StepParams<D>,
        solids: usize,
        source: SolidForceSource,
    ) -> Vec<SolidLoad> {
        let zero = vec![[0.0; 6]; solids];
        if self.error.is_some() || solids == 0 {
            return zero;
        }
        if source == SolidForceSource::Correction {
            self.ensure_correction_buffers(); // the increments it reads hold `n` floats
        }
        let Some(g) = self.grid.as_ref() else { return zero };
        if self.solid_out.len() < 6 * solids {
            let r = self.dev.alloc_zeros::<f64>(6 * solids);
            match record(&mut self.error, "allocating the solid forces", r) {
                Some(b) => self.solid_out = b,
                None => return zero,
            }
        }
        let r = self.dev.zero(&mut self.solid_out);
        if record(&mut self.error, "clearing the solid forces", r).is_none() {
            return zero;
        }
        let pressure = match source {
            SolidForceSource::Forces(_) => &self.f.pressure,
            SolidForceSource::Correction => &self.delta_p,
        };
        let n = self.n as u32;
        // The generated family's entry: the pair-term set, then the [HA06] variant
        // (`solid_forces{terms}{phases}`, kernels/launch.table).
        let entry = source.pair_terms().bits() as usize + PairTerms::SETS * params.phases as usize;
        // About 8 particles per thread (grid-stride loop in kernels/solid_forces.cu).
        // SAFETY: as in `launch!`; solid_out holds 6 doubles per solid (force, then moment).
        let r = unsafe {
            self.dev.solid_forces(
                entry,
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.velocity,
                &self.f.mass,
                &self.f.density,
                pressure,
                &self.f.kind,
                &self.f.id,
                self.f.wall_velocity.as_ref().unwrap_or(&self.f.velocity),
                &self.owned,
                &mut self.solid_out,
            )
        };
        if record(&mut self.error, "summing the forces on solids", r).is_none() {
            return zero;
        }
        let out = self.dev.download(&self.solid_out);
        let Some(mut v) = record(&mut self.error, "copying the solid forces", out) else {
            return zero;
        };
        // Each load summed over the ranks of a split run, as on the CPU.
        v.truncate(6 * solids);
        self.partition.sum(&mut v);
        v.chunks_exact(6).map(|c| std::array::from_fn(|k| c[k])).collect()
    }
}
