//! Precision, vector types and the one global reduction.
//!
//! Particle state is single precision (`Real = f32`) as in the paper (section 3). Every
//! global sum (total mass, momentum, forces on solids, density-error statistics) goes through
//! [`sum_in_order`], which accumulates in `f64` over fixed chunks and adds the chunk sums in
//! index order, so the result is bitwise independent of the number of rayon threads.

use rayon::prelude::*;

/// Floating-point type of all particle fields (single precision, as in the paper).
pub type Real = f32;

/// A `D`-dimensional vector of [`Real`] (position [m], velocity [m/s], acceleration [m/s^2]).
pub type Vector<const D: usize> = nalgebra::SVector<Real, D>;

/// Number of items per chunk of [`sum_in_order`]; fixed so sums do not depend on thread count.
pub const REDUCTION_CHUNK: usize = 4096;

/// Sums `term(i)` for `i in 0..len` in `f64`, `N` quantities at once.
///
/// Chunks of [`REDUCTION_CHUNK`] items are summed sequentially, in parallel across chunks,
/// and the chunk sums are added in chunk order: the result is the same for any thread count.
/// With fewer chunks than worker threads (a few thousand items) the terms are evaluated in
/// parallel first and then added in the same order, so a sum over a neighbour loop does not
/// run on one thread; the result is the same bit for bit.
pub fn sum_in_order<const N: usize, F>(len: usize, term: F) -> [f64; N]
where
    F: Fn(usize) -> [f64; N] + Sync,
{
    let chunks = len.div_ceil(REDUCTION_CHUNK);
    if chunks < rayon::current_num_threads() && len > 1 {
        let terms: Vec<[f64; N]> = (0..len).into_par_iter().map(&term).collect();
        let mut total = [0.0f64; N];
        for chunk in terms.chunks(REDUCTION_CHUNK) {
            let mut acc = [0.0f64; N];
            for t in chunk {
                for k in 0..N {
                    acc[k] += t[k];
                }
            }
            for k in 0..N {
                total[k] += acc[k];
            }
        }
        return total;
    }
    let partial: Vec<[f64; N]> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut acc = [0.0f64; N];
            let end = ((c + 1) * REDUCTION_CHUNK).min(len);
            for i in c * REDUCTION_CHUNK..end {
                let t = term(i);
                for k in 0..N {
                    acc[k] += t[k];
                }
            }
            acc
        })
        .collect();
    let mut total = [0.0f64; N];
    for p in partial {
        for k in 0..N {
            total[k] += p[k];
        }
    }
    total
}

/// Largest `term(i)` for `i in 0..len` (`f64::NEG_INFINITY` when `len == 0`); a NaN term wins,
/// so a non-finite state cannot hide behind a maximum.
pub fn max_in_order<F>(len: usize, term: F) -> f64
where
    F: Fn(usize) -> f64 + Sync + Send,
{
    max_each_in_order(len, |i| [term(i)])[0]
}

/// [`max_in_order`] of `N` terms at once, in one pass: each component's largest value, NaN if
/// any of that component's terms is NaN, `−∞` for `len = 0`.
pub fn max_each_in_order<const N: usize, F>(len: usize, term: F) -> [f64; N]
where
    F: Fn(usize) -> [f64; N] + Sync + Send,
{
    (0..len).into_par_iter().map(term).reduce(
        || [f64::NEG_INFINITY; N],
        |a, b| std::array::from_fn(|k| max_or_nan(a[k], b[k])),
    )
}

/// The larger of `a` and `b`, NaN if either is (`f64::max` would drop the NaN): the reduction
/// of [`max_in_order`], for loops that reduce while they compute.
#[inline(always)]
pub fn max_or_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// `max(x, 0)`, but NaN stays NaN (`f64::max` would drop it): for a maximum whose NaN must
/// reach the caller, such as the correction's residual.
#[inline(always)]
pub fn non_negative_or_nan(x: f64) -> f64 {
    if x.is_nan() { x } else { x.max(0.0) }
}

/// Sums `term(i)` per group: `term` returns the group (`< groups`) and the value, `N` numbers
/// (a force's three components, or a force and its moment), or `None` to skip item `i`. Same
/// fixed-chunk order as [`sum_in_order`], so thread-count independent.
pub fn sum_by_group<const N: usize, F>(len: usize, groups: usize, term: F) -> Vec<[f64; N]>
where
    F: Fn(usize) -> Option<(usize, [f64; N])> + Sync,
{
    let chunks = len.div_ceil(REDUCTION_CHUNK);
    let partial: Vec<Vec<[f64; N]>> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut acc = vec![[0.0f64; N]; groups];
            let end = ((c + 1) * REDUCTION_CHUNK).min(len);
            for i in c * REDUCTION_CHUNK..end {
                if let Some((g, t)) = term(i) {
                    if let Some(slot) = acc.get_mut(g) {
                        for k in 0..N {
                            slot[k] += t[k];
                        }
                    }
                }
            }
            acc
        })
        .collect();
    let mut total = vec![[0.0f64; N]; groups];
    for p in partial {
        for (t, v) in total.iter_mut().zip(p) {
            for k in 0..N {
                t[k] += v[k];
            }
        }
    }
    total
}

/// Pads a `D`-vector to three components (z = 0 in 2D) for output and force records.
pub fn to_xyz<const D: usize>(v: &Vector<D>) -> [f64; 3] {
    let mut out = [0.0; 3];
    for k in 0..D.min(3) {
        out[k] = f64::from(v[k]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sum_in_order_is_independent_of_thread_count() {
        let term = |i: usize| [((i as f64) * 0.1).sin(), 1.0];
        let a = sum_in_order(100_003, term);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("pool");
        let b = pool.install(|| sum_in_order(100_003, term));
        assert_eq!(a, b);
        assert_eq!(a[1], 100_003.0);
    }

    #[test]
    fn max_in_order_propagates_nan() {
        assert!(max_in_order(10, |i| if i == 3 { f64::NAN } else { i as f64 }).is_nan());
        assert_eq!(max_in_order(10, |i| i as f64), 9.0);
        assert_eq!(max_in_order(0, |i| i as f64), f64::NEG_INFINITY);
    }
}
