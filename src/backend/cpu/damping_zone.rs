//! The `damping_zone` stage (twin of `kernels/damping_zone.cu`): fluid velocities relaxed
//! towards zero in the zone ([AEA17], `physics::damping_zone`).

use super::CpuBackend;
use crate::fields::{FLUID, Fields};
use crate::physics::damping_zone::DampingZone;
use rayon::prelude::*;

impl<const D: usize> CpuBackend<D> {
    pub(super) fn damping_zone(&mut self, fields: &mut Fields<D>, zone: &DampingZone<D>, dt: f32) {
        let (kind, position) = (&fields.kind, &fields.position);
        fields.velocity.par_iter_mut().enumerate().for_each(|(i, u)| {
            if kind[i] == FLUID {
                *u *= zone.velocity_factor(&position[i], dt);
            }
        });
    }
}
