//! Scene → plan: the list of stages one integrator stage runs (once per step for symplectic
//! Euler, three times for SSP-RK3). A term the scene does not ask for is not in the plan (or is
//! compiled out of the force loop), so it costs nothing.

use super::Integrator;
use super::stage::{SolidsAt, Stage, SubStage};
use crate::fields::Field;
use crate::model::pair_terms::{PairTerm, PairTerms};
use crate::model::{DensityEquation, ForceTerms, GradientMoment, SurfaceTensionModel, WallModel};
use crate::periodic::PeriodicAxes;

/// What the plan depends on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlanInputs {
    /// The optional pair terms of the force stage the scene lists among its effects.
    pub pair_terms: PairTerms,
    /// The scene lists the `rotating_frame` effect.
    pub rotating_frame: bool,
    /// The scene lists the `surface_tension` effect: its model.
    pub surface_tension: Option<SurfaceTensionModel>,
    /// The scene has at least one solid.
    pub solids: bool,
    /// At least one solid has a prescribed motion.
    pub moving_solids: bool,
    /// The time integrator.
    pub integrator: Integrator,
    /// The `corrected` solver: eqs. (23)–(24) after every integrator stage.
    pub corrected: bool,
    /// How fluid density evolves: summed (18), or integrated by the continuity equation with
    /// density diffusion (the `density_diffusion` effect, `wcsph` only).
    pub density: DensityEquation,
    /// The scene has a damping zone (`physics::damping_zone`).
    pub damping_zone: bool,
    /// The periodic axes (`crate::periodic`); none: no wrap stage.
    pub periodic: PeriodicAxes,
    /// The pressure gradient's moment: the lattice's, or measured every integrator stage
    /// (`Stage::GradientMoment`).
    pub gradient_moment: GradientMoment,
}

/// The stages of one integrator stage, in order (PAPER.md sections 1 and 2).
///
/// With the correction, pressure is not the equation of state of the density (19) with the
/// scene's `C` but the pressure the correction found (`solver::step`), so the plan has no
/// `EquationOfState` stage and walls take the extrapolated pressure only.
///
/// Moving solids are placed first, at the stage's start time, and (`corrected`) again at the
/// time of the stage's result before its correction (`SolidsAt`).
///
/// With the continuity equation ([`DensityEquation::ContinuityFourtakas2019`]) the fluid's
/// density is state: no summation. Its rate is taken on the stage's state right after the sort
/// (after the no-slip wall velocity, which the rate uses as the forces do), and solids keep the
/// density the wall stage gives them. When the density advances:
/// - SSP-RK3: with positions and velocities at the end of each stage, by the same Shu–Osher
///   combination (the method of lines; RK3's stability region holds the acoustic modes).
/// - Symplectic Euler: at the start of the next step, before the equation of state, by the last
///   step's `dt` (`Clock::last_dt`): `u^{n+1} = u^n + dt a(x^n, ρ^n)`, `x^{n+1} = x^n + dt
///   u^{n+1}`, `ρ^{n+1} = ρ^n + dt R(x^{n+1}, u^{n+1})`. The density takes the new velocity as the
///   positions do; with the old one (`ρ^n + dt R(x^n, u^n)`) the pair density–velocity is a
///   forward Euler step of the acoustic waves, which grows at any `dt` (measured: a resting tank
///   at CFL 0.2 reached 1.3 m/s in 0.5 s).
pub fn plan(inputs: PlanInputs) -> Vec<Stage> {
    let mut plan = Vec::new();
    if inputs.moving_solids {
        plan.push(Stage::MoveSolids(SolidsAt::StageStart));
    }
    plan.push(Stage::SortByCell);
    let continuity = inputs.density == DensityEquation::ContinuityFourtakas2019;
    // [A12] eqs. (22)-(23): no-slip walls for the viscous force (17) (and the continuity sum).
    let no_slip = inputs.solids && inputs.pair_terms.contains(PairTerm::Viscosity);
    if continuity {
        if no_slip {
            plan.push(Stage::WallVelocity);
        }
        plan.push(Stage::DensityRate);
        if inputs.integrator == Integrator::SymplecticEuler {
            plan.push(Stage::IntegrateDensity);
        }
    } else {
        plan.push(Stage::Density);
    }
    if !inputs.corrected {
        plan.push(Stage::EquationOfState);
    }
    if inputs.solids {
        plan.push(Stage::WallPressure(if inputs.corrected {
            WallModel::Extrapolated
        } else {
            WallModel::ExtrapolatedOrSummed
        }));
        if no_slip && !continuity {
            plan.push(Stage::WallVelocity);
        }
    }
    if inputs.gradient_moment == GradientMoment::Measured {
        // On the stage's positions and densities, walls' included, before the first pressure
        // force of the stage (the correction of the stage uses it too).
        plan.push(Stage::GradientMoment);
    }
    plan.push(Stage::Forces(ForceTerms {
        pair: inputs.pair_terms,
        rotating_frame: inputs.rotating_frame,
    }));
    if let Some(model) = inputs.surface_tension {
        // After the force stage, which sets the acceleration they add to.
        plan.extend([Stage::SurfaceNormals(model), Stage::SurfaceTension(model)]);
    }
    if inputs.solids {
        // The reaction of the force stage's pair terms.
        plan.push(Stage::SolidForces(inputs.pair_terms));
    }
    plan.push(Stage::TimeStep);
    plan.push(match inputs.integrator {
        Integrator::SymplecticEuler => Stage::Integrate,
        Integrator::Rk3 => Stage::RkStage,
    });
    if continuity && inputs.integrator == Integrator::Rk3 {
        plan.push(Stage::IntegrateDensity);
    }
    if inputs.corrected {
        if inputs.moving_solids {
            plan.push(Stage::MoveSolids(SolidsAt::StageResult));
        }
        plan.push(Stage::Correction);
    }
    if inputs.damping_zone {
        // On the stage's final velocities; the driver runs it once a step, after the last
        // integrator stage.
        plan.push(Stage::DampingZone);
    }
    if !inputs.periodic.is_empty() {
        // Once a step, after every stage that moves particles (`crate::periodic`).
        plan.push(Stage::WrapPositions(inputs.periodic));
    }
    plan
}

/// The particle fields `plan` needs: everything a stage or a sub-stage reads or writes, plus the
/// identity every output and checkpoint carries. A field outside this list is not allocated
/// (`Fields::is_allocated`). The sort is left out: it permutes whatever is allocated.
/// `multiphase`: the scene has the `multiphase` effect (the stages' variants read the rest
/// density, `Stage::reads_in`).
pub fn needed_fields(plan: &[Stage], solids: bool, multiphase: bool) -> Vec<Field> {
    let mut needed = vec![Field::Id];
    for stage in plan.iter().filter(|s| **s != Stage::SortByCell) {
        needed.extend(stage.reads_in(plan, multiphase));
        needed.extend(stage.writes_in(plan));
        for sub in stage
            .sub_stages(solids)
            .into_iter()
            .chain(stage.velocity_sub_stages(solids))
        {
            if sub != SubStage::SortByCell {
                needed.extend(sub.reads_in(plan, multiphase));
                needed.extend_from_slice(sub.writes());
            }
        }
    }
    Field::ALL.into_iter().filter(|f| needed.contains(f)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs() -> PlanInputs {
        PlanInputs {
            pair_terms: PairTerms::NONE,
            rotating_frame: false,
            surface_tension: None,
            solids: false,
            moving_solids: false,
            integrator: Integrator::SymplecticEuler,
            corrected: false,
            density: DensityEquation::Summation,
            damping_zone: false,
            periodic: PeriodicAxes::NONE,
            gradient_moment: GradientMoment::Lattice,
        }
    }

    #[test]
    fn a_measured_gradient_moment_runs_after_the_walls_and_before_the_forces() {
        for corrected in [false, true] {
            let p = plan(PlanInputs {
                solids: true,
                corrected,
                gradient_moment: GradientMoment::Measured,
                ..inputs()
            });
            let at = |want: fn(&Stage) -> bool| p.iter().position(want).expect("planned");
            let moment = at(|s| *s == Stage::GradientMoment);
            assert!(
                at(|s| matches!(s, Stage::WallPressure(_))) < moment,
                "walls' density first"
            );
            assert!(
                moment < at(|s| matches!(s, Stage::Forces(_))),
                "before the pressure force"
            );
            let lattice = plan(PlanInputs {
                solids: true,
                corrected,
                ..inputs()
            });
            assert!(
                !lattice.contains(&Stage::GradientMoment),
                "the lattice's kappa: no stage"
            );
        }
    }

    #[test]
    fn continuity_replaces_the_summation_and_integrates_density_after_the_move() {
        for integrator in [Integrator::SymplecticEuler, Integrator::Rk3] {
            let p = plan(PlanInputs {
                solids: true,
                pair_terms: PairTerms::NONE.with(PairTerm::Viscosity),
                integrator,
                density: DensityEquation::ContinuityFourtakas2019,
                ..inputs()
            });
            assert!(!p.contains(&Stage::Density));
            let rate = p.iter().position(|s| *s == Stage::DensityRate).expect("a rate");
            let walls = p
                .iter()
                .position(|s| *s == Stage::WallVelocity)
                .expect("no-slip walls");
            assert!(walls < rate, "the rate reads the wall velocity");
            let advance = p
                .iter()
                .position(|s| *s == Stage::IntegrateDensity)
                .expect("advanced");
            let eos = p
                .iter()
                .position(|s| *s == Stage::EquationOfState)
                .expect("eq. (19)");
            match integrator {
                // The last step's motion, before the pressure reads the density.
                Integrator::SymplecticEuler => assert!(rate < advance && advance < eos),
                Integrator::Rk3 => assert_eq!(advance, p.len() - 1),
            }
            let needed = needed_fields(&p, true, false);
            assert!(needed.contains(&Field::DensityRate));
            assert_eq!(
                needed.contains(&Field::DensityStart),
                integrator == Integrator::Rk3,
                "{integrator:?}"
            );
        }
        let summed = plan(inputs());
        assert!(!summed.contains(&Stage::DensityRate) && !summed.contains(&Stage::IntegrateDensity));
        assert!(!needed_fields(&summed, false, false).contains(&Field::DensityRate));
    }

    #[test]
    fn the_guard_reads_the_step_start_only_under_ssp_rk3() {
        let euler = plan(PlanInputs {
            solids: true,
            ..inputs()
        });
        let rk3 = plan(PlanInputs {
            solids: true,
            integrator: Integrator::Rk3,
            ..inputs()
        });
        let guard = SubStage::KeepOut;
        assert!(!guard.reads_in(&euler, false).contains(&Field::PositionStart));
        assert!(guard.reads_in(&rk3, false).contains(&Field::PositionStart));
        assert!(needed_fields(&rk3, true, false).contains(&Field::PositionStart));
        assert!(!needed_fields(&euler, true, false).contains(&Field::PositionStart));
    }

    #[test]
    fn plan_omits_what_the_scene_does_not_ask_for() {
        let bare = plan(inputs());
        assert!(!bare.iter().any(|s| matches!(s, Stage::WallPressure(_))));
        assert!(!bare.iter().any(|s| matches!(s, Stage::SolidForces(_))));
        assert!(!bare.contains(&Stage::Correction));
        assert!(!bare.iter().any(|s| matches!(s, Stage::MoveSolids(_))));
        assert!(
            !bare
                .iter()
                .any(|s| matches!(s, Stage::SurfaceNormals(_) | Stage::SurfaceTension(_)))
        );
        assert!(bare.contains(&Stage::Forces(ForceTerms {
            pair: PairTerms::NONE,
            rotating_frame: false,
        })));
        let all = PairTerm::ALL.into_iter().fold(PairTerms::NONE, PairTerms::with);
        let full = plan(PlanInputs {
            pair_terms: all,
            rotating_frame: true,
            solids: true,
            ..inputs()
        });
        assert_eq!(full.len(), 9, "with viscosity and solids: wall_velocity");
        assert!(full.contains(&Stage::WallVelocity));
        assert!(
            !plan(PlanInputs {
                solids: true,
                ..inputs()
            })
            .contains(&Stage::WallVelocity),
            "no viscosity, no wall velocity"
        );
        assert!(
            !plan(PlanInputs {
                pair_terms: PairTerms::NONE.with(PairTerm::Viscosity),
                ..inputs()
            })
            .contains(&Stage::WallVelocity),
            "no solids, no wall velocity"
        );
        assert!(full.contains(&Stage::Forces(ForceTerms {
            pair: all,
            rotating_frame: true,
        })));
        assert!(
            full.contains(&Stage::SolidForces(all)),
            "the reaction of the same terms"
        );
    }

    #[test]
    fn surface_tension_runs_its_two_stages_right_after_the_forces() {
        for integrator in [Integrator::SymplecticEuler, Integrator::Rk3] {
            for corrected in [false, true] {
                let p = plan(PlanInputs {
                    surface_tension: Some(SurfaceTensionModel::SurfaceStress),
                    solids: true,
                    integrator,
                    corrected,
                    ..inputs()
                });
                let at = p
                    .iter()
                    .position(|s| matches!(s, Stage::Forces(_)))
                    .expect("a force stage");
                assert_eq!(
                    &p[at + 1..at + 3],
                    &[
                        Stage::SurfaceNormals(SurfaceTensionModel::SurfaceStress),
                        Stage::SurfaceTension(SurfaceTensionModel::SurfaceStress)
                    ]
                );
            }
        }
    }

    #[test]
    fn corrected_plan_replaces_the_equation_of_state_by_the_correction() {
        let p = plan(PlanInputs {
            solids: true,
            integrator: Integrator::Rk3,
            corrected: true,
            ..inputs()
        });
        assert!(!p.contains(&Stage::EquationOfState));
        assert!(p.contains(&Stage::WallPressure(WallModel::Extrapolated)));
        assert_eq!(&p[p.len() - 2..], &[Stage::RkStage, Stage::Correction]);
        assert!(
            !p.iter().any(|s| matches!(s, Stage::MoveSolids(_))),
            "fixed solids cost nothing"
        );
    }

    #[test]
    fn the_damping_zone_runs_last_and_only_with_a_zone() {
        for integrator in [Integrator::SymplecticEuler, Integrator::Rk3] {
            for corrected in [false, true] {
                let with = plan(PlanInputs {
                    damping_zone: true,
                    integrator,
                    corrected,
                    ..inputs()
                });
                assert_eq!(
                    with.last(),
                    Some(&Stage::DampingZone),
                    "{integrator:?} {corrected}"
                );
                assert_eq!(with.iter().filter(|s| **s == Stage::DampingZone).count(), 1);
                let without = plan(PlanInputs {
                    integrator,
                    corrected,
                    ..inputs()
                });
                assert!(
                    !without.contains(&Stage::DampingZone),
                    "a flume-less scene pays nothing"
                );
                assert_eq!(&with[..with.len() - 1], &without[..]);
            }
        }
    }

    #[test]
    fn periodic_axes_wrap_positions_last_and_only_with_periodic_axes() {
        let x = PeriodicAxes::NONE.with(0);
        for integrator in [Integrator::SymplecticEuler, Integrator::Rk3] {
            for damping_zone in [false, true] {
                let base = PlanInputs {
                    integrator,
                    damping_zone,
                    corrected: true,
                    ..inputs()
                };
                let with = plan(PlanInputs { periodic: x, ..base });
                assert_eq!(with.last(), Some(&Stage::WrapPositions(x)));
                let without = plan(base);
                assert_eq!(&with[..with.len() - 1], &without[..], "nothing else changes");
            }
        }
    }

    #[test]
    fn moving_solids_are_placed_before_the_forces_and_before_each_correction() {
        let wcsph = plan(PlanInputs {
            solids: true,
            moving_solids: true,
            ..inputs()
        });
        assert_eq!(wcsph[0], Stage::MoveSolids(SolidsAt::StageStart));
        assert_eq!(
            wcsph.iter().filter(|s| matches!(s, Stage::MoveSolids(_))).count(),
            1
        );
        let corrected = plan(PlanInputs {
            solids: true,
            moving_solids: true,
            integrator: Integrator::Rk3,
            corrected: true,
            ..inputs()
        });
        assert_eq!(corrected[0], Stage::MoveSolids(SolidsAt::StageStart));
        assert_eq!(
            &corrected[corrected.len() - 3..],
            &[
                Stage::RkStage,
                Stage::MoveSolids(SolidsAt::StageResult),
                Stage::Correction
            ]
        );
    }
}
