//! The stages of a step. The same snake_case names appear as `Backend` methods (and, with the
//! CUDA backend, as kernel names), so timers and benchmark rows line up by construction.

use crate::backend::{ForceTerms, WallModel};

/// When in an integrator stage [`Stage::MoveSolids`] places the moving solids.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolidsAt {
    /// At the time the stage's forces are evaluated, `t^n + c_k dt` (the integrator's `t/dt`).
    StageStart,
    /// At the time of the stage's result, `t^n + τ_k`, before the position correction of that
    /// result: the correction then keeps the fluid out of the walls where they are at that time,
    /// which is also the next stage's start (SSP-RK3: `τ = dt, dt/2, dt` and `c = 0, 1, 1/2`), so
    /// the walls do not jump between a correction and the next force evaluation.
    StageResult,
}

/// One stage of the solver's plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Prescribed motion (`boundary::motion`): solid particles to `x0 + d(t)`, velocity `d'(t)`.
    /// Only in scenes where some solid moves.
    MoveSolids(SolidsAt),
    /// Section 3: cell keys, radix sort, reorder, cell ranges.
    SortByCell,
    /// Eq. (18): density by summation.
    Density,
    /// Eq. (19): pressure from density.
    EquationOfState,
    /// Boundary: solid-particle pressure ([A12] eq. 27). Only in scenes with solids.
    WallPressure(WallModel),
    /// Eqs. (15)–(17), (6): fluid acceleration, with the terms the scene asks for.
    Forces(ForceTerms),
    /// Fig. 4: force of the fluid on each named solid. Only in scenes with solids.
    SolidForces,
    /// Time step from the state (or the scene's fixed step), and the state guards.
    TimeStep,
    /// Symplectic Euler update of velocity and position.
    Integrate,
    /// One stage of the third-order SSP Runge–Kutta scheme (Shu & Osher 1988; PAPER.md note 8).
    RkStage,
    /// Eqs. (23)–(24): the position correction loop (the `corrected` solver, section 2).
    Correction,
}

impl Stage {
    /// The stage's snake_case name (as the backend method).
    pub fn name(&self) -> &'static str {
        match self {
            Stage::MoveSolids(_) => "move_solids",
            Stage::SortByCell => "sort_by_cell",
            Stage::Density => "density",
            Stage::EquationOfState => "equation_of_state",
            Stage::WallPressure(_) => "wall_pressure",
            Stage::Forces(_) => "forces",
            Stage::SolidForces => "solid_forces",
            Stage::TimeStep => "time_step",
            Stage::Integrate => "integrate",
            Stage::RkStage => "rk_stage",
            Stage::Correction => "correct_positions",
        }
    }
}
