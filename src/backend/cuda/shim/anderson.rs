//! Launchers of the velocity solve's iteration (`kernels/shim/exports_anderson.inc`, kernels of
//! `kernels/anderson.cu`): `anderson_difference`, `anderson_dots` (the backend's launch shape,
//! about n/64 threads), `anderson_mix`, `velocity_solve_increments`,
//! `velocity_solve_solid_pressure`, `velocity_from_displacement`. The rest of the sequence is in
//! the other groups (`correction_pressure_fluid`, `correction_pressure_wall`,
//! `correction_displacement` and their multiphase variants). Same arguments as the kernels.
#![allow(missing_docs)]

#[link(name = "sph_kernel_shim_2", kind = "static")]
unsafe extern "C" {
    pub fn sph_shim_anderson_difference_2(
        n: u32,
        slot: u32,
        pressure: *const f32,
        previous: *const f32,
        f: *const f32,
        previous_f: *const f32,
        dp_slots: *mut f32,
        df_slots: *mut f32,
    );
    pub fn sph_shim_anderson_dots_2(n: u32, count: u32, a: *const f32, slots: *const f32, out: *mut f64);
    pub fn sph_shim_anderson_mix_2(
        n: u32,
        held: u32,
        gamma: *const f32,
        kind: *const u32,
        f: *const f32,
        dp_slots: *const f32,
        df_slots: *const f32,
        previous: *mut f32,
        previous_f: *mut f32,
        pressure: *mut f32,
    );
    pub fn sph_shim_velocity_solve_increments_2(
        n: u32,
        kind: *const u32,
        pressure: *const f32,
        pressure_start: *const f32,
        delta_p: *mut f32,
    );
    pub fn sph_shim_velocity_solve_solid_pressure_2(
        n: u32,
        kind: *const u32,
        pressure_start: *const f32,
        delta_p: *const f32,
        pressure: *mut f32,
    );
    pub fn sph_shim_velocity_from_displacement_2(
        n: u32,
        tau: f32,
        kind: *const u32,
        velocity_start: *const f32,
        displacement: *const f32,
        vel: *mut f32,
    );
}

#[link(name = "sph_kernel_shim_3", kind = "static")]
unsafe extern "C" {
    pub fn sph_shim_anderson_difference_3(
        n: u32,
        slot: u32,
        pressure: *const f32,
        previous: *const f32,
        f: *const f32,
        previous_f: *const f32,
        dp_slots: *mut f32,
        df_slots: *mut f32,
    );
    pub fn sph_shim_anderson_dots_3(n: u32, count: u32, a: *const f32, slots: *const f32, out: *mut f64);
    pub fn sph_shim_anderson_mix_3(
        n: u32,
        held: u32,
        gamma: *const f32,
        kind: *const u32,
        f: *const f32,
        dp_slots: *const f32,
        df_slots: *const f32,
        previous: *mut f32,
        previous_f: *mut f32,
        pressure: *mut f32,
    );
    pub fn sph_shim_velocity_solve_increments_3(
        n: u32,
        kind: *const u32,
        pressure: *const f32,
        pressure_start: *const f32,
        delta_p: *mut f32,
    );
    pub fn sph_shim_velocity_solve_solid_pressure_3(
        n: u32,
        kind: *const u32,
        pressure_start: *const f32,
        delta_p: *const f32,
        pressure: *mut f32,
    );
    pub fn sph_shim_velocity_from_displacement_3(
        n: u32,
        tau: f32,
        kind: *const u32,
        velocity_start: *const f32,
        displacement: *const f32,
        vel: *mut f32,
    );
}
