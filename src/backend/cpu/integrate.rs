//! The `integrate`, `store_step_start` and `rk_stage` stages, and their density twins of the
//! `density_diffusion` effect, `integrate_density`, `store_density_start` and
//! `rk_density_stage` (twin of `kernels/integrate.cu`).

use super::CpuBackend;
use crate::fields::{FLUID, Fields};
use rayon::prelude::*;

impl<const D: usize> CpuBackend<D> {
    pub(super) fn integrate(&mut self, fields: &mut Fields<D>, dt: f32) {
        let kind = &fields.kind;
        let acceleration = &fields.acceleration;
        fields
            .velocity
            .par_iter_mut()
            .zip(fields.position.par_iter_mut())
            .enumerate()
            .for_each(|(i, (u, x))| {
                if kind[i] == FLUID {
                    *u += acceleration[i] * dt;
                    *x += *u * dt;
                }
            });
    }

    pub(super) fn store_step_start(&mut self, fields: &mut Fields<D>) {
        fields.position_start.clone_from(&fields.position);
        fields.velocity_start.clone_from(&fields.velocity);
    }

    pub(super) fn rk_stage(&mut self, fields: &mut Fields<D>, dt: f32, a: f32, b: f32) {
        let Fields {
            position,
            velocity,
            acceleration,
            kind,
            position_start,
            velocity_start,
            ..
        } = fields;
        velocity
            .par_iter_mut()
            .zip(position.par_iter_mut())
            .enumerate()
            .for_each(|(i, (u, x))| {
                if kind[i] == FLUID {
                    let x_euler = *x + *u * dt;
                    let u_euler = *u + acceleration[i] * dt;
                    *x = position_start[i] * a + x_euler * b;
                    *u = velocity_start[i] * a + u_euler * b;
                }
            });
    }

    pub(super) fn integrate_density(&mut self, fields: &mut Fields<D>, dt: f32) {
        let (kind, rate) = (&fields.kind, &fields.density_rate);
        fields.density.par_iter_mut().enumerate().for_each(|(i, rho)| {
            if kind[i] == FLUID {
                *rho += rate[i] * dt;
            }
        });
    }

    pub(super) fn store_density_start(&mut self, fields: &mut Fields<D>) {
        fields.density_start.clone_from(&fields.density);
    }

    pub(super) fn rk_density_stage(&mut self, fields: &mut Fields<D>, dt: f32, a: f32, b: f32) {
        let (kind, rate, start) = (&fields.kind, &fields.density_rate, &fields.density_start);
        fields.density.par_iter_mut().enumerate().for_each(|(i, rho)| {
            if kind[i] == FLUID {
                let euler = *rho + rate[i] * dt;
                *rho = start[i] * a + euler * b;
            }
        });
    }
}
