//! The step driver, the only one: walks the plan and calls the backend, stage by stage, in the
//! order of the paper's algorithm (section 1, weakly compressible form).

use super::stage::Stage;
use super::timestep::{self, TimeStepInputs, TimeStepLimit};
use super::{Simulation, StepError, StepReport};
use crate::backend::{Backend, StateExtremes};

impl<const D: usize> Simulation<D> {
    /// Advances the simulation by one step, ending no later than `end_time` [s].
    pub fn step(&mut self, end_time: f64) -> Result<StepReport, StepError> {
        let params = self.step_params();
        let step = self.clock.step;
        let time = self.clock.time;
        let mut report = StepReport {
            dt: 0.0,
            limit: TimeStepLimit::Fixed,
            extremes: StateExtremes::default(),
        };
        for stage in &self.plan {
            let (b, f) = (&mut self.backend, &mut self.fields);
            match *stage {
                Stage::SortByCell => {
                    b.sort_by_cell(f, params.h)
                        .map_err(|source| StepError::Grid { step, source })? // section 3
                }
                Stage::Density => b.density(f, &params), // eq. (18)
                Stage::EquationOfState => b.equation_of_state(f, &params), // eq. (19)
                Stage::WallPressure => b.wall_pressure(f, &params), // [A12] eq. (27)
                Stage::Forces(terms) => b.forces(f, &params, terms), // eqs. (15)-(17), (6)
                Stage::SolidForces => {
                    self.solid_force = b.solid_forces(f, &params, self.solid_names.len()) // Fig. 4
                }
                Stage::TimeStep => {
                    let e = b.state_extremes(f, &params);
                    if let Some((i, quantity)) = e.non_finite {
                        return Err(StepError::NonFinite {
                            step,
                            time,
                            particle: f.id[i],
                            quantity,
                        });
                    }
                    if let Some(i) = e.escaped {
                        let position = (0..D).map(|k| f64::from(f.position[i][k])).collect();
                        return Err(StepError::Escaped {
                            step,
                            time,
                            particle: f.id[i],
                            position,
                        });
                    }
                    let c = &self.config;
                    let (dt, limit) = timestep::choose(&TimeStepInputs {
                        h: c.h,
                        sound_speed: c.sound_speed,
                        cfl: c.cfl,
                        max_speed: e.max_speed,
                        max_acceleration: e.max_acceleration,
                        kinematic_viscosity: c.viscosity.unwrap_or(0.0) / c.rho0,
                        fixed: c.dt,
                        remaining: end_time - time,
                    });
                    report = StepReport {
                        dt,
                        limit,
                        extremes: e,
                    };
                }
                Stage::Integrate => b.integrate(f, report.dt as f32), // eq. (15), symplectic Euler
            }
        }
        let e = &report.extremes;
        let s = &mut self.stats;
        s.max_abs_density_error = s.max_abs_density_error.max(e.max_abs_density_error);
        s.sum_mean_abs_density_error += e.mean_abs_density_error;
        s.max_compression = s.max_compression.max(e.max_compression);
        s.sum_mean_compression += e.mean_compression;
        self.clock.time += report.dt;
        self.clock.step += 1;
        Ok(report)
    }
}
