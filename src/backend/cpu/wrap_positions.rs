//! The `wrap_positions` stage (twin of `kernels/wrap_positions.cu`): fluid particles that left
//! the domain along a periodic axis come back one period away (`crate::periodic`).

use super::CpuBackend;
use crate::fields::{FLUID, Fields};
use crate::model::params::StepParams;
use rayon::prelude::*;

impl<const D: usize> CpuBackend<D> {
    pub(super) fn wrap_positions(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        let periodic = params.periodic();
        let kind = &fields.kind;
        fields.position.par_iter_mut().enumerate().for_each(|(i, x)| {
            if kind[i] == FLUID {
                *x = periodic.wrap(*x);
            }
        });
    }
}
