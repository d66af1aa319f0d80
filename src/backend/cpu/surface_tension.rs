//! The `surface_normals` and `surface_tension` stages, the latter with either model (twin of
//! `kernels/surface_tension.cu`).

use super::CpuBackend;
use crate::fields::{FLUID, Fields};
use crate::math::Vector;
use crate::model::SurfaceTensionModel;
use crate::model::params::StepParams;
use crate::physics::{
    surface_stress::{surface_stress_acceleration, surface_weight, tensile_factor},
    surface_tension::{normal_term, surface_tension_acceleration},
};
use rayon::prelude::*;

impl<const D: usize> CpuBackend<D> {
    pub(super) fn surface_normals(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        let kernel = params.smoothing();
        let grid = &self.grid;
        let mut normal = std::mem::take(&mut fields.normal);
        normal.resize(fields.len(), Vector::zeros());
        let f = &*fields;
        // [AAT13] (3) weighs each neighbour by m_j/ρ_j; the surface stress by its rest volume
        // m_j/ρ0_j (`physics::surface_stress`: a colour field without the surface layer's
        // overshoot).
        let rest_volume = params.surface_tension_model == SurfaceTensionModel::SurfaceStress;
        let rest = |j: usize| params.phases.rest_density(&f.rest_density, j, params.rho0);
        normal.par_iter_mut().enumerate().for_each(|(i, n)| {
            let mut sum = Vector::zeros();
            if f.kind[i] == FLUID {
                grid.for_each_neighbour(&f.position, i, |j, d, _| {
                    if f.kind[j] == FLUID {
                        let rho_j = if rest_volume { rest(j) } else { f.density[j] };
                        sum += normal_term(&kernel, f.mass[j], rho_j, &d);
                    }
                });
            }
            *n = sum * params.h;
        });
        fields.normal = normal;
    }

    pub(super) fn surface_tension(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        if params.surface_tension_model == SurfaceTensionModel::SurfaceStress {
            self.surface_stress(fields, params);
            return;
        }
        let grid = &self.grid;
        let mut acceleration = std::mem::take(&mut fields.acceleration);
        let f = &*fields;
        let (gamma, rho0, h) = (params.surface_tension_gamma, params.rho0, params.h);
        acceleration.par_iter_mut().enumerate().for_each(|(i, a)| {
            if f.kind[i] != FLUID {
                return;
            }
            let (rho_i, n_i) = (f.density[i], f.normal[i]);
            let mut sum = Vector::zeros();
            grid.for_each_neighbour(&f.position, i, |j, d, r2| {
                if j == i || f.kind[j] != FLUID {
                    return;
                }
                // [AAT13] (1)-(5): cohesion and curvature, fluid neighbours only.
                sum += surface_tension_acceleration(
                    gamma,
                    rho0,
                    h,
                    f.mass[j],
                    rho_i,
                    f.density[j],
                    &n_i,
                    &f.normal[j],
                    &d,
                    r2.sqrt(),
                );
            });
            *a += sum;
        });
        fields.acceleration = acceleration;
    }

    /// The `surface_tension` stage with the surface stress (`physics::surface_stress`): the pair
    /// force of the capillary stresses of `i` and `j`, added to the acceleration of fluid `i`.
    fn surface_stress(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        let kernel = params.smoothing();
        let grid = &self.grid;
        let mut acceleration = std::mem::take(&mut fields.acceleration);
        let f = &*fields;
        let (sigma, h) = (params.surface_tension_sigma, params.h);
        let w_dx = kernel.w(params.spacing * params.spacing);
        let rest = |j: usize| params.phases.rest_density(&f.rest_density, j, params.rho0);
        acceleration.par_iter_mut().enumerate().for_each(|(i, a)| {
            if f.kind[i] != FLUID {
                return;
            }
            let (n_i, rho0_i) = (f.normal[i], rest(i));
            let bulk_i = surface_weight(n_i.norm()) == 0.0;
            let mut sum = Vector::zeros();
            grid.for_each_neighbour(&f.position, i, |j, d, r2| {
                if j == i || f.kind[j] != FLUID {
                    return;
                }
                // Neither carries a stress: no force, and no kernel to evaluate.
                if bulk_i && surface_weight(f.normal[j].norm()) == 0.0 {
                    return;
                }
                let grad = kernel.grad_w_spiky(&d, r2.sqrt()) * params.pressure_gradient_scale;
                let tensile = tensile_factor(kernel.w(r2), w_dx);
                sum += surface_stress_acceleration(
                    sigma,
                    h,
                    f.mass[j],
                    rho0_i,
                    rest(j),
                    &n_i,
                    &f.normal[j],
                    &grad,
                    tensile,
                );
            });
            *a += sum;
        });
        fields.acceleration = acceleration;
    }
}
