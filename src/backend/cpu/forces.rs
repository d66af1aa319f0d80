//! The `forces` stage, eqs. (15)–(17) and (6), and the pressure terms `p/ρ²` it shares with
//! the correction and the forces on solids (twin of `kernels/forces.cu`).

use super::CpuBackend;
use crate::fields::{FLUID, Fields};
use crate::grid::Grid;
use crate::math::{Real, Vector};
use crate::model::ForceTerms;
use crate::model::pair_terms::{add_pair_terms, with_pair_terms};
use crate::model::params::StepParams;
use crate::physics::{
    multiphase::{self, Phases},
    pair::Pair,
    pressure::{pressure_acceleration_from_terms, pressure_term},
    rotating_frame::rotating_frame_acceleration,
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
    with_pair_terms!(terms.pair.bits(), TERMS => if terms.rotating_frame {
        fluid_acceleration::<D, TERMS, true, MULTIPHASE>(grid, f, params, q, i)
    } else {
        fluid_acceleration::<D, TERMS, false, MULTIPHASE>(grid, f, params, q, i)
    })
}

/// Eqs. (15)–(17) and (6) for fluid particle `i`, monomorphised on the optional terms: the pair
/// terms of `TERMS` (`model::pair_terms`, summed in table order after the pressure force) and the
/// rotating frame ([B67] §3.2); with `MULTIPHASE` the pressure force is [HA06]'s volume form
/// (`physics::multiphase`) and `terms` hold `p V²`.
#[inline(always)]
fn fluid_acceleration<const D: usize, const TERMS: u32, const ROTATING: bool, const MULTIPHASE: bool>(
    grid: &Grid<D>,
    fields: &Fields<D>,
    params: &StepParams<D>,
    terms: &[Real],
    i: usize,
) -> Vector<D> {
    let kernel = params.smoothing();
    let (q_i, rho_i, u_i) = (terms[i], fields.density[i], fields.velocity[i]);
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
        let u_j = &fields.velocity[j];
        let pair = Pair {
            x_ij: &d,
            r,
            u_i: &u_i,
            u_j,
            viscous_u_i: &u_i,
            // A solid carries its no-slip velocity ([A12] eqs. 22-23) where the scene has one.
            viscous_u_j: if fields.kind[j] == FLUID {
                u_j
            } else {
                fields.wall_velocity.get(j).unwrap_or(u_j)
            },
            rho_i,
            rho_j,
            m_j,
            grad_w: &grad,
            kernel: &kernel,
            wall: fields.kind[j] != FLUID,
        };
        add_pair_terms::<D, TERMS>(&mut a, params, &pair);
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
