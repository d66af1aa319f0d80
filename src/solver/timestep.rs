//! The explicit time step: the largest stable step from the sound speed, the forces, the
//! viscosity and a floating body's contact, or the scene's fixed step; and stage `TimeStep`,
//! which checks the state (escaped and non-finite particles) before choosing it.
//!
//! With support radius `h` [m] (twice the usual smoothing length `ĥ = h/2`):
//! - sound (CFL):   `dt ≤ cfl · h / (C + |u|max)`
//! - force:         `dt ≤ 0.25 · sqrt(h / |a|max)`  (Monaghan 1992, with `ĥ` → `h`, conservative)
//! - viscosity:     `dt ≤ 0.125 · ĥ² ρ0 / μ`         (Morris, Fox & Zhu 1997)
//!
//! - contact:       `dt ≤ CONTACT_STEP / ω_c` with a floating body's contact frequency `ω_c`
//!   (`boundary::contact`), for a fixed step too: the contact is explicit
//! - mooring:       `dt ≤ CONTACT_STEP / ω_m` with a floating body's mooring frequency `ω_m`
//!   (`RigidBody::mooring_frequency`), for the same reason
//!
//! and never past the end time.
//!
//! A fixed step (`solver.dt`) is taken as given unless it is above a stability limit: then the
//! force and viscous limits above and the acoustic limit at CFL number 1, `h / (C + |u|max)`,
//! cut it, and the step records the limit that did. Validation already refuses a `wcsph` step
//! above `h / C`; the flow speed can only add to `C` at run time. This holds for `wcsph` only:
//! the corrected solver (passed here without a sound speed) keeps its fixed step, whose largest
//! stable value is a property of the correction (`scene::validate::corrected_step_bound`).

use super::{Simulation, StepError, StepReport};
use crate::model::params::StepParams;
use crate::physics::pair::ViscousMedium;

/// Which criterion limited a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TimeStepLimit {
    /// The scene's fixed `solver.dt`.
    Fixed,
    /// Sound speed plus flow speed (CFL).
    SoundSpeed,
    /// Flow speed alone (CFL; the corrected solver).
    FlowSpeed,
    /// Largest acceleration.
    Force,
    /// Viscous diffusion.
    Viscosity,
    /// A floating body's contact with a solid (`boundary::contact`).
    Contact,
    /// A floating body's mooring lines (`RigidBody::mooring_frequency`).
    Mooring,
    /// Shortened to land on the end time.
    EndTime,
}

impl TimeStepLimit {
    /// The name `steps.csv` and `summary.json` use (`fixed`, `sound_speed`, ...).
    pub fn name(self) -> &'static str {
        match self {
            TimeStepLimit::Fixed => "fixed",
            TimeStepLimit::SoundSpeed => "sound_speed",
            TimeStepLimit::FlowSpeed => "flow_speed",
            TimeStepLimit::Force => "force",
            TimeStepLimit::Viscosity => "viscosity",
            TimeStepLimit::Contact => "contact",
            TimeStepLimit::Mooring => "mooring",
            TimeStepLimit::EndTime => "end_time",
        }
    }
}

impl std::fmt::Display for TimeStepLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Whether a step `dt` [s] chosen by `limit` at time `time` [s] cannot advance a run that ends
/// at `end_time` [s]: `dt` is zero, negative or not finite; `time + dt == time` in f64; or, for a
/// step not cut to land on the end time, `end_time + dt == end_time` (below the f64 resolution
/// of the end time, so the run would need more than 2^52 such steps). A step cut to the end
/// time is exempt from the last test (it may legitimately be one ulp of `time`), and so is an
/// infinite end time (stepping without an end, as the tests and benches do).
pub fn stalls(dt: f64, limit: TimeStepLimit, time: f64, end_time: f64) -> bool {
    !(dt > 0.0 && dt.is_finite())
        || time + dt == time
        || (limit != TimeStepLimit::EndTime && end_time.is_finite() && end_time + dt == end_time)
}

/// Inputs of the time-step choice, in SI units.
#[derive(Clone, Copy, Debug)]
pub struct TimeStepInputs {
    /// Support radius `h` [m].
    pub h: f64,
    /// Sound speed `C` [m/s]; 0 for the corrected solver (no acoustic limit).
    pub sound_speed: f64,
    /// CFL number (scene `solver.cfl`).
    pub cfl: f64,
    /// Largest fluid speed [m/s].
    pub max_speed: f64,
    /// Largest fluid acceleration [m/s²].
    pub max_acceleration: f64,
    /// Kinematic viscosity `μ/ρ0` [m²/s] (0 without viscosity).
    pub kinematic_viscosity: f64,
    /// Fixed step from the scene [s].
    pub fixed: Option<f64>,
    /// The stiffest floating body's contact frequency `ω_c` [rad/s]; `None` without contact.
    pub contact_frequency: Option<f64>,
    /// The stiffest floating body's mooring frequency `ω_m` [rad/s]
    /// (`RigidBody::mooring_frequency`); `None` without moorings.
    pub mooring_frequency: Option<f64>,
    /// Time left until the end of the run [s].
    pub remaining: f64,
}

/// The step [s] and the criterion that limited it.
pub fn choose(inputs: &TimeStepInputs) -> (f64, TimeStepLimit) {
    let (mut dt, mut limit) = match inputs.fixed {
        // The corrected solver (no sound speed here) keeps its fixed step: its largest stable
        // step is a question of the correction, not of these explicit limits.
        Some(dt) if inputs.sound_speed <= 0.0 => (dt, TimeStepLimit::Fixed),
        Some(dt) => {
            let mut best = (dt, TimeStepLimit::Fixed);
            for (limit, kind) in [
                (
                    inputs.h / (inputs.sound_speed + inputs.max_speed),
                    TimeStepLimit::SoundSpeed,
                ),
                (force_limit(inputs), TimeStepLimit::Force),
                (viscous_limit(inputs), TimeStepLimit::Viscosity),
            ] {
                if limit < best.0 {
                    best = (limit, kind);
                }
            }
            best
        }
        None => {
            // Without a sound speed (the corrected solver) the CFL number applies to the flow.
            let speed = inputs.sound_speed + inputs.max_speed;
            let mut best = if speed > 0.0 {
                (
                    inputs.cfl * inputs.h / speed,
                    if inputs.sound_speed > 0.0 {
                        TimeStepLimit::SoundSpeed
                    } else {
                        TimeStepLimit::FlowSpeed
                    },
                )
            } else {
                (f64::INFINITY, TimeStepLimit::FlowSpeed)
            };
            let f = force_limit(inputs);
            if f < best.0 {
                best = (f, TimeStepLimit::Force);
            }
            let v = viscous_limit(inputs);
            if v < best.0 {
                best = (v, TimeStepLimit::Viscosity);
            }
            best
        }
    };
    for (w, kind) in [
        (inputs.contact_frequency, TimeStepLimit::Contact),
        (inputs.mooring_frequency, TimeStepLimit::Mooring),
    ] {
        if let Some(w) = w {
            let c = crate::boundary::contact::CONTACT_STEP / w;
            if c < dt {
                dt = c;
                limit = kind;
            }
        }
    }
    if inputs.remaining < dt {
        dt = inputs.remaining;
        limit = TimeStepLimit::EndTime;
    }
    (dt, limit)
}

/// Force limit `0.25 sqrt(h / |a|max)` [s]; infinite without acceleration.
fn force_limit(inputs: &TimeStepInputs) -> f64 {
    if inputs.max_acceleration > 0.0 {
        0.25 * (inputs.h / inputs.max_acceleration).sqrt()
    } else {
        f64::INFINITY
    }
}

/// Viscous limit `0.125 ĥ² / ν` [s] with `ĥ = h/2`; infinite without viscosity.
fn viscous_limit(inputs: &TimeStepInputs) -> f64 {
    if inputs.kinematic_viscosity > 0.0 {
        0.125 * (0.5 * inputs.h).powi(2) / inputs.kinematic_viscosity
    } else {
        f64::INFINITY
    }
}

impl<const D: usize> Simulation<D> {
    /// The state guards and the time step (stage `TimeStep`).
    pub(super) fn choose_time_step(
        &mut self,
        params: &StepParams<D>,
        end_time: f64,
    ) -> Result<StepReport, StepError> {
        let (step, time) = (self.clock.step, self.clock.time);
        let mut e = self.backend.state_extremes(&self.fields, params);
        let mut removed = 0;
        // Split across ranks, every rank removes when any has a particle to remove (the removal
        // and the extremes after it are collective).
        let mut escaped = [f64::from(u8::from(e.non_finite.is_none() && e.escaped.is_some()))];
        if self.config.on_escape == super::escape::EscapePolicy::Remove {
            self.backend.sum_over_ranks(&mut escaped);
        }
        if escaped[0] > 0.0 && self.config.on_escape == super::escape::EscapePolicy::Remove {
            self.fields_stale = self.backend.holds_state();
            self.sync_fields()
                .map_err(|source| StepError::Backend { step, source })?;
            removed = self.remove_escaped()?;
            e = self.backend.state_extremes(&self.fields, params);
        }
        if e.non_finite.is_some() || e.escaped.is_some() {
            // Name the particle from the backend's own state (device order for CUDA).
            self.fields_stale = self.backend.holds_state();
            self.sync_fields()
                .map_err(|source| StepError::Backend { step, source })?;
        }
        let f = &self.fields;
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
        let mut inputs = TimeStepInputs {
            h: c.h,
            // The corrected solver has no acoustic limit: its pressure does not come from (19).
            sound_speed: if c.correction.is_some() {
                0.0
            } else {
                c.sound_speed
            },
            cfl: c.cfl,
            // A moving wall sweeps through the fluid like a flow of its speed.
            max_speed: e.max_speed.max(self.wall_speed),
            max_acceleration: e.max_acceleration,
            // Each pair term's equivalent kinematic viscosity (`PairTerm::step_viscosity`).
            kinematic_viscosity: c.pair_terms.step_viscosity(&ViscousMedium {
                sound_speed: c.sound_speed,
                h: c.h,
                dimension: D,
                lightest_rho0: self.lightest_rho0,
                viscosity_scale: f64::from(self.viscosity_scale),
            }),
            fixed: c.dt,
            contact_frequency: None,
            mooring_frequency: self.mooring_frequency(),
            remaining: end_time - time,
        };
        let (mut dt, mut limit) = choose(&inputs);
        // A floating body that may touch a solid within the step bounds it (`boundary::contact`).
        if let Some(w) = self.contact_frequency(dt) {
            inputs.contact_frequency = Some(w);
            (dt, limit) = choose(&inputs);
        }
        if stalls(dt, limit, time, end_time) {
            return Err(StepError::Stalled {
                step,
                time,
                dt,
                limit,
                end_time,
            });
        }
        Ok(StepReport {
            dt,
            limit,
            extremes: e,
            removed,
            created: 0,
            outflow: 0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs() -> TimeStepInputs {
        TimeStepInputs {
            h: 0.02,
            sound_speed: 20.0,
            cfl: 0.2,
            max_speed: 0.0,
            max_acceleration: 9.81,
            kinematic_viscosity: 1e-6,
            fixed: None,
            contact_frequency: None,
            mooring_frequency: None,
            remaining: 1.0,
        }
    }

    #[test]
    fn a_floating_body_in_contact_or_moored_bounds_the_step_even_a_fixed_one() {
        let w = 1000.0;
        let c = crate::boundary::contact::CONTACT_STEP / w;
        for fixed in [None, Some(1.0)] {
            let (dt, limit) = choose(&TimeStepInputs {
                contact_frequency: Some(w),
                sound_speed: 0.0,
                fixed,
                ..inputs()
            });
            assert_eq!((dt, limit), (c, TimeStepLimit::Contact));
            let (dt, limit) = choose(&TimeStepInputs {
                contact_frequency: Some(0.5 * w),
                mooring_frequency: Some(w),
                sound_speed: 0.0,
                fixed,
                ..inputs()
            });
            assert_eq!((dt, limit), (c, TimeStepLimit::Mooring));
        }
    }

    #[test]
    fn sound_speed_limits_a_quiet_fluid() {
        let (dt, limit) = choose(&inputs());
        assert_eq!(limit, TimeStepLimit::SoundSpeed);
        assert!((dt - 0.2 * 0.02 / 20.0).abs() < 1e-15);
    }

    #[test]
    fn viscosity_and_force_limit_when_they_are_stiffer() {
        let (_, limit) = choose(&TimeStepInputs {
            kinematic_viscosity: 10.0,
            ..inputs()
        });
        assert_eq!(limit, TimeStepLimit::Viscosity);
        let (_, limit) = choose(&TimeStepInputs {
            max_acceleration: 1e6,
            ..inputs()
        });
        assert_eq!(limit, TimeStepLimit::Force);
        let (dt, limit) = choose(&TimeStepInputs {
            fixed: Some(1e-3),
            remaining: 1e-4,
            ..inputs()
        });
        assert_eq!((dt, limit), (1e-4, TimeStepLimit::EndTime));
    }

    #[test]
    fn limit_names_are_the_serialized_ones() {
        use TimeStepLimit::*;
        for limit in [
            Fixed, SoundSpeed, FlowSpeed, Force, Viscosity, Contact, Mooring, EndTime,
        ] {
            assert_eq!(serde_json::to_value(limit).unwrap(), limit.name());
        }
    }

    #[test]
    fn a_step_that_cannot_advance_the_time_stalls() {
        use TimeStepLimit::*;
        assert!(!stalls(1e-4, SoundSpeed, 0.5, 1.0));
        assert!(stalls(0.0, Viscosity, 0.0, 1.0));
        assert!(stalls(f64::NAN, Fixed, 0.0, 1.0));
        assert!(stalls(f64::INFINITY, Fixed, 0.0, 1.0));
        // Advances t = 0 but not the end time: the run would never finish.
        assert!(stalls(1e-300, Fixed, 0.0, 1.0));
        assert!(stalls(1e-17, Fixed, 0.5, 1.0));
        // Stepping without an end time.
        assert!(!stalls(1e-4, SoundSpeed, 0.0, f64::INFINITY));
        assert!(stalls(0.0, Viscosity, 0.0, f64::INFINITY));
        // The last step, cut to the end time, may be one ulp of t.
        let t = 1.0 - f64::EPSILON / 2.0;
        assert!(!stalls(1.0 - t, EndTime, t, 1.0));
    }

    #[test]
    fn a_fixed_step_is_cut_to_the_stability_limits() {
        // Within every limit: taken as given.
        let (dt, limit) = choose(&TimeStepInputs {
            fixed: Some(1e-4),
            ..inputs()
        });
        assert_eq!((dt, limit), (1e-4, TimeStepLimit::Fixed));
        // wcsph: the acoustic limit at CFL 1, h / (C + |u|) = 0.02 / 40 = 5e-4 s.
        let (dt, limit) = choose(&TimeStepInputs {
            fixed: Some(1e-3),
            max_speed: 20.0,
            ..inputs()
        });
        assert_eq!(limit, TimeStepLimit::SoundSpeed);
        assert!((dt - 5e-4).abs() < 1e-15);
        // Force: 0.25 sqrt(0.02 / 1e4) = 3.54e-4 s < the fixed 5e-4 s.
        let (dt, limit) = choose(&TimeStepInputs {
            fixed: Some(5e-4),
            max_acceleration: 1e4,
            ..inputs()
        });
        assert_eq!(limit, TimeStepLimit::Force);
        assert!((dt - 0.25 * (0.02f64 / 1e4).sqrt()).abs() < 1e-15);
        // Viscosity: 0.125 (0.01)^2 / 0.1 = 1.25e-4 s.
        let (dt, limit) = choose(&TimeStepInputs {
            fixed: Some(5e-4),
            kinematic_viscosity: 0.1,
            ..inputs()
        });
        assert_eq!(limit, TimeStepLimit::Viscosity);
        assert!((dt - 1.25e-4).abs() < 1e-15);
        // The corrected solver (no sound speed) keeps its fixed step.
        let (dt, limit) = choose(&TimeStepInputs {
            fixed: Some(5e-3),
            sound_speed: 0.0,
            kinematic_viscosity: 0.1,
            ..inputs()
        });
        assert_eq!((dt, limit), (5e-3, TimeStepLimit::Fixed));
    }
}
