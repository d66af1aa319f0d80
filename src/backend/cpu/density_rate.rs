//! The `density_rate` stage: the continuity equation with [F19] density diffusion (twin of
//! `kernels/density_rate.cu`); its time integration is in `integrate`.

use super::CpuBackend;
use crate::fields::{FLUID, Fields};
use crate::model::params::StepParams;
use crate::physics::density_diffusion::{DiffusionCoefficients, continuity_term, diffusion_term};
use rayon::prelude::*;

impl<const D: usize> CpuBackend<D> {
    pub(super) fn density_rate(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        let kernel = params.smoothing();
        let weight = params.density_weight();
        let c = DiffusionCoefficients::new(
            params.density_diffusion,
            params.h,
            params.c2,
            params.rho0,
            &params.gravity,
        );
        let grid = &self.grid;
        let n = fields.len();
        let mut rate = std::mem::take(&mut fields.density_rate);
        rate.resize(n, 0.0);
        let f = &*fields;
        rate.par_iter_mut().enumerate().for_each(|(i, out)| {
            if f.kind[i] != FLUID {
                *out = 0.0;
                return;
            }
            let (u_i, rho_i) = (f.velocity[i], f.density[i]);
            let mut sum = 0.0;
            grid.for_each_neighbour(&f.position, i, |j, d, r2| {
                if j == i {
                    return;
                }
                let r = r2.sqrt();
                let fluid = f.kind[j] == FLUID;
                // A solid moves with the velocity the force stage gives it (no-slip walls).
                let u_j = if fluid {
                    &f.velocity[j]
                } else {
                    f.wall_velocity.get(j).unwrap_or(&f.velocity[j])
                };
                sum += continuity_term(&kernel, weight, f.mass[j], &(u_i - u_j), &d, r);
                if fluid {
                    // Fluid-fluid only, as DualSPHysics: a wall's density is the wall model's.
                    sum += diffusion_term(&kernel, weight, &c, rho_i, f.density[j], f.mass[j], &d, r);
                }
            });
            *out = sum;
        });
        fields.density_rate = rate;
    }
}
