//! Launchers of the neighbour-search and density-side kernels (`kernels/shim/exports_neighbours.inc`).
#![allow(missing_docs)]

use crate::backend::params::StepParams;

#[link(name = "sph_kernel_shim_2", kind = "static")]
unsafe extern "C" {
    pub fn sph_shim_equation_of_state_2(
        n: u32,
        p: *const StepParams<2>,
        density: *const f32,
        kind: *const u32,
        pressure: *mut f32,
    );
}

#[link(name = "sph_kernel_shim_3", kind = "static")]
unsafe extern "C" {
    pub fn sph_shim_equation_of_state_3(
        n: u32,
        p: *const StepParams<3>,
        density: *const f32,
        kind: *const u32,
        pressure: *mut f32,
    );
}
