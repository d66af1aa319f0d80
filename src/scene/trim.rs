//! Keeps the particles of different bodies apart: the last step of [`generate()`](super::generate()).
//!
//! Each body (a `[[fluid_box]]` or a `[[solid]]`) is built on its own lattice, anchored at its
//! own `min` corner, so two bodies that touch meet where their lattices happen to fall. When box
//! extents are whole spacings they meet one spacing apart; when they are not (a shipped scene
//! coarsened with `--set particles.spacing=…`), a particle of one body can land half a spacing or
//! less from a particle of the next, and that pair starts with a pressure spike that throws
//! particles at metres per second before anything has moved.
//!
//! The rule: a particle of body `b` is removed if it lies closer than
//! [`MIN_GAP`]` · (s_b + s_o) / 2` to a kept particle of a body `o` of higher priority, where `s`
//! is each body's lattice spacing (`dx`, or a compressed box's finer spacing). Priority: solids
//! before fluid boxes (the walls define the geometry; a fluid particle next to a wall is the one
//! that yields), and within each kind the scene order. Pairs within one body are never compared:
//! they are on one lattice, at least its spacing apart, except a `coincident` box's twins, which
//! are placed on purpose.
//!
//! The removals are reported ([`Trimmed`]); a body that would lose more than half of its
//! particles is not trimmed but refused (the scene would no longer be the one written).

use std::fmt;

use nalgebra::SVector;

/// Smallest distance between particles of different bodies, as a fraction of their mean lattice
/// spacing (dimensionless). Below 1 so that bodies meeting on a whole number of spacings (exactly one spacing
/// apart, up to `f32` rounding) keep every particle; above 1/2 so that no half-spacing overlap
/// survives, with room for the diagonal pairs of lattices offset on two axes.
pub const MIN_GAP: f64 = 0.9;

/// A fraction of a body's particles above which trimming refuses instead (see the module doc).
pub const MAX_TRIMMED_FRACTION: f64 = 0.5;

/// One body of a scene, as named in messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Body {
    /// `solid[i]`.
    Solid(usize),
    /// `fluid_box[i]`.
    FluidBox(usize),
}

impl fmt::Display for Body {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Body::Solid(i) => write!(f, "solid[{i}]"),
            Body::FluidBox(i) => write!(f, "fluid_box[{i}]"),
        }
    }
}

/// Particles of one body removed for lying too close to another body's particles.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Trimmed {
    /// The body that lost particles.
    pub removed_from: Body,
    /// The body whose particles were too close (the first one found, by priority).
    pub next_to: Body,
    /// Particles removed.
    pub count: u64,
    /// Particles the body had before trimming.
    pub of: u64,
}

/// A body's particles handed to [`trim`], in priority order.
pub(crate) struct Points<'a, const D: usize> {
    /// Which body.
    pub body: Body,
    /// Its lattice spacing \[m\].
    pub spacing: f64,
    /// Its positions \[m\].
    pub position: &'a [SVector<f32, D>],
}

/// The result of [`trim`]: per body (same order as given), which particles stay.
pub(crate) struct Kept {
    /// `keep[b][i]`: particle `i` of body `b` stays.
    pub keep: Vec<Vec<bool>>,
    /// The removals, by body then neighbour, in priority order.
    pub trimmed: Vec<Trimmed>,
}

/// Cell key of `p` for cells of size `cell` \[m\], its axes reversed so that the
/// lexicographic order runs fastest along x: the three cells `x−1, x, x+1` of one row are then
/// one contiguous range of a sorted key list.
fn row_key<const D: usize>(p: &SVector<f32, D>, cell: f64) -> [i64; D] {
    std::array::from_fn(|k| (f64::from(p[D - 1 - k]) / cell).floor() as i64)
}

/// Applies the module's rule to `bodies`, given in priority order (highest first).
///
/// Every particle is listed once, sorted by cell (32 B per particle in 3D, no per-cell
/// allocation: generation's peak memory stays below the run's). Bodies are decided in priority
/// order, so when body `b` is trimmed the `keep` flags of every body before it are final.
pub(crate) fn trim<const D: usize>(bodies: &[Points<'_, D>]) -> Kept {
    let widest = bodies.iter().map(|b| b.spacing).fold(0.0, f64::max);
    let cell = MIN_GAP * widest;
    let mut keep: Vec<Vec<bool>> = Vec::with_capacity(bodies.len());
    let mut trimmed = Vec::new();
    if !(cell > 0.0 && cell.is_finite()) || bodies.len() < 2 {
        keep.extend(bodies.iter().map(|b| vec![true; b.position.len()]));
        return Kept { keep, trimmed };
    }
    // (cell, body, particle) of every body but the last, whose particles no one is held against.
    let listed = &bodies[..bodies.len() - 1];
    let mut sorted: Vec<([i64; D], u32, u32)> =
        Vec::with_capacity(listed.iter().map(|b| b.position.len()).sum());
    for (b, body) in listed.iter().enumerate() {
        for (i, p) in body.position.iter().enumerate() {
            sorted.push((row_key(p, cell), b as u32, i as u32));
        }
    }
    sorted.sort_unstable();
    let rows = 3usize.pow(D as u32 - 1);
    for (b, body) in bodies.iter().enumerate() {
        let mut mine = Vec::with_capacity(body.position.len());
        let mut by_neighbour: Vec<(usize, u64)> = Vec::new();
        for p in body.position {
            let c = row_key(p, cell);
            let mut hit: Option<usize> = None;
            for r in 0..rows {
                // The row of cells offset by r on the axes other than x (key positions 0..D-1).
                let mut lo = c;
                let mut rest = r;
                for qk in lo.iter_mut().take(D - 1) {
                    *qk += (rest % 3) as i64 - 1;
                    rest /= 3;
                }
                let mut hi = lo;
                lo[D - 1] -= 1;
                hi[D - 1] += 1;
                let first = sorted.partition_point(|e| e.0 < lo);
                for &(_, o, j) in sorted[first..].iter().take_while(|e| e.0 <= hi) {
                    let (o, j) = (o as usize, j as usize);
                    if o >= b || hit.is_some_and(|h| h <= o) || !keep[o][j] {
                        continue;
                    }
                    let other = &bodies[o];
                    let limit = MIN_GAP * 0.5 * (body.spacing + other.spacing);
                    if (p - other.position[j]).cast::<f64>().norm() < limit {
                        hit = Some(o);
                    }
                }
            }
            match hit {
                Some(o) => {
                    match by_neighbour.iter_mut().find(|(n, _)| *n == o) {
                        Some((_, count)) => *count += 1,
                        None => by_neighbour.push((o, 1)),
                    }
                    mine.push(false);
                }
                None => mine.push(true),
            }
        }
        by_neighbour.sort_unstable();
        for (o, count) in by_neighbour {
            if let Some(other) = bodies.get(o) {
                trimmed.push(Trimmed {
                    removed_from: body.body,
                    next_to: other.body,
                    count,
                    of: body.position.len() as u64,
                });
            }
        }
        keep.push(mine);
    }
    Kept { keep, trimmed }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(x0: f32, n: usize, dx: f32) -> Vec<SVector<f32, 1>> {
        (0..n).map(|i| SVector::from([x0 + i as f32 * dx])).collect()
    }

    #[test]
    fn whole_spacings_keep_everything_and_half_spacings_trim_the_lower_priority() {
        let a = row(0.5, 4, 1.0);
        let b = row(4.5, 3, 1.0);
        let bodies = [
            Points {
                body: Body::Solid(0),
                spacing: 1.0,
                position: &a,
            },
            Points {
                body: Body::FluidBox(0),
                spacing: 1.0,
                position: &b,
            },
        ];
        let kept = trim(&bodies);
        assert!(kept.keep.iter().flatten().all(|k| *k));
        assert!(kept.trimmed.is_empty());
        let c = row(4.0, 3, 1.0);
        let bodies = [
            Points {
                body: Body::Solid(0),
                spacing: 1.0,
                position: &a,
            },
            Points {
                body: Body::FluidBox(0),
                spacing: 1.0,
                position: &c,
            },
        ];
        let kept = trim(&bodies);
        assert_eq!(kept.keep[1], [false, true, true]);
        assert_eq!(
            kept.trimmed,
            [Trimmed {
                removed_from: Body::FluidBox(0),
                next_to: Body::Solid(0),
                count: 1,
                of: 3
            }]
        );
    }

    #[test]
    fn pairs_within_one_body_are_not_compared() {
        let twins = vec![SVector::from([0.5f32]), SVector::from([0.5f32])];
        let kept = trim(&[Points {
            body: Body::FluidBox(0),
            spacing: 1.0,
            position: &twins,
        }]);
        assert_eq!(kept.keep[0], [true, true]);
    }
}
