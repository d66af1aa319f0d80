//! `[periodic]` (`sph::periodic`): the periodic Poiseuille scene validates to its axes and
//! plans the `wrap_positions` stage last; each bad input is one problem naming its key.

use crate::common::scene::{edit, parse, problem_with};
use sph::periodic::PeriodicAxes;
use sph::run::plan_inputs;
use sph::solver::plan::plan;
use sph::solver::stage::Stage;

fn text() -> String {
    let path = format!(
        "{}/tests/scenes/poiseuille_periodic_2d.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    std::fs::read_to_string(path).expect("the periodic test scene")
}

#[test]
fn periodic_axes_are_a_value_the_plan_carries() {
    let scene = parse(&text()).expect("valid");
    let x = PeriodicAxes::NONE.with(0);
    assert_eq!(scene.periodic, x);
    let stages = plan(plan_inputs(&scene));
    assert_eq!(stages.last(), Some(&Stage::WrapPositions(x)));
    let walled = parse(&edit(&text(), "[periodic]\naxes = [\"x\"]\n", "")).expect("valid");
    assert_eq!(walled.periodic, PeriodicAxes::NONE);
    assert!(
        !plan(plan_inputs(&walled))
            .iter()
            .any(|s| matches!(s, Stage::WrapPositions(_))),
        "no periodic axis, no wrap stage"
    );
}

#[test]
fn bad_periodic_axes_name_the_key() {
    let axes = "axes = [\"x\"]";
    problem_with(
        &edit(&text(), axes, "axes = []"),
        "periodic.axes",
        "lists no axis",
    );
    problem_with(
        &edit(&text(), axes, "axes = [\"z\"]"),
        "periodic.axes[0]",
        "does not exist in 2D",
    );
    problem_with(
        &edit(&text(), axes, "axes = [\"x\", \"x\"]"),
        "periodic.axes[1]",
        "listed twice",
    );
    problem_with(
        &edit(&text(), axes, "axes = [\"w\"]"),
        "periodic.axes[0]",
        "unknown variant",
    );
}

#[test]
fn the_period_must_hold_three_smoothing_lengths_and_whole_spacings() {
    // 5 spacings, less than 3 h = 6 spacings (boxes shrunk with the domain).
    let short = text().replace("0.3,", "0.025,");
    problem_with(&short, "periodic.axes[0]", "less than 3 smoothing lengths");
    // 60.5 spacings.
    let fraction = edit(&text(), "max = [0.3, 0.15]", "max = [0.3025, 0.15]");
    problem_with(&fraction, "periodic.axes[0]", "not a whole number");
}
