//! Which rank owns which region of space: slabs along the longest axis, or recursive coordinate
//! bisection (Berger & Bokhari 1987), both cut at particle-count quantiles so that every rank
//! starts with about the same number of particles.
//!
//! A decomposition is a list of axis-aligned regions, one per rank, that tile the domain box:
//! every point of the domain lies in exactly one region (lower faces closed, upper faces open,
//! the domain's upper faces closed), and a point outside the domain belongs to the region whose
//! box is nearest, so a particle that leaves the domain still has one owner.

use crate::math::{Real, Vector};
use crate::periodic::Periodic;

/// How the domain is cut among the ranks (a value the run carries, `--decomposition`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Parallel slabs along the domain's longest axis.
    Slabs,
    /// Recursive coordinate bisection: each box is cut across its longest axis, the ranks split
    /// in two halves (the first `n/2`, the rest), at the count quantile that gives each half its
    /// share.
    Bisection,
}

/// An axis-aligned box `[lo, hi)` of space [m].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region<const D: usize> {
    /// Lower corner [m].
    pub lo: Vector<D>,
    /// Upper corner [m].
    pub hi: Vector<D>,
}

impl<const D: usize> Region<D> {
    /// The Euclidean distance from `x` to the box [m]; 0 inside.
    pub fn distance(&self, x: &Vector<D>) -> Real {
        self.distance_periodic(x, &Periodic::none())
    }

    /// [`Region::distance`] to the nearest of the box's periodic images: along a periodic
    /// axis of period `L` the gap is the least over `x_k` and `x_k ± L` (`crate::periodic`'s
    /// minimum image, so a particle near one face of the domain is near a region at the other).
    pub fn distance_periodic(&self, x: &Vector<D>, periodic: &Periodic<D>) -> Real {
        let gap = |k: usize, v: Real| (self.lo[k] - v).max(v - self.hi[k]).max(0.0);
        let mut sum = 0.0;
        for k in 0..D {
            let mut g = gap(k, x[k]);
            if periodic.axes.contains(k) {
                let l = periodic.length[k];
                g = g.min(gap(k, x[k] - l)).min(gap(k, x[k] + l));
            }
            sum += g * g;
        }
        sum.sqrt()
    }

    /// The axis along which the box is longest (the first of equals).
    pub fn longest_axis(&self) -> usize {
        let extent = self.hi - self.lo;
        (0..D).fold(0, |best, k| if extent[k] > extent[best] { k } else { best })
    }
}

/// The regions of `ranks` ranks, one each, tiling `domain`.
#[derive(Clone, Debug, PartialEq)]
pub struct Decomposition<const D: usize> {
    /// The whole domain.
    pub domain: Region<D>,
    /// Region of rank `r` at index `r`.
    pub regions: Vec<Region<D>>,
}

impl<const D: usize> Decomposition<D> {
    /// One region, the whole domain: a single rank.
    pub fn single(domain: Region<D>) -> Self {
        Self {
            domain,
            regions: vec![domain],
        }
    }

    /// Cuts `domain` among `ranks` ranks by `method`, balancing the number of `points` (the
    /// particle positions of the whole run) per rank. With no points the cuts are even in
    /// length. `ranks` ≥ 1.
    pub fn build(domain: Region<D>, points: &[Vector<D>], ranks: usize, method: Method) -> Self {
        assert!(ranks >= 1, "a decomposition needs a rank");
        let mut regions = Vec::with_capacity(ranks);
        let mut inside: Vec<Vector<D>> = points.to_vec();
        match method {
            Method::Slabs => {
                let axis = domain.longest_axis();
                slabs(domain, &mut inside, ranks, axis, &mut regions);
            }
            Method::Bisection => bisect(domain, &mut inside, ranks, &mut regions),
        }
        Self { domain, regions }
    }

    /// Number of ranks.
    pub fn ranks(&self) -> usize {
        self.regions.len()
    }

    /// The rank that owns a particle at `x`: the region that contains it, or for a point
    /// outside the domain the region nearest to it (the lowest rank of equals).
    pub fn owner(&self, x: &Vector<D>) -> usize {
        let mut best = (Real::INFINITY, 0);
        for (rank, region) in self.regions.iter().enumerate() {
            if self.contains(region, x) {
                return rank;
            }
            let d = region.distance(x);
            if d < best.0 {
                best = (d, rank);
            }
        }
        best.1
    }

    /// Whether `region` holds `x`: closed below, open above except on the domain's upper face.
    fn contains(&self, region: &Region<D>, x: &Vector<D>) -> bool {
        (0..D).all(|k| {
            let above = x[k] >= region.lo[k];
            let below = x[k] < region.hi[k] || (region.hi[k] == self.domain.hi[k] && x[k] <= region.hi[k]);
            above && below
        })
    }
}

/// The load imbalance of per-rank particle counts: `max / mean − 1` (0 when even; 0 with no
/// particles at all).
pub fn imbalance(counts: &[usize]) -> f64 {
    let total: usize = counts.iter().sum();
    if total == 0 || counts.is_empty() {
        return 0.0;
    }
    let mean = total as f64 / counts.len() as f64;
    *counts.iter().max().expect("non-empty") as f64 / mean - 1.0
}

/// The coordinate along `axis` below which `share` of `points` lie, as the midpoint between the
/// neighbouring sorted coordinates, clamped into `[lo, hi]`; `lo + share (hi − lo)` without
/// points. Reorders `points` (a partial sort).
fn quantile_cut<const D: usize>(
    points: &mut [Vector<D>],
    axis: usize,
    share: f64,
    lo: Real,
    hi: Real,
) -> Real {
    if points.is_empty() {
        return lo + (share as Real) * (hi - lo);
    }
    let k = ((share * points.len() as f64).round() as usize).clamp(0, points.len());
    if k == 0 {
        return lo + (share as Real) * (hi - lo);
    }
    if k == points.len() {
        let largest = points.iter().map(|p| p[axis]).fold(Real::NEG_INFINITY, Real::max);
        return (largest + (hi - largest) * 0.5).clamp(lo, hi);
    }
    points.select_nth_unstable_by(k, |a, b| a[axis].total_cmp(&b[axis]));
    let above = points[k][axis];
    let below = points[..k]
        .iter()
        .map(|p| p[axis])
        .fold(Real::NEG_INFINITY, Real::max);
    (0.5 * (below + above)).clamp(lo, hi)
}

/// Points of `points` strictly below `cut` along `axis` first; returns how many.
fn split_at_cut<const D: usize>(points: &mut [Vector<D>], axis: usize, cut: Real) -> usize {
    let mut first = 0;
    for k in 0..points.len() {
        if points[k][axis] < cut {
            points.swap(first, k);
            first += 1;
        }
    }
    first
}

/// `ranks` slabs of `region` along `axis`, appended to `out` in increasing coordinate.
fn slabs<const D: usize>(
    region: Region<D>,
    points: &mut [Vector<D>],
    ranks: usize,
    axis: usize,
    out: &mut Vec<Region<D>>,
) {
    if ranks == 1 {
        out.push(region);
        return;
    }
    let share = 1.0 / ranks as f64;
    let cut = quantile_cut(points, axis, share, region.lo[axis], region.hi[axis]);
    let below = split_at_cut(points, axis, cut);
    let (mut first, mut rest) = (region, region);
    first.hi[axis] = cut;
    rest.lo[axis] = cut;
    out.push(first);
    slabs(rest, &mut points[below..], ranks - 1, axis, out);
}

/// Recursive coordinate bisection of `region` among `ranks` ranks, appended to `out`.
fn bisect<const D: usize>(
    region: Region<D>,
    points: &mut [Vector<D>],
    ranks: usize,
    out: &mut Vec<Region<D>>,
) {
    if ranks == 1 {
        out.push(region);
        return;
    }
    let axis = region.longest_axis();
    let low_ranks = ranks / 2;
    let share = low_ranks as f64 / ranks as f64;
    let cut = quantile_cut(points, axis, share, region.lo[axis], region.hi[axis]);
    let below = split_at_cut(points, axis, cut);
    let (mut low, mut high) = (region, region);
    low.hi[axis] = cut;
    high.lo[axis] = cut;
    let (first, second) = points.split_at_mut(below);
    bisect(low, first, low_ranks, out);
    bisect(high, second, ranks - low_ranks, out);
}
