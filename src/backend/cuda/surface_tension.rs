//! Stages `surface_normals` and `surface_tension` on the device (`kernels/surface_tension.cu`, both
//! models).

use super::*;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    pub(super) fn launch_surface_normals(&mut self, params: &StepParams<D>) {
        if self.error.is_some() {
            return;
        }
        let Some(g) = self.grid.as_ref() else { return };
        if self.normal.is_none() {
            let r = self.dev.alloc_zeros::<f32>((self.n * D).max(1));
            match record(&mut self.error, "allocating the surface normals", r) {
                Some(b) => self.normal = Some(b),
                None => return,
            }
        }
        let n = self.n as u32;
        let Some(normal) = self.normal.as_mut() else {
            return;
        };
        let rest = match params.phases {
            // The kernel reads no rest density then; any f32 buffer stands in.
            Phases::Single => &self.f.density,
            Phases::Multi => match multiphase_rest(&self.f.rest_density, &mut self.error) {
                Some(rest) => rest,
                None => return,
            },
        };
        launch!(
            self,
            "computing the surface normals",
            surface_normals(
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.mass,
                &self.f.density,
                rest,
                &self.f.kind,
                &self.f.id,
                normal
            )
        );
    }

    pub(super) fn launch_surface_tension(&mut self, params: &StepParams<D>) {
        if self.error.is_some() {
            return;
        }
        let (Some(g), Some(normal)) = (self.grid.as_ref(), self.normal.as_ref()) else {
            return;
        };
        let n = self.n as u32;
        let rest = match params.phases {
            // The kernel reads no rest density then; any f32 buffer stands in.
            Phases::Single => &self.f.density,
            Phases::Multi => match multiphase_rest(&self.f.rest_density, &mut self.error) {
                Some(rest) => rest,
                None => return,
            },
        };
        launch!(
            self,
            "computing the surface tension",
            surface_tension(
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.mass,
                &self.f.density,
                rest,
                &self.f.kind,
                &self.f.id,
                normal,
                &mut self.f.acceleration
            )
        );
    }
}
