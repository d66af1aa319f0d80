//! The steps the driver runs inside a stage ([`SubStage`]): the correction loop and the
//! no-penetration guard, each with its equation, fields and multiphase variant, as
//! `super::Stage` has them.

use super::{MP_DENSITY, MP_ERROR, MP_PRESSURE, MultiphaseVariant, Stage};
use crate::fields::Field;
use Field::*;

impl SubStage {
    /// The step's multiphase variant, if it has one.
    pub fn multiphase(&self) -> Option<MultiphaseVariant> {
        match self {
            SubStage::Density => Some(MP_DENSITY),
            SubStage::CorrectionError => Some(MP_ERROR),
            SubStage::CorrectionPressure => Some(MultiphaseVariant {
                equation: "(19), note 5, own rho0",
                description: "increments from each particle's own rest density",
                reads_rest_density: true,
            }),
            SubStage::SolidForces | SubStage::CorrectPositions | SubStage::VelocityFromPressure => {
                Some(MP_PRESSURE)
            }
            SubStage::MixVelocityPressure => Some(MultiphaseVariant {
                equation: "(19), note 5, own rho0",
                description: "the map g(P) with each particle's own rest density",
                reads_rest_density: true,
            }),
            SubStage::PredictedDensity => Some(MultiphaseVariant {
                equation: "[HA06] m_i, own rho0",
                description: "the particle's own mass in the rate and its own rest density",
                reads_rest_density: true,
            }),
            _ => None,
        }
    }
}

/// A step the driver runs inside a [`Stage`] (`Stage::sub_stages`); each is one `Backend` method
/// of the same name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SubStage {
    /// The correction's re-sort, once particles drifted `RESORT_DRIFT · h` since the last sort.
    SortByCell,
    /// Eq. (18) on the corrected positions.
    Density,
    /// Eq. (24) with note 6: the largest compression, and the loop's residual.
    CorrectionError,
    /// Eq. (19) with the correction's stiffness (note 5): pressure increments `δp`.
    CorrectionPressure,
    /// The sweep's push on each named solid (Fig. 4).
    SolidForces,
    /// Eq. (23): displacement from `δp`, and the velocity change `Δx/τ` (note 7).
    CorrectPositions,
    /// The no-penetration guard (`boundary::keep_out`).
    KeepOut,
    /// The velocity solve's start: remembers velocity, pressure and density.
    BeginVelocitySolve,
    /// The velocity solve's first pressure: the start's plus the increments the same integrator
    /// stage's solve ended with at the last step.
    WarmStartVelocitySolve,
    /// The density `base + τ dρ/dt` the velocities would give `τ` later (`base`: ρ0 inside the
    /// fluid, the particle's own density at the free surface).
    PredictedDensity,
    /// The velocity solve's next pressure: an Anderson-accelerated projected Jacobi sweep
    /// (`solver::anderson`).
    MixVelocityPressure,
    /// The velocity solve's velocities `u_start + τ a^press(P − P_start)`, positions fixed.
    VelocityFromPressure,
    /// The velocity solve's increments, kept by particle id for the same stage's next solve.
    RecordVelocitySolve,
    /// The velocity solve's end: pressure keeps only what it released, or everything is restored.
    EndVelocitySolve,
}

impl SubStage {
    /// The snake_case name (as the backend method).
    pub fn name(&self) -> &'static str {
        match self {
            SubStage::SortByCell => "sort_by_cell",
            SubStage::Density => "density",
            SubStage::CorrectionError => "correction_error",
            SubStage::CorrectionPressure => "correction_pressure",
            SubStage::SolidForces => "solid_forces",
            SubStage::CorrectPositions => "correct_positions",
            SubStage::KeepOut => "keep_out",
            SubStage::BeginVelocitySolve => "begin_velocity_solve",
            SubStage::WarmStartVelocitySolve => "warm_start_velocity_solve",
            SubStage::RecordVelocitySolve => "record_velocity_solve",
            SubStage::PredictedDensity => "predicted_density",
            SubStage::MixVelocityPressure => "mix_velocity_pressure",
            SubStage::VelocityFromPressure => "velocity_from_pressure",
            SubStage::EndVelocitySolve => "end_velocity_solve",
        }
    }

    /// What the step implements: the PAPER.md equation (or the source) it follows.
    pub fn equation(&self) -> &'static str {
        match self {
            SubStage::SortByCell => "section 3",
            SubStage::Density => "(18)",
            SubStage::CorrectionError => "(24), note 6",
            SubStage::CorrectionPressure => "(19), note 5",
            SubStage::SolidForces => "Fig. 4: (16)",
            SubStage::CorrectPositions => "(23), note 7",
            SubStage::KeepOut => "boundary::keep_out",
            SubStage::BeginVelocitySolve
            | SubStage::WarmStartVelocitySolve
            | SubStage::RecordVelocitySolve
            | SubStage::EndVelocitySolve => "velocity solve",
            SubStage::PredictedDensity => "continuity with (18)'s kernel",
            SubStage::MixVelocityPressure => "(19), note 6, [WN11]",
            SubStage::VelocityFromPressure => "(16), positions fixed",
        }
    }

    /// What the step computes, in words.
    pub fn description(&self) -> &'static str {
        match self {
            SubStage::SortByCell => "re-sort, only once particles drifted far since the last sort",
            SubStage::Density => "density by summation",
            SubStage::CorrectionError => "largest compression; stop when below delta or at the cap",
            SubStage::CorrectionPressure => "pressure increments from the density error, added to pressure",
            SubStage::SolidForces => "the sweep's push on each named solid",
            SubStage::CorrectPositions => "move by dt^2 f^press/rho, velocity += dx/tau",
            SubStage::KeepOut => {
                "put fluid particles that entered a solid back through the face they came in by (SSP-RK3: from position_start)"
            }
            SubStage::BeginVelocitySolve => "remember velocity, pressure and density",
            SubStage::WarmStartVelocitySolve => {
                "fluid pressure = max(P_start + dP, 0), dP the increments of the same stage's last solve, by particle id"
            }
            SubStage::RecordVelocitySolve => {
                "keep each fluid particle's P - P_start by id for the same stage's next solve (none if given up)"
            }
            SubStage::PredictedDensity => {
                "density the velocities would give tau later: base + tau drho/dt (base rho0, own density at the free surface)"
            }
            SubStage::MixVelocityPressure => {
                "next pressure: Anderson mix of max(P + k (rho* - rho0), 0) over the last iterates, P >= 0"
            }
            SubStage::VelocityFromPressure => {
                "velocity = start + tau f^press(P - P_start)/rho, increments extrapolated to walls"
            }
            SubStage::EndVelocitySolve => {
                "acting pressure = the solve's P, and pressure keeps only what the solve released; given up (residual doubled or cap): velocity and pressure restored, acting pressure = pressure; density (18) restored"
            }
        }
    }

    /// The particle fields the step reads.
    pub fn reads(&self) -> &'static [Field] {
        match self {
            SubStage::SortByCell => &[Position],
            SubStage::Density => &[Position, Mass, Kind],
            SubStage::CorrectionError => &[Density, Pressure, Kind],
            SubStage::CorrectionPressure => &[Position, Density, Pressure, Kind],
            SubStage::SolidForces => &[Position, Density, Mass, Kind],
            SubStage::CorrectPositions => &[Position, Density, Mass, Kind],
            // With SSP-RK3 it also reads PositionStart (`reads_in`).
            SubStage::KeepOut => &[Position, Velocity, Mass, Kind],
            SubStage::BeginVelocitySolve => &[Velocity, Pressure, Density],
            SubStage::WarmStartVelocitySolve => &[Pressure, Kind, Id],
            SubStage::RecordVelocitySolve => &[Pressure, Kind, Id],
            SubStage::EndVelocitySolve => &[Velocity, Pressure],
            SubStage::PredictedDensity => &[Position, Velocity, Mass, Kind],
            SubStage::MixVelocityPressure => &[Density, Pressure, Kind],
            SubStage::VelocityFromPressure => &[Position, Pressure, Mass, Kind],
        }
    }

    /// The particle fields the step reads within `plan`: [`SubStage::reads`], the step start
    /// `Field::PositionStart` for the no-penetration guard where the plan integrates with
    /// SSP-RK3 ([`Stage::RkStage`] stores it; the guard puts a particle back through the face
    /// its segment from there entered by), and `Field::RestDensity` where the `multiphase`
    /// effect's variant reads it.
    pub fn reads_in(&self, plan: &[Stage], multiphase: bool) -> Vec<Field> {
        let mut fields = self.reads().to_vec();
        if *self == SubStage::KeepOut && plan.contains(&Stage::RkStage) {
            fields.push(PositionStart);
        }
        if multiphase && self.multiphase().is_some_and(|v| v.reads_rest_density) {
            fields.push(Field::RestDensity);
        }
        fields
    }

    /// The particle fields the step writes.
    pub fn writes(&self) -> &'static [Field] {
        match self {
            SubStage::SortByCell => &Field::ALL,
            SubStage::Density => &[Density],
            SubStage::CorrectionError | SubStage::SolidForces => &[],
            SubStage::CorrectionPressure => &[Pressure],
            SubStage::CorrectPositions | SubStage::KeepOut => &[Position, Velocity],
            SubStage::BeginVelocitySolve | SubStage::RecordVelocitySolve => &[],
            SubStage::WarmStartVelocitySolve => &[Pressure],
            SubStage::PredictedDensity => &[Density],
            SubStage::MixVelocityPressure => &[Pressure],
            SubStage::VelocityFromPressure => &[Velocity, Pressure],
            SubStage::EndVelocitySolve => &[Velocity, Pressure, Density, ActingPressure],
        }
    }
}
