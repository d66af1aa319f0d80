//! The `sort_by_cell` stage and the dry solids it finds (twin of `kernels/sort_by_cell.cu`).

use super::CpuBackend;
use crate::fields::{FLUID, Fields};
use crate::grid::GridError;
use crate::model::params::StepParams;
use rayon::prelude::*;

impl<const D: usize> CpuBackend<D> {
    pub(super) fn sort_by_cell(
        &mut self,
        fields: &mut Fields<D>,
        params: &StepParams<D>,
    ) -> Result<(), GridError> {
        let perm = self
            .grid
            .sort_periodic(&fields.position, params.h, &params.periodic())?;
        self.delta_p_previous.clear();
        self.delta_p.clear();
        fields.permute(perm, &mut self.scratch);
        self.grid.link(&fields.id, &fields.position);
        self.find_dry_solids(&fields.kind);
        Ok(())
    }

    /// Whether particle `i` is a solid without fluid candidates since the last sort.
    #[inline(always)]
    pub(super) fn is_dry(&self, i: usize) -> bool {
        self.dry.get(i).copied().unwrap_or(false)
    }

    /// Recomputes [`CpuBackend::dry`] for the sorted `kind`: a running count of fluid particles
    /// in sorted order tells whether a candidate range holds any.
    pub(super) fn find_dry_solids(&mut self, kind: &[u32]) {
        let fluid_before = &mut self.fluid_before;
        fluid_before.clear();
        fluid_before.push(0u32);
        let mut count = 0u32;
        for &k in kind {
            count += u32::from(k == FLUID);
            fluid_before.push(count);
        }
        let (grid, fluid_before) = (&self.grid, &self.fluid_before);
        self.dry.clear();
        self.dry.par_extend((0..kind.len()).into_par_iter().map(|i| {
            kind[i] != FLUID
                && grid
                    .neighbour_ranges(i)
                    .all(|r| fluid_before[r.end] == fluid_before[r.start])
        }));
        let dry = &self.dry;
        self.wet.clear();
        self.wet
            .extend((0..kind.len() as u32).filter(|&i| kind[i as usize] != FLUID && !dry[i as usize]));
    }
}
