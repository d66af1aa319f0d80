//! The `sort_by_cell` stage (section 3) on every backend: the sort is a permutation that keeps
//! each particle's fields together bitwise, and it groups the particles by cells of side `h` in
//! key order (axis 0 fastest), strays outside the domain included. The grids differ: the CPU's
//! is sparse over the particles' bounding box, aligned at multiples of `h` (`grid.rs`); the CUDA
//! backend's is dense over the domain, from `domain_min − h`, with cell coordinates clamped
//! into it (`backend::cuda::grid`, `cell_of` of `kernels/sph.cuh`). Within a cell the CPU keeps
//! the order it found (a stable radix sort) and CUDA orders by id (`order_cells`).

use crate::setup::{RHO0, Rng, Under, add_strays, backends, index_of_id, scene};
use sph::backend::cuda::grid::GridGeometry;
use sph::fields::Fields;
use sph::math::Vector;
use sph::model::params::StepParams;

/// The bits of every field particle `i` of `f` carries (the optional ones where allocated), to
/// compare particles exactly.
fn particle_bits<const D: usize>(f: &Fields<D>, i: usize) -> Vec<u32> {
    let mut v = vec![f.id[i], f.kind[i]];
    let vectors = [
        &f.position,
        &f.velocity,
        &f.acceleration,
        &f.position_start,
        &f.velocity_start,
        &f.wall_velocity,
        &f.normal,
    ];
    for field in vectors {
        if let Some(x) = field.get(i) {
            v.extend(x.iter().map(|c| c.to_bits()));
        }
    }
    for field in [&f.density, &f.pressure, &f.mass, &f.rest_density] {
        if let Some(x) = field.get(i) {
            v.push(x.to_bits());
        }
    }
    v
}

/// Which optional fields `f` carries: position_start, velocity_start, wall_velocity, normal,
/// rest_density.
fn allocated<const D: usize>(f: &Fields<D>) -> [bool; 5] {
    [
        !f.position_start.is_empty(),
        !f.velocity_start.is_empty(),
        !f.wall_velocity.is_empty(),
        !f.normal.is_empty(),
        !f.rest_density.is_empty(),
    ]
}

/// The cell of `x` in `under`'s grid, slowest axis first (so tuples compare in key order).
fn cell<const D: usize>(under: Under, p: &StepParams<D>, x: &Vector<D>) -> Vec<i64> {
    match under {
        // `Grid::sort`: floor(x / h) in f64, unbounded.
        Under::Cpu => {
            let inv = 1.0 / f64::from(p.h);
            (0..D)
                .rev()
                .map(|k| (f64::from(x[k]) * inv).floor() as i64)
                .collect()
        }
        // `cell_of` (kernels/sph.cuh): f32, clamped into the padded dense grid.
        Under::Shim | Under::Gpu => {
            let g = GridGeometry::new(&p.domain_min, &p.domain_max, p.h).expect("a valid domain");
            (0..D)
                .rev()
                .map(|k| {
                    let c = ((x[k] - g.origin[k]) * g.inv_cell).floor();
                    let hi = g.dims[k] as i64 - 2;
                    if c.is_nan() || c < 1.0 {
                        1
                    } else {
                        (c as i64).min(hi)
                    }
                })
                .collect()
        }
    }
}

/// Checks that `after` is `before` sorted by cell on `under`: the same particles (ids a
/// permutation, each with its fields bitwise), grouped by cell in key order, ordered within a
/// cell as the backend orders them. Returns the number of cells occupied.
fn check_sorted<const D: usize>(
    under: Under,
    p: &StepParams<D>,
    before: &Fields<D>,
    after: &Fields<D>,
    what: &str,
) -> usize {
    let n = before.len();
    assert_eq!(after.len(), n, "{under:?} {D}D {what}: particle count");
    // Every core field, wall_velocity and rest_density come back; CUDA keeps the step-start
    // copies and the normals on the device only (its `download`), the CPU carries all.
    let (had, has) = (allocated(before), allocated(after));
    for (k, (&a, &b)) in had.iter().zip(&has).enumerate() {
        let carried = under == Under::Cpu || k == 2 || k == 4;
        assert_eq!(
            b,
            a && carried,
            "{under:?} {D}D {what}: optional field {k} allocated"
        );
    }
    let mut seen = vec![false; n];
    for &id in &after.id {
        assert!(
            !std::mem::replace(&mut seen[id as usize], true),
            "{under:?}: id {id} twice"
        );
    }
    let at = index_of_id(before);
    // The fields the backend carries.
    let mut carried = before.clone();
    if under != Under::Cpu {
        carried.position_start.clear();
        carried.velocity_start.clear();
        carried.normal.clear();
    }
    for i in 0..n {
        assert_eq!(
            particle_bits(after, i),
            particle_bits(&carried, at[after.id[i] as usize]),
            "{under:?} {D}D {what}: particle {}'s fields",
            after.id[i]
        );
    }
    // Grouped by cell, cells in key order; within a cell the backend's order.
    let cells: Vec<Vec<i64>> = after.position.iter().map(|x| cell(under, p, x)).collect();
    let mut occupied = usize::from(n > 0);
    for i in 1..n {
        assert!(
            cells[i - 1] <= cells[i],
            "{under:?} {D}D {what}: particle {i} in cell {:?} after cell {:?}",
            cells[i],
            cells[i - 1]
        );
        if cells[i - 1] != cells[i] {
            occupied += 1;
            continue;
        }
        let (a, b) = (after.id[i - 1], after.id[i]);
        match under {
            // Stable: the order the particles had before.
            Under::Cpu => assert!(
                at[a as usize] < at[b as usize],
                "{under:?} {D}D {what}: ids {a}, {b} swapped within their cell"
            ),
            // `order_cells`: ascending id.
            Under::Shim | Under::Gpu => {
                assert!(
                    a < b,
                    "{under:?} {D}D {what}: ids {a}, {b} not ascending in their cell"
                )
            }
        }
    }
    // The same without either grid: inside the domain (no clamping), the slowest axis is
    // ordered to within one cell side (a few f32 roundings of the cell coordinate allowed).
    let inside = |x: &Vector<D>| (0..D).all(|k| x[k] >= p.domain_min[k] && x[k] <= p.domain_max[k]);
    let mut highest = f32::NEG_INFINITY;
    for x in after.position.iter().filter(|x| inside(x)) {
        assert!(
            highest < x[D - 1] + p.h * (1.0 + 1.0e-5),
            "{under:?} {D}D {what}: axis {} at {} after {highest}",
            D - 1,
            x[D - 1]
        );
        highest = highest.max(x[D - 1]);
    }
    occupied
}

fn check_sort<const D: usize>(seed: u64) {
    let (mut f, p) = scene::<D>(seed);
    add_strays(&mut f, &p, seed ^ 0x5151);
    // Every optional field, distinct per particle, so each gather is checked.
    let mut rng = Rng(seed ^ 0xa5a5);
    let mut random = |a: f32| Vector::<D>::from_fn(|_, _| rng.sym(a));
    f.position_start = f.position.iter().map(|x| x + random(0.01)).collect();
    f.velocity_start = (0..f.len()).map(|_| random(1.0)).collect();
    f.normal = (0..f.len()).map(|_| random(1.0)).collect();
    f.rest_density = (0..f.len()).map(|i| RHO0 * (1.0 + 1.0e-3 * i as f32)).collect();
    assert!(
        f.id.windows(2).any(|w| w[0] > w[1]),
        "the input is not in id order"
    );
    for under in backends() {
        // The first sort, of the shuffled input.
        let (out, ()) = under.run(&f, &p, |_, _| ());
        let occupied = check_sorted(under, &p, &f, &out, "first sort");
        assert!(occupied > 20, "{under:?} {D}D: only {occupied} cells occupied");
        // A second sort of sorted particles changes nothing, order included.
        let (again, once) = under.run(&f, &p, |b, f| {
            b.download(f).expect("download");
            let once = f.clone();
            b.sort_by_cell(f, &p).expect("finite positions");
            once
        });
        for i in 0..f.len() {
            assert_eq!(
                particle_bits(&again, i),
                particle_bits(&once, i),
                "{under:?} {D}D: the second sort moved particle {i}"
            );
        }
        // After the fluid moved (up to about one cell): a fresh order for the new positions.
        let (moved, before) = under.run(&f, &p, |b, f| {
            b.integrate(f, 0.02);
            b.download(f).expect("download");
            let before = f.clone();
            b.sort_by_cell(f, &p).expect("finite positions");
            before
        });
        check_sorted(under, &p, &before, &moved, "sort after a move");
        let reordered = (0..f.len()).filter(|&i| moved.id[i] != before.id[i]).count();
        assert!(
            reordered > 100,
            "{under:?} {D}D: the move reordered only {reordered}"
        );
        eprintln!("{under:?} {D}D sort_by_cell: {occupied} cells, {reordered} reordered after a move");
    }
}

#[test]
fn sort_by_cell_keeps_every_field_and_groups_particles_by_cell() {
    check_sort::<2>(0x2545_f491_4f6c_dd1d);
    check_sort::<3>(0x9e37_79b9_7f4a_7c15);
}
