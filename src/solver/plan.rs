//! Scene → plan: the list of stages a step runs. A term the scene does not ask for is not in the
//! plan (or is compiled out of the force loop), so it costs nothing.

use super::stage::Stage;
use crate::backend::ForceTerms;

/// What the plan depends on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlanInputs {
    /// The scene lists the `viscosity` effect.
    pub viscosity: bool,
    /// The scene lists the `artificial_viscosity` effect.
    pub artificial_viscosity: bool,
    /// The scene has at least one solid.
    pub solids: bool,
}

/// The weakly compressible step (PAPER.md section 1), in order.
pub fn wcsph_plan(inputs: PlanInputs) -> Vec<Stage> {
    let mut plan = vec![Stage::SortByCell, Stage::Density, Stage::EquationOfState];
    if inputs.solids {
        plan.push(Stage::WallPressure);
    }
    plan.push(Stage::Forces(ForceTerms {
        viscosity: inputs.viscosity,
        artificial_viscosity: inputs.artificial_viscosity,
    }));
    if inputs.solids {
        plan.push(Stage::SolidForces);
    }
    plan.push(Stage::TimeStep);
    plan.push(Stage::Integrate);
    plan
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plan_omits_what_the_scene_does_not_ask_for() {
        let bare = wcsph_plan(PlanInputs {
            viscosity: false,
            artificial_viscosity: false,
            solids: false,
        });
        assert!(!bare.contains(&Stage::WallPressure));
        assert!(!bare.contains(&Stage::SolidForces));
        assert!(bare.contains(&Stage::Forces(ForceTerms {
            viscosity: false,
            artificial_viscosity: false
        })));
        let full = wcsph_plan(PlanInputs {
            viscosity: true,
            artificial_viscosity: true,
            solids: true,
        });
        assert_eq!(full.len(), 8);
    }
}
