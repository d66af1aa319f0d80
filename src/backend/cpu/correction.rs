//! The position correction, eqs. (23)–(24), and the velocity solve built on its sweep (twins
//! of `kernels/correction.cu` and `kernels/anderson.cu`).

use super::CpuBackend;
use super::forces::{fill_pressure_terms, fill_volume_pressure_terms};
use crate::backend::{CorrectionError, Sweep};
use crate::fields::{FLUID, Fields};
use crate::math::{Real, Vector, max_each_in_order, max_or_nan, non_negative_or_nan};
use crate::model::params::StepParams;
use crate::neighbour_list::SpikyGradients;
use crate::physics::{
    correction,
    multiphase::{self, Phases},
    pressure::{pressure_acceleration_from_terms, pressure_term},
};
use crate::smoothing::Smoothing;
use rayon::prelude::*;

impl<const D: usize> CpuBackend<D> {
    pub(super) fn correction_error(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> CorrectionError {
        let f = fields;
        let (rest, rho0) = (&f.rest_density, params.rho0);
        let partition = &self.partition;
        let mut maxima = max_each_in_order(f.len(), |i| {
            if f.kind[i] == FLUID && partition.counts(i) {
                // (24) against the particle's own phase with the multiphase effect ([HA06]).
                let rho0 = params.phases.rest_density(rest, i, rho0);
                [
                    correction::compression(f.density[i], rho0),
                    correction::residual(f.density[i], rho0, f.pressure[i]),
                ]
            } else {
                [0.0; 2]
            }
        });
        self.partition.max(&mut maxima); // over ranks: one residual for all
        let [compression, residual] = maxima;
        CorrectionError {
            compression: compression.max(0.0),
            residual: non_negative_or_nan(residual),
        }
    }

    pub(super) fn begin_correction(&mut self, _fields: &mut Fields<D>) {
        // Both buffers: `correction_pressure` swaps them before it reads the previous one.
        self.delta_p_previous.clear();
        self.delta_p.clear();
    }

    pub(super) fn correction_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, k: f32) {
        // The last sweep's increments become the previous ones (heavy-ball momentum): a swap of
        // buffers, not a copy; `delta_p` is overwritten below.
        std::mem::swap(&mut self.delta_p, &mut self.delta_p_previous);
        let n = fields.len();
        if self.dry.len() != n {
            self.find_dry_solids(&fields.kind);
        }
        self.delta_p.resize(n, 0.0);
        let beta = correction::MOMENTUM;
        let prev = &self.delta_p_previous;
        let has_prev = prev.len() == n;
        // Fluid first: eq. (19) with the correction's stiffness, pressure kept >= 0 (note 6),
        // added to the pressure in the same pass.
        let (kind, density, rho0) = (&fields.kind, &fields.density, params.rho0);
        let rest = &fields.rest_density;
        self.delta_p
            .par_iter_mut()
            .zip(fields.pressure.par_iter_mut())
            .enumerate()
            .for_each(|(i, (dp, p))| {
                *dp = if kind[i] == FLUID {
                    // Heavy-ball momentum on the increments (see `physics::correction::MOMENTUM`).
                    let m = if has_prev { beta * prev[i] } else { 0.0 };
                    // The particle's own phase with the multiphase effect ([HA06]).
                    let rho0 = params.phases.rest_density(rest, i, rho0);
                    correction::pressure_increment(density[i], rho0, *p + m, k) + m
                } else {
                    0.0
                };
                *p += *dp;
            });
        let f = &*fields;
        // Then the solids with fluid candidates (the others get 0): [A12] extrapolation of the
        // fluid increments, without the gravity term (gravity acts in the force stage, not in
        // the correction), of either sign, with the wall's accumulated pressure kept
        // non-negative: a wall must not pull a compressed particle onto itself (measured: that
        // held a particle against the floor of the dam break through 1000 sweeps), but it must
        // give back pressure its fluid gives back. With increments clamped at zero instead, a
        // wall's pressure only grew and pushed its neighbours below ρ0 while they still carried
        // pressure: on `scenes/hard/rest_3d.toml` stages stalled at the 1,000-sweep cap at
        // 999.3–999.5 kg/m³ one or two spacings from the side walls.
        self.extrapolate_increments(f, &f.density, params);
        for (&w, &dp) in self.wet.iter().zip(&self.wet_increments) {
            let p = &mut fields.pressure[w as usize];
            let dp = (*p + dp).max(0.0) - *p;
            self.delta_p[w as usize] = dp;
            *p += dp;
        }
    }

    pub(super) fn correct_positions(
        &mut self,
        fields: &mut Fields<D>,
        params: &StepParams<D>,
        tau: f32,
        kick_tau: f32,
        max_step: f32,
    ) -> Sweep {
        let sweep = self.correction_displacements(fields, &fields.density, params, tau, max_step);
        let scale = sweep.scale as Real;
        let displacement = &self.displacement;
        let kind = &fields.kind;
        fields
            .position
            .par_iter_mut()
            .zip(fields.velocity.par_iter_mut())
            .enumerate()
            .for_each(|(i, (x, u))| {
                if kind[i] == FLUID {
                    let dx = displacement[i] * scale;
                    *x += dx;
                    *u += dx / kick_tau; // PAPER.md note 7: the projection's velocity change
                }
            });
        sweep
    }

    /// Eq. (23) without moving anything: `Δx = τ² a^press(δp)` of every fluid particle into
    /// `displacement`, and one scale for all that keeps the largest within `max_step` [m]
    /// (pair displacements stay antisymmetric, so momentum stays conserved).
    fn correction_displacements(
        &mut self,
        fields: &Fields<D>,
        density: &[Real],
        params: &StepParams<D>,
        tau: f32,
        max_step: f32,
    ) -> Sweep {
        let kernel = params.smoothing();
        let pairs = SpikyGradients::Grid(&self.grid);
        let n = fields.len();
        let f = fields;
        if params.phases == Phases::Multi {
            fill_volume_pressure_terms(&mut self.pressure_terms, &self.delta_p, &f.mass, density);
        } else {
            fill_pressure_terms(&mut self.pressure_terms, &self.delta_p, density);
        }
        let q = &self.pressure_terms;
        let tau2 = tau * tau;
        self.displacement.resize(n, Vector::zeros());
        let partition = &self.partition;
        // The displacements and their largest length (over this rank's own) in one pass.
        let largest = self
            .displacement
            .par_iter_mut()
            .enumerate()
            .map(|(i, out)| {
                *out = if f.kind[i] != FLUID {
                    Vector::zeros()
                } else {
                    pressure_displacement(&f.position, &f.mass, pairs, &kernel, params, q, i, tau2)
                };
                if partition.counts(i) {
                    f64::from(out.norm())
                } else {
                    0.0
                }
            })
            .reduce(|| f64::NEG_INFINITY, max_or_nan)
            .max(0.0);
        // One scale on every rank (only a finite cap scales).
        let mut largest = [largest];
        if max_step.is_finite() {
            self.partition.max(&mut largest);
        }
        let [largest] = largest;
        let scale = if largest > f64::from(max_step) {
            (f64::from(max_step) / largest) as Real
        } else {
            1.0
        };
        Sweep {
            largest: largest * f64::from(scale),
            scale: f64::from(scale),
        }
    }

    pub(super) fn begin_velocity_solve(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        self.delta_p_previous.clear();
        self.delta_p.clear();
        // The fluid's pairs and gradients, and the wet solids' fluid pairs, which the solve's
        // sweeps visit (`crate::neighbour_list`).
        let (kind, kernel) = (&fields.kind, params.smoothing());
        if self.dry.len() != fields.len() {
            self.find_dry_solids(kind);
        }
        self.velocity_neighbours
            .build(&self.grid, &kernel, &fields.position, |i| kind[i] == FLUID);
        self.wet_pairs
            .build(&self.grid, &kernel, &fields.position, &self.wet, |j| {
                kind[j] == FLUID
            });
        self.velocity_solve_start.clone_from(&fields.velocity);
        self.pressure_solve_start.clone_from(&fields.pressure);
        self.anderson.reset();
        self.density_solve_start.clone_from(&fields.density);
    }

    pub(super) fn mix_velocity_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, k: f32) {
        self.anderson
            .mix(fields, params.phases, params.rho0, k, &mut self.partition);
    }

    /// The velocities `u = u_start + τ a^press(P − P_start)` of the solve's current pressure
    /// (`Backend::velocity_from_pressure`), in three parallel passes: the fluid's increments
    /// with their pressure terms, the wet solids' extrapolated increments, and the displacement
    /// `τ² a^press` (23) turned into the velocity in the same pass. The same floats as
    /// `correction_displacements` followed by the velocity update: the passes are fused
    /// because at a few thousand particles a parallel pass costs about what its work does.
    pub(super) fn velocity_from_pressure(
        &mut self,
        fields: &mut Fields<D>,
        params: &StepParams<D>,
        tau: f32,
    ) {
        let n = fields.len();
        let multiphase = params.phases == Phases::Multi;
        // The solve's density: the sum (18) at its fixed positions, not the predicted one.
        let density = std::mem::take(&mut self.density_solve_start);
        let term = |dp: Real, i: usize| {
            if multiphase {
                multiphase::pressure_term(dp, fields.mass[i], density[i])
            } else {
                pressure_term(dp, density[i])
            }
        };
        let start = &self.pressure_solve_start;
        let kind = &fields.kind;
        self.delta_p.resize(n, 0.0);
        self.pressure_terms.resize(n, 0.0);
        self.delta_p
            .par_iter_mut()
            .zip(self.pressure_terms.par_iter_mut())
            .zip(fields.pressure.par_iter())
            .enumerate()
            .for_each(|(i, ((dp, q), p))| {
                *dp = if kind[i] == FLUID { p - start[i] } else { 0.0 };
                *q = term(*dp, i);
            });
        self.extrapolate_listed_increments(&density);
        for (&w, &r) in self.wet.iter().zip(&self.wet_increments) {
            let w = w as usize;
            let p0 = self.pressure_solve_start[w];
            let dp = (p0 + r).max(0.0) - p0; // the wall's pressure stays >= 0
            self.delta_p[w] = dp;
            self.pressure_terms[w] = term(dp, w);
            fields.pressure[w] = p0 + dp;
        }
        let kernel = params.smoothing();
        let pairs = SpikyGradients::List(&self.velocity_neighbours);
        let (q, start) = (&self.pressure_terms, &self.velocity_solve_start);
        let tau2 = tau * tau;
        let (position, mass, kind) = (&fields.position, &fields.mass, &fields.kind);
        fields.velocity.par_iter_mut().enumerate().for_each(|(i, u)| {
            if kind[i] == FLUID {
                let dx = pressure_displacement(position, mass, pairs, &kernel, params, q, i, tau2);
                *u = start[i] + dx / tau;
            }
        });
        self.density_solve_start = density;
    }

    pub(super) fn end_velocity_solve(&mut self, fields: &mut Fields<D>, keep: bool) {
        if keep {
            fields.acting_pressure.clone_from(&fields.pressure);
            let start = &self.pressure_solve_start;
            fields
                .pressure
                .par_iter_mut()
                .zip(start.par_iter())
                .for_each(|(p, p0)| *p = p.min(*p0));
        } else {
            fields.velocity.clone_from(&self.velocity_solve_start);
            fields.pressure.clone_from(&self.pressure_solve_start);
            fields.acting_pressure.clone_from(&fields.pressure);
        }
        // Positions did not move: the sum (18) is still the one remembered at the start.
        fields.density.clone_from(&self.density_solve_start);
        self.velocity_neighbours.clear();
        self.wet_pairs.clear();
    }
}

/// Eq. (23) for fluid particle `i`: `Δx = τ² a^press` [m] from the pressure terms `q`
/// (`physics::pressure::pressure_term`, or [HA06]'s volume terms with the multiphase effect) of
/// `i` and its neighbours (positions [m], masses [kg]), with the scaled spiky gradient (16).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn pressure_displacement<const D: usize>(
    position: &[Vector<D>],
    mass: &[Real],
    pairs: SpikyGradients<'_, D>,
    kernel: &Smoothing<D>,
    params: &StepParams<D>,
    q: &[Real],
    i: usize,
    tau2: Real,
) -> Vector<D> {
    let multiphase = params.phases == Phases::Multi;
    let mut a = Vector::<D>::zeros();
    pairs.for_each(position, kernel, i, |j, spiky| {
        let grad = spiky * params.pressure_gradient_scale;
        if multiphase {
            a += multiphase::pressure_acceleration(q[i], q[j], mass[i], &grad); // [HA06]
        } else {
            a += pressure_acceleration_from_terms(q[i], q[j], mass[j], &grad);
        }
    });
    a * tau2 // eq. (23)
}
