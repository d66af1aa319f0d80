//! The `solid_forces` stage: the fluid's force on each named solid (twin of
//! `kernels/solid_forces.cu`).

use super::CpuBackend;
use super::forces::fill_volume_pressure_terms;
use crate::backend::SolidForceSource;
use crate::boundary::solid_force::force_on_solid;
use crate::fields::{FLUID, Fields};
use crate::math::{Vector, sum_by_group, to_xyz};
use crate::model::params::StepParams;
use crate::physics::multiphase::{self, Phases};

impl<const D: usize> CpuBackend<D> {
    pub(super) fn solid_forces(
        &mut self,
        fields: &Fields<D>,
        params: &StepParams<D>,
        solids: usize,
        source: SolidForceSource,
    ) -> Vec<[f64; 3]> {
        let kernel = params.smoothing();
        let neighbours = Self::neighbours(&self.grid, &self.velocity_neighbours);
        let f = fields;
        // The correction moves particles by pressure alone: its own pressures, no viscous terms.
        let params = source.params(params);
        let pressure = match source {
            SolidForceSource::Forces => &f.pressure,
            SolidForceSource::Correction => &self.delta_p,
        };
        if pressure.len() != f.len() {
            return vec![[0.0; 3]; solids];
        }
        // [HA06] (`multiphase`): the pressure pair term in the volume form, as the fluid feels it;
        // the viscous terms as without it.
        let multiphase = params.phases == Phases::Multi;
        if multiphase {
            fill_volume_pressure_terms(&mut self.pressure_terms, pressure, &f.mass, &f.density);
        }
        let q = &self.pressure_terms;
        sum_by_group(f.len(), solids, |s| {
            let kind = f.kind[s];
            if kind == FLUID || self.is_dry(s) {
                return None;
            }
            let mut force = Vector::<D>::zeros();
            neighbours.for_each_neighbour(&f.position, s, |j, d, r2| {
                if f.kind[j] != FLUID {
                    return;
                }
                let r = r2.sqrt();
                let grad = kernel.grad_w_spiky(&d, r) * params.pressure_gradient_scale;
                let (p_s, p_j) = if multiphase {
                    (0.0, 0.0)
                } else {
                    (pressure[s], pressure[j])
                };
                let mut pair = force_on_solid(
                    &params,
                    [f.mass[s], p_s, f.density[s]],
                    [f.mass[j], p_j, f.density[j]],
                    &d,
                    [&f.velocity[s], &f.velocity[j]],
                    f.wall_velocity.get(s).unwrap_or(&f.velocity[s]),
                    &grad,
                    kernel.laplacian_w_viscosity(r),
                );
                if multiphase {
                    pair += multiphase::pressure_acceleration(q[s], q[j], 1.0, &grad);
                }
                force += pair;
            });
            Some((kind as usize - 1, to_xyz(&force)))
        })
    }
}
