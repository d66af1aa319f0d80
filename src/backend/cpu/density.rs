//! The `density`, `equation_of_state` and `predicted_density` stages (twins of
//! `kernels/density.cu` and `kernels/equation_of_state.cu`).

use super::CpuBackend;
use crate::fields::{FLUID, Fields};
use crate::model::params::StepParams;
use crate::physics::{
    density::{DensityKernel, density_kernel_gradient, density_term, velocity_solve_base},
    eos,
    multiphase::{self, Phases},
};
use rayon::prelude::*;

impl<const D: usize> CpuBackend<D> {
    pub(super) fn density(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        let kernel = params.smoothing();
        let weight = params.density_weight();
        let grid = &self.grid;
        let (position, mass, kind) = (&fields.position, &fields.mass, &fields.kind);
        if params.phases == Phases::Multi {
            // [HA06]: ρ_i = m_i Σ_j W_ij, blind to the neighbours' phases.
            fields.density.par_iter_mut().enumerate().for_each(|(i, rho)| {
                if kind[i] != FLUID {
                    return;
                }
                let mut sigma = 0.0;
                grid.for_each_neighbour(position, i, |_, _, r2| {
                    sigma += multiphase::number_density_term(&kernel, weight, r2)
                });
                *rho = multiphase::density(mass[i], sigma);
            });
            return;
        }
        fields.density.par_iter_mut().enumerate().for_each(|(i, rho)| {
            if kind[i] != FLUID {
                return;
            }
            let mut sum = 0.0;
            grid.for_each_neighbour(position, i, |j, _, r2| {
                sum += density_term(&kernel, weight, mass[j], r2)
            });
            *rho = sum;
        });
    }

    pub(super) fn equation_of_state(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        let kind = &fields.kind;
        let density = &fields.density;
        let rest = &fields.rest_density;
        fields.pressure.par_iter_mut().enumerate().for_each(|(i, p)| {
            if kind[i] == FLUID {
                // With the multiphase effect, each particle's own rest density ([HA06]).
                let rho0 = params.phases.rest_density(rest, i, params.rho0);
                *p = eos::pressure(density[i], rho0, params.c2);
            }
        });
    }

    pub(super) fn predicted_density(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, tau: f32) {
        let kernel = params.smoothing();
        let weight = params.density_weight();
        let (velocity, mass, kind) = (&fields.velocity, &fields.mass, &fields.kind);
        let rest = &fields.rest_density;
        let multiphase = params.phases == Phases::Multi;
        let start = &self.density_solve_start;
        assert_eq!(
            start.len(),
            fields.len(),
            "predicted_density outside a velocity solve"
        );
        let base = |i: usize| velocity_solve_base(start[i], params.phases.rest_density(rest, i, params.rho0));
        let m = |i: usize, j: usize| if multiphase { mass[i] } else { mass[j] };
        match weight.kernel {
            // `corrected`: the list's spiky gradients (`crate::neighbour_list`), scaled as
            // `density_kernel_gradient` scales them.
            DensityKernel::ScaledSpiky => {
                let list = &self.velocity_neighbours;
                fields.density.par_iter_mut().enumerate().for_each(|(i, rho)| {
                    if kind[i] != FLUID {
                        return;
                    }
                    let mut rate = 0.0;
                    list.for_each_gradient(i, |j, spiky| {
                        let grad = spiky * weight.spiky_scale;
                        rate += m(i, j) * (velocity[i] - velocity[j]).dot(&grad);
                    });
                    *rho = base(i) + tau * rate;
                });
            }
            DensityKernel::Poly6 => {
                let (grid, position) = (&self.grid, &fields.position);
                fields.density.par_iter_mut().enumerate().for_each(|(i, rho)| {
                    if kind[i] != FLUID {
                        return;
                    }
                    let mut rate = 0.0;
                    grid.for_each_neighbour(position, i, |j, d, r2| {
                        if j != i {
                            let grad = density_kernel_gradient(&kernel, weight, &d, r2.sqrt());
                            rate += m(i, j) * (velocity[i] - velocity[j]).dot(&grad);
                        }
                    });
                    *rho = base(i) + tau * rate;
                });
            }
        }
    }
}
