//! Launchers of the neighbour-search and density-side kernels (`kernels/shim/exports_neighbours.inc`):
//! `sort_by_cell` (`cell_hash`, `scan_chunks`, `scan_chunk_sums`, `scan_add`, `scatter`,
//! `order_cells`, `gather_*`), `density`, `predicted_density` (the velocity solve's),
//! `equation_of_state`, `wall_pressure`, `wall_velocity`, and the test-only `neighbour_list`. Vectors are `D` floats per particle; `GridGeometry` and `StepParams` come by
//! pointer.
#![allow(missing_docs)]

use crate::backend::cuda::grid::GridGeometry;
use crate::backend::params::StepParams;

/// The fields of `StepParams` in declaration order, as `sph_shim_step_params_layout_D` reports
/// their offsets.
pub const STEP_PARAMS_FIELDS: usize = 21;

#[link(name = "sph_kernel_shim_2", kind = "static")]
unsafe extern "C" {
    /// `StepParams`'s size and its fields' offsets in declaration order, as the kernels lay it
    /// out ([`STEP_PARAMS_FIELDS`] + 1 values).
    pub fn sph_shim_step_params_layout_2(out: *mut u64);
    pub fn sph_shim_cell_hash_2(
        n: u32,
        g: *const GridGeometry<2>,
        pos: *const f32,
        key: *mut u32,
        cell_count: *mut u32,
    );
    pub fn sph_shim_scan_chunks_2(m: u32, chunk: u32, input: *const u32, out: *mut u32, chunk_sums: *mut u32);
    pub fn sph_shim_scan_chunk_sums_2(chunks: u32, chunk_sums: *mut u32);
    pub fn sph_shim_scan_add_2(m: u32, chunk: u32, out: *mut u32, chunk_sums: *const u32);
    pub fn sph_shim_scatter_2(
        n: u32,
        key: *const u32,
        cell_start: *const u32,
        cell_fill: *mut u32,
        perm: *mut u32,
    );
    pub fn sph_shim_order_cells_2(ncell: u32, cell_start: *const u32, id: *const u32, perm: *mut u32);
    pub fn sph_shim_gather_vec_2(n: u32, perm: *const u32, src: *const f32, dst: *mut f32);
    pub fn sph_shim_gather_f32_2(n: u32, perm: *const u32, src: *const f32, dst: *mut f32);
    pub fn sph_shim_gather_u32_2(n: u32, perm: *const u32, src: *const u32, dst: *mut u32);
    pub fn sph_shim_density_2(
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
    pub fn sph_shim_predicted_density_2(
        n: u32,
        p: *const StepParams<2>,
        g: *const GridGeometry<2>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        kind: *const u32,
        density_start: *const f32,
        tau: f32,
        density: *mut f32,
    );
    pub fn sph_shim_equation_of_state_2(
        n: u32,
        p: *const StepParams<2>,
        density: *const f32,
        kind: *const u32,
        pressure: *mut f32,
    );
    pub fn sph_shim_wall_pressure_2(
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
    pub fn sph_shim_wall_velocity_2(
        n: u32,
        p: *const StepParams<2>,
        g: *const GridGeometry<2>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        kind: *const u32,
        wall_vel: *mut f32,
    );
    /// Test only: the neighbours `SPH_FOR_EACH_CANDIDATE` yields with `r < h`; `count[i]` of
    /// them, the first `max` in `list[i * max ..]`.
    pub fn sph_shim_neighbour_list_2(
        n: u32,
        h: f32,
        g: *const GridGeometry<2>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        max: u32,
        count: *mut u32,
        list: *mut u32,
    );
}

#[link(name = "sph_kernel_shim_3", kind = "static")]
unsafe extern "C" {
    /// `StepParams`'s size and its fields' offsets in declaration order, as the kernels lay it
    /// out ([`STEP_PARAMS_FIELDS`] + 1 values).
    pub fn sph_shim_step_params_layout_3(out: *mut u64);
    pub fn sph_shim_cell_hash_3(
        n: u32,
        g: *const GridGeometry<3>,
        pos: *const f32,
        key: *mut u32,
        cell_count: *mut u32,
    );
    pub fn sph_shim_scan_chunks_3(m: u32, chunk: u32, input: *const u32, out: *mut u32, chunk_sums: *mut u32);
    pub fn sph_shim_scan_chunk_sums_3(chunks: u32, chunk_sums: *mut u32);
    pub fn sph_shim_scan_add_3(m: u32, chunk: u32, out: *mut u32, chunk_sums: *const u32);
    pub fn sph_shim_scatter_3(
        n: u32,
        key: *const u32,
        cell_start: *const u32,
        cell_fill: *mut u32,
        perm: *mut u32,
    );
    pub fn sph_shim_order_cells_3(ncell: u32, cell_start: *const u32, id: *const u32, perm: *mut u32);
    pub fn sph_shim_gather_vec_3(n: u32, perm: *const u32, src: *const f32, dst: *mut f32);
    pub fn sph_shim_gather_f32_3(n: u32, perm: *const u32, src: *const f32, dst: *mut f32);
    pub fn sph_shim_gather_u32_3(n: u32, perm: *const u32, src: *const u32, dst: *mut u32);
    pub fn sph_shim_density_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        mass: *const f32,
        kind: *const u32,
        density: *mut f32,
    );
    pub fn sph_shim_predicted_density_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        mass: *const f32,
        kind: *const u32,
        density_start: *const f32,
        tau: f32,
        density: *mut f32,
    );
    pub fn sph_shim_equation_of_state_3(
        n: u32,
        p: *const StepParams<3>,
        density: *const f32,
        kind: *const u32,
        pressure: *mut f32,
    );
    pub fn sph_shim_wall_pressure_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
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
    pub fn sph_shim_wall_velocity_3(
        n: u32,
        p: *const StepParams<3>,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        vel: *const f32,
        kind: *const u32,
        wall_vel: *mut f32,
    );
    /// Test only: the neighbours `SPH_FOR_EACH_CANDIDATE` yields with `r < h`; `count[i]` of
    /// them, the first `max` in `list[i * max ..]`.
    pub fn sph_shim_neighbour_list_3(
        n: u32,
        h: f32,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        max: u32,
        count: *mut u32,
        list: *mut u32,
    );
}
