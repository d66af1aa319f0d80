//! Particle counts by arithmetic alone: the lattice size of each box under the rules of
//! [`generate`](mod@super::generate)'s module doc, and the checked `u64` counts that the validator
//! and `generate::count_particles` give, without placing a particle.

use super::validate::RawProblem;
use super::{FluidBox, KeyPath, Scene, Solid, SolidShape};
use crate::geometry::Volume;

/// Largest supported dimension for counting.
const MAX_DIM: usize = 3;

/// Particle counts of a scene, as [`generate()`](super::generate()) places them before trimming
/// (exact when its [`GenerationReport::trimmed`](super::GenerationReport::trimmed) is empty, an
/// upper bound otherwise).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParticleCounts {
    /// Number of fluid particles.
    pub fluid: u64,
    /// Number of particles of each solid, by name, in scene order.
    pub solid: Vec<(String, u64)>,
    /// `fluid` plus all solids.
    pub total: u64,
}

/// Lattice size of a box along each axis.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Dims {
    n: [u64; MAX_DIM],
    d: usize,
}

impl Dims {
    pub(super) fn axes(&self) -> &[u64] {
        self.n.get(..self.d).unwrap_or_default()
    }
}

/// Name of axis `k` for messages.
pub(crate) fn axis_name(k: usize) -> String {
    match k {
        0 => "x".into(),
        1 => "y".into(),
        2 => "z".into(),
        _ => format!("{k}"),
    }
}

/// `n_k = round((max_k - min_k) / dx)` per axis; `path` names the box.
pub(crate) fn lattice_dims(min: &[f64], max: &[f64], dx: f64, path: &KeyPath) -> Result<Dims, RawProblem> {
    if min.len() != max.len() || min.len() > MAX_DIM || min.is_empty() {
        return Err(RawProblem::new(
            path.clone(),
            format!("box corners must have 1 to {MAX_DIM} equal-length entries"),
        ));
    }
    let mut n = [0u64; MAX_DIM];
    for (k, ((&lo, &hi), slot)) in min.iter().zip(max).zip(n.iter_mut()).enumerate() {
        let ratio = ((hi - lo) / dx).round();
        if !ratio.is_finite() || ratio > f64::from(u32::MAX) {
            return Err(RawProblem::new(
                path.k("max"),
                format!(
                    "too many particles along axis {}: extent {} m / spacing {dx} m is not below {}",
                    axis_name(k),
                    hi - lo,
                    u32::MAX
                ),
            ));
        }
        if ratio < 1.0 {
            return Err(RawProblem::new(
                path.k("max"),
                format!(
                    "box is thinner than the particle spacing along axis {}: max - min = {} m, spacing = {:e} m",
                    axis_name(k),
                    hi - lo,
                    dx
                ),
            ));
        }
        *slot = ratio as u64;
    }
    Ok(Dims { n, d: min.len() })
}

fn overflow(path: &KeyPath) -> RawProblem {
    RawProblem::new(
        path.clone(),
        "particle count overflows a 64-bit integer".to_string(),
    )
}

/// Product of the lattice sizes, checked.
fn product(mut iter: impl Iterator<Item = Option<u64>>) -> Option<u64> {
    iter.try_fold(1u64, |acc, n| acc.checked_mul(n?))
}

/// Particles of a filled lattice box.
pub(crate) fn box_count(min: &[f64], max: &[f64], dx: f64, path: &KeyPath) -> Result<u64, RawProblem> {
    let dims = lattice_dims(min, max, dx, path)?;
    product(dims.axes().iter().map(|&n| Some(n))).ok_or_else(|| overflow(path))
}

/// Tolerance, in spacings, under which an extent counts as a whole number of spacings.
pub(super) const WHOLE: f64 = 1e-6;

/// Lattice size of a fluid box at spacing `s` \[m\]: `floor(E_k / s + WHOLE)` per axis, at
/// least 1 (`generate`'s module doc); the errors of [`lattice_dims`].
pub(super) fn fluid_dims(min: &[f64], max: &[f64], s: f64, path: &KeyPath) -> Result<Dims, RawProblem> {
    let mut dims = lattice_dims(min, max, s, path)?;
    for ((n, &lo), &hi) in dims.n.iter_mut().zip(min).zip(max) {
        let inside = ((hi - lo) / s + WHOLE).floor();
        if inside >= 1.0 && inside < *n as f64 {
            *n = inside as u64;
        }
    }
    Ok(dims)
}

/// Particles of a fluid box: its lattice at [`FluidBox::lattice_spacing`] plus its coincident
/// twins ([`FluidBox::twins`]); another shape: its lattice points inside, as a solid's.
pub(crate) fn fluid_box_count(fb: &FluidBox, dx: f64, path: &KeyPath) -> Result<u64, RawProblem> {
    let (min, max) = (&fb.region.min, &fb.region.max);
    if !matches!(fb.volume, Volume::Aabb { .. }) {
        return shape_count(&fb.volume, min.len(), dx, path);
    }
    let dims = fluid_dims(min, max, fb.lattice_spacing(dx, min.len()), path)?;
    let n = product(dims.axes().iter().map(|&n| Some(n))).ok_or_else(|| overflow(path))?;
    n.checked_add(fb.twins(n)).ok_or_else(|| overflow(path))
}

/// The lattice a shape other than an axis-aligned box is filled on: anchored at the lower
/// corner of its bounding box, `ceil(E_k / dx) + 1` points along axis k (one more than can be
/// inside, so that rounding never drops a layer), as `i64` indices.
pub(crate) fn shape_lattice(
    volume: &Volume,
    dim: usize,
    dx: f64,
    path: &KeyPath,
) -> Result<(Vec<f64>, Vec<i64>), RawProblem> {
    let (min, max) = volume.bounds(dim);
    let mut n = Vec::with_capacity(dim);
    for (k, (lo, hi)) in min.iter().zip(&max).enumerate() {
        let m = ((hi - lo) / dx).ceil() + 1.0;
        if !m.is_finite() || m > f64::from(u32::MAX) {
            return Err(RawProblem::new(
                path.clone(),
                format!(
                    "too many particles along axis {}: extent {} m / spacing {dx} m is not below {}",
                    axis_name(k),
                    hi - lo,
                    u32::MAX
                ),
            ));
        }
        n.push(m.max(1.0) as i64);
    }
    Ok((min, n))
}

/// Most lattice columns a mesh's bounding box may span (1e8: 0.8 GB of column index while it is
/// filled), far beyond the particle counts a run can hold.
const MAX_MESH_COLUMNS: i64 = 100_000_000;

/// Particles of a shape other than an axis-aligned box: its lattice points inside
/// ([`Volume::lattice_inside`]), counted one by one; at least one.
fn shape_count(volume: &Volume, dim: usize, dx: f64, path: &KeyPath) -> Result<u64, RawProblem> {
    let (min, n) = shape_lattice(volume, dim, dx, path)?;
    let points = product(n.iter().map(|&m| u64::try_from(m).ok())).ok_or_else(|| overflow(path))?;
    if points > u64::from(u32::MAX) {
        return Err(RawProblem::new(
            path.clone(),
            format!("the shape's bounding box holds {points} lattice points, more than the u32 index limit"),
        ));
    }
    // A mesh's column test holds an index per lattice column (8 B each) while it runs.
    let columns = n.iter().take(2).product::<i64>();
    if matches!(volume, Volume::Mesh(_)) && columns > MAX_MESH_COLUMNS {
        return Err(RawProblem::new(
            path.clone(),
            format!(
                "the mesh's bounding box spans {columns} lattice columns along z, more than {MAX_MESH_COLUMNS}: \
                 use a coarser particles.spacing or a smaller mesh"
            ),
        ));
    }
    let mut count = 0u64;
    match dim {
        2 => volume.lattice_inside::<2>([min[0], min[1]], [n[0], n[1]], dx, |_| count += 1),
        _ => volume.lattice_inside::<3>([min[0], min[1], min[2]], [n[0], n[1], n[2]], dx, |_| count += 1),
    }
    if count == 0 {
        return Err(RawProblem::new(
            path.clone(),
            format!(
                "{} holds no lattice point at particles.spacing = {dx} m: make it larger than a spacing",
                volume.describe(dim)
            ),
        ));
    }
    Ok(count)
}

/// Particles of one solid: a box, a container with `layers` wall layers, or another shape's
/// lattice points inside it.
pub(crate) fn solid_count(solid: &Solid, dx: f64, layers: u64, path: &KeyPath) -> Result<u64, RawProblem> {
    let (min, max) = (&solid.region.min, &solid.region.max);
    match (solid.shape, &solid.volume) {
        (SolidShape::Container, _) => {
            let dims = lattice_dims(min, max, dx, path)?;
            let axes = dims.axes();
            let last = axes.len().saturating_sub(1);
            let outer = product(axes.iter().enumerate().map(|(k, &n)| {
                let grow = if solid.open_top && k == last {
                    layers
                } else {
                    layers.checked_mul(2)?
                };
                n.checked_add(grow)
            }));
            let inner = product(axes.iter().map(|&n| Some(n)));
            match (outer, inner) {
                (Some(o), Some(i)) => o.checked_sub(i).ok_or_else(|| overflow(path)),
                _ => Err(overflow(path)),
            }
        }
        (_, Volume::Aabb { .. }) => box_count(min, max, dx, path),
        (_, volume) => shape_count(volume, min.len(), dx, path),
    }
}

/// Counts the particles of every fluid box and solid; the first problem found
/// is returned.
pub(crate) fn count_raw(scene: &Scene) -> Result<ParticleCounts, RawProblem> {
    let dx = scene.spacing;
    let layers = scene.wall_layers();
    let mut fluid = 0u64;
    for (i, fb) in scene.fluid_boxes.iter().enumerate() {
        let path = KeyPath::key("fluid_box").i(i);
        let n = fluid_box_count(fb, dx, &path)?;
        fluid = fluid.checked_add(n).ok_or_else(|| overflow(&path))?;
    }
    let mut total = fluid;
    let mut solid = Vec::with_capacity(scene.solids.len());
    for (i, s) in scene.solids.iter().enumerate() {
        let path = KeyPath::key("solid").i(i);
        let n = solid_count(s, dx, layers, &path)?;
        total = total.checked_add(n).ok_or_else(|| overflow(&path))?;
        solid.push((s.name.clone(), n));
    }
    Ok(ParticleCounts { fluid, solid, total })
}
