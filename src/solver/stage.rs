//! The stages of a step. The same snake_case names appear as `Backend` methods (and, with the
//! CUDA backend, as kernel names), so timers and benchmark rows line up by construction.
//!
//! Each stage also says what it implements (PAPER.md equation numbers; [A12] Adami, Hu & Adams,
//! J. Comput. Phys. 231 (2012); [M92] Monaghan 1992; [MFZ97] Morris, Fox & Zhu 1997; [AAT13]
//! Akinci, Akinci & Teschner 2013; [LNSZZ94] Lafaurie et al. 1994, the capillary stress;
//! [M00a] Monaghan 2000, artificial stress; [F19] Fourtakas et al., Comput. Fluids 190
//! (2019), density diffusion; [WN11] Walker & Ni,
//! SIAM J. Numer. Anal. 49 (2011), Anderson acceleration; [AEA17] Altomare et al., Coastal Eng.
//! 127 (2017), the damping zone; [HA06] Hu & Adams 2006, the `multiphase` variants:
//! [`MultiphaseVariant`]) and which particle fields it reads and
//! writes, one function per piece (`sph plan` prints them), next to the stage itself so the two
//! cannot drift apart. [`SubStage`] does the same for the steps the driver (`solver::step`) runs
//! inside a stage: the correction loop and the no-penetration guard.

use crate::fields::Field;
use crate::model::pair_terms::{PairTerm, PairTerms};
use crate::model::{ForceTerms, SurfaceTensionModel, WallModel};
use crate::periodic::PeriodicAxes;
use Field::{
    Acceleration, ActingPressure, Density, DensityRate, DensityStart, Id, Kind, Mass, Normal, Position,
    PositionStart, Pressure, Velocity, VelocityStart, WallVelocity,
};

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
    /// The continuity equation with [F19] density diffusion: `dρ/dt` of fluid particles
    /// (`physics::density_diffusion`). Only with the `density_diffusion` effect, in place of
    /// [`Stage::Density`].
    DensityRate,
    /// Eq. (19): pressure from density.
    EquationOfState,
    /// Boundary: solid-particle pressure ([A12] eq. 27). Only in scenes with solids.
    WallPressure(WallModel),
    /// Boundary: the no-slip velocity solid particles carry in the viscous force (17) ([A12]
    /// eqs. 22–23, `boundary::wall_velocity`). Only in scenes with viscosity and solids.
    WallVelocity,
    /// The first moment `κ` of the spiky gradient measured on the particles as they stand
    /// ([BL99] eq. 43's scalar part, `physics::gradient_moment`): the pressure force and the
    /// correction of this integrator stage divide by it. Only with
    /// `GradientMoment::Measured` (the `corrected` default).
    GradientMoment,
    /// Eqs. (15)–(17), (6): fluid acceleration, with the terms the scene asks for.
    Forces(ForceTerms),
    /// [AAT13] eq. (3): surface normals of fluid particles (with rest volumes for the surface
    /// stress: `h ∇c`). Only with the `surface_tension` effect.
    SurfaceNormals(SurfaceTensionModel),
    /// The surface tension added to the fluid acceleration: the capillary stress
    /// (`physics::surface_stress`, [LNSZZ94], [M00a]) or [AAT13] eqs. (1)–(5). Only with the
    /// `surface_tension` effect.
    SurfaceTension(SurfaceTensionModel),
    /// Fig. 4: force of the fluid on each named solid, the reaction of the pressure force and of
    /// these pair terms (the force stage's). Only in scenes with solids.
    SolidForces(PairTerms),
    /// Time step from the state (or the scene's fixed step), and the state guards.
    TimeStep,
    /// Symplectic Euler update of velocity and position.
    Integrate,
    /// One stage of the third-order SSP Runge–Kutta scheme (Shu & Osher 1988; PAPER.md note 8).
    RkStage,
    /// Eqs. (23)–(24): the position correction loop (the `corrected` solver, section 2).
    Correction,
    /// The fluid density advanced by [`Stage::DensityRate`]'s rate: with symplectic Euler at the
    /// start of a step, `ρ += dt dρ/dt` with the last step's `dt` (the rate of the positions and
    /// velocities that step reached, `solver::plan`); with SSP-RK3 at the end of each stage, the
    /// Shu–Osher combination with the step-start density. Only with the `density_diffusion`
    /// effect.
    IntegrateDensity,
    /// The damping zone ([AEA17] Altomare et al. 2017, `physics::damping_zone`): fluid
    /// velocities relaxed towards zero, once a step after the last integrator stage. Only in
    /// scenes with a `[damping_zone]`.
    DampingZone,
    /// Periodic boundaries (`crate::periodic`): a fluid particle that left the domain along one
    /// of these axes moves back by one period, once a step after the last integrator stage.
    /// Only in scenes with a `[periodic]` table.
    WrapPositions(PeriodicAxes),
}

impl Stage {
    /// The stage's snake_case name (as the backend method).
    pub fn name(&self) -> &'static str {
        match self {
            Stage::MoveSolids(_) => "move_solids",
            Stage::SortByCell => "sort_by_cell",
            Stage::Density => "density",
            Stage::DensityRate => "density_rate",
            Stage::EquationOfState => "equation_of_state",
            Stage::WallPressure(_) => "wall_pressure",
            Stage::WallVelocity => "wall_velocity",
            Stage::GradientMoment => "gradient_moment",
            Stage::Forces(_) => "forces",
            Stage::SurfaceNormals(_) => "surface_normals",
            Stage::SurfaceTension(_) => "surface_tension",
            Stage::SolidForces(_) => "solid_forces",
            Stage::TimeStep => "time_step",
            Stage::Integrate => "integrate",
            Stage::RkStage => "rk_stage",
            Stage::Correction => "correct_positions",
            Stage::IntegrateDensity => "integrate_density",
            Stage::DampingZone => "damping_zone",
            Stage::WrapPositions(_) => "wrap_positions",
        }
    }

    /// What the stage implements: the PAPER.md equation (or the source) it follows.
    pub fn equation(&self) -> String {
        let text = match self {
            Stage::MoveSolids(_) => "x0 + d(t)",
            Stage::SortByCell => "section 3",
            Stage::Density => "(18)",
            Stage::DensityRate => "continuity, [F19] diffusion",
            Stage::EquationOfState => "(19)",
            Stage::WallPressure(_) => "[A12] (27)",
            Stage::WallVelocity => "[A12] (22)-(23)",
            Stage::GradientMoment => "(16), [BL99] (43)",
            Stage::Forces(terms) => {
                let mut parts = vec!["(16)"];
                parts.extend(terms.pair.iter().map(PairTerm::equation));
                parts.push("(6)");
                if terms.rotating_frame {
                    parts.push("[B67] 3.2");
                }
                return format!("(15): {}", parts.join(", "));
            }
            Stage::SurfaceNormals(SurfaceTensionModel::SurfaceStress) => "[AAT13] (3), m/rho0",
            Stage::SurfaceNormals(SurfaceTensionModel::Akinci) => "[AAT13] (3)",
            Stage::SurfaceTension(SurfaceTensionModel::SurfaceStress) => "[LNSZZ94], [M00a]",
            Stage::SurfaceTension(SurfaceTensionModel::Akinci) => "[AAT13] (1)-(5)",
            Stage::SolidForces(_) => "Fig. 4",
            Stage::TimeStep => "CFL, [M92], [MFZ97]",
            Stage::Integrate => "(15)",
            Stage::RkStage => "(15), note 8",
            Stage::Correction => "(23)-(24)",
            Stage::IntegrateDensity => "continuity, note 8",
            Stage::DampingZone => "[AEA17]",
            Stage::WrapPositions(_) => "periodic",
        };
        text.to_string()
    }

    /// What the stage computes, in words.
    pub fn description(&self) -> String {
        let text = match self {
            Stage::MoveSolids(SolidsAt::StageStart) => "moving solids to where they are at the stage's start",
            Stage::MoveSolids(SolidsAt::StageResult) => {
                "moving solids to where they are at the stage's result"
            }
            Stage::SortByCell => "cell keys, radix sort, reorder of every field, cell ranges",
            Stage::Density => "density by summation (fluid)",
            Stage::DensityRate => {
                "drho/dt = sum m_j (u_i - u_j).grad W (walls at the forces' velocity) + F19 diffusion of the non-hydrostatic density difference over fluid neighbours (fluid)"
            }
            Stage::EquationOfState => "pressure from density, clamped at zero (note 6)",
            Stage::WallPressure(WallModel::ExtrapolatedOrSummed) => {
                "solid pressure: extrapolated from the fluid, or (19) of its own density if larger"
            }
            Stage::WallPressure(WallModel::Extrapolated) => "solid pressure extrapolated from the fluid",
            Stage::WallVelocity => {
                "no-slip walls: solid velocity in (17) is 2 u_wall minus the fluid's Shepard average"
            }
            Stage::GradientMoment => {
                "kappa = mean over fluid with Shepard sum >= 0.95 of -(1/D) sum (m/rho) x_ij . grad W; the pressure force divides by it"
            }
            Stage::Forces(terms) => {
                let mut parts = vec!["pressure force"];
                parts.extend(terms.pair.iter().map(PairTerm::label));
                parts.push("body force");
                if terms.rotating_frame {
                    parts.push("Coriolis and centrifugal force");
                }
                return format!("acceleration: {}", parts.join(", "));
            }
            Stage::SurfaceNormals(SurfaceTensionModel::SurfaceStress) => {
                "colour gradient h grad c = h sum (m/rho0) grad W over fluid neighbours (fluid)"
            }
            Stage::SurfaceNormals(SurfaceTensionModel::Akinci) => {
                "surface normals h sum (m/rho) grad W over fluid neighbours (fluid)"
            }
            Stage::SurfaceTension(SurfaceTensionModel::SurfaceStress) => {
                "acceleration += pair force of the capillary stresses sigma' |grad c| (I - N N), with artificial stress (fluid)"
            }
            Stage::SurfaceTension(SurfaceTensionModel::Akinci) => {
                "acceleration += cohesion and curvature forces of fluid neighbours, gamma from sigma (fluid)"
            }
            Stage::SolidForces(_) => "force of the fluid on each named solid: the forces stage's pair terms",
            Stage::TimeStep => {
                "time step from sound, flow, forces and viscosity; state guards (first integrator stage only)"
            }
            Stage::Integrate => "symplectic Euler: u += a dt, then x += u dt (fluid)",
            Stage::RkStage => "one SSP-RK3 stage (the first also stores x^n, u^n)",
            Stage::Correction => "position correction loop, until the compression is below delta",
            Stage::IntegrateDensity => {
                "symplectic Euler: rho += dt drho/dt with the last step's dt and the rate of the state it reached; SSP-RK3: the stage with rho^n (the first also stores it) (fluid)"
            }
            Stage::DampingZone => {
                "u *= max(0, 1 - dt beta r^2), r the depth into the damping zone (fluid; once a step, after the last integrator stage)"
            }
            Stage::WrapPositions(axes) => {
                return format!(
                    "x -= L or x += L along the periodic axes {:?} outside the domain (fluid; once a step, after the last integrator stage)",
                    axes.names()
                );
            }
        };
        text.to_string()
    }

    /// The particle fields the stage reads.
    pub fn reads(&self) -> &'static [Field] {
        match self {
            Stage::MoveSolids(_) => &[Kind, Id],
            Stage::SortByCell => &[Position],
            Stage::Density => &[Position, Mass, Kind],
            Stage::DensityRate => &[Position, Velocity, Density, Mass, Kind],
            Stage::EquationOfState => &[Density, Kind],
            Stage::WallPressure(_) => &[Position, Density, Pressure, Mass, Kind],
            Stage::WallVelocity => &[Position, Velocity, Kind],
            Stage::GradientMoment => &[Position, Density, Mass, Kind],
            Stage::Forces(terms) if terms.pair != PairTerms::NONE || terms.rotating_frame => {
                &[Position, Velocity, Density, Pressure, Mass, Kind]
            }
            Stage::Forces(_) => &[Position, Density, Pressure, Mass, Kind],
            Stage::SurfaceNormals(SurfaceTensionModel::SurfaceStress) => &[Position, Mass, Kind],
            Stage::SurfaceNormals(SurfaceTensionModel::Akinci) => &[Position, Density, Mass, Kind],
            Stage::SurfaceTension(SurfaceTensionModel::SurfaceStress) => {
                &[Position, Mass, Kind, Normal, Acceleration]
            }
            Stage::SurfaceTension(SurfaceTensionModel::Akinci) => {
                &[Position, Density, Mass, Kind, Normal, Acceleration]
            }
            Stage::SolidForces(_) => &[Position, Velocity, Density, Pressure, Mass, Kind],
            Stage::TimeStep => &[Position, Velocity, Acceleration, Density, Kind],
            Stage::Integrate => &[Velocity, Acceleration, Kind],
            Stage::RkStage => &[
                Position,
                Velocity,
                Acceleration,
                Kind,
                PositionStart,
                VelocityStart,
            ],
            Stage::Correction => &[Position, Density, Pressure, Mass, Kind],
            Stage::IntegrateDensity => &[Density, DensityRate, Kind],
            Stage::DampingZone => &[Position, Velocity, Kind],
            Stage::WrapPositions(_) => &[Position, Kind],
        }
    }

    /// The particle fields the stage reads within `plan`: [`Stage::reads`], the no-slip
    /// velocity of solids (`Field::WallVelocity`) where the plan computes it
    /// ([`Stage::WallVelocity`], scenes with viscosity and solids): the viscous force (17) of
    /// the forces stage and its reaction on the solids read it; and with the `multiphase`
    /// effect, `Field::RestDensity` where the stage's [`MultiphaseVariant`] reads it.
    pub fn reads_in(&self, plan: &[Stage], multiphase: bool) -> Vec<Field> {
        let mut fields = self.reads().to_vec();
        let no_slip = plan.contains(&Stage::WallVelocity);
        let reader = match self {
            Stage::Forces(t) => t.pair.contains(PairTerm::Viscosity),
            Stage::SolidForces(t) => t.contains(PairTerm::Viscosity),
            // The continuity sum moves walls as the forces do.
            Stage::DensityRate => true,
            _ => false,
        };
        if no_slip && reader {
            fields.push(WallVelocity);
        }
        if multiphase && self.multiphase().is_some_and(|v| v.reads_rest_density) {
            fields.push(Field::RestDensity);
        }
        if *self == Stage::IntegrateDensity && plan.contains(&Stage::RkStage) {
            fields.push(DensityStart);
        }
        fields
    }

    /// The particle fields the stage writes within `plan`: [`Stage::writes`], and with SSP-RK3
    /// the step-start density [`Stage::IntegrateDensity`] stores.
    pub fn writes_in(&self, plan: &[Stage]) -> Vec<Field> {
        let mut fields = self.writes().to_vec();
        if *self == Stage::IntegrateDensity && plan.contains(&Stage::RkStage) {
            fields.push(DensityStart);
        }
        fields
    }

    /// The particle fields the stage writes.
    pub fn writes(&self) -> &'static [Field] {
        match self {
            Stage::MoveSolids(_) => &[Position, Velocity],
            Stage::SortByCell => &Field::ALL,
            Stage::Density => &[Density],
            Stage::DensityRate => &[DensityRate],
            Stage::EquationOfState => &[Pressure],
            Stage::WallPressure(_) => &[Density, Pressure],
            Stage::WallVelocity => &[WallVelocity],
            Stage::Forces(_) => &[Acceleration],
            Stage::SurfaceNormals(_) => &[Normal],
            Stage::SurfaceTension(_) => &[Acceleration],
            Stage::GradientMoment | Stage::SolidForces(_) | Stage::TimeStep => &[],
            Stage::Integrate => &[Position, Velocity],
            Stage::RkStage => &[Position, Velocity, PositionStart, VelocityStart],
            Stage::Correction => &[Position, Velocity, Density, Pressure, ActingPressure],
            Stage::IntegrateDensity => &[Density],
            Stage::DampingZone => &[Velocity],
            Stage::WrapPositions(_) => &[Position],
        }
    }

    /// The steps the driver runs inside this stage, in order (`solver::step`): the correction
    /// loop's sweep, and the no-penetration guard after a move when the scene has solids.
    pub fn sub_stages(&self, solids: bool) -> Vec<SubStage> {
        match self {
            Stage::Integrate | Stage::RkStage if solids => vec![SubStage::KeepOut],
            Stage::Correction => {
                let mut sweep = vec![
                    SubStage::SortByCell,
                    SubStage::Density,
                    SubStage::CorrectionError,
                    SubStage::CorrectionPressure,
                ];
                if solids {
                    sweep.push(SubStage::SolidForces);
                }
                sweep.push(SubStage::CorrectPositions);
                if solids {
                    sweep.push(SubStage::KeepOut);
                }
                sweep
            }
            _ => Vec::new(),
        }
    }

    /// The steps of the velocity solve the driver runs after the correction loop of a stage
    /// (`Simulation::solve_velocities`): its start and warm start, each iteration, its record and
    /// end, its push on the solids. Empty for every other stage.
    pub fn velocity_sub_stages(&self, solids: bool) -> Vec<SubStage> {
        if *self != Stage::Correction {
            return Vec::new();
        }
        let mut steps = vec![
            SubStage::BeginVelocitySolve,
            SubStage::WarmStartVelocitySolve,
            SubStage::PredictedDensity,
            SubStage::CorrectionError,
            SubStage::MixVelocityPressure,
            SubStage::VelocityFromPressure,
            SubStage::RecordVelocitySolve,
            SubStage::EndVelocitySolve,
        ];
        if solids {
            steps.push(SubStage::SolidForces);
        }
        steps
    }
}

/// What a stage or sub-stage runs instead with the `multiphase` effect ([HA06] Hu & Adams,
/// J. Comput. Phys. 213 (2006); `physics::multiphase`). The backends select these variants when
/// `Fields::rest_density` is allocated, which happens exactly when the scene has the effect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MultiphaseVariant {
    /// The equation or source.
    pub equation: &'static str,
    /// What changes, in words.
    pub description: &'static str,
    /// Whether the variant reads `Fields::rest_density` (beside the stage's own fields).
    pub reads_rest_density: bool,
}

const MP_DENSITY: MultiphaseVariant = MultiphaseVariant {
    equation: "[HA06] rho = m sum W",
    description: "number density times the particle's own mass, instead of (18)",
    reads_rest_density: false,
};
const MP_EOS: MultiphaseVariant = MultiphaseVariant {
    equation: "(19), own rho0",
    description: "each particle's own rest density",
    reads_rest_density: true,
};
const MP_PRESSURE: MultiphaseVariant = MultiphaseVariant {
    equation: "[HA06] volume form",
    description: "pressure pair force -(p_i V_i^2 + p_j V_j^2) grad W / m_i, V = m/rho, instead of (16)",
    reads_rest_density: false,
};
const MP_ERROR: MultiphaseVariant = MultiphaseVariant {
    equation: "(24), own rho0",
    description: "density error against each particle's own rest density",
    reads_rest_density: true,
};

impl Stage {
    /// The stage's multiphase variant, if it has one (`None`: the stage runs as without the
    /// effect).
    pub fn multiphase(&self) -> Option<MultiphaseVariant> {
        match self {
            Stage::Density => Some(MP_DENSITY),
            Stage::EquationOfState => Some(MP_EOS),
            Stage::WallPressure(WallModel::ExtrapolatedOrSummed) => Some(MultiphaseVariant {
                equation: "[HA06] m_w sum W",
                description: "the summed branch reads the wall's number density; (27) uses each fluid neighbour's own density",
                reads_rest_density: false,
            }),
            Stage::Forces(_) | Stage::SolidForces(_) => Some(MP_PRESSURE),
            Stage::TimeStep => Some(MP_ERROR),
            Stage::SurfaceNormals(SurfaceTensionModel::SurfaceStress)
            | Stage::SurfaceTension(SurfaceTensionModel::SurfaceStress) => Some(MultiphaseVariant {
                equation: "own rho0",
                description: "each particle's rest volume m/rho0 from its own phase",
                reads_rest_density: true,
            }),
            Stage::Correction => Some(MultiphaseVariant {
                equation: "(23)-(24), [HA06]",
                description: "increments and error against each particle's own rest density; volume-form displacement",
                reads_rest_density: true,
            }),
            _ => None,
        }
    }
}

#[path = "sub_stage.rs"]
mod sub_stage;
pub use sub_stage::SubStage;
