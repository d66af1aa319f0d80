//! `[[open_boundary]]` (`sph::boundary::open`): the open channel scene validates to its two
//! boundaries; each bad input is a problem naming its key.

use crate::common::scene::{edit, parse, problem_with};
use sph::scene::schema::OpenBoundaryKind;

fn text() -> String {
    let path = format!("{}/scenes/open_channel_2d.toml", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(path).expect("the open channel scene")
}

#[test]
fn the_open_channel_has_an_inflow_and_an_outflow() {
    let scene = parse(&text()).expect("valid");
    let b = &scene.open_boundaries;
    assert_eq!(b.len(), 2);
    assert_eq!(
        (b[0].kind, b[0].axis, b[0].inward),
        (OpenBoundaryKind::Inflow, 0, 1.0)
    );
    assert_eq!(
        (b[1].kind, b[1].axis, b[1].inward),
        (OpenBoundaryKind::Outflow, 0, -1.0)
    );
    // h = 2 dx: the default depth is 2 h/dx + 1 = 5 layers.
    assert_eq!((b[0].layers, b[1].layers), (5, 5));
    assert_eq!(b[0].velocity, vec![0.2, 0.0]);
    assert_eq!(b[0].ramp, Some(1.0));
}

#[test]
fn bad_open_boundaries_name_the_key() {
    let t = text();
    let inflow_normal = "normal = [1.0, 0.0]";
    problem_with(
        &edit(&t, inflow_normal, "normal = [0.0, 0.0]"),
        "open_boundary[0].normal",
        "zero length",
    );
    problem_with(
        &edit(&t, inflow_normal, "normal = [1.0, 0.5]"),
        "open_boundary[0].normal",
        "along a coordinate axis",
    );
    problem_with(
        &edit(&t, "velocity = [0.2, 0.0]", "velocity = [-0.2, 0.0]"),
        "open_boundary[0].velocity",
        "points out of the fluid",
    );
    problem_with(
        &edit(&t, "velocity = [0.2, 0.0]\n", ""),
        "open_boundary[0].velocity",
        "needs its mean velocity",
    );
    problem_with(
        &edit(
            &t,
            "min = [0.6, 0.0]\nmax = [0.6, 0.1]",
            "min = [0.64, 0.0]\nmax = [0.64, 0.1]",
        ),
        "open_boundary[1]",
        "outside the domain",
    );
    problem_with(
        &edit(
            &t,
            "min = [0.6, 0.0]\nmax = [0.6, 0.1]",
            "min = [0.6, 0.0]\nmax = [0.61, 0.1]",
        ),
        "open_boundary[1].max",
        "must equal min along the normal's axis x",
    );
    problem_with(
        &edit(
            &t,
            "min = [0.6, 0.0]\nmax = [0.6, 0.1]",
            "min = [0.6, -0.01]\nmax = [0.6, 0.1]",
        ),
        "open_boundary[1]",
        "overlaps solid \"bottom\"",
    );
    problem_with(
        &edit(&t, "kind = \"wcsph\"", "kind = \"corrected\""),
        "open_boundary[0]",
        "needs solver.kind = \"wcsph\"",
    );
    problem_with(
        &edit(&t, "ramp = 1.0", "ramp = 1.0\nlayers = 1"),
        "open_boundary[0].layers",
        "must be in [2, 1000]",
    );
    problem_with(
        &edit(
            &t,
            "normal = [-1.0, 0.0]",
            "normal = [-1.0, 0.0]\nvelocity = [0.2, 0.0]",
        ),
        "open_boundary[1].velocity",
        "a free exit",
    );
    problem_with(
        &edit(&t, "ramp = 1.0", "ramp = 0.0"),
        "open_boundary[0].ramp",
        "must be > 0",
    );
    // The outflow on the inflow's section (its fluid side reversed): it drained the channel.
    problem_with(
        &edit(
            &t,
            "min = [0.6, 0.0]\nmax = [0.6, 0.1]\nnormal = [-1.0, 0.0]",
            "min = [0.0, 0.05]\nmax = [0.0, 0.1]\nnormal = [-1.0, 0.0]",
        ),
        "open_boundary[1]",
        "lies on open_boundary[0]'s section",
    );
    // An outflow just behind the inflow's plane, its buffer in the inflow's.
    problem_with(
        &edit(
            &t,
            "min = [0.6, 0.0]\nmax = [0.6, 0.1]\nnormal = [-1.0, 0.0]",
            "min = [-0.01, 0.0]\nmax = [-0.01, 0.1]\nnormal = [1.0, 0.0]",
        ),
        "open_boundary[1]",
        "overlaps open_boundary[0]'s buffer",
    );
}
