//! Initial particle placement on a Cartesian lattice.
//!
//! Every box is filled on a lattice anchored at its own `min` corner: particle `i_k` along axis k
//! at `min_k + (i_k + 0.5) s` (computed in `f64`, stored as `f32`), `s` the box's spacing.
//!
//! - A **fluid box** of extent `E_k` holds `n_k = floor(E_k / s + 1e-6)` particles along axis k
//!   (at least one when `E_k >= s/2`): every particle lies at least `s/2` inside every face, so
//!   two fluid boxes that share a face are at least one spacing apart whatever their extents
//!   (the `1e-6` keeps a whole number of spacings whole through floating-point rounding). A
//!   box thinner than one spacing but at least half of one keeps a single layer at `min + s/2`,
//!   which reaches up to `s/2` past its `max` face.
//! - A **solid box** holds `n_k = round(E_k / dx)`, its particles between `0` and `dx` inside its
//!   faces, so that a solid reaches its faces as closely as the lattice allows.
//! - Every **other solid shape** (a rotated box, cylinder, sphere or mesh, [`crate::geometry`])
//!   is filled on a lattice anchored at the lower corner of its bounding box with the lattice
//!   points inside the shape (surface included): a mesh cube whose extents are whole spacings
//!   therefore fills exactly as the same `box`. Solids are filled, not hollowed: a body's
//!   particles beyond `L` layers from its surface cost memory but keep the count equal to the
//!   volume over `dx^D`, and the fluid sees a full kernel support from any side. These shapes
//!   may overlap a fluid box: the fluid particles within [`MIN_GAP`] spacings of theirs are
//!   removed by [`super::trim`] (the solid displaces the fluid).
//! - A **container** with inside box `[min, max]` has walls of `L = ceil(h / dx - 1e-9)` layers:
//!   lattice indices `i_k in -L..n_k + L` with `n_k = round(E_k / dx)` on every axis, keeping the
//!   points outside the inside index range on at least one axis; an open top drops
//!   `i_{D-1} >= n_{D-1}` (last axis = vertical).
//!
//! When extents are whole spacings all bodies meet one spacing apart and nothing more happens.
//! When they are not, a solid's particles (or a thin fluid layer) can still land closer than a
//! spacing to another body's; [`super::trim`] then removes the particles of the lower-priority
//! body (fluid before solid, later before earlier) that lie closer than
//! [`MIN_GAP`] spacings, and [`generate_reported`] says what it removed
//! and which fluid axes were not whole spacings. [`count_particles`] gives the counts before
//! that trimming by arithmetic alone (exact when nothing is trimmed).
//!
//! A **fluid volume of another shape** (`[[fluid_box]] shape`, or a rotated box) is filled as a
//! shaped solid is, at spacing `dx`: an STL cube whose extents are whole spacings fills exactly
//! as the same fluid box. It is trimmed against solids as a fluid box is.
//!
//! A fluid box with `compression = c` uses the finer spacing `dx / (1 + c)^(1/D)` for its own
//! lattice; one with `coincident = f` adds a twin, at the same position, right after each of
//! `floor(n f)` evenly spread lattice particles (see [`FluidBox`]).

use nalgebra::SVector;

use super::count::{Dims, WHOLE, count_raw, fluid_box_count, fluid_dims, lattice_dims, shape_lattice};
use super::trim::{self, Body, MAX_TRIMMED_FRACTION, MIN_GAP, Points, Trimmed};
use super::validate::RawProblem;
use super::{Aabb, FluidBox, KeyPath, Location, Problem, Scene, SceneError, Solid, SolidShape};
use crate::geometry::{Volume, for_each_index};

pub use super::count::ParticleCounts;

/// Initial particles of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout<const D: usize> {
    /// Fluid particle positions \[m\], all fluid boxes in scene order.
    pub fluid_position: Vec<SVector<f32, D>>,
    /// Fluid particle velocities \[m/s\], parallel to `fluid_position`.
    pub fluid_velocity: Vec<SVector<f32, D>>,
    /// The `[[fluid_box]]` index of each fluid particle, parallel to `fluid_position`.
    pub fluid_box: Vec<u32>,
    /// Solid particles, one entry per `[[solid]]`, in scene order.
    pub solids: Vec<SolidParticles<D>>,
}

/// The particles of one solid body.
#[derive(Debug, Clone, PartialEq)]
pub struct SolidParticles<const D: usize> {
    /// The solid's name.
    pub name: String,
    /// Particle positions \[m\].
    pub position: Vec<SVector<f32, D>>,
}

/// A fluid box axis whose extent is not a whole number of spacings.
#[derive(Debug, Clone, PartialEq)]
pub struct Fitted {
    /// The `[[fluid_box]]` index.
    pub fluid_box: usize,
    /// The axis (0 = x).
    pub axis: usize,
    /// The extent in spacings, `(max - min) / s`.
    pub spacings: f64,
    /// Particle layers placed along the axis (see the module doc).
    pub layers: u64,
}

/// What [`generate_reported`] did beyond filling boxes with whole spacings; `sph check` prints it.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GenerationReport {
    /// Fluid box axes that are not whole spacings, in scene order.
    pub fitted: Vec<Fitted>,
    /// Particles removed for lying closer than [`MIN_GAP`] spacings to another body's.
    pub trimmed: Vec<Trimmed>,
}

/// Container wall thickness in layers: `L = ceil(h / dx - 1e-9)` for kernel
/// support radius `h` \[m\] and spacing `dx` \[m\] (0 for non-finite input).
pub fn wall_layers(h: f64, dx: f64) -> u64 {
    let l = (h / dx - 1e-9).ceil();
    if l.is_finite() && l > 0.0 {
        l.min(f64::from(u32::MAX)) as u64
    } else {
        0
    }
}

/// The fluid box axes that are not whole spacings, with the layers placed.
fn fitted(scene: &Scene) -> Vec<Fitted> {
    let mut out = Vec::new();
    for (i, fb) in scene.fluid_boxes.iter().enumerate() {
        if !matches!(fb.volume, Volume::Aabb { .. }) {
            continue;
        }
        let (min, max) = (&fb.region.min, &fb.region.max);
        let s = fb.lattice_spacing(scene.spacing, min.len());
        let Ok(dims) = fluid_dims(min, max, s, &KeyPath::key("fluid_box").i(i)) else {
            continue;
        };
        for (axis, ((&n, &lo), &hi)) in dims.axes().iter().zip(min).zip(max).enumerate() {
            let spacings = (hi - lo) / s;
            if (spacings - spacings.round()).abs() > WHOLE {
                out.push(Fitted {
                    fluid_box: i,
                    axis,
                    spacings,
                    layers: n,
                });
            }
        }
    }
    out
}

/// The rest density of every fluid particle's phase \[kg/m^3\], in [`generate()`]'s order (each
/// particle's box's `rho0`, or else `fluid.rho0`): what the `multiphase` effect gives
/// `Simulation::with_phases`. Generates the particles to know which ones trimming kept.
///
/// # Errors
/// As [`generate()`].
pub fn fluid_rest_density(scene: &Scene) -> Result<Vec<f64>, SceneError> {
    let boxes = match scene.dimension {
        2 => generate::<2>(scene)?.fluid_box,
        _ => generate::<3>(scene)?.fluid_box,
    };
    let rho = |b: u32| {
        let fb = scene.fluid_boxes.get(b as usize);
        fb.and_then(|fb| fb.rho0).unwrap_or(scene.rho0)
    };
    Ok(boxes.into_iter().map(rho).collect())
}

fn generate_error(raw: RawProblem) -> SceneError {
    SceneError::Invalid {
        origin: "scene".into(),
        problems: vec![Problem {
            key: raw.path.to_string(),
            location: Location::Unknown,
            reason: raw.reason,
        }],
    }
}

/// Counts the particles [`generate()`] would create, without creating them
/// (pure checked `u64` arithmetic).
pub fn count_particles(scene: &Scene) -> Result<ParticleCounts, SceneError> {
    count_raw(scene).map_err(generate_error)
}

/// Corner as a fixed-size array, or an error naming `path`.
fn corner<const D: usize>(v: &[f64], path: &KeyPath) -> Result<[f64; D], SceneError> {
    <[f64; D]>::try_from(v).map_err(|_| {
        generate_error(RawProblem::new(
            path.clone(),
            format!("expected {D} entries, found {}", v.len()),
        ))
    })
}

/// Position of lattice index `idx` relative to corner `min` \[m\].
fn lattice_point<const D: usize>(min: &[f64; D], idx: &[i64; D], dx: f64) -> SVector<f32, D> {
    SVector::<f32, D>::from_fn(|k, _| (min[k] + (idx[k] as f64 + 0.5) * dx) as f32)
}

fn reserve<T>(v: &mut Vec<T>, n: u64) -> Result<(), SceneError> {
    let n = usize::try_from(n).unwrap_or(usize::MAX);
    v.try_reserve_exact(n).map_err(|e| {
        generate_error(RawProblem::new(
            KeyPath::key("particles").k("spacing"),
            format!("cannot allocate {n} particles: {e}"),
        ))
    })
}

/// Lattice sizes as `i64` indices.
fn dims_i64<const D: usize>(dims: &Dims) -> [i64; D] {
    let mut out = [0i64; D];
    for (o, &n) in out.iter_mut().zip(dims.axes()) {
        *o = i64::try_from(n).unwrap_or(i64::MAX);
    }
    out
}

/// Generates the initial particles of `scene` in `D` dimensions ([`generate_reported`] without
/// the report).
///
/// # Errors
/// As [`generate_reported`].
pub fn generate<const D: usize>(scene: &Scene) -> Result<Layout<D>, SceneError> {
    generate_reported(scene).map(|(layout, _)| layout)
}

/// Generates the initial particles of `scene` in `D` dimensions (the module doc's lattices, then
/// [`super::trim`]) and reports the fitted axes and trimmed particles.
///
/// Errors if `D != scene.dimension`, if a vector has the wrong length, a box is thinner than
/// half a spacing, the count exceeds `u32::MAX` or memory, or trimming would remove more than
/// [`MAX_TRIMMED_FRACTION`] of a body's particles (the error names both bodies and
/// `particles.spacing`).
pub fn generate_reported<const D: usize>(scene: &Scene) -> Result<(Layout<D>, GenerationReport), SceneError> {
    if D != scene.dimension {
        return Err(SceneError::Dimension {
            scene: scene.dimension,
            requested: D,
        });
    }
    let counts = count_particles(scene)?;
    if counts.total > u64::from(u32::MAX) {
        return Err(generate_error(RawProblem::new(
            KeyPath::key("particles").k("spacing"),
            format!("{} particles exceed the u32 index limit", counts.total),
        )));
    }
    let dx = scene.spacing;
    let mut fluid = Vec::with_capacity(scene.fluid_boxes.len());
    for (i, fb) in scene.fluid_boxes.iter().enumerate() {
        fluid.push(fill_fluid_box::<D>(fb, dx, &KeyPath::key("fluid_box").i(i))?);
    }
    let mut solids = Vec::with_capacity(scene.solids.len());
    for (i, (s, (_, n))) in scene.solids.iter().zip(&counts.solid).enumerate() {
        solids.push(fill_solid::<D>(
            s,
            dx,
            scene.wall_layers(),
            *n,
            &KeyPath::key("solid").i(i),
        )?);
    }
    let bodies: Vec<Points<'_, D>> = solids
        .iter()
        .enumerate()
        .map(|(i, p)| Points {
            body: Body::Solid(i),
            spacing: dx,
            position: p,
        })
        .chain(
            scene
                .fluid_boxes
                .iter()
                .zip(&fluid)
                .enumerate()
                .map(|(i, (fb, p))| Points {
                    body: Body::FluidBox(i),
                    spacing: fb.lattice_spacing(dx, D),
                    position: p,
                }),
        )
        .collect();
    let kept = trim::trim(&bodies);
    refuse_heavy_trims(scene, &kept.trimmed)?;
    let mut keep = kept.keep.iter();
    let mut layout = Layout {
        fluid_position: Vec::new(),
        fluid_velocity: Vec::new(),
        fluid_box: Vec::new(),
        solids: Vec::with_capacity(scene.solids.len()),
    };
    for (s, p) in scene.solids.iter().zip(&solids) {
        let k = keep.next().map(Vec::as_slice).unwrap_or_default();
        layout.solids.push(SolidParticles {
            name: s.name.clone(),
            position: p.iter().zip(k).filter(|(_, k)| **k).map(|(x, _)| *x).collect(),
        });
    }
    let n_fluid = kept
        .keep
        .iter()
        .skip(solids.len())
        .flatten()
        .filter(|k| **k)
        .count();
    reserve(&mut layout.fluid_position, n_fluid as u64)?;
    reserve(&mut layout.fluid_velocity, n_fluid as u64)?;
    reserve(&mut layout.fluid_box, n_fluid as u64)?;
    for (i, (fb, p)) in scene.fluid_boxes.iter().zip(&fluid).enumerate() {
        let k = keep.next().map(Vec::as_slice).unwrap_or_default();
        let v = SVector::<f32, D>::from_iterator(fb.velocity.iter().map(|&c| c as f32));
        for (x, _) in p.iter().zip(k).filter(|(_, k)| **k) {
            layout.fluid_position.push(*x);
            layout.fluid_velocity.push(v);
            layout.fluid_box.push(u32::try_from(i).unwrap_or(u32::MAX));
        }
    }
    let report = GenerationReport {
        fitted: fitted(scene),
        trimmed: kept.trimmed,
    };
    Ok((layout, report))
}

/// The lattice particles of one fluid box, twins included (right after their originals).
fn fill_fluid_box<const D: usize>(
    fb: &FluidBox,
    dx: f64,
    path: &KeyPath,
) -> Result<Vec<SVector<f32, D>>, SceneError> {
    corner::<D>(&fb.velocity, &path.k("velocity"))?;
    if !matches!(fb.volume, Volume::Aabb { .. }) {
        let n = fluid_box_count(fb, dx, path).map_err(generate_error)?;
        let mut out = Vec::new();
        reserve(&mut out, n)?;
        fill_shape::<D>(&fb.volume, dx, path, &mut out)?;
        return Ok(out);
    }
    let min = corner::<D>(&fb.region.min, &path.k("min"))?;
    let spacing = fb.lattice_spacing(dx, D);
    let dims = fluid_dims(&fb.region.min, &fb.region.max, spacing, path).map_err(generate_error)?;
    let n = fluid_box_count(fb, dx, path).map_err(generate_error)?;
    let mut out = Vec::new();
    reserve(&mut out, n)?;
    let mut k = 0u64;
    for_each_index([0; D], dims_i64::<D>(&dims), |idx| {
        let x = lattice_point(&min, idx, spacing);
        out.push(x);
        if fb.has_twin(k) {
            // The twin right after its original: the same f32 position, bit for bit.
            out.push(x);
        }
        k += 1;
    });
    Ok(out)
}

/// The particles of one solid (`n` of them, from [`solid_count`]) with `layers` wall layers.
fn fill_solid<const D: usize>(
    s: &Solid,
    dx: f64,
    layers: u64,
    n: u64,
    path: &KeyPath,
) -> Result<Vec<SVector<f32, D>>, SceneError> {
    let layers = i64::try_from(layers).unwrap_or(i64::MAX);
    let mut position = Vec::new();
    reserve(&mut position, n)?;
    match (s.shape, &s.volume) {
        (SolidShape::Container, _) => {
            let min = corner::<D>(&s.region.min, &path.k("min"))?;
            let dims = lattice_dims(&s.region.min, &s.region.max, dx, path).map_err(generate_error)?;
            let n_in = dims_i64::<D>(&dims);
            let lo = [-layers; D];
            let mut hi = n_in.map(|n| n.saturating_add(layers));
            if s.open_top {
                if let (Some(h), Some(&n)) = (hi.last_mut(), n_in.last()) {
                    *h = n;
                }
            }
            for_each_index(lo, hi, |idx| {
                let outside = idx.iter().zip(&n_in).any(|(&i, &n)| i < 0 || i >= n);
                if outside {
                    position.push(lattice_point(&min, idx, dx));
                }
            });
        }
        (_, Volume::Aabb { .. }) => {
            let min = corner::<D>(&s.region.min, &path.k("min"))?;
            let dims = lattice_dims(&s.region.min, &s.region.max, dx, path).map_err(generate_error)?;
            for_each_index([0; D], dims_i64::<D>(&dims), |idx| {
                position.push(lattice_point(&min, idx, dx))
            });
        }
        (_, volume) => fill_shape::<D>(volume, dx, path, &mut position)?,
    }
    Ok(position)
}

/// Appends the lattice points inside a shape other than an axis-aligned box (a solid's or a
/// fluid volume's): the lattice anchored at the lower corner of its bounding box, spacing `dx`.
fn fill_shape<const D: usize>(
    volume: &Volume,
    dx: f64,
    path: &KeyPath,
    out: &mut Vec<SVector<f32, D>>,
) -> Result<(), SceneError> {
    let (lo, size) = shape_lattice(volume, D, dx, path).map_err(generate_error)?;
    let min = corner::<D>(&lo, path)?;
    let size: [i64; D] = std::array::from_fn(|k| size.get(k).copied().unwrap_or(0));
    volume.lattice_inside::<D>(min, size, dx, |idx| out.push(lattice_point(&min, idx, dx)));
    Ok(())
}

/// Refuses the scene if trimming took more than [`MAX_TRIMMED_FRACTION`] of any body's
/// particles: one problem per such body, naming it, its neighbours and `particles.spacing`.
fn refuse_heavy_trims(scene: &Scene, trimmed: &[Trimmed]) -> Result<(), SceneError> {
    let mut problems = Vec::new();
    let mut rest = trimmed;
    while let Some(first) = rest.first() {
        let n = rest
            .iter()
            .take_while(|t| t.removed_from == first.removed_from)
            .count();
        let (group, tail) = rest.split_at(n);
        rest = tail;
        let removed: u64 = group.iter().map(|t| t.count).sum();
        if (removed as f64) <= MAX_TRIMMED_FRACTION * first.of as f64 {
            continue;
        }
        let next: Vec<String> = group.iter().map(|t| describe(scene, t.next_to)).collect();
        problems.push(Problem {
            key: match first.removed_from {
                Body::Solid(i) => KeyPath::key("solid").i(i),
                Body::FluidBox(i) => KeyPath::key("fluid_box").i(i),
            }
            .to_string(),
            location: Location::Unknown,
            reason: format!(
                "at particles.spacing = {} m, {removed} of this box's {} particles lie within {MIN_GAP} spacings of {}'s; \
                 trimming them would change the scene: give the boxes extents that are whole spacings, or another particles.spacing",
                scene.spacing,
                first.of,
                next.join(" and ")
            ),
        });
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(SceneError::Invalid {
            origin: "scene".into(),
            problems,
        })
    }
}

/// A body as messages name it: `fluid_box[1] [min, max]` or `solid[0] "tank" [min, max]`.
pub fn describe(scene: &Scene, body: Body) -> String {
    match body {
        Body::FluidBox(i) => match scene.fluid_boxes.get(i) {
            Some(fb) => match &fb.volume {
                Volume::Aabb { .. } => format!("{body} {}", fmt_box(&fb.region)),
                volume => format!("{body} {}", volume.describe(scene.dimension)),
            },
            None => body.to_string(),
        },
        Body::Solid(i) => match scene.solids.get(i) {
            Some(s) => match (s.shape, &s.volume) {
                (SolidShape::Container, _) | (_, Volume::Aabb { .. }) => {
                    format!("{body} \"{}\" {}", s.name, fmt_box(&s.region))
                }
                (_, volume) => format!("{body} \"{}\" {}", s.name, volume.describe(scene.dimension)),
            },
            None => body.to_string(),
        },
    }
}

/// The box occupied by a solid's particles, including container walls (the other shapes: the
/// box that bounds them).
pub(crate) fn solid_extent(s: &Solid, dx: f64, layers: u64) -> Aabb {
    match s.shape {
        SolidShape::Box | SolidShape::Cylinder | SolidShape::Sphere | SolidShape::Mesh => s.region.clone(),
        SolidShape::Container => {
            let w = layers as f64 * dx;
            let last = s.region.max.len().saturating_sub(1);
            Aabb {
                min: s.region.min.iter().map(|m| m - w).collect(),
                max: s
                    .region
                    .max
                    .iter()
                    .enumerate()
                    .map(|(k, m)| if s.open_top && k == last { *m } else { m + w })
                    .collect(),
            }
        }
    }
}

pub(crate) fn fmt_box(b: &Aabb) -> String {
    format!("[{:?}, {:?}]", b.min, b.max)
}

/// First axis on which `inner` sticks out of `outer` by more than `tol`.
pub(crate) fn outside_axis(inner: &Aabb, outer: &Aabb, tol: f64) -> Option<usize> {
    (0..inner.min.len().min(outer.min.len())).find(|&k| {
        let (a, b) = (inner.min.get(k), inner.max.get(k));
        let (lo, hi) = (outer.min.get(k), outer.max.get(k));
        matches!((a, lo), (Some(a), Some(lo)) if *a < lo - tol)
            || matches!((b, hi), (Some(b), Some(hi)) if *b > hi + tol)
    })
}

/// Intersection of two boxes if it has positive volume (widths > `tol`).
pub(crate) fn intersection(a: &Aabb, b: &Aabb, tol: f64) -> Option<Aabb> {
    let min: Vec<f64> = a.min.iter().zip(&b.min).map(|(x, y)| x.max(*y)).collect();
    let max: Vec<f64> = a.max.iter().zip(&b.max).map(|(x, y)| x.min(*y)).collect();
    let positive = min.iter().zip(&max).all(|(lo, hi)| hi - lo > tol);
    positive.then_some(Aabb { min, max })
}
