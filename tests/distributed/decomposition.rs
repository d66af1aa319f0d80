//! Regions: every point has one owner whose region holds it, and the counts are balanced.

use crate::particles::random_fields;
use proptest::prelude::*;
use sph::distributed::{Decomposition, Method, Region, imbalance};
use sph::math::Vector;

fn domain<const D: usize>() -> Region<D> {
    let extent = [2.0, 1.0, 0.5];
    Region {
        lo: Vector::zeros(),
        hi: Vector::from_fn(|c, _| extent[c]),
    }
}

/// Per-rank counts of `points` under `decomposition`, checking that each point's owner region
/// holds it (closed below, open above but on the domain's upper face).
fn counts<const D: usize>(decomposition: &Decomposition<D>, points: &[Vector<D>]) -> Vec<usize> {
    let mut counts = vec![0; decomposition.ranks()];
    for x in points {
        let owner = decomposition.owner(x);
        assert_eq!(
            decomposition.regions[owner].distance(x),
            0.0,
            "{x:?} outside its owner's region"
        );
        counts[owner] += 1;
    }
    counts
}

/// The regions' volumes add up to the domain's, so with every point in its owner's region they
/// tile it without overlap.
fn assert_tiles<const D: usize>(decomposition: &Decomposition<D>) {
    let volume = |r: &Region<D>| (0..D).map(|k| (r.hi[k] - r.lo[k]) as f64).product::<f64>();
    let sum: f64 = decomposition.regions.iter().map(volume).sum();
    let whole = volume(&decomposition.domain);
    assert!((sum / whole - 1.0).abs() < 1e-5, "regions cover {sum} of {whole}");
    for r in &decomposition.regions {
        assert!((0..D).all(|k| r.lo[k] <= r.hi[k]), "inverted region {r:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Slabs and bisection on 1-8 ranks: the regions tile the domain, every particle lies in
    /// its owner's region, and each rank holds its share of the particles within the ranks'
    /// count: a cut falls at a count quantile, each cut rounds by at most one particle, and
    /// bisection has at most `ranks − 1` cuts.
    #[test]
    fn regions_tile_the_domain_with_balanced_counts(seed in 1u64.., ranks in 1usize..=8, n in 200usize..2000, bisection: bool) {
        let fields = random_fields::<2>(n, seed);
        let method = if bisection { Method::Bisection } else { Method::Slabs };
        let d = Decomposition::build(domain(), &fields.position, ranks, method);
        prop_assert_eq!(d.ranks(), ranks);
        assert_tiles(&d);
        let counts = counts(&d, &fields.position);
        let share = n as f64 / ranks as f64;
        for c in &counts {
            prop_assert!((*c as f64 - share).abs() <= ranks as f64, "counts {:?} for {} particles", counts, n);
        }
    }
}

/// In 3D, bisection cuts the longest axis first: 4 ranks on a 2 x 1 x 0.5 box cut x, then y.
#[test]
fn bisection_cuts_the_longest_axis_first_in_3d() {
    let fields = random_fields::<3>(4000, 7);
    let d = Decomposition::build(domain(), &fields.position, 4, Method::Bisection);
    assert_tiles(&d);
    // Each half of x is cut across y (now the longest: 1 against about 1 and 0.5).
    let x_cut = d.regions[0].hi[0];
    assert!((x_cut - 1.0).abs() < 0.05, "x cut at {x_cut}");
    for r in &d.regions {
        assert_eq!(r.lo[2], 0.0);
        assert_eq!(r.hi[2], 0.5);
    }
    let counts = counts(&d, &fields.position);
    assert!(imbalance(&counts) < 0.01, "counts {counts:?}");
}

/// Water on one side of the tank (a dam-break column in the first fifth of the domain):
/// even-length slabs would leave most ranks empty, count-quantile cuts balance them to within
/// a particle per cut, far inside the 20 % of the load-balance criterion.
#[test]
fn a_column_on_one_side_is_shared_evenly() {
    let mut fields = random_fields::<2>(3000, 11);
    for x in &mut fields.position {
        x[0] *= 0.2;
    }
    let even = Decomposition::build(domain(), &[], 4, Method::Slabs);
    let even_counts = counts(&even, &fields.position);
    assert!(imbalance(&even_counts) > 2.9, "even slabs: {even_counts:?}");
    for method in [Method::Slabs, Method::Bisection] {
        let d = Decomposition::build(domain(), &fields.position, 4, method);
        let c = counts(&d, &fields.position);
        assert!(imbalance(&c) < 0.01, "{method:?}: {c:?}");
    }
}

/// A particle outside the domain (escaping, before it is removed) still has exactly one owner:
/// the nearest region.
#[test]
fn a_point_outside_the_domain_belongs_to_the_nearest_region() {
    let d = Decomposition::build(domain::<2>(), &[], 4, Method::Slabs);
    assert_eq!(d.owner(&Vector::<2>::new(-1.0, 0.5)), 0);
    assert_eq!(d.owner(&Vector::<2>::new(3.0, 0.5)), 3);
    assert_eq!(
        d.owner(&Vector::<2>::new(2.0, 1.0)),
        3,
        "the domain's upper corner is inside"
    );
}

/// Along a periodic axis a region's distance is to its nearest image: a point just inside the
/// domain's upper face is near a region at its lower face, by the gap through the period; other
/// axes and a domain without periodic axes keep the plain distance.
#[test]
fn the_distance_to_a_region_goes_through_the_period() {
    use sph::periodic::{Periodic, PeriodicAxes};
    let lower = Region::<2> {
        lo: Vector::<2>::new(0.0, 0.0),
        hi: Vector::<2>::new(0.5, 1.0),
    };
    let periodic = Periodic::<2>::new(
        PeriodicAxes::NONE.with(0),
        Vector::<2>::new(0.0, 0.0),
        Vector::<2>::new(2.0, 1.0),
    );
    let x = Vector::<2>::new(1.9, 0.5);
    assert!((lower.distance(&x) - 1.4).abs() < 1e-6);
    assert!((lower.distance_periodic(&x, &periodic) - 0.1).abs() < 1e-6);
    assert_eq!(lower.distance_periodic(&x, &Periodic::none()), lower.distance(&x));
    // Above the region along y (not periodic) as well: both gaps count.
    let y = Vector::<2>::new(1.9, 1.2);
    let expected = (0.1f32 * 0.1 + 0.2 * 0.2).sqrt();
    assert!((lower.distance_periodic(&y, &periodic) - expected).abs() < 1e-6);
}
