//! The `wall_pressure` and `wall_velocity` stages and the [A12] extrapolation of pressure
//! increments onto the wet solids (twins of `kernels/wall_pressure.cu` and
//! `kernels/wall_velocity.cu`).

use super::CpuBackend;
use crate::boundary::{
    rigid::SolidKinematics, wall_pressure::WallPressureSums, wall_velocity::WallVelocitySums,
};
use crate::fields::{FLUID, Fields};
use crate::math::{Real, Vector};
use crate::model::WallModel;
use crate::model::params::StepParams;
use crate::physics::{
    density::density_term,
    eos,
    multiphase::{self, Phases},
    rotating_frame::centrifugal_acceleration,
};
use rayon::prelude::*;

impl<const D: usize> CpuBackend<D> {
    pub(super) fn wall_pressure(
        &mut self,
        fields: &mut Fields<D>,
        params: &StepParams<D>,
        model: WallModel,
        kinematics: &[SolidKinematics<D>],
    ) {
        let kernel = params.smoothing();
        let grid = &self.grid;
        let f = &*fields;
        let rotating = params.rotating();
        let multiphase = params.phases == Phases::Multi;
        self.wall.clear();
        let dry = &self.dry;
        self.wall.par_extend((0..f.len()).into_par_iter().map(|w| {
            if f.kind[w] == FLUID {
                return (f.pressure[w], f.density[w]);
            }
            // No fluid neighbour: (27) gives zero; the summed density (19) of the other model
            // still needs the wall's own neighbours.
            if model == WallModel::Extrapolated && dry.get(w).copied().unwrap_or(false) {
                return (0.0, eos::density_from_pressure(0.0, params.rho0, params.c2));
            }
            let mut sums = WallPressureSums::<D>::default();
            let mut summed_density = 0.0;
            grid.for_each_neighbour(&f.position, w, |j, d, r2| {
                let weight = kernel.w(r2);
                if multiphase {
                    summed_density += multiphase::number_density_term(&kernel, params.density_weight(), r2);
                } else {
                    summed_density += density_term(&kernel, params.density_weight(), f.mass[j], r2);
                }
                if f.kind[j] == FLUID {
                    // [A12] (27) with each fluid neighbour's own density (its phase's, [HA06]).
                    sums.add(f.pressure[j], f.density[j], &d, weight);
                }
            });
            if multiphase {
                summed_density = multiphase::wall_density(f.mass[w], summed_density);
            }
            // [A12] eq. (27): the body acceleration in the wall's frame, `g − a_w`, with the
            // wall's acceleration at this particle (`boundary::rigid`).
            let mut body = match kinematics.get(f.kind[w] as usize - 1) {
                Some(k) => params.gravity - k.acceleration_at(&f.position[w]),
                None => params.gravity,
            };
            if rotating {
                // In a rotating frame the wall's body acceleration includes the centrifugal one
                // at the wall particle ([B67] §3.2; the wall is at rest in the frame, so no
                // Coriolis term).
                body += centrifugal_acceleration(
                    &params.angular_velocity,
                    &params.rotation_centre,
                    &f.position[w],
                );
            }
            let mut p = sums.pressure(&body);
            if model == WallModel::ExtrapolatedOrSummed {
                p = p.max(eos::pressure(summed_density, params.rho0, params.c2));
            }
            (p, eos::density_from_pressure(p, params.rho0, params.c2))
        }));
        let wall = &self.wall;
        fields
            .pressure
            .par_iter_mut()
            .zip(fields.density.par_iter_mut())
            .enumerate()
            .for_each(|(i, (p, rho))| {
                (*p, *rho) = wall[i];
            });
    }

    pub(super) fn wall_velocity(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        let kernel = params.smoothing();
        let n = fields.len();
        fields.wall_velocity.resize(n, Vector::zeros());
        let mut out = std::mem::take(&mut fields.wall_velocity);
        let (grid, f) = (&self.grid, &*fields);
        out.par_iter_mut().enumerate().for_each(|(w, v)| {
            if f.kind[w] == FLUID {
                return;
            }
            let mut sums = WallVelocitySums::<D>::default();
            if !self.is_dry(w) {
                grid.for_each_neighbour(&f.position, w, |j, _, r2| {
                    if f.kind[j] == FLUID {
                        sums.add(&f.velocity[j], kernel.w(r2));
                    }
                });
            }
            *v = sums.viscous_velocity(&f.velocity[w]); // [A12] eqs. (22)-(23)
        });
        fields.wall_velocity = out;
    }

    /// [A12] eq. (27) without gravity: each wet solid's increment, the Shepard average of its
    /// fluid neighbours' `delta_p` (densities `density` [kg/m³]), into `wet_increments`.
    pub(super) fn extrapolate_increments(&mut self, f: &Fields<D>, density: &[Real], params: &StepParams<D>) {
        let kernel = params.smoothing();
        let neighbours = &self.grid;
        let fluid_dp = &self.delta_p;
        self.wet_increments.clear();
        self.wet_increments.par_extend(self.wet.par_iter().map(|&w| {
            let mut sums = WallPressureSums::<D>::default();
            neighbours.for_each_neighbour(&f.position, w as usize, |j, d, r2| {
                if f.kind[j] == FLUID {
                    sums.add(fluid_dp[j], density[j], &d, kernel.w(r2));
                }
            });
            sums.increment()
        }));
    }

    /// [`CpuBackend::extrapolate_increments`] in a velocity solve, from the wet solids' fluid
    /// pairs listed at its start (`crate::neighbour_list::WetSolidPairs`): bitwise the same.
    pub(super) fn extrapolate_listed_increments(&mut self, density: &[Real]) {
        let (pairs, fluid_dp) = (&self.wet_pairs, &self.delta_p);
        self.wet_increments.clear();
        self.wet_increments
            .par_extend((0..self.wet.len()).into_par_iter().map(|k| {
                let mut sums = WallPressureSums::<D>::default();
                pairs.for_each_fluid(k, |j, d, w| sums.add(fluid_dp[j], density[j], d, w));
                sums.increment()
            }));
    }
}
