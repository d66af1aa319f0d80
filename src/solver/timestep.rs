//! The explicit time step: the largest stable step from the sound speed, the forces and the
//! viscosity, or the scene's fixed step.
//!
//! With support radius `h` [m] (twice the usual smoothing length `ĥ = h/2`):
//! - sound (CFL):   `dt ≤ cfl · h / (C + |u|max)`
//! - force:         `dt ≤ 0.25 · sqrt(h / |a|max)`  (Monaghan 1992, with `ĥ` → `h`, conservative)
//! - viscosity:     `dt ≤ 0.125 · ĥ² ρ0 / μ`         (Morris, Fox & Zhu 1997)
//!
//! and never past the end time.

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
    /// Shortened to land on the end time.
    EndTime,
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
    /// Time left until the end of the run [s].
    pub remaining: f64,
}

/// The step [s] and the criterion that limited it.
pub fn choose(inputs: &TimeStepInputs) -> (f64, TimeStepLimit) {
    let (mut dt, mut limit) = match inputs.fixed {
        Some(dt) => (dt, TimeStepLimit::Fixed),
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
            if inputs.max_acceleration > 0.0 {
                let f = 0.25 * (inputs.h / inputs.max_acceleration).sqrt();
                if f < best.0 {
                    best = (f, TimeStepLimit::Force);
                }
            }
            if inputs.kinematic_viscosity > 0.0 {
                let v = 0.125 * (0.5 * inputs.h).powi(2) / inputs.kinematic_viscosity;
                if v < best.0 {
                    best = (v, TimeStepLimit::Viscosity);
                }
            }
            best
        }
    };
    if inputs.remaining < dt {
        dt = inputs.remaining;
        limit = TimeStepLimit::EndTime;
    }
    (dt, limit)
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
            remaining: 1.0,
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
}
