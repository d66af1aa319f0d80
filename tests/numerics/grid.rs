//! The neighbour grid (`sph::grid`) against brute force, in 2D and 3D: after `sort`, permuting
//! the positions by the returned permutation and `link`, `for_each_neighbour` visits exactly the
//! particles `neighbours_naive` finds, once each, with the right offsets and squared distances.
//! Also: the velocity solve's `NeighbourList` visiting exactly what the grid visits (same order,
//! bitwise the same spiky gradients), memory independent of empty space, errors (not panics) for bad
//! input, and `Fields::permute` moving every particle field. And the grid's candidate lists:
//! after every particle drifted by up to `RESORT_DRIFT h` since the sort (as the correction
//! allows), `for_each_neighbour` still visits exactly what the cells' ranges hold within `h`,
//! in their order, with the same offsets.

use proptest::prelude::*;
use sph::fields::{Fields, PermuteScratch};
use sph::grid::{CANDIDATE_SKIN, Grid, GridError, neighbours_naive};
use sph::math::{Real, Vector};
use sph::neighbour_list::{NeighbourList, SpikyGradients, WetSolidPairs};
use sph::smoothing::Smoothing;

/// Sorts `cloud` with `grid`, checks the permutation, permutes, links and compares every
/// particle's neighbours with brute force. Returns the positions in sorted order.
fn assert_neighbours_match<const D: usize>(
    grid: &mut Grid<D>,
    cloud: &[Vector<D>],
    h: Real,
) -> Vec<Vector<D>> {
    let n = cloud.len();
    let perm = grid
        .sort(cloud, h)
        .expect("a finite cloud of modest extent sorts")
        .to_vec();
    assert_eq!(perm.len(), n, "permutation length");
    let mut seen = vec![false; n];
    for &p in &perm {
        let p = p as usize;
        assert!(p < n && !seen[p], "sort did not return a permutation: {perm:?}");
        seen[p] = true;
    }
    let positions: Vec<Vector<D>> = perm.iter().map(|&p| cloud[p as usize]).collect();
    // Each particle's id is its index in the cloud.
    grid.link(&perm, &positions);
    assert_eq!(grid.cell_size(), h);
    assert!(
        grid.cell_count() <= n,
        "{} non-empty cells for {n} particles",
        grid.cell_count()
    );
    for i in 0..n {
        let mut visited = Vec::new();
        grid.for_each_neighbour(&positions, i, |j, d, r2| {
            // Coincident pairs get `pair_offset`'s fixed direction (note 4).
            let raw = positions[i] - positions[j];
            let expected = sph::smoothing::pair_offset(raw, raw.norm_squared(), perm[i], perm[j], h);
            assert_eq!(d, expected.0, "offset passed for pair ({i}, {j})");
            assert_eq!(r2, d.norm_squared(), "r² passed for pair ({i}, {j})");
            visited.push(j);
        });
        visited.sort_unstable();
        let naive = neighbours_naive(&positions, i, h);
        assert_eq!(
            visited, naive,
            "neighbours of particle {i} at {:?} (h = {h}): grid vs brute force",
            positions[i]
        );
    }
    assert_list_matches_grid(grid, &positions);
    assert_drifted_visits_match_cells(grid, &positions);
    positions
}

/// Every `(j, offset bits)` the cells' ranges (`Grid::neighbour_ranges`) hold within `h` of
/// particle `i` at `positions`, in their order, with the offset `for_each_neighbour` passes (the
/// minimum image and the coincident tie-break): what the candidate lists must reproduce.
pub(crate) fn cell_walk<const D: usize>(
    grid: &Grid<D>,
    positions: &[Vector<D>],
    i: usize,
) -> Vec<(usize, Vec<u32>)> {
    let h = grid.cell_size();
    let id = grid.ids();
    let mut out = Vec::new();
    for range in grid.neighbour_ranges(i) {
        for j in range {
            let d = grid.periodic().minimum_image(positions[i] - positions[j]);
            let r2 = d.norm_squared();
            if r2 < h * h {
                let (d, _) = sph::smoothing::pair_offset(d, r2, id[i], id[j], h);
                out.push((j, d.iter().map(|c| c.to_bits()).collect()));
            }
        }
    }
    out
}

/// `for_each_neighbour`'s visits of particle `i`, as [`cell_walk`] gives them.
pub(crate) fn list_walk<const D: usize>(
    grid: &Grid<D>,
    positions: &[Vector<D>],
    i: usize,
) -> Vec<(usize, Vec<u32>)> {
    let mut out = Vec::new();
    grid.for_each_neighbour(positions, i, |j, d, _| {
        out.push((j, d.iter().map(|c| c.to_bits()).collect()))
    });
    out
}

/// Moves every particle of the linked `grid` by `RESORT_DRIFT h` in a direction of its own (a
/// hash of its index) and checks that the candidate lists still give the cells' pairs.
pub(crate) fn assert_drifted_visits_match_cells<const D: usize>(grid: &Grid<D>, positions: &[Vector<D>]) {
    let h = grid.cell_size();
    let step = (sph::solver::step::RESORT_DRIFT as Real) * h;
    let drifted: Vec<Vector<D>> = positions
        .iter()
        .enumerate()
        .map(|(i, x)| {
            let mut u = Vector::<D>::from_fn(|k, _| {
                let z = (i as u64 * 0x9E37_79B9_7F4A_7C15 + k as u64 * 0xBF58_476D_1CE4_E5B9) >> 40;
                z as Real / (1u64 << 24) as Real - 0.5
            });
            if u.norm() == 0.0 {
                u[0] = 1.0;
            }
            x + u.normalize() * step
        })
        .collect();
    for i in 0..positions.len() {
        assert_eq!(
            list_walk(grid, &drifted, i),
            cell_walk(grid, &drifted, i),
            "particle {i} after a drift of RESORT_DRIFT h: candidate lists vs cells"
        );
    }
}

/// Every `(j, ∇W_spiky)` a loop visits for particle `i`, in its order, as bits.
type Visits = Vec<(usize, Vec<u32>)>;

fn visits<const D: usize>(visit: impl FnOnce(&mut dyn FnMut(usize, Vector<D>))) -> Visits {
    let mut out = Vec::new();
    visit(&mut |j, g: Vector<D>| out.push((j, g.iter().map(|c| c.to_bits()).collect())));
    out
}

/// A `NeighbourList` built from the linked `grid` visits, for each selected particle, exactly
/// the grid's pairs `j ≠ i` in the grid's order, each with bitwise the spiky gradient of the
/// grid's offset and squared distance (so a sweep over it sums the same floats), and nothing
/// for the others. Built twice into one list (all particles, then every third one skipped), as
/// the backend reuses it between velocity solves; and `SpikyGradients` gives the same from the
/// grid and from the list. The wet solids' list of fluid pairs likewise.
fn assert_list_matches_grid<const D: usize>(grid: &Grid<D>, positions: &[Vector<D>]) {
    let kernel = Smoothing::<D>::new(grid.cell_size()).expect("2D or 3D");
    let mut list = NeighbourList::default();
    for skip_every_third in [false, true] {
        let selected = |i: usize| !(skip_every_third && i % 3 == 0);
        list.build(grid, &kernel, positions, selected);
        assert_eq!(list.len(), positions.len(), "the list covers every particle");
        for i in 0..positions.len() {
            let from_list = visits::<D>(|f| list.for_each_gradient(i, f));
            if selected(i) {
                let from_grid = visits::<D>(|f| {
                    grid.for_each_neighbour(positions, i, |j, d, r2| {
                        if j != i {
                            f(j, kernel.grad_w_spiky(&d, r2.sqrt()));
                        }
                    })
                });
                assert_eq!(from_list, from_grid, "particle {i}: list vs grid");
                let through =
                    |s: SpikyGradients<'_, D>| visits::<D>(|f| s.for_each(positions, &kernel, i, f));
                assert_eq!(through(SpikyGradients::List(&list)), from_grid, "particle {i}");
                assert_eq!(through(SpikyGradients::Grid(grid)), from_grid, "particle {i}");
            } else {
                assert!(from_list.is_empty(), "particle {i} was not selected");
            }
        }
    }
    list.clear();
    assert!(list.is_empty());
    // The wet solids' fluid pairs: every third particle a "solid", every other one of those
    // "wet"; the list gives each wet solid's fluid pairs in the grid's order, with the grid's
    // offset and the poly6 weight of its squared distance, bit for bit.
    let is_fluid = |j: usize| j % 3 != 0;
    let wet: Vec<u32> = (0..positions.len() as u32).filter(|i| i % 6 == 0).collect();
    let mut wet_pairs = WetSolidPairs::default();
    wet_pairs.build(grid, &kernel, positions, &wet, is_fluid);
    let bits = |d: &Vector<D>, w: Real| (d.iter().map(|c| c.to_bits()).collect::<Vec<_>>(), w.to_bits());
    for (k, &w) in wet.iter().enumerate() {
        let mut from_list = Vec::new();
        wet_pairs.for_each_fluid(k, |j, d, weight| from_list.push((j, bits(d, weight))));
        let mut from_grid = Vec::new();
        grid.for_each_neighbour(positions, w as usize, |j, d, r2| {
            if is_fluid(j) {
                from_grid.push((j, bits(&d, kernel.w(r2))));
            }
        });
        assert_eq!(from_list, from_grid, "wet solid {w}: list vs grid");
    }
    wet_pairs.clear();
    assert!(wet_pairs.is_empty());
}

fn check<const D: usize>(cloud: &[Vector<D>], h: Real) -> Vec<Vector<D>> {
    assert_neighbours_match(&mut Grid::<D>::default(), cloud, h)
}

fn v2(x: Real, y: Real) -> Vector<2> {
    Vector::<2>::new(x, y)
}

fn v3(x: Real, y: Real, z: Real) -> Vector<3> {
    Vector::<3>::new(x, y, z)
}

/// A coordinate: either anywhere in `[−span, span]·h`, or exactly on a cell face `k·h`.
fn coordinate(h: Real, span: i32) -> impl Strategy<Value = Real> {
    let s = span as Real;
    prop_oneof![
        3 => (-s..=s).prop_map(move |t| t * h),
        1 => (-span..=span).prop_map(move |k| k as Real * h),
    ]
}

/// A cloud of up to 150 particles in a box of `span` cells around the origin, possibly offset.
fn cloud<const D: usize>() -> impl Strategy<Value = (Vec<Vector<D>>, Real)> {
    (0.01f32..2.0, 1i32..8, -50i32..50).prop_flat_map(|(h, span, shift)| {
        let point = prop::collection::vec(coordinate(h, span), D)
            .prop_map(move |c| Vector::<D>::from_iterator(c.into_iter().map(|v| v + shift as Real * h)));
        (prop::collection::vec(point, 0..150), Just(h))
    })
}

/// A small deterministic generator (SplitMix64) for the explicit sparse-cloud cases.
struct SplitMix(u64);

impl SplitMix {
    fn next_unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

proptest! {
    #[test]
    fn grid_finds_exactly_the_brute_force_neighbours_in_2d((a, ha) in cloud::<2>(), (b, hb) in cloud::<2>()) {
        // The same grid is reused for a second cloud, as the solver reuses it every step.
        let mut grid = Grid::<2>::default();
        assert_neighbours_match(&mut grid, &a, ha);
        assert_neighbours_match(&mut grid, &b, hb);
    }

    #[test]
    fn grid_finds_exactly_the_brute_force_neighbours_in_3d((a, ha) in cloud::<3>(), (b, hb) in cloud::<3>()) {
        let mut grid = Grid::<3>::default();
        assert_neighbours_match(&mut grid, &a, ha);
        assert_neighbours_match(&mut grid, &b, hb);
    }
}

#[test]
fn candidate_lists_hold_a_pair_that_drifts_into_the_support() {
    // Two particles just beyond h at the sort, each drifting RESORT_DRIFT h towards the other:
    // within h afterwards, so the lists must hold them (the skin covers twice that drift).
    let h: Real = 0.1;
    let drift = sph::solver::step::RESORT_DRIFT as Real * h;
    assert!(2.0 * drift <= CANDIDATE_SKIN * h);
    let gap = h + 1.8 * drift;
    // Mid-cell (cells of side h from 0), so the pair lies in neighbouring cells.
    let cloud = vec![
        v3(0.55, 0.55, 0.55),
        v3(0.55 + gap, 0.55, 0.55),
        v3(0.55, 0.57, 0.55),
    ];
    let mut grid = Grid::<3>::default();
    let perm = grid.sort(&cloud, h).expect("finite").to_vec();
    let positions: Vec<Vector<3>> = perm.iter().map(|&p| cloud[p as usize]).collect();
    grid.link(&perm, &positions);
    let (a, b) = (
        perm.iter().position(|&p| p == 0).expect("in the sort"),
        perm.iter().position(|&p| p == 1).expect("in the sort"),
    );
    let mut moved = positions.clone();
    moved[a][0] += drift;
    moved[b][0] -= drift;
    let mut seen = false;
    grid.for_each_neighbour(&moved, a, |j, _, r2| seen |= j == b && r2 < h * h);
    assert!(seen, "the pair drifted within h and must be visited");
    assert_eq!(list_walk(&grid, &moved, a), cell_walk(&grid, &moved, a));
}

#[test]
fn grid_handles_all_points_in_one_cell() {
    let h = 0.1;
    let cloud2: Vec<_> = (0..40)
        .map(|i| v2(0.01 + 0.002 * i as Real, 0.05 - 0.001 * i as Real))
        .collect();
    check(&cloud2, h);
    let cloud3: Vec<_> = (0..40)
        .map(|i| {
            v3(
                0.01 + 0.002 * i as Real,
                0.05 - 0.001 * i as Real,
                0.099 - 0.002 * i as Real,
            )
        })
        .collect();
    check(&cloud3, h);
    let mut grid = Grid::<3>::default();
    assert_neighbours_match(&mut grid, &cloud3, h);
    assert_eq!(grid.cell_count(), 1);
}

#[test]
fn grid_handles_points_exactly_on_cell_faces() {
    for h in [0.1f32, 0.25, 1.0, 0.37] {
        // Every lattice point k·h, k in −3..=3, including negative faces and the origin, and
        // points half a cell off the faces.
        let ks: Vec<Real> = (-6..=6).map(|k| k as Real * 0.5).collect();
        let mut cloud2 = Vec::new();
        let mut cloud3 = Vec::new();
        for &a in &ks {
            for &b in &ks {
                cloud2.push(v2(a * h, b * h));
                for &c in ks.iter().step_by(2) {
                    cloud3.push(v3(a * h, b * h, c * h));
                }
            }
        }
        let on_face = check(&cloud2, h);
        // On this lattice of spacing h/2 the origin's neighbours are its 3×3 block; the points
        // (±h, 0) and (0, ±h) are exactly h away and excluded (the support is open).
        let origin = on_face
            .iter()
            .position(|x| *x == v2(0.0, 0.0))
            .expect("origin is in the cloud");
        assert_eq!(neighbours_naive(&on_face, origin, h).len(), 9, "h = {h}");
        check(&cloud3, h);
    }
}

#[test]
fn grid_memory_does_not_grow_with_empty_space() {
    let h = 0.05;
    let mut rng = SplitMix(7);
    let mut cloud: Vec<Vector<3>> = (0..50)
        .map(|_| {
            let mut c = || (rng.next_unit() * 2.0e4 - 1.0e4) as Real;
            v3(c(), c(), c())
        })
        .collect();
    // A few close pairs so that some particles do have neighbours.
    for i in 0..5 {
        let x = cloud[i];
        cloud.push(x + v3(0.03, 0.0, 0.01));
    }
    let mut grid = Grid::<3>::default();
    let sorted = assert_neighbours_match(&mut grid, &cloud, h);
    assert!(
        grid.heap_bytes() < 1 << 20,
        "grid holds {} bytes for {} particles",
        grid.heap_bytes(),
        cloud.len()
    );
    let with_neighbour = (0..sorted.len())
        .filter(|&i| neighbours_naive(&sorted, i, h).len() > 1)
        .count();
    assert_eq!(with_neighbour, 10);

    let mut rng = SplitMix(11);
    let cloud2: Vec<Vector<2>> = (0..50)
        .map(|_| {
            let mut c = || (rng.next_unit() * 2.0e4 - 1.0e4) as Real;
            v2(c(), c())
        })
        .collect();
    let mut grid2 = Grid::<2>::default();
    assert_neighbours_match(&mut grid2, &cloud2, h);
    assert!(
        grid2.heap_bytes() < 1 << 20,
        "2D grid holds {} bytes",
        grid2.heap_bytes()
    );
}

#[test]
fn grid_handles_one_and_zero_particles() {
    let h = 0.1;
    let mut grid = Grid::<3>::default();
    assert_neighbours_match(&mut grid, &[], h);
    assert_eq!(grid.cell_count(), 0);
    let one = assert_neighbours_match(&mut grid, &[v3(-1.5, 2.0, 1.0e3)], h);
    assert_eq!(grid.cell_count(), 1);
    let mut visited = Vec::new();
    grid.for_each_neighbour(&one, 0, |j, d, r2| visited.push((j, d, r2)));
    assert_eq!(visited, vec![(0, Vector::<3>::zeros(), 0.0)]);
    // Back to empty after a non-empty cloud (reuse of the buffers).
    assert_neighbours_match(&mut grid, &[], h);
    assert_eq!(grid.cell_count(), 0);

    let mut grid2 = Grid::<2>::default();
    assert_neighbours_match(&mut grid2, &[], h);
    assert_neighbours_match(&mut grid2, &[v2(0.0, 0.0)], h);
}

#[test]
fn grid_handles_coincident_points() {
    let h = 0.2;
    let mut cloud3 = vec![v3(0.3, -0.1, 0.2); 7];
    cloud3.extend(vec![v3(0.0, 0.0, 0.0); 5]);
    cloud3.extend(vec![v3(0.2, 0.0, 0.0); 3]); // exactly h from the origin: not neighbours
    let sorted = check(&cloud3, h);
    let i = sorted
        .iter()
        .position(|x| *x == v3(0.0, 0.0, 0.0))
        .expect("present");
    assert_eq!(neighbours_naive(&sorted, i, h).len(), 5);
    let mut cloud2 = vec![v2(-0.4, -0.4); 9];
    cloud2.push(v2(-0.39, -0.4));
    check(&cloud2, h);
}

#[test]
fn grid_rejects_non_finite_positions() {
    let mut grid = Grid::<3>::default();
    let mut cloud = vec![
        v3(0.0, 0.0, 0.0),
        v3(0.1, 0.0, 0.0),
        v3(0.0, 0.1, 0.0),
        v3(0.0, 0.0, 0.1),
    ];
    cloud[3].y = Real::NAN;
    assert_eq!(
        grid.sort(&cloud, 0.1).map(<[u32]>::to_vec),
        Err(GridError::NonFinitePosition { particle: 3 })
    );
    cloud[3].y = 0.0;
    cloud[1].z = Real::INFINITY;
    assert_eq!(
        grid.sort(&cloud, 0.1).map(<[u32]>::to_vec),
        Err(GridError::NonFinitePosition { particle: 1 })
    );
    let mut grid2 = Grid::<2>::default();
    let cloud2 = vec![v2(0.0, 0.0), v2(Real::NEG_INFINITY, 0.0)];
    assert_eq!(
        grid2.sort(&cloud2, 0.1).map(<[u32]>::to_vec),
        Err(GridError::NonFinitePosition { particle: 1 })
    );
    // The grid still works after an error.
    check(&[v3(0.0, 0.0, 0.0), v3(0.05, 0.0, 0.0)], 0.1);
    assert_neighbours_match(&mut grid, &[v3(0.0, 0.0, 0.0), v3(0.05, 0.0, 0.0)], 0.1);
}

fn too_many_cells<const D: usize>(extent: Real, h: Real) {
    let mut a = Vector::<D>::zeros();
    let mut b = Vector::<D>::zeros();
    for k in 0..D {
        a[k] = -extent;
        b[k] = extent;
    }
    let mut grid = Grid::<D>::default();
    // `catch_unwind` so that a panic is reported as this test's failure with the input named.
    let result = std::panic::catch_unwind(move || grid.sort(&[a, b], h).map(<[u32]>::to_vec));
    match result {
        Ok(Err(GridError::TooManyCells { .. })) => {}
        Ok(other) => {
            panic!("{D}D, points at ±{extent:e}, h = {h:e}: expected TooManyCells, got {other:?}")
        }
        Err(_) => {
            panic!("{D}D, points at ±{extent:e}, h = {h:e}: sort panicked instead of returning TooManyCells")
        }
    }
}

#[test]
fn grid_rejects_extents_too_large_to_key() {
    // Cell coordinates that fit an i64 but whose product overflows a 64-bit key.
    too_many_cells::<3>(1.0e15, 1.0e-3);
    too_many_cells::<2>(1.0e15, 1.0e-3);
}

#[test]
fn grid_rejects_absurd_extents() {
    // Cell coordinates beyond i64 (±1e36 cells).
    too_many_cells::<3>(1.0e30, 1.0e-6);
    too_many_cells::<2>(1.0e30, 1.0e-6);
}

/// Particles whose every field holds a value unique to the particle, derived from its id.
fn distinct_fields<const D: usize>(n: usize) -> Fields<D> {
    let vec = |i: usize, base: Real| Vector::<D>::from_fn(|k, _| base + i as Real + 0.125 * k as Real);
    let mut f = Fields::<D>::default();
    for i in 0..n {
        f.push(
            vec(i, 0.0),
            vec(i, 1.0e4),
            1.0 + i as Real,
            1000.0 + i as Real,
            7 * i as u32 + 1,
        );
    }
    for i in 0..n {
        f.acceleration[i] = vec(i, -2.0e4);
        f.pressure[i] = -5.0 - i as Real;
        f.position_start.push(vec(i, 3.0e4));
        f.velocity_start.push(vec(i, 4.0e4));
        f.wall_velocity.push(vec(i, 5.0e4));
        f.normal.push(vec(i, 5.0e4));
        f.rest_density.push(500.0 + 3.0 * i as Real);
        f.density_rate.push(-70.0 - 5.0 * i as Real);
        f.density_start.push(900.0 + 7.0 * i as Real);
        f.acting_pressure.push(40.0 + 11.0 * i as Real);
    }
    f
}

/// Checks every field of `f` against `original` through `id`, and `id` against `perm`.
fn assert_moved_together<const D: usize>(f: &Fields<D>, original: &Fields<D>, expected_id: &[u32]) {
    // Destructured without `..`: adding a field to `Fields` fails to compile here until this
    // test checks it too.
    let Fields {
        position,
        velocity,
        acceleration,
        density,
        pressure,
        mass,
        kind,
        id,
        position_start,
        velocity_start,
        wall_velocity,
        normal,
        rest_density,
        density_rate,
        density_start,
        acting_pressure,
    } = f;
    let n = original.len();
    for field_len in [
        position.len(),
        velocity.len(),
        acceleration.len(),
        density.len(),
        pressure.len(),
        mass.len(),
        kind.len(),
        id.len(),
        position_start.len(),
        velocity_start.len(),
        wall_velocity.len(),
        normal.len(),
        rest_density.len(),
        density_rate.len(),
        density_start.len(),
        acting_pressure.len(),
    ] {
        assert_eq!(field_len, n);
    }
    assert_eq!(id.as_slice(), expected_id, "ids after permute");
    for i in 0..n {
        let o = id[i] as usize;
        assert_eq!(position[i], original.position[o], "position of new {i} (id {o})");
        assert_eq!(velocity[i], original.velocity[o], "velocity of new {i} (id {o})");
        assert_eq!(
            acceleration[i], original.acceleration[o],
            "acceleration of new {i} (id {o})"
        );
        assert_eq!(density[i], original.density[o], "density of new {i} (id {o})");
        assert_eq!(pressure[i], original.pressure[o], "pressure of new {i} (id {o})");
        assert_eq!(mass[i], original.mass[o], "mass of new {i} (id {o})");
        assert_eq!(kind[i], original.kind[o], "kind of new {i} (id {o})");
        assert_eq!(
            position_start[i], original.position_start[o],
            "position_start of {i}"
        );
        assert_eq!(
            velocity_start[i], original.velocity_start[o],
            "velocity_start of {i}"
        );
        assert_eq!(
            wall_velocity[i], original.wall_velocity[o],
            "wall_velocity of {i}"
        );
        assert_eq!(normal[i], original.normal[o], "normal of {i}");
        assert_eq!(rest_density[i], original.rest_density[o], "rest_density of {i}");
        assert_eq!(density_rate[i], original.density_rate[o], "density_rate of {i}");
        assert_eq!(
            density_start[i], original.density_start[o],
            "density_start of {i}"
        );
        assert_eq!(
            acting_pressure[i], original.acting_pressure[o],
            "acting_pressure of {i}"
        );
    }
}

fn permutes_every_field<const D: usize>(first: &[u32], second: &[u32]) {
    let n = first.len();
    let original = distinct_fields::<D>(n);
    assert_eq!(original.id, (0..n as u32).collect::<Vec<_>>());
    let mut f = original.clone();
    let mut scratch = PermuteScratch::<D>::default();
    f.permute(first, &mut scratch);
    assert_moved_together(&f, &original, first);
    // A second reorder reusing the scratch composes: new i holds old first[second[i]].
    f.permute(second, &mut scratch);
    let composed: Vec<u32> = second.iter().map(|&s| first[s as usize]).collect();
    assert_moved_together(&f, &original, &composed);
}

fn permutation() -> impl Strategy<Value = (Vec<u32>, Vec<u32>)> {
    (0usize..200).prop_flat_map(|n| {
        let identity: Vec<u32> = (0..n as u32).collect();
        (
            Just(identity.clone()).prop_shuffle(),
            Just(identity).prop_shuffle(),
        )
    })
}

proptest! {
    #[test]
    fn fields_permute_moves_every_field_in_2d((first, second) in permutation()) {
        permutes_every_field::<2>(&first, &second);
    }

    #[test]
    fn fields_permute_moves_every_field_in_3d((first, second) in permutation()) {
        permutes_every_field::<3>(&first, &second);
    }
}

#[test]
fn fields_permute_by_the_grid_sort_keeps_particles_whole() {
    // The solver's use: sort by cell, then permute the fields by the returned permutation.
    let n = 64;
    let mut f = distinct_fields::<3>(n);
    for i in 0..n {
        f.position[i] = v3(
            (i * 37 % 11) as Real * 0.07,
            (i * 13 % 7) as Real * -0.05,
            (i % 5) as Real * 0.11,
        );
    }
    let original = f.clone();
    let mut grid = Grid::<3>::default();
    let perm = grid.sort(&f.position, 0.1).expect("finite").to_vec();
    f.permute(&perm, &mut PermuteScratch::default());
    grid.link(&f.id, &f.position);
    assert_moved_together(&f, &original, &perm);
    for i in 0..n {
        let mut visited = Vec::new();
        grid.for_each_neighbour(&f.position, i, |j, _, _| visited.push(j));
        visited.sort_unstable();
        assert_eq!(visited, neighbours_naive(&f.position, i, 0.1));
    }
}
