//! The `forces` stage, eqs. (15)–(17) and (6), and the pressure terms `p/ρ²` it shares with
//! the correction and the forces on solids (twin of `kernels/forces.cu`).

use super::CpuBackend;
use crate::fields::{FLUID, Fields};
use crate::grid::Grid;
use crate::math::{Real, Vector};
use crate::model::ForceTerms;
use crate::model::params::StepParams;
use crate::physics::{
    artificial_viscosity::artificial_viscous_acceleration,
    multiphase::{self, Phases},
    pressure::{pressure_acceleration_from_terms, pressure_term},
    rotating_frame::rotating_frame_acceleration,
    viscosity::viscous_acceleration,
};
use rayon::prelude::*;

impl<const D: usize> CpuBackend<D> {
    pub(super) fn forces(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, terms: ForceTerms) {
        let multiphase = params.phases == Phases::Multi;
        if multiphase {
            fill_volume_pressure_terms(
                &mut self.pressure_terms,
                &fields.pressure,
                &fields.mass,
                &fields.density,
            );
        } else {
            fill_pressure_terms(&mut self.pressure_terms, &fields.pressure, &fields.density);
        }
        let (grid, q) = (&self.grid, &self.pressure_terms);
        let mut acceleration = std::mem::take(&mut fields.acceleration);
        let f = &*fields;
        if multiphase {
            acceleration.par_iter_mut().enumerate().for_each(|(i, a)| {
                *a = fluid_acceleration_for::<D, true>(grid, f, params, q, terms, i);
            });
        } else {
            acceleration.par_iter_mut().enumerate().for_each(|(i, a)| {
                *a = fluid_acceleration_for::<D, false>(grid, f, params, q, terms, i);
            });
        }
        fields.acceleration = acceleration;
    }
}

/// The force stage for fluid particle `i` (zero for solids), the term set dispatched to its
/// monomorphised [`fluid_acceleration`].
#[inline(always)]
fn fluid_acceleration_for<const D: usize, const MULTIPHASE: bool>(
    grid: &Grid<D>,
    f: &Fields<D>,
    params: &StepParams<D>,
    q: &[Real],
    terms: ForceTerms,
    i: usize,
) -> Vector<D> {
    if f.kind[i] != FLUID {
        return Vector::zeros();
    }
    match (terms.viscosity, terms.artificial_viscosity, terms.rotating_frame) {
        (false, false, false) => {
            fluid_acceleration::<D, false, false, false, MULTIPHASE>(grid, f, params, q, i)
        }
        (true, false, false) => {
            fluid_acceleration::<D, true, false, false, MULTIPHASE>(grid, f, params, q, i)
        }
        (false, true, false) => {
            fluid_acceleration::<D, false, true, false, MULTIPHASE>(grid, f, params, q, i)
        }
        (true, true, false) => fluid_acceleration::<D, true, true, false, MULTIPHASE>(grid, f, params, q, i),
        (false, false, true) => {
            fluid_acceleration::<D, false, false, true, MULTIPHASE>(grid, f, params, q, i)
        }
        (true, false, true) => fluid_acceleration::<D, true, false, true, MULTIPHASE>(grid, f, params, q, i),
        (false, true, true) => fluid_acceleration::<D, false, true, true, MULTIPHASE>(grid, f, params, q, i),
        (true, true, true) => fluid_acceleration::<D, true, true, true, MULTIPHASE>(grid, f, params, q, i),
    }
}

/// Eqs. (15)–(17) and (6) for fluid particle `i`, monomorphised on the optional terms: viscosity
/// (17), artificial viscosity ([M92]) and the rotating frame ([B67] §3.2); with `MULTIPHASE` the
/// pressure force is [HA06]'s volume form (`physics::multiphase`) and `terms` hold `p V²`.
#[inline(always)]
fn fluid_acceleration<
    const D: usize,
    const VISCOUS: bool,
    const ARTIFICIAL: bool,
    const ROTATING: bool,
    const MULTIPHASE: bool,
>(
    grid: &Grid<D>,
    fields: &Fields<D>,
    params: &StepParams<D>,
    terms: &[Real],
    i: usize,
) -> Vector<D> {
    let kernel = params.smoothing();
    let (q_i, rho_i, u_i) = (terms[i], fields.density[i], fields.velocity[i]);
    // Eq. (17) with the lattice's Laplacian moment undone (`physics::lattice`).
    let mu = params.mu * params.viscosity_scale;
    let mut a = params.gravity; // eq. (6)
    if ROTATING {
        // [B67] §3.2: Coriolis and centrifugal.
        a += rotating_frame_acceleration(
            &params.angular_velocity,
            &params.rotation_centre,
            &fields.position[i],
            &u_i,
        );
    }
    grid.for_each_neighbour(&fields.position, i, |j, d, r2| {
        if j == i {
            return;
        }
        let r = r2.sqrt();
        let (m_j, rho_j) = (fields.mass[j], fields.density[j]);
        let grad = kernel.grad_w_spiky(&d, r) * params.pressure_gradient_scale;
        if MULTIPHASE {
            a += multiphase::pressure_acceleration(q_i, terms[j], fields.mass[i], &grad); // [HA06]
        } else {
            a += pressure_acceleration_from_terms(q_i, terms[j], m_j, &grad);
        }
        if ARTIFICIAL {
            let u_ij = u_i - fields.velocity[j];
            a += artificial_viscous_acceleration(
                params.alpha,
                params.c,
                params.h,
                &d,
                &u_ij,
                rho_i,
                rho_j,
                m_j,
                &grad,
            );
        }
        if VISCOUS {
            let lap = kernel.laplacian_w_viscosity(r);
            // A solid carries its no-slip velocity ([A12] eqs. 22-23) where the scene has one.
            let u_j = if fields.kind[j] == FLUID {
                &fields.velocity[j]
            } else {
                fields.wall_velocity.get(j).unwrap_or(&fields.velocity[j])
            };
            a += viscous_acceleration(mu, &u_i, u_j, rho_i, rho_j, m_j, lap);
        }
    });
    a
}

/// `terms[i] = pressure[i] (mass[i]/density[i])²` ([HA06] `p V²`, `physics::multiphase`).
pub(super) fn fill_volume_pressure_terms(
    terms: &mut Vec<Real>,
    pressure: &[Real],
    mass: &[Real],
    density: &[Real],
) {
    terms.clear();
    terms.par_extend(
        pressure
            .par_iter()
            .zip(mass)
            .zip(density)
            .map(|((&p, &m), &rho)| multiphase::pressure_term(p, m, rho)),
    );
}

/// `terms[i] = pressure[i]/density[i]²` (`physics::pressure::pressure_term`), in a reused buffer.
pub(super) fn fill_pressure_terms(terms: &mut Vec<Real>, pressure: &[Real], density: &[Real]) {
    terms.clear();
    terms.par_extend(
        pressure
            .par_iter()
            .zip(density)
            .map(|(&p, &rho)| pressure_term(p, rho)),
    );
}
