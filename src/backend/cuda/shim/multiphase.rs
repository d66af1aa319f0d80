//! Launchers of the `multiphase` effect's kernels (`kernels/shim/exports_multiphase.inc`), 2D:
//! `density_multiphase`, `predicted_density_multiphase`, `equation_of_state_multiphase`,
//! `wall_pressure_multiphase`, `forces_p_mp`, `forces_pv_mp`, and the correction's `correction_error_multiphase`,
//! `correction_pressure_fluid_multiphase`, `correction_displacement_multiphase`, and
//! `solid_forces_multiphase`, `state_extremes_multiphase`.
#![allow(missing_docs)]

use crate::backend::cuda::extremes::DeviceExtremes;
use crate::backend::cuda::grid::GridGeometry;
use crate::backend::params::StepParams;

#[link(name = "sph_kernel_shim_2", kind = "static")]
unsafe extern "C" {
    pub fn sph_shim_density_multiphase_2(
        n: u32,
        p: *const StepParams<2>,
        g: *const GridGeometry<2>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        mass: *const f32,
        kind: *const u32,
        density: *mut f32,
    );
    pub fn sph_shim_predicted_density_multiphase_2(
        n: u32,
        p: *const StepParams<2>,
        g: *const GridGeometry<2>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        rest: *const f32,
        kind: *const u32,
        density_start: *const f32,
        tau: f32,
        density: *mut f32,
    );
    pub fn sph_shim_equation_of_state_multiphase_2(
        n: u32,
        p: *const StepParams<2>,
        density: *const f32,
        rest: *const f32,
        kind: *const u32,
        pressure: *mut f32,
    );
    pub fn sph_shim_wall_pressure_multiphase_2(
        n: u32,
        p: *const StepParams<2>,
        g: *const GridGeometry<2>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        mass: *const f32,
        kind: *const u32,
        wall_acc: *const f32,
        extrapolated_or_summed: i32,
        pressure: *mut f32,
        density: *mut f32,
    );
    pub fn sph_shim_forces_p_mp_2(
        n: u32,
        p: *const StepParams<2>,
        g: *const GridGeometry<2>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        wall_vel: *const f32,
        acc: *mut f32,
    );
    pub fn sph_shim_forces_pv_mp_2(
        n: u32,
        p: *const StepParams<2>,
        g: *const GridGeometry<2>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        wall_vel: *const f32,
        acc: *mut f32,
    );
    pub fn sph_shim_correction_error_multiphase_2(
        n: u32,
        rest: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        out: *mut i32,
    );
    pub fn sph_shim_correction_pressure_fluid_multiphase_2(
        n: u32,
        rest: *const f32,
        k: f32,
        beta: f32,
        has_prev: i32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        delta_p_prev: *const f32,
        delta_p: *mut f32,
    );
    pub fn sph_shim_correction_displacement_multiphase_2(
        n: u32,
        p: *const StepParams<2>,
        g: *const GridGeometry<2>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        mass: *const f32,
        density: *const f32,
        delta_p: *const f32,
        kind: *const u32,
        tau2: f32,
        displacement: *mut f32,
        largest: *mut i32,
    );
    pub fn sph_shim_solid_forces_multiphase_2(
        n: u32,
        p: *const StepParams<2>,
        g: *const GridGeometry<2>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        wall_vel: *const f32,
        out: *mut f64,
    );
    pub fn sph_shim_state_extremes_multiphase_2(
        n: u32,
        p: *const StepParams<2>,
        pos: *const f32,
        vel: *const f32,
        acc: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        rest: *const f32,
        out: *mut DeviceExtremes,
    );
}
