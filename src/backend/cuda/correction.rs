//! The position correction (eqs. 23-24) and the velocity solve's start and end on the device
//! (`kernels/correction.cu`); the solve's iteration is in `anderson`.

use super::*;

/// What a sweep reports when nothing ran (no grid yet, or an earlier failure).
const NO_SWEEP: Sweep = Sweep {
    largest: 0.0,
    scale: 1.0,
};

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    /// Sizes the `corrected` solver's buffers (`delta_p`, `displacement`, the `*_solve_start`
    /// copies) to the particle count at its first stage; later calls find them sized. A reload
    /// (new particle count, a split run's halo rebuild within a correction) makes them small
    /// again, so the stages that write them first call this too.
    pub(super) fn ensure_correction_buffers(&mut self) {
        if self.delta_p.len() >= self.n || self.error.is_some() {
            return;
        }
        let (n, dn) = (self.n.max(1), (self.n * D).max(1));
        let dev = &self.dev;
        let r = (|| -> Result<(), DeviceFault> {
            self.delta_p = dev.alloc_zeros::<f32>(n)?;
            self.displacement = dev.alloc_zeros::<f32>(dn)?;
            self.velocity_solve_start = dev.alloc_zeros::<f32>(dn)?;
            self.pressure_solve_start = dev.alloc_zeros::<f32>(n)?;
            self.density_solve_start = dev.alloc_zeros::<f32>(n)?;
            Ok(())
        })();
        record(&mut self.error, "allocating the correction's buffers", r);
    }

    /// Launches eq. (23) without moving anything (`correction_displacement`, or its [HA06]
    /// variant): `Δx = τ² a^press(δp)` of every fluid particle into `displacement`, with the
    /// densities (18) in the `density` field or, for the velocity solve (`solve_start`), those
    /// `begin_velocity_solve` remembered; the bits of the largest |Δx| go to `reduce_i32[0]`
    /// through atomicMax, which the caller clears first when it reads them. `None` without a
    /// grid or after a failure.
    pub(super) fn launch_displacements(
        &mut self,
        params: &StepParams<D>,
        tau: f32,
        solve_start: bool,
    ) -> Option<()> {
        let g = self.grid.as_ref()?;
        if self.error.is_some() {
            return None;
        }
        let n = self.n as u32;
        let tau2 = tau * tau;
        let density = if solve_start {
            &self.density_solve_start
        } else {
            &self.f.density
        };
        launch!(
            self,
            "computing displacements",
            correction_displacement(
                params.phases as usize,
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.mass,
                density,
                &self.delta_p,
                &self.f.kind,
                &self.f.id,
                &self.owned,
                tau2,
                &mut self.displacement,
                &mut self.reduce_i32
            )
        );
        Some(())
    }

    /// `correct_positions`' displacements (as `CpuBackend::correction_displacements`): eq. (23)
    /// into `displacement`, and the one scale that keeps the largest within `max_step` [m].
    /// `None` without a grid or after a failure.
    fn correction_displacements(&mut self, params: &StepParams<D>, tau: f32, max_step: f32) -> Option<Sweep> {
        self.ensure_correction_buffers();
        self.grid.as_ref()?;
        if self.error.is_some() {
            return None;
        }
        let r = self.dev.zero(&mut self.reduce_i32);
        record(&mut self.error, "clearing the largest displacement", r)?;
        self.launch_displacements(params, tau, false)?;
        let out = self.dev.download(&self.reduce_i32);
        let out = record(&mut self.error, "copying the largest displacement", out)?;
        // One scale on every rank of a split run (only a finite cap scales), as on the CPU.
        let mut largest = [max_from_bits(out[0])];
        if max_step.is_finite() {
            self.partition.max(&mut largest);
        }
        Some(sweep(largest[0], max_step))
    }

    pub(super) fn launch_correction_error(&mut self, params: &StepParams<D>) -> CorrectionError {
        let failed = CorrectionError {
            compression: f64::NAN,
            residual: f64::NAN,
        };
        if self.error.is_some() {
            return failed;
        }
        let r = self.dev.zero(&mut self.reduce_i32);
        if record(&mut self.error, "clearing the residual", r).is_none() {
            return failed;
        }
        let n = self.n as u32;
        if params.phases == Phases::Multi {
            let Some(rest) = multiphase_rest(&self.f.rest_density, &mut self.error) else {
                return failed;
            };
            launch!(
                self,
                "reducing the density error",
                correction_error_multiphase(
                    n,
                    rest,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    &self.owned,
                    &mut self.reduce_i32
                )
            );
        } else {
            launch!(
                self,
                "reducing the density error",
                correction_error(
                    n,
                    params.rho0,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    &self.owned,
                    &mut self.reduce_i32
                )
            );
        }
        let out = self.dev.download(&self.reduce_i32);
        let Some(v) = record(&mut self.error, "copying the residual", out) else {
            return failed;
        };
        // Over the ranks of a split run: one residual for all (a NaN anywhere stays NaN).
        let mut maxima = [max_from_bits(v[0]), max_from_bits_or_nan(v[1])];
        self.partition.max(&mut maxima);
        CorrectionError {
            compression: maxima[0],
            residual: maxima[1],
        }
    }

    pub(super) fn launch_begin_correction(&mut self) {
        self.has_previous = false;
        self.ensure_correction_buffers();
    }

    pub(super) fn launch_correction_pressure(&mut self, params: &StepParams<D>, k: f32) {
        self.ensure_correction_buffers();
        let Some(g) = self.grid.as_ref() else { return };
        let n = self.n as u32;
        let beta = crate::physics::correction::MOMENTUM;
        let has_previous = i32::from(self.has_previous);
        if params.phases == Phases::Multi {
            let Some(rest) = multiphase_rest(&self.f.rest_density, &mut self.error) else {
                return;
            };
            launch!(
                self,
                "computing pressure increments",
                correction_pressure_fluid_multiphase(
                    n,
                    rest,
                    k,
                    beta,
                    has_previous,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    &self.delta_p_previous,
                    &mut self.delta_p
                )
            );
        } else {
            launch!(
                self,
                "computing pressure increments",
                correction_pressure_fluid(
                    n,
                    params.rho0,
                    k,
                    beta,
                    has_previous,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    &self.delta_p_previous,
                    &mut self.delta_p
                )
            );
        }
        launch!(
            self,
            "extrapolating pressure increments to walls",
            correction_pressure_wall(
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.f.density,
                &self.f.pressure,
                &self.f.kind,
                &self.f.id,
                &mut self.delta_p
            )
        );
        launch!(
            self,
            "adding pressure increments",
            correction_pressure_apply(n, &self.delta_p, &mut self.f.pressure, &mut self.delta_p_previous)
        );
        self.has_previous = true;
    }

    pub(super) fn launch_correct_positions(
        &mut self,
        params: &StepParams<D>,
        tau: f32,
        kick_tau: f32,
        max_step: f32,
    ) -> Sweep {
        let Some(sweep) = self.correction_displacements(params, tau, max_step) else {
            return NO_SWEEP;
        };
        let n = self.n as u32;
        let scale = sweep.scale as Real;
        launch!(
            self,
            "moving particles",
            apply_displacement(
                n,
                scale,
                kick_tau,
                &self.f.kind,
                &self.displacement,
                &mut self.f.position,
                &mut self.f.velocity
            )
        );
        sweep
    }

    pub(super) fn launch_begin_velocity_solve(&mut self) {
        self.has_previous = false;
        self.anderson.reset();
        self.ensure_correction_buffers();
        if self.error.is_some() {
            return;
        }
        let r = self
            .dev
            .copy(&self.f.velocity, &mut self.velocity_solve_start)
            .and_then(|()| self.dev.copy(&self.f.pressure, &mut self.pressure_solve_start))
            .and_then(|()| self.dev.copy(&self.f.density, &mut self.density_solve_start));
        record(
            &mut self.error,
            "remembering the velocities, pressures and densities",
            r,
        );
    }

    pub(super) fn launch_end_velocity_solve(&mut self, keep: bool) {
        if self.error.is_some() {
            return;
        }
        // The saved buffers hold at least one entry; `copy` moves the fields' lengths back.
        if keep {
            self.launch_record_acting_pressure();
            let n = self.n as u32;
            launch!(
                self,
                "keeping the released pressure",
                keep_pressure_decreases(n, &self.pressure_solve_start, &mut self.f.pressure)
            );
        } else {
            let r = self
                .dev
                .copy(&self.velocity_solve_start, &mut self.f.velocity)
                .and_then(|()| self.dev.copy(&self.pressure_solve_start, &mut self.f.pressure));
            record(&mut self.error, "restoring the velocities and pressures", r);
            self.launch_record_acting_pressure();
        }
        // Positions did not move: the sum (18) is still the one remembered at the start.
        let r = self.dev.copy(&self.density_solve_start, &mut self.f.density);
        record(&mut self.error, "restoring the densities", r);
    }

    /// `acting_pressure = pressure` (`Backend::record_acting_pressure`); the buffer is made at
    /// the first use where the uploaded fields had none.
    pub(super) fn launch_record_acting_pressure(&mut self) {
        if self.error.is_some() {
            return;
        }
        if self.f.acting_pressure.is_none() {
            let r = self.dev.alloc_zeros::<f32>(self.n.max(1));
            self.f.acting_pressure = record(&mut self.error, "allocating the acting pressure", r);
        }
        let Some(acting) = self.f.acting_pressure.as_mut() else {
            return;
        };
        let r = self.dev.copy(&self.f.pressure, acting);
        record(&mut self.error, "recording the acting pressure", r);
    }
}
