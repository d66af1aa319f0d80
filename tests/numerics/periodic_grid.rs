//! The neighbour grid with periodic axes (`sph::periodic`) against brute force with the minimum
//! image: for random clouds in a random period (any length of at least 3 cells, not a whole
//! number of them, so the stretched cells of `L/⌊L/h⌋` are exercised), with positions up to
//! `0.2 h` outside the period (as between two wraps), `for_each_neighbour` visits exactly the
//! particles whose minimum-image offset is shorter than `h`, once each, with that offset; the
//! velocity solve's `NeighbourList` visits the same pairs with the spiky gradients of the same
//! offsets.

use proptest::prelude::*;
use sph::grid::{Grid, GridError, neighbours_naive_periodic};
use sph::math::{Real, Vector};
use sph::neighbour_list::NeighbourList;
use sph::periodic::{Periodic, PeriodicAxes};
use sph::smoothing::Smoothing;

/// Pairs whose squared minimum-image distance lies within this fraction of `h²` from `h²` are
/// not compared: at the rim the f32 rounding of `d ∓ L` (a few ulps of `L`) decides on which
/// side of `h` the pair falls, while the grid places cells in f64; every kernel is zero there
/// (poly6 `(h² − r²)³` ≈ 1e-15 of its peak), so no sum depends on the choice.
const RIM: Real = 1.0e-4;

fn assert_periodic_neighbours_match<const D: usize>(cloud: &[Vector<D>], h: Real, periodic: &Periodic<D>) {
    let mut grid = Grid::<D>::default();
    let perm = grid
        .sort_periodic(cloud, h, periodic)
        .expect("a period of at least 3 cells")
        .to_vec();
    let positions: Vec<Vector<D>> = perm.iter().map(|&p| cloud[p as usize]).collect();
    // Each particle's id is its index in the cloud.
    grid.link(&perm, &positions);
    let at_rim = |i: usize, j: usize| {
        let r2 = periodic.minimum_image(positions[i] - positions[j]).norm_squared();
        (r2 - h * h).abs() <= RIM * h * h
    };
    super::grid::assert_drifted_visits_match_cells(&grid, &positions);
    let mut across = 0;
    for i in 0..positions.len() {
        let mut visited = Vec::new();
        grid.for_each_neighbour(&positions, i, |j, d, _| {
            let raw = positions[i] - positions[j];
            let image = periodic.minimum_image(raw);
            let expected = sph::smoothing::pair_offset(image, image.norm_squared(), perm[i], perm[j], h);
            assert_eq!(d, expected.0, "offset of pair ({i}, {j})");
            if image != raw {
                across += 1;
            }
            visited.push(j);
        });
        let mut sorted = visited.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(
            sorted.len(),
            visited.len(),
            "particle {i}: a neighbour visited twice"
        );
        let naive = neighbours_naive_periodic(&positions, i, h, periodic);
        let visited: Vec<usize> = sorted.into_iter().filter(|&j| !at_rim(i, j)).collect();
        let naive: Vec<usize> = naive.into_iter().filter(|&j| !at_rim(i, j)).collect();
        assert_eq!(
            visited, naive,
            "neighbours of particle {i} at {:?} (h = {h}, {periodic:?})",
            positions[i]
        );
    }
    let kernel = Smoothing::<D>::new(h).expect("2D or 3D");
    let mut list = NeighbourList::default();
    list.build(&grid, &kernel, &positions, |_| true);
    for i in 0..positions.len() {
        let mut from_grid = Vec::new();
        grid.for_each_neighbour(&positions, i, |j, d, r2| {
            if j != i {
                from_grid.push((j, kernel.grad_w_spiky(&d, r2.sqrt())));
            }
        });
        let mut from_list = Vec::new();
        list.for_each_gradient(i, |j, g| from_list.push((j, g)));
        assert_eq!(from_list, from_grid, "particle {i}: list vs grid");
    }
    // Dense enough clouds always have pairs across the seam (not asserted per case: a sparse
    // cloud may have none).
    let _ = across;
}

/// A cloud of up to 200 particles in a period `[min, min + L)` per axis, `L` between 3 and 7.5
/// cells, a random non-empty set of periodic axes, positions up to `0.2 h` outside the period.
fn periodic_cloud<const D: usize>() -> impl Strategy<Value = (Vec<Vector<D>>, Real, Periodic<D>)> {
    (
        0.01f32..2.0,
        1u32..(1 << D),
        prop::collection::vec(3.0f32..7.5, D),
        prop::collection::vec(-20.0f32..20.0, D),
    )
        .prop_flat_map(|(h, mask, cells, shift)| {
            let mut axes = PeriodicAxes::NONE;
            for k in 0..D {
                if mask & (1 << k) != 0 {
                    axes = axes.with(k);
                }
            }
            let min = Vector::<D>::from_fn(|k, _| shift[k] * h);
            let max = Vector::<D>::from_fn(|k, _| min[k] + cells[k] * h);
            let periodic = Periodic::new(axes, min, max);
            let point = prop::collection::vec(-0.2f32..1.2, D).prop_map(move |t| {
                Vector::<D>::from_fn(|k, _| {
                    let l = max[k] - min[k];
                    // Outside by at most 0.2 h.
                    let t = t[k].clamp(-0.2 * h / l, 1.0 + 0.2 * h / l);
                    min[k] + t * l
                })
            });
            (prop::collection::vec(point, 0..200), Just(h), Just(periodic))
        })
}

proptest! {
    #[test]
    fn periodic_grid_finds_exactly_the_minimum_image_neighbours_in_2d((cloud, h, periodic) in periodic_cloud::<2>()) {
        assert_periodic_neighbours_match(&cloud, h, &periodic);
    }

    #[test]
    fn periodic_grid_finds_exactly_the_minimum_image_neighbours_in_3d((cloud, h, periodic) in periodic_cloud::<3>()) {
        assert_periodic_neighbours_match(&cloud, h, &periodic);
    }
}

/// A lattice filling a 2D period in x (6 cells of h = 2.1 dx): every particle has as many
/// neighbours as one in the middle, so none is missing at the seam, and pairs across it exist.
#[test]
fn a_lattice_filling_the_period_has_no_seam() {
    let (dx, h) = (0.01f32, 0.021f32);
    let (nx, ny) = (14usize, 12usize);
    let cloud: Vec<Vector<2>> = (0..nx * ny)
        .map(|c| Vector::<2>::new((c % nx) as Real + 0.5, (c / nx) as Real + 0.5) * dx)
        .collect();
    let periodic = Periodic::new(
        PeriodicAxes::NONE.with(0),
        Vector::<2>::zeros(),
        Vector::<2>::new(nx as Real * dx, 1.0),
    );
    let mut grid = Grid::<2>::default();
    let perm = grid
        .sort_periodic(&cloud, h, &periodic)
        .expect("6 cells")
        .to_vec();
    let positions: Vec<Vector<2>> = perm.iter().map(|&p| cloud[p as usize]).collect();
    grid.link(&perm, &positions);
    let count = |i: usize| {
        let mut c = 0;
        grid.for_each_neighbour(&positions, i, |_, _, _| c += 1);
        c
    };
    // Rows 3..ny-3 are away from the (non-periodic) top and bottom.
    let inner: Vec<usize> = (0..positions.len())
        .filter(|&i| (3.0 * dx..(ny as Real - 3.0) * dx).contains(&positions[i][1]))
        .collect();
    let full = count(inner[0]);
    assert_eq!(
        full, 13,
        "a lattice point within h = 2.1 dx has 12 neighbours and itself"
    );
    for &i in &inner {
        assert_eq!(count(i), full, "particle at {:?}", positions[i]);
    }
}

#[test]
fn a_period_shorter_than_three_cells_is_an_error() {
    let periodic = Periodic::new(
        PeriodicAxes::NONE.with(1),
        Vector::<2>::zeros(),
        Vector::<2>::new(1.0, 0.059),
    );
    let cloud = vec![Vector::<2>::new(0.5, 0.01)];
    let err = Grid::<2>::default()
        .sort_periodic(&cloud, 0.02, &periodic)
        .expect_err("2 cells");
    assert!(matches!(err, GridError::PeriodTooShort { axis: 1, .. }), "{err}");
}
