//! The `integrate`, `store_step_start` and `rk_stage` stages (twin of `kernels/integrate.cu`).

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
}
