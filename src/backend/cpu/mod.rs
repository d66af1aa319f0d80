//! The rayon-parallel CPU backend: the reference implementation of every stage.
//!
//! Every loop is a gather (particle `i` writes only its own slots), and every global sum goes
//! through `math::sum_in_order`, so results are bitwise identical for any thread count.

use super::params::StepParams;
use super::{
    Backend, CorrectionError, ForceTerms, SolidForceSource, StateExtremes, SurfaceTensionModel, Sweep,
    WallModel,
};
use crate::boundary::keep_out::{KeepOutBox, KeepOutReport};
use crate::boundary::motion::{SolidKinematics, SolidReference};
use crate::boundary::{
    solid_force::force_on_solid, wall_pressure::WallPressureSums, wall_velocity::WallVelocitySums,
};
use crate::fields::{FLUID, Fields, PermuteScratch};
use crate::grid::{Grid, GridError};
use crate::math::{Real, Vector, max_each_in_order, max_or_nan, sum_by_group, sum_in_order, to_xyz};
use crate::neighbour_list::{NeighbourList, Neighbours};
use crate::physics::{
    artificial_viscosity::artificial_viscous_acceleration,
    correction,
    density::{density_kernel_gradient, density_term, velocity_solve_base},
    eos,
    multiphase::{self, Phases},
    pressure::{pressure_acceleration_from_terms, pressure_term},
    rotating_frame::{centrifugal_acceleration, rotating_frame_acceleration},
    surface_stress::{surface_stress_acceleration, surface_weight, tensile_factor},
    surface_tension::{normal_term, surface_tension_acceleration},
    viscosity::viscous_acceleration,
};
use anderson::AndersonBuffers;
use rayon::prelude::*;

mod anderson;

/// CPU backend state: the neighbour grid and reusable scratch buffers.
#[derive(Debug, Default)]
pub struct CpuBackend<const D: usize> {
    /// The neighbour grid of the last `sort_by_cell`.
    pub grid: Grid<D>,
    scratch: PermuteScratch<D>,
    wall: Vec<(Real, Real)>,
    /// Pressure increments `δp` of the current correction sweep [Pa].
    delta_p: Vec<Real>,
    /// Displacements `Δx` of the current correction sweep [m].
    displacement: Vec<Vector<D>>,
    /// Pressure increments of the previous sweep (heavy-ball momentum), empty after a sort.
    delta_p_previous: Vec<Real>,
    /// Per particle since the last sort: a solid with no fluid particle among its neighbour
    /// candidates (`Grid::neighbour_ranges`). Its wall pressure, correction increment and
    /// force on its solid are exactly zero until the next sort, so the solid loops skip it
    /// (the tank walls far from the water: half the particles of the 3D column scene). Empty
    /// before the first sort: nothing is skipped (the correction finds them on first use).
    dry: Vec<bool>,
    /// The other solids (indices, ascending), whose correction increments are summed.
    wet: Vec<u32>,
    /// The correction increments of the `wet` solids [Pa], before they are scattered.
    wet_increments: Vec<Real>,
    /// Velocities [m/s] at the start of the velocity solve (`begin_velocity_solve`).
    velocity_solve_start: Vec<Vector<D>>,
    /// Pressures [Pa] at the start of the velocity solve.
    pressure_solve_start: Vec<Real>,
    /// Densities (18) [kg/m³] at the start of the velocity solve, for its base density
    /// (`physics::density::velocity_solve_base`).
    density_solve_start: Vec<Real>,
    /// `p/ρ²` per particle (`physics::pressure::pressure_term`) of the current pressure loop.
    pressure_terms: Vec<Real>,
    /// Scratch of `find_dry_solids`: fluid particles before each sorted index.
    fluid_before: Vec<u32>,
    /// The pairs of the fluid and the wet solids at the velocity solve's fixed positions,
    /// built by `begin_velocity_solve` and cleared by `end_velocity_solve`
    /// (`crate::neighbour_list`). Non-empty exactly while a solve runs (it lists every particle).
    velocity_neighbours: NeighbourList,
    /// The velocity solve's Anderson acceleration (`anderson.rs`).
    anderson: AndersonBuffers,
}

impl<const D: usize> CpuBackend<D> {
    /// The `surface_tension` stage with the surface stress (`physics::surface_stress`): the pair
    /// force of the capillary stresses of `i` and `j`, added to the acceleration of fluid `i`.
    fn surface_stress(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        let kernel = params.smoothing();
        let grid = &self.grid;
        let mut acceleration = std::mem::take(&mut fields.acceleration);
        let f = &*fields;
        let (sigma, h) = (params.surface_tension_sigma, params.h);
        let w_dx = kernel.w(params.spacing * params.spacing);
        let rest = |j: usize| params.phases.rest_density(&f.rest_density, j, params.rho0);
        acceleration.par_iter_mut().enumerate().for_each(|(i, a)| {
            if f.kind[i] != FLUID {
                return;
            }
            let (n_i, rho0_i) = (f.normal[i], rest(i));
            let bulk_i = surface_weight(n_i.norm()) == 0.0;
            let mut sum = Vector::zeros();
            grid.for_each_neighbour(&f.position, i, |j, d, r2| {
                if j == i || f.kind[j] != FLUID {
                    return;
                }
                // Neither carries a stress: no force, and no kernel to evaluate.
                if bulk_i && surface_weight(f.normal[j].norm()) == 0.0 {
                    return;
                }
                let grad = kernel.grad_w_spiky(&d, r2.sqrt()) * params.pressure_gradient_scale;
                let tensile = tensile_factor(kernel.w(r2), w_dx);
                sum += surface_stress_acceleration(
                    sigma,
                    h,
                    f.mass[j],
                    rho0_i,
                    rest(j),
                    &n_i,
                    &f.normal[j],
                    &grad,
                    tensile,
                );
            });
            *a += sum;
        });
        fields.acceleration = acceleration;
    }

    /// A backend with empty buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// Bytes held by the grid and scratch buffers.
    pub fn heap_bytes(&self) -> usize {
        self.grid.heap_bytes()
            + self.wall.capacity() * 8
            + self.delta_p.capacity() * 4
            + self.delta_p_previous.capacity() * 4
            + self.velocity_solve_start.capacity() * D * 4
            + self.pressure_solve_start.capacity() * 4
            + self.density_solve_start.capacity() * 4
            + self.displacement.capacity() * D * 4
            + self.dry.capacity()
            + self.wet.capacity() * 4
            + self.wet_increments.capacity() * 4
            + self.pressure_terms.capacity() * 4
            + self.fluid_before.capacity() * 4
            + self.velocity_neighbours.heap_bytes()
            + self.anderson.heap_bytes()
    }

    /// The velocity solve's `list` while one runs (positions fixed; the list is empty
    /// otherwise), else the `grid`.
    fn neighbours<'a>(grid: &'a Grid<D>, list: &'a NeighbourList) -> Neighbours<'a, D> {
        if list.is_empty() {
            Neighbours::Grid(grid)
        } else {
            Neighbours::List(list)
        }
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
        let neighbours = Self::neighbours(&self.grid, &self.velocity_neighbours);
        let n = fields.len();
        let f = fields;
        let multiphase = params.phases == Phases::Multi;
        if multiphase {
            fill_volume_pressure_terms(&mut self.pressure_terms, &self.delta_p, &f.mass, density);
        } else {
            fill_pressure_terms(&mut self.pressure_terms, &self.delta_p, density);
        }
        let q = &self.pressure_terms;
        let tau2 = tau * tau;
        self.displacement.resize(n, Vector::zeros());
        // The displacements and their largest length in one pass.
        let largest = self
            .displacement
            .par_iter_mut()
            .enumerate()
            .map(|(i, out)| {
                *out = if f.kind[i] != FLUID {
                    Vector::zeros()
                } else {
                    let mut a = Vector::<D>::zeros();
                    neighbours.for_each_neighbour(&f.position, i, |j, d, r2| {
                        if j == i {
                            return;
                        }
                        let grad = kernel.grad_w_spiky(&d, r2.sqrt()) * params.pressure_gradient_scale;
                        if multiphase {
                            a += multiphase::pressure_acceleration(q[i], q[j], f.mass[i], &grad); // [HA06]
                        } else {
                            a += pressure_acceleration_from_terms(q[i], q[j], f.mass[j], &grad);
                        }
                    });
                    a * tau2 // eq. (23)
                };
                f64::from(out.norm())
            })
            .reduce(|| f64::NEG_INFINITY, max_or_nan)
            .max(0.0);
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

    /// [A12] eq. (27) without gravity: each wet solid's increment, the Shepard average of its
    /// fluid neighbours' `delta_p` (densities `density` [kg/m³]), into `wet_increments`.
    fn extrapolate_increments(&mut self, f: &Fields<D>, density: &[Real], params: &StepParams<D>) {
        let kernel = params.smoothing();
        let neighbours = Self::neighbours(&self.grid, &self.velocity_neighbours);
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

    /// Whether particle `i` is a solid without fluid candidates since the last sort.
    #[inline(always)]
    fn is_dry(&self, i: usize) -> bool {
        self.dry.get(i).copied().unwrap_or(false)
    }

    /// Recomputes [`CpuBackend::dry`] for the sorted `kind`: a running count of fluid particles
    /// in sorted order tells whether a candidate range holds any.
    fn find_dry_solids(&mut self, kind: &[u32]) {
        let fluid_before = &mut self.fluid_before;
        fluid_before.clear();
        fluid_before.push(0u32);
        let mut count = 0u32;
        for &k in kind {
            count += u32::from(k == FLUID);
            fluid_before.push(count);
        }
        let (grid, fluid_before) = (&self.grid, &self.fluid_before);
        self.dry.clear();
        self.dry.par_extend((0..kind.len()).into_par_iter().map(|i| {
            kind[i] != FLUID
                && grid
                    .neighbour_ranges(i)
                    .all(|r| fluid_before[r.end] == fluid_before[r.start])
        }));
        let dry = &self.dry;
        self.wet.clear();
        self.wet
            .extend((0..kind.len() as u32).filter(|&i| kind[i as usize] != FLUID && !dry[i as usize]));
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

impl<const D: usize> Backend<D> for CpuBackend<D> {
    fn name(&self) -> &'static str {
        "cpu"
    }

    fn kind(&self) -> super::BackendKind {
        super::BackendKind::Cpu
    }

    fn heap_bytes(&self) -> usize {
        CpuBackend::heap_bytes(self)
    }

    fn sort_by_cell(&mut self, fields: &mut Fields<D>, h: f32) -> Result<(), GridError> {
        let perm = self.grid.sort(&fields.position, h)?;
        self.delta_p_previous.clear();
        self.delta_p.clear();
        fields.permute(perm, &mut self.scratch);
        self.grid.link();
        self.find_dry_solids(&fields.kind);
        Ok(())
    }

    fn density(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        let kernel = params.smoothing();
        let weight = params.density_weight();
        let grid = &self.grid;
        let (position, mass, kind) = (&fields.position, &fields.mass, &fields.kind);
        if params.phases == Phases::Multi {
            // [HA06]: ρ_i = m_i Σ_j W_ij, blind to the neighbours' phases.
            fields.density.par_iter_mut().enumerate().for_each(|(i, rho)| {
                if kind[i] != FLUID {
                    return;
                }
                let mut sigma = 0.0;
                grid.for_each_neighbour(position, i, |_, _, r2| {
                    sigma += multiphase::number_density_term(&kernel, weight, r2)
                });
                *rho = multiphase::density(mass[i], sigma);
            });
            return;
        }
        fields.density.par_iter_mut().enumerate().for_each(|(i, rho)| {
            if kind[i] != FLUID {
                return;
            }
            let mut sum = 0.0;
            grid.for_each_neighbour(position, i, |j, _, r2| {
                sum += density_term(&kernel, weight, mass[j], r2)
            });
            *rho = sum;
        });
    }

    fn equation_of_state(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        let kind = &fields.kind;
        let density = &fields.density;
        let rest = &fields.rest_density;
        fields.pressure.par_iter_mut().enumerate().for_each(|(i, p)| {
            if kind[i] == FLUID {
                // With the multiphase effect, each particle's own rest density ([HA06]).
                let rho0 = params.phases.rest_density(rest, i, params.rho0);
                *p = eos::pressure(density[i], rho0, params.c2);
            }
        });
    }

    fn move_solids(
        &mut self,
        fields: &mut Fields<D>,
        reference: &SolidReference<D>,
        kinematics: &[SolidKinematics<D>],
    ) {
        let (kind, id) = (&fields.kind, &fields.id);
        fields
            .position
            .par_iter_mut()
            .zip(fields.velocity.par_iter_mut())
            .enumerate()
            .for_each(|(i, (x, u))| {
                if kind[i] != FLUID {
                    let k = &kinematics[kind[i] as usize - 1];
                    *x = reference.position[(id[i] - reference.first_id) as usize] + k.displacement;
                    *u = k.velocity;
                }
            });
    }

    fn wall_pressure(
        &mut self,
        fields: &mut Fields<D>,
        params: &StepParams<D>,
        model: WallModel,
        wall_acceleration: &[Vector<D>],
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
            // [A12] eq. (27): the body acceleration in the wall's frame, `g − a_w`.
            let mut body = match wall_acceleration.get(f.kind[w] as usize - 1) {
                Some(a) => params.gravity - a,
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

    fn wall_velocity(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
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

    fn forces(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, terms: ForceTerms) {
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

    fn surface_normals(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        let kernel = params.smoothing();
        let grid = &self.grid;
        let mut normal = std::mem::take(&mut fields.normal);
        normal.resize(fields.len(), Vector::zeros());
        let f = &*fields;
        // [AAT13] (3) weighs each neighbour by m_j/ρ_j; the surface stress by its rest volume
        // m_j/ρ0_j (`physics::surface_stress`: a colour field without the surface layer's
        // overshoot).
        let rest_volume = params.surface_tension_model == SurfaceTensionModel::SurfaceStress;
        let rest = |j: usize| params.phases.rest_density(&f.rest_density, j, params.rho0);
        normal.par_iter_mut().enumerate().for_each(|(i, n)| {
            let mut sum = Vector::zeros();
            if f.kind[i] == FLUID {
                grid.for_each_neighbour(&f.position, i, |j, d, _| {
                    if f.kind[j] == FLUID {
                        let rho_j = if rest_volume { rest(j) } else { f.density[j] };
                        sum += normal_term(&kernel, f.mass[j], rho_j, &d);
                    }
                });
            }
            *n = sum * params.h;
        });
        fields.normal = normal;
    }

    fn surface_tension(&mut self, fields: &mut Fields<D>, params: &StepParams<D>) {
        if params.surface_tension_model == SurfaceTensionModel::SurfaceStress {
            self.surface_stress(fields, params);
            return;
        }
        let grid = &self.grid;
        let mut acceleration = std::mem::take(&mut fields.acceleration);
        let f = &*fields;
        let (gamma, rho0, h) = (params.surface_tension_gamma, params.rho0, params.h);
        acceleration.par_iter_mut().enumerate().for_each(|(i, a)| {
            if f.kind[i] != FLUID {
                return;
            }
            let (rho_i, n_i) = (f.density[i], f.normal[i]);
            let mut sum = Vector::zeros();
            grid.for_each_neighbour(&f.position, i, |j, d, r2| {
                if j == i || f.kind[j] != FLUID {
                    return;
                }
                // [AAT13] (1)-(5): cohesion and curvature, fluid neighbours only.
                sum += surface_tension_acceleration(
                    gamma,
                    rho0,
                    h,
                    f.mass[j],
                    rho_i,
                    f.density[j],
                    &n_i,
                    &f.normal[j],
                    &d,
                    r2.sqrt(),
                );
            });
            *a += sum;
        });
        fields.acceleration = acceleration;
    }

    fn solid_forces(
        &mut self,
        fields: &Fields<D>,
        params: &StepParams<D>,
        solids: usize,
        source: SolidForceSource,
    ) -> Vec<[f64; 3]> {
        let kernel = params.smoothing();
        let neighbours = Self::neighbours(&self.grid, &self.velocity_neighbours);
        let f = fields;
        // The correction moves particles by pressure alone: its own pressures, no viscous terms.
        let params = source.params(params);
        let pressure = match source {
            SolidForceSource::Forces => &f.pressure,
            SolidForceSource::Correction => &self.delta_p,
        };
        if pressure.len() != f.len() {
            return vec![[0.0; 3]; solids];
        }
        // [HA06] (`multiphase`): the pressure pair term in the volume form, as the fluid feels it;
        // the viscous terms as without it.
        let multiphase = params.phases == Phases::Multi;
        if multiphase {
            fill_volume_pressure_terms(&mut self.pressure_terms, pressure, &f.mass, &f.density);
        }
        let q = &self.pressure_terms;
        sum_by_group(f.len(), solids, |s| {
            let kind = f.kind[s];
            if kind == FLUID || self.is_dry(s) {
                return None;
            }
            let mut force = Vector::<D>::zeros();
            neighbours.for_each_neighbour(&f.position, s, |j, d, r2| {
                if f.kind[j] != FLUID {
                    return;
                }
                let r = r2.sqrt();
                let grad = kernel.grad_w_spiky(&d, r) * params.pressure_gradient_scale;
                let (p_s, p_j) = if multiphase {
                    (0.0, 0.0)
                } else {
                    (pressure[s], pressure[j])
                };
                let mut pair = force_on_solid(
                    &params,
                    [f.mass[s], p_s, f.density[s]],
                    [f.mass[j], p_j, f.density[j]],
                    &d,
                    [&f.velocity[s], &f.velocity[j]],
                    f.wall_velocity.get(s).unwrap_or(&f.velocity[s]),
                    &grad,
                    kernel.laplacian_w_viscosity(r),
                );
                if multiphase {
                    pair += multiphase::pressure_acceleration(q[s], q[j], 1.0, &grad);
                }
                force += pair;
            });
            Some((kind as usize - 1, to_xyz(&force)))
        })
    }

    fn state_extremes(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> StateExtremes {
        let f = fields;
        let n = f.len();
        // Each particle's own rest density with the multiphase effect ([HA06]).
        let rest = &f.rest_density;
        let error = |i: usize| {
            let rho0 = f64::from(params.phases.rest_density(rest, i, params.rho0));
            (f64::from(f.density[i]) - rho0) / rho0
        };
        let fluid = |i: usize| f.kind[i] == FLUID;
        // The largest speed, acceleration, |error|, compression and deficit in one pass.
        let [max_speed, max_acceleration, max_abs, max_comp, max_deficit] = max_each_in_order(n, |i| {
            if !fluid(i) {
                return [0.0; 5];
            }
            let e = error(i);
            [
                f64::from(f.velocity[i].norm()),
                f64::from(f.acceleration[i].norm()),
                e.abs(),
                e.max(0.0),
                (-e).max(0.0),
            ]
        });
        let [count, abs_sum, comp_sum] = sum_in_order(n, |i| {
            if !fluid(i) {
                return [0.0; 3];
            }
            let e = error(i);
            [1.0, e.abs(), e.max(0.0)]
        });
        let non_finite = if (max_speed + max_acceleration + max_abs).is_finite() {
            None
        } else {
            first_non_finite(f)
        };
        let outside =
            |x: &Vector<D>| (0..D).any(|k| x[k] < params.domain_min[k] || x[k] > params.domain_max[k]);
        let escaped = (0..n)
            .into_par_iter()
            .find_first(|&i| fluid(i) && outside(&f.position[i]));
        let mean = |s: f64| if count > 0.0 { s / count } else { 0.0 };
        StateExtremes {
            max_speed: max_speed.max(0.0),
            max_acceleration: max_acceleration.max(0.0),
            max_abs_density_error: max_abs.max(0.0),
            mean_abs_density_error: mean(abs_sum),
            max_compression: max_comp.max(0.0),
            mean_compression: mean(comp_sum),
            max_surface_deficit: max_deficit.max(0.0),
            mean_surface_deficit: mean(abs_sum - comp_sum),
            non_finite,
            escaped,
        }
    }

    fn integrate(&mut self, fields: &mut Fields<D>, dt: f32) {
        let kind = &fields.kind;
        let acceleration = &fields.acceleration;
        fields
            .velocity
            .par_iter_mut()
            .zip(fields.position.par_iter_mut())
            .enumerate()
            .for_each(|(i, (u, x))| {
                if kind[i] == FLUID {
                    *u += acceleration[i] * dt;
                    *x += *u * dt;
                }
            });
    }

    fn store_step_start(&mut self, fields: &mut Fields<D>) {
        fields.position_start.clone_from(&fields.position);
        fields.velocity_start.clone_from(&fields.velocity);
    }

    fn rk_stage(&mut self, fields: &mut Fields<D>, dt: f32, a: f32, b: f32) {
        let Fields {
            position,
            velocity,
            acceleration,
            kind,
            position_start,
            velocity_start,
            ..
        } = fields;
        velocity
            .par_iter_mut()
            .zip(position.par_iter_mut())
            .enumerate()
            .for_each(|(i, (u, x))| {
                if kind[i] == FLUID {
                    let x_euler = *x + *u * dt;
                    let u_euler = *u + acceleration[i] * dt;
                    *x = position_start[i] * a + x_euler * b;
                    *u = velocity_start[i] * a + u_euler * b;
                }
            });
    }

    fn correction_error(&mut self, fields: &Fields<D>, params: &StepParams<D>) -> CorrectionError {
        let f = fields;
        let (rest, rho0) = (&f.rest_density, params.rho0);
        let [compression, residual] = max_each_in_order(f.len(), |i| {
            if f.kind[i] == FLUID {
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
        CorrectionError {
            compression: compression.max(0.0),
            residual: residual.max(0.0),
        }
    }

    fn begin_correction(&mut self, _fields: &mut Fields<D>) {
        // Both buffers: `correction_pressure` swaps them before it reads the previous one.
        self.delta_p_previous.clear();
        self.delta_p.clear();
    }

    fn correction_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, k: f32) {
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

    fn correct_positions(
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

    fn begin_velocity_solve(&mut self, fields: &mut Fields<D>) {
        self.delta_p_previous.clear();
        self.delta_p.clear();
        // The fluid and the solids with fluid candidates: the loops of the solve's sweeps.
        let (kind, dry) = (&fields.kind, &self.dry);
        self.velocity_neighbours.build(&self.grid, &fields.position, |i| {
            kind[i] == FLUID || !dry.get(i).copied().unwrap_or(false)
        });
        self.velocity_solve_start.clone_from(&fields.velocity);
        self.pressure_solve_start.clone_from(&fields.pressure);
        self.anderson.reset();
        self.density_solve_start.clone_from(&fields.density);
    }

    fn predicted_density(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, tau: f32) {
        let kernel = params.smoothing();
        let weight = params.density_weight();
        let list = &self.velocity_neighbours;
        let (position, velocity, mass, kind) =
            (&fields.position, &fields.velocity, &fields.mass, &fields.kind);
        let rest = &fields.rest_density;
        let multiphase = params.phases == Phases::Multi;
        let start = &self.density_solve_start;
        assert_eq!(
            start.len(),
            fields.len(),
            "predicted_density outside a velocity solve"
        );
        fields.density.par_iter_mut().enumerate().for_each(|(i, rho)| {
            if kind[i] != FLUID {
                return;
            }
            let mut rate = 0.0;
            list.for_each_neighbour(position, i, |j, d, r2| {
                if j != i {
                    let grad = density_kernel_gradient(&kernel, weight, &d, r2.sqrt());
                    let m = if multiphase { mass[i] } else { mass[j] };
                    rate += m * (velocity[i] - velocity[j]).dot(&grad);
                }
            });
            *rho =
                velocity_solve_base(start[i], params.phases.rest_density(rest, i, params.rho0)) + tau * rate;
        });
    }

    fn mix_velocity_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, k: f32) {
        self.anderson.mix(fields, params.phases, params.rho0, k);
    }

    fn velocity_from_pressure(&mut self, fields: &mut Fields<D>, params: &StepParams<D>, tau: f32) {
        let n = fields.len();
        let start = &self.pressure_solve_start;
        let kind = &fields.kind;
        self.delta_p.resize(n, 0.0);
        self.delta_p
            .par_iter_mut()
            .zip(fields.pressure.par_iter())
            .enumerate()
            .for_each(|(i, (dp, p))| *dp = if kind[i] == FLUID { p - start[i] } else { 0.0 });
        // The solve's density: the sum (18) at its fixed positions, not the predicted one.
        let density = std::mem::take(&mut self.density_solve_start);
        self.extrapolate_increments(fields, &density, params);
        for (&w, &r) in self.wet.iter().zip(&self.wet_increments) {
            let w = w as usize;
            let p0 = self.pressure_solve_start[w];
            let dp = (p0 + r).max(0.0) - p0; // the wall's pressure stays >= 0
            self.delta_p[w] = dp;
            fields.pressure[w] = p0 + dp;
        }
        self.correction_displacements(fields, &density, params, tau, f32::INFINITY);
        self.density_solve_start = density;
        let (start, displacement) = (&self.velocity_solve_start, &self.displacement);
        let kind = &fields.kind;
        fields.velocity.par_iter_mut().enumerate().for_each(|(i, u)| {
            if kind[i] == FLUID {
                *u = start[i] + displacement[i] / tau;
            }
        });
    }

    fn end_velocity_solve(&mut self, fields: &mut Fields<D>, keep: bool) {
        if keep {
            let start = &self.pressure_solve_start;
            fields
                .pressure
                .par_iter_mut()
                .zip(start.par_iter())
                .for_each(|(p, p0)| *p = p.min(*p0));
        } else {
            fields.velocity.clone_from(&self.velocity_solve_start);
            fields.pressure.clone_from(&self.pressure_solve_start);
        }
        // Positions did not move: the sum (18) is still the one remembered at the start.
        fields.density.clone_from(&self.density_solve_start);
        self.velocity_neighbours.clear();
    }

    fn keep_out(
        &mut self,
        fields: &mut Fields<D>,
        boxes: &[KeepOutBox<D>],
        solids: usize,
        margin: f32,
        from_step_start: bool,
    ) -> KeepOutReport {
        let mut report = KeepOutReport::none(solids);
        if boxes.is_empty() {
            return report;
        }
        let (kind, mass) = (&fields.kind, &fields.mass);
        // The step's start positions, stored by `store_step_start` (SSP-RK3): the side each
        // particle came from (`KeepOutBox::push_out`).
        let start: &[Vector<D>] = if from_step_start {
            &fields.position_start
        } else {
            &[]
        };
        // Each particle's pushes (solid, axis, m Δu), gathered in index order and summed in that
        // order, so the result does not depend on the thread count.
        let pushes: Vec<Vec<(u32, usize, f64)>> = fields
            .position
            .par_iter_mut()
            .zip(fields.velocity.par_iter_mut())
            .enumerate()
            .filter_map(|(i, (x, u))| {
                if kind[i] != FLUID {
                    return None;
                }
                let from = start.get(i);
                let mut mine = Vec::new();
                for b in boxes {
                    let before = *u;
                    if let Some(axis) = b.push_out(x, u, margin, from) {
                        let du = f64::from(u[axis]) - f64::from(before[axis]);
                        mine.push((b.solid, axis, f64::from(mass[i]) * du));
                    }
                }
                (!mine.is_empty()).then_some(mine)
            })
            .collect();
        for (solid, axis, dp) in pushes.into_iter().flatten() {
            report.pushes += 1;
            if let Some(slot) = report.impulse.get_mut(solid as usize) {
                slot[axis] += dp;
            }
        }
        report
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

/// `terms[i] = pressure[i] (mass[i]/density[i])²` ([HA06] `p V²`, `physics::multiphase`).
fn fill_volume_pressure_terms(terms: &mut Vec<Real>, pressure: &[Real], mass: &[Real], density: &[Real]) {
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
fn fill_pressure_terms(terms: &mut Vec<Real>, pressure: &[Real], density: &[Real]) {
    terms.clear();
    terms.par_extend(
        pressure
            .par_iter()
            .zip(density)
            .map(|(&p, &rho)| pressure_term(p, rho)),
    );
}

/// First particle with a non-finite position, velocity, acceleration, density or pressure.
fn first_non_finite<const D: usize>(f: &Fields<D>) -> Option<(usize, &'static str)> {
    let finite = |v: &Vector<D>| v.iter().all(|c| c.is_finite());
    (0..f.len()).find_map(|i| {
        if !finite(&f.position[i]) {
            Some((i, "position"))
        } else if !finite(&f.velocity[i]) {
            Some((i, "velocity"))
        } else if !finite(&f.acceleration[i]) {
            Some((i, "acceleration"))
        } else if !f.density[i].is_finite() {
            Some((i, "density"))
        } else if !f.pressure[i].is_finite() {
            Some((i, "pressure"))
        } else {
            None
        }
    })
}
