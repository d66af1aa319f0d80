//! Launchers of the force, integration and correction kernels (`kernels/shim/exports_dynamics.inc`):
//! `forces_p`, `forces_pv`, `forces_pa`, `forces_pva`, `forces_pr`, `forces_pvr`, `forces_par`,
//! `forces_pvar`, `solid_forces`, `state_extremes`,
//! `integrate`, `store_step_start`, `rk_stage`, `correction_error`, `correction_pressure_fluid`,
//! `correction_pressure_wall`, `correction_pressure_apply`, `correction_displacement`,
//! `apply_displacement`, `keep_out`, `move_solids`. Same arguments as the kernels, `StepParams` and
//! `GridGeometry` by pointer.
#![allow(missing_docs)]

use crate::backend::cuda::extremes::DeviceExtremes;
use crate::backend::cuda::grid::GridGeometry;
use crate::backend::params::StepParams;

#[link(name = "sph_kernel_shim_2", kind = "static")]
unsafe extern "C" {
    pub fn sph_shim_forces_p_2(
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
        acc: *mut f32,
    );
    pub fn sph_shim_forces_pv_2(
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
        acc: *mut f32,
    );
    pub fn sph_shim_forces_pa_2(
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
        acc: *mut f32,
    );
    pub fn sph_shim_forces_pva_2(
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
        acc: *mut f32,
    );
    pub fn sph_shim_forces_pr_2(
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
        acc: *mut f32,
    );
    pub fn sph_shim_forces_pvr_2(
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
        acc: *mut f32,
    );
    pub fn sph_shim_forces_par_2(
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
        acc: *mut f32,
    );
    pub fn sph_shim_forces_pvar_2(
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
        acc: *mut f32,
    );
    pub fn sph_shim_solid_forces_2(
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
        out: *mut f64,
    );
    pub fn sph_shim_move_solids_2(
        n: u32,
        kind: *const u32,
        id: *const u32,
        first_id: u32,
        reference: *const f32,
        motion: *const f32,
        pos: *mut f32,
        vel: *mut f32,
    );
    pub fn sph_shim_state_extremes_2(
        n: u32,
        p: *const StepParams<2>,
        pos: *const f32,
        vel: *const f32,
        acc: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        out: *mut DeviceExtremes,
    );
    pub fn sph_shim_integrate_2(
        n: u32,
        dt: f32,
        kind: *const u32,
        acc: *const f32,
        vel: *mut f32,
        pos: *mut f32,
    );
    pub fn sph_shim_store_step_start_2(
        n: u32,
        pos: *const f32,
        vel: *const f32,
        pos_start: *mut f32,
        vel_start: *mut f32,
    );
    pub fn sph_shim_rk_stage_2(
        n: u32,
        dt: f32,
        a: f32,
        b: f32,
        kind: *const u32,
        acc: *const f32,
        pos_start: *const f32,
        vel_start: *const f32,
        pos: *mut f32,
        vel: *mut f32,
    );
    pub fn sph_shim_correction_error_2(
        n: u32,
        rho0: f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        out: *mut i32,
    );
    pub fn sph_shim_correction_pressure_fluid_2(
        n: u32,
        rho0: f32,
        k: f32,
        beta: f32,
        has_prev: i32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        delta_p_prev: *const f32,
        delta_p: *mut f32,
    );
    pub fn sph_shim_correction_pressure_wall_2(
        n: u32,
        p: *const StepParams<2>,
        g: *const GridGeometry<2>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        density: *const f32,
        kind: *const u32,
        delta_p: *mut f32,
    );
    pub fn sph_shim_correction_pressure_apply_2(
        n: u32,
        delta_p: *const f32,
        pressure: *mut f32,
        delta_p_prev: *mut f32,
    );
    pub fn sph_shim_correction_displacement_2(
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
    pub fn sph_shim_apply_displacement_2(
        n: u32,
        scale: f32,
        tau: f32,
        kind: *const u32,
        displacement: *const f32,
        pos: *mut f32,
        vel: *mut f32,
    );
    pub fn sph_shim_keep_out_2(
        n: u32,
        boxes: u32,
        boxes_data: *const f32,
        margin: f32,
        kind: *const u32,
        mass: *const f32,
        pos: *mut f32,
        vel: *mut f32,
        out: *mut f64,
    );
    /// `sizeof(Extremes)`, then each field's offset (11 values).
    pub fn sph_shim_extremes_layout_2(out: *mut u32);
}

#[link(name = "sph_kernel_shim_3", kind = "static")]
unsafe extern "C" {
    pub fn sph_shim_forces_p_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        acc: *mut f32,
    );
    pub fn sph_shim_forces_pv_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        acc: *mut f32,
    );
    pub fn sph_shim_forces_pa_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        acc: *mut f32,
    );
    pub fn sph_shim_forces_pva_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        acc: *mut f32,
    );
    pub fn sph_shim_forces_pr_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        acc: *mut f32,
    );
    pub fn sph_shim_forces_pvr_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        acc: *mut f32,
    );
    pub fn sph_shim_forces_par_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        acc: *mut f32,
    );
    pub fn sph_shim_forces_pvar_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        acc: *mut f32,
    );
    pub fn sph_shim_solid_forces_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        out: *mut f64,
    );
    pub fn sph_shim_move_solids_3(
        n: u32,
        kind: *const u32,
        id: *const u32,
        first_id: u32,
        reference: *const f32,
        motion: *const f32,
        pos: *mut f32,
        vel: *mut f32,
    );
    pub fn sph_shim_state_extremes_3(
        n: u32,
        p: *const StepParams<3>,
        pos: *const f32,
        vel: *const f32,
        acc: *const f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        out: *mut DeviceExtremes,
    );
    pub fn sph_shim_integrate_3(
        n: u32,
        dt: f32,
        kind: *const u32,
        acc: *const f32,
        vel: *mut f32,
        pos: *mut f32,
    );
    pub fn sph_shim_store_step_start_3(
        n: u32,
        pos: *const f32,
        vel: *const f32,
        pos_start: *mut f32,
        vel_start: *mut f32,
    );
    pub fn sph_shim_rk_stage_3(
        n: u32,
        dt: f32,
        a: f32,
        b: f32,
        kind: *const u32,
        acc: *const f32,
        pos_start: *const f32,
        vel_start: *const f32,
        pos: *mut f32,
        vel: *mut f32,
    );
    pub fn sph_shim_correction_error_3(
        n: u32,
        rho0: f32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        out: *mut i32,
    );
    pub fn sph_shim_correction_pressure_fluid_3(
        n: u32,
        rho0: f32,
        k: f32,
        beta: f32,
        has_prev: i32,
        density: *const f32,
        pressure: *const f32,
        kind: *const u32,
        delta_p_prev: *const f32,
        delta_p: *mut f32,
    );
    pub fn sph_shim_correction_pressure_wall_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        density: *const f32,
        kind: *const u32,
        delta_p: *mut f32,
    );
    pub fn sph_shim_correction_pressure_apply_3(
        n: u32,
        delta_p: *const f32,
        pressure: *mut f32,
        delta_p_prev: *mut f32,
    );
    pub fn sph_shim_correction_displacement_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
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
    pub fn sph_shim_apply_displacement_3(
        n: u32,
        scale: f32,
        tau: f32,
        kind: *const u32,
        displacement: *const f32,
        pos: *mut f32,
        vel: *mut f32,
    );
    pub fn sph_shim_keep_out_3(
        n: u32,
        boxes: u32,
        boxes_data: *const f32,
        margin: f32,
        kind: *const u32,
        mass: *const f32,
        pos: *mut f32,
        vel: *mut f32,
        out: *mut f64,
    );
    /// `sizeof(Extremes)`, then each field's offset (11 values).
    pub fn sph_shim_extremes_layout_3(out: *mut u32);
}
