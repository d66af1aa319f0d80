//! The velocity solve's iteration on the device (`kernels/anderson.cu`), twins of
//! `CpuBackend::mix_velocity_pressure` and `CpuBackend::velocity_from_pressure`: Anderson
//! acceleration [WN11] of the projected Jacobi map `g(P) = max(P + k (ρ* − ρ0), 0)`
//! (`solver::anderson`), with the window's differences and the dot products on the device and
//! the small least-squares solve on the host (`AndersonState::coefficients`), then the velocities
//! `u = u_start + τ a^press(P − P_start)` at the solve's fixed positions. A child module of
//! `device` (it reads the backend's private buffers); `CudaBackend`'s `Backend` methods call it.

use super::{CudaBackend, record};
use crate::backend::cuda::launch::{Buffer, DeviceFault, Launch, Memory};
use crate::math::Real;
use crate::model::params::StepParams;
use crate::physics::multiphase::Phases;
use crate::solver::anderson::WINDOW;

/// The acceleration's device buffers, allocated at the first `mix_velocity_pressure` (a `wcsph`
/// run and a `corrected` run without velocity solve hold none): `WINDOW n` floats each for the
/// differences (slot-major, `slot l` at `[l n, (l + 1) n)`), `n` each for the previous iterate,
/// its `f` and the current `f = g(P) − P` [Pa], and `WINDOW` for `γ` and for the dot products.
pub(super) struct AndersonBuffers<K: Memory> {
    dp: K::Buf<f32>,
    df: K::Buf<f32>,
    previous: K::Buf<f32>,
    previous_f: K::Buf<f32>,
    f: K::Buf<f32>,
    gamma: K::Buf<f32>,
    dots: K::Buf<f64>,
}

impl<K: Memory> AndersonBuffers<K> {
    /// Device bytes held (for `Backend::heap_bytes`).
    pub(super) fn num_bytes(&self) -> usize {
        [
            &self.dp,
            &self.df,
            &self.previous,
            &self.previous_f,
            &self.f,
            &self.gamma,
        ]
        .iter()
        .map(|b| b.num_bytes())
        .sum::<usize>()
            + self.dots.num_bytes()
    }
}

/// Which vector `anderson_dots` multiplies the slots with.
#[derive(Clone, Copy)]
enum DotsWith {
    /// The `Δf` of this slot: a row of the Gram matrix.
    Slot(usize),
    /// The current `f`: the right-hand side of the normal equations.
    F,
}

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    /// Allocates [`AndersonBuffers`] once; `false` after a failure (recorded) or an earlier one.
    fn ensure_anderson_buffers(&mut self) -> bool {
        if self.error.is_some() {
            return false;
        }
        if self.anderson_buffers.is_some() {
            return true;
        }
        let n = self.n.max(1);
        let s = &self.dev;
        let r = (|| -> Result<AndersonBuffers<K>, DeviceFault> {
            Ok(AndersonBuffers {
                dp: s.alloc_zeros::<f32>(WINDOW * n)?,
                df: s.alloc_zeros::<f32>(WINDOW * n)?,
                previous: s.alloc_zeros::<f32>(n)?,
                previous_f: s.alloc_zeros::<f32>(n)?,
                f: s.alloc_zeros::<f32>(n)?,
                gamma: s.alloc_zeros::<f32>(WINDOW)?,
                dots: s.alloc_zeros::<f64>(WINDOW)?,
            })
        })();
        self.anderson_buffers = record(&mut self.error, "allocating the velocity solve's window", r);
        self.anderson_buffers.is_some()
    }

    /// `out[l] = Σ_i a_i Δf_l,i` for the first `count` slots (over ranks), in f64 (`anderson_dots`; the CPU
    /// sums in a fixed order with `math::sum_in_order`, the atomics in any). `None` after a
    /// failure.
    fn anderson_dots(&mut self, with: DotsWith, count: usize) -> Option<[f64; WINDOW]> {
        debug_assert!(count <= WINDOW);
        let b = self.anderson_buffers.as_mut()?;
        let r = self.dev.zero(&mut b.dots);
        record(&mut self.error, "clearing the dot products", r)?;
        let (n, count32) = (self.n as u32, count as u32);
        // About 64 particles per thread (grid-stride), one set of `WINDOW` f64 atomics per 64.
        let (a, offset) = match with {
            DotsWith::Slot(s) => (&b.df, (s * self.n) as u32),
            DotsWith::F => (&b.f, 0),
        };
        launch!(
            self,
            "reducing the window's dot products",
            anderson_dots(n, count32, a, offset, &b.df, &self.owned, &mut b.dots)
        );
        let out = self.dev.download(&b.dots);
        let out = record(&mut self.error, "copying the dot products", out)?;
        let mut dots = [0.0; WINDOW];
        dots.copy_from_slice(&out[..WINDOW]);
        // Over the ranks of a split run (each counts its own particles).
        self.partition.sum(&mut dots);
        Some(dots)
    }

    /// `Backend::mix_velocity_pressure` on the device: `f = g(P) − P` (the correction's fluid
    /// kernel without momentum), the newest differences and their Gram row, the right-hand side
    /// `Δf_l·f`, `γ` on the host, then the mixed and projected pressure (`anderson_mix`, which
    /// also keeps `P`, `f` as the previous iterate).
    pub(super) fn mix_pressure(&mut self, params: &StepParams<D>, k: f32) {
        if self.n == 0 || !self.ensure_anderson_buffers() {
            return;
        }
        let n = self.n as u32;
        let Some(b) = self.anderson_buffers.as_mut() else {
            return;
        };
        // No momentum: the kernels then read no previous increments (any n floats will do).
        let (beta, no_previous) = (0.0f32, 0i32);
        if params.phases == Phases::Multi {
            let Some(rest) = super::multiphase_rest(&self.f.rest_density, &mut self.error) else {
                return;
            };
            launch!(
                self,
                "computing the fixed-point residual",
                correction_pressure_fluid_multiphase(
                    n,
                    rest,
                    k,
                    beta,
                    no_previous,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    &self.delta_p_previous,
                    &mut b.f
                )
            );
        } else {
            launch!(
                self,
                "computing the fixed-point residual",
                correction_pressure_fluid(
                    n,
                    params.rho0,
                    k,
                    beta,
                    no_previous,
                    &self.f.density,
                    &self.f.pressure,
                    &self.f.kind,
                    &self.delta_p_previous,
                    &mut b.f
                )
            );
        }
        if self.anderson.has_previous {
            let s = self.anderson.next;
            let slot = s as u32;
            launch!(
                self,
                "storing the newest differences",
                anderson_difference(
                    n,
                    slot,
                    &self.f.pressure,
                    &b.previous,
                    &b.f,
                    &b.previous_f,
                    &mut b.dp,
                    &mut b.df
                )
            );
            // The new slot against every slot holding a difference, itself included.
            let valid = (self.anderson.held + 1).min(WINDOW);
            let Some(row) = self.anderson_dots(DotsWith::Slot(s), valid) else {
                return;
            };
            self.anderson.push(&row);
        }
        let held = self.anderson.held;
        let rhs = if held > 0 {
            let Some(rhs) = self.anderson_dots(DotsWith::F, held) else {
                return;
            };
            rhs
        } else {
            [0.0; WINDOW]
        };
        let gamma = self.anderson.coefficients(&rhs).map(|g| g as Real);
        let Some(b) = self.anderson_buffers.as_mut() else {
            return;
        };
        let r = self.dev.write(&gamma, &mut b.gamma);
        if record(&mut self.error, "uploading the mixing coefficients", r).is_none() {
            return;
        }
        let held32 = held as u32;
        launch!(
            self,
            "mixing the pressure",
            anderson_mix(
                n,
                held32,
                &b.gamma,
                &self.f.kind,
                &b.f,
                &b.dp,
                &b.df,
                &mut b.previous,
                &mut b.previous_f,
                &mut self.f.pressure
            )
        );
        self.anderson.has_previous = true;
    }

    /// `Backend::velocity_from_pressure` on the device: the fluid's increments `P − P_start`,
    /// the walls' extrapolated from them ([A12] eq. 27, the start's pressure and density, so
    /// `correction_pressure_wall` gives `max(P0_w + r, 0) − P0_w`) with the walls' pressure
    /// `P0_w + δp_w`, eq. (23)'s displacement with the densities (18) of the start and no
    /// scaling (its largest-|Δx| output is left unread), then `u = u_start + Δx / τ` for fluid.
    /// The increments stay in `delta_p` for `solid_forces` (`SolidForceSource::Correction`).
    /// A solid without fluid within `h` gets `max(P0, 0) − P0`, the CPU's 0 (it skips dry
    /// solids) for the non-negative pressures walls carry, as in `correction_pressure`.
    pub(super) fn pressure_to_velocity(&mut self, params: &StepParams<D>, tau: f32) {
        if self.error.is_some() {
            return;
        }
        let Some(g) = self.grid.as_ref() else { return };
        let n = self.n as u32;
        launch!(
            self,
            "computing the solve's increments",
            velocity_solve_increments(
                n,
                &self.f.kind,
                &self.f.pressure,
                &self.pressure_solve_start,
                &mut self.delta_p
            )
        );
        launch!(
            self,
            "extrapolating the solve's increments to walls",
            correction_pressure_wall(
                n,
                params,
                &g.geometry,
                &g.cell_start,
                &g.cell_key,
                &self.f.position,
                &self.density_solve_start,
                &self.pressure_solve_start,
                &self.f.kind,
                &self.f.id,
                &mut self.delta_p
            )
        );
        launch!(
            self,
            "setting the walls' pressure",
            velocity_solve_solid_pressure(
                n,
                &self.f.kind,
                &self.pressure_solve_start,
                &self.delta_p,
                &mut self.f.pressure
            )
        );
        if self.launch_displacements(params, tau, true).is_none() {
            return;
        }
        launch!(
            self,
            "setting velocities",
            velocity_from_displacement(
                n,
                tau,
                &self.f.kind,
                &self.velocity_solve_start,
                &self.displacement,
                &mut self.f.velocity
            )
        );
    }
}
