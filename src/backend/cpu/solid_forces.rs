//! The `solid_forces` stage: the fluid's force on each named solid and its moment about the
//! origin (`backend::SolidLoad`; twin of `kernels/solid_forces.cu`).

use super::CpuBackend;
use super::forces::fill_volume_pressure_terms;
use crate::backend::{SolidForceSource, SolidLoad};
use crate::boundary::solid_force::{force_on_solid, particle_load};
use crate::fields::{FLUID, Fields};
use crate::math::{Vector, sum_by_group};
use crate::model::pair_terms::with_pair_terms;
use crate::model::params::StepParams;
use crate::physics::multiphase::{self, Phases};
use crate::physics::pair::Pair;

impl<const D: usize> CpuBackend<D> {
    pub(super) fn solid_forces(
        &mut self,
        fields: &Fields<D>,
        params: &StepParams<D>,
        solids: usize,
        source: SolidForceSource,
    ) -> Vec<SolidLoad> {
        let kernel = params.smoothing();
        let neighbours = &self.grid;
        let f = fields;
        // The correction moves particles by pressure alone: its own pressures, no pair terms.
        let terms = source.pair_terms();
        let pressure = match source {
            SolidForceSource::Forces(_) => &f.pressure,
            SolidForceSource::Correction => &self.delta_p,
        };
        if pressure.len() != f.len() {
            // Nothing to add here, but every rank takes part in the sum below.
            let mut loads = vec![[0.0; 6]; solids];
            self.add_over_ranks(&mut loads);
            return loads;
        }
        // [HA06] (`multiphase`): the pressure pair term in the volume form, as the fluid feels it;
        // the viscous terms as without it.
        let multiphase = params.phases == Phases::Multi;
        if multiphase {
            fill_volume_pressure_terms(&mut self.pressure_terms, pressure, &f.mass, &f.density);
        }
        let q = &self.pressure_terms;
        let partition = &self.partition;
        let mut loads = with_pair_terms!(terms.bits(), TERMS => sum_by_group(f.len(), solids, |s| {
            let kind = f.kind[s];
            // Dry solids add nothing; a ghost's load is its owner's.
            if kind == FLUID || self.is_dry(s) || !partition.counts(s) {
                return None;
            }
            let mut force = Vector::<D>::zeros();
            neighbours.for_each_neighbour(&f.position, s, |j, d, r2| {
                if f.kind[j] != FLUID {
                    return;
                }
                let r = r2.sqrt();
                let grad = kernel.grad_w_spiky(&d, r) * params.pressure_gradient_scale;
                let pressures = if multiphase {
                    [0.0, 0.0]
                } else {
                    [pressure[s], pressure[j]]
                };
                let pair = Pair {
                    x_ij: &d,
                    r,
                    u_i: &f.velocity[s],
                    u_j: &f.velocity[j],
                    viscous_u_i: f.wall_velocity.get(s).unwrap_or(&f.velocity[s]),
                    viscous_u_j: &f.velocity[j],
                    rho_i: f.density[s],
                    rho_j: f.density[j],
                    m_j: f.mass[j],
                    grad_w: &grad,
                    kernel: &kernel,
                    wall: true,
                };
                let mut pair = force_on_solid::<D, TERMS>(params, f.mass[s], pressures, &pair);
                if multiphase {
                    pair += multiphase::pressure_acceleration(q[s], q[j], 1.0, &grad);
                }
                force += pair;
            });
            Some((kind as usize - 1, particle_load(&f.position[s], &force)))
        }));
        self.add_over_ranks(&mut loads);
        loads
    }

    /// Each load summed over ranks (`backend::partition`).
    pub(super) fn add_over_ranks(&mut self, loads: &mut [SolidLoad]) {
        let mut flat: Vec<f64> = loads.iter().flatten().copied().collect();
        self.partition.sum(&mut flat);
        for (load, total) in loads.iter_mut().zip(flat.chunks_exact(6)) {
            load.copy_from_slice(total);
        }
    }
}
