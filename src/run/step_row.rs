//! One row of `steps.csv`: what the step just taken did. `sph run` writes it and the Python
//! package keeps it in memory, from the same values.

use super::STEP_COLUMNS;
use crate::output::CsvValue;
use crate::solver::{Simulation, StepReport};

/// One row of `steps.csv` ([`STEP_COLUMNS`], in that order).
#[derive(Clone, Debug, PartialEq)]
pub struct StepRow {
    /// Steps taken so far, this one included.
    pub step: u64,
    /// Time at the end of the step [s].
    pub time: f64,
    /// The step [s].
    pub dt: f64,
    /// The criterion that limited it (`TimeStepLimit::name`).
    pub limit: String,
    /// Largest fluid speed at the start of the step [m/s].
    pub max_speed: f64,
    /// Largest compression `(ρ − ρ0)/ρ0` at the start of the step.
    pub max_compression: f64,
    /// Largest relative density deficit of a free-surface particle at the start of the step.
    pub max_surface_deficit: f64,
    /// Position-correction sweeps the step took (`corrected`; 0 for `wcsph`).
    pub correction_iterations: u64,
    /// Fluid particles removed for having left the domain.
    pub removed: u64,
    /// Fluid particles created behind an inflow.
    pub created: u64,
    /// Fluid particles removed past an outflow's buffer.
    pub outflow: u64,
}

impl StepRow {
    /// The row of the step `report` that `sim` has just taken; `iterations_before` is the
    /// correction's sweep count before it (`sim.stats().correction.iterations`).
    pub fn of<const D: usize>(sim: &Simulation<D>, report: &StepReport, iterations_before: u64) -> Self {
        let clock = sim.clock();
        let e = &report.extremes;
        Self {
            step: clock.step,
            time: clock.time,
            dt: report.dt,
            limit: report.limit.name().to_string(),
            max_speed: e.max_speed,
            max_compression: e.max_compression,
            max_surface_deficit: e.max_surface_deficit,
            correction_iterations: sim.stats().correction.iterations - iterations_before,
            removed: report.removed,
            created: report.created,
            outflow: report.outflow,
        }
    }

    /// The row's values, in [`STEP_COLUMNS`] order.
    pub fn values(&self) -> [CsvValue<'_>; STEP_COLUMNS.len()] {
        [
            CsvValue::Int(self.step as i64),
            CsvValue::Float(self.time),
            CsvValue::Float(self.dt),
            CsvValue::Text(&self.limit),
            CsvValue::Float(self.max_speed),
            CsvValue::Float(self.max_compression),
            CsvValue::Float(self.max_surface_deficit),
            CsvValue::Int(self.correction_iterations as i64),
            CsvValue::Int(self.removed as i64),
            CsvValue::Int(self.created as i64),
            CsvValue::Int(self.outflow as i64),
        ]
    }
}
