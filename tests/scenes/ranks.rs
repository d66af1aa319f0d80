//! `[ranks]` (how a run across ranks cuts its domain): defaults, each key, and bad values named
//! by their key.

use crate::common::scene::{parse, problem_with};
use sph::distributed::{Method, Rebalance};
use sph::scene::RankSettings;

fn text(ranks: &str) -> String {
    let path = format!("{}/scenes/dam_break_2d.toml", env!("CARGO_MANIFEST_DIR"));
    let scene = std::fs::read_to_string(path).expect("the shipped dam break");
    format!("{scene}\n{ranks}")
}

#[test]
fn ranks_keys_set_the_cut_and_the_rebalance() {
    assert_eq!(parse(&text("")).expect("valid").ranks, RankSettings::default());
    assert_eq!(
        RankSettings::default(),
        RankSettings {
            method: Method::Bisection,
            rebalance: Rebalance::Above(0.1)
        }
    );
    let slabs = parse(&text("[ranks]\ndecomposition = \"slabs\"\nrebalance = 0.25\n")).expect("valid");
    assert_eq!(
        slabs.ranks,
        RankSettings {
            method: Method::Slabs,
            rebalance: Rebalance::Above(0.25)
        }
    );
    let never = parse(&text("[ranks]\nrebalance = \"never\"\n")).expect("valid");
    assert_eq!(never.ranks.rebalance, Rebalance::Never);
}

#[test]
fn bad_ranks_values_name_the_key() {
    problem_with(
        &text("[ranks]\nrebalance = 0.0\n"),
        "ranks.rebalance",
        "must be > 0",
    );
    problem_with(
        &text("[ranks]\nrebalance = \"sometimes\"\n"),
        "ranks.rebalance",
        "\"never\"",
    );
    problem_with(
        &text("[ranks]\ndecomposition = \"cubes\"\n"),
        "ranks.decomposition",
        "unknown variant",
    );
    problem_with(&text("[ranks]\nsplit = 2\n"), "ranks.split", "unknown field");
}
