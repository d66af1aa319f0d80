//! What a point probe reads from the particles: SPH interpolation of the fluid's pressure and
//! velocity at a point, and the free-surface height along a gauge's line.
//!
//! Every sum uses the poly6 kernel (20) with the scene's `h` and each particle's volume
//! `V_j = m_j/ρ_j`, in f64 over the f32 fields.
//!
//! **Pressure and velocity** at `x` (fluid particles only): `Σ_j q_j V_j W(x − x_j) /
//! max(Σ_j V_j W(x − x_j), S_MIN)`. Near a wall or the free surface the kernel support is only
//! partly filled with fluid; dividing by the fluid's own kernel sum (Shepard's normalisation)
//! removes that bias, so a sensor on a wall reads the fluid's pressure there and not about half
//! of it. A wall's face fills half the support with fluid, the corner of a floor and a wall a
//! quarter (3D: an edge a quarter, a corner an eighth); all lie above [`SHEPARD_MIN`] = 0.1 and
//! are normalised fully. Below it the sum is divided by `SHEPARD_MIN` instead: a dry sensor
//! reads 0, one at the edge of a passing particle's support a fraction of its pressure, and the
//! reading stays continuous (DualSPHysics' measuring tool drops the normalisation below a
//! kernel sum of 0.5, which would halve a sensor on a wall and make the reading jump).
//!
//! **Level** (a wave gauge): the fluid-and-solid kernel sum `c(x) = Σ_j V_j W(x − x_j)` is
//! about 1 inside the water (solids fill the support near the floor) and falls to 0 above the
//! surface; the gauge climbs its line from its foot in steps of `h/8` and reports the first
//! height where `c` drops below [`LEVEL_THRESHOLD`] = 1/2 (the surface of a half space),
//! linearly interpolated between the steps. A droplet above the water is never reached, and
//! one particle alone never reaches 1/2 (`V W(0)` is 1/π in 2D and 0.2 in 3D at `h = 2 dx`).
//! A gauge whose foot is dry reads 0.
//!
//! **Flow rate** through a segment (2D, [m²/s] per unit depth) or rectangle (3D, [m³/s]) normal
//! to `axis`: the section is divided into cells about `h/4` wide; each cell adds its area times
//! the interpolated fluid velocity along `axis` at its centre times the wet fraction there, the
//! fluid-and-solid kernel sum capped at 1 (1 in the water and next to walls, 1/2 at the free
//! surface, 0 in the air), so a section reaching above the water counts only the water.
//!
//! **A sensor's face** (a pressure probe with a `diameter`): the mean of the interpolated
//! pressure over the segment (2D) or disc (3D), [`face_average`] at points at most
//! [`FACE_SPACING`] `h` apart.

use crate::fields::{FLUID, Fields};
use crate::math::Real;
use crate::smoothing::Smoothing;

/// The fluid kernel sum below which the Shepard normalisation stops (a full support sums to 1).
pub const SHEPARD_MIN: f64 = 0.1;

/// The kernel sum that marks the free surface for a level gauge.
pub const LEVEL_THRESHOLD: f64 = 0.5;

/// The particles within `h` of `x` that `keep` selects: `(j, V_j W(x − x_j))`.
fn weights<const D: usize>(
    fields: &Fields<D>,
    kernel: &Smoothing<D>,
    x: &[f64],
    keep: impl Fn(usize) -> bool,
) -> Vec<(usize, f64)> {
    let h2 = f64::from(kernel.h) * f64::from(kernel.h);
    (0..fields.len())
        .filter(|&j| keep(j))
        .filter_map(|j| {
            let r2: f64 = (0..D)
                .map(|k| (x[k] - f64::from(fields.position[j][k])).powi(2))
                .sum();
            (r2 < h2).then(|| {
                let volume = f64::from(fields.mass[j]) / f64::from(fields.density[j]);
                (j, volume * f64::from(kernel.w(r2 as Real)))
            })
        })
        .filter(|(_, w)| w.is_finite() && *w > 0.0)
        .collect()
}

/// The Shepard-normalised fluid interpolation of `value(j)` at `x` (see the module
/// documentation); 0 where no fluid particle is within `h`.
pub fn fluid_value<const D: usize>(
    fields: &Fields<D>,
    kernel: &Smoothing<D>,
    x: &[f64],
    value: impl Fn(usize) -> f64,
) -> f64 {
    let w = weights(fields, kernel, x, |j| fields.kind[j] == FLUID);
    let sum: f64 = w.iter().map(|(_, w)| w).sum();
    let weighted: f64 = w.iter().map(|&(j, w)| value(j) * w).sum();
    weighted / sum.max(SHEPARD_MIN)
}

/// The fluid pressure at `x` [Pa].
pub fn pressure<const D: usize>(fields: &Fields<D>, kernel: &Smoothing<D>, x: &[f64]) -> f64 {
    pressure_of(fields, &fields.pressure, kernel, x)
}

/// The interpolated fluid value of the per-particle pressures `values` [Pa] at `x`
/// (`probe::PressureReading::values`); NaN where `values` does not hold one per particle.
pub fn pressure_of<const D: usize>(
    fields: &Fields<D>,
    values: &[Real],
    kernel: &Smoothing<D>,
    x: &[f64],
) -> f64 {
    if values.len() != fields.len() {
        return f64::NAN;
    }
    fluid_value(fields, kernel, x, |j| f64::from(values[j]))
}

/// The fluid velocity's component along `axis` at `x` [m/s].
pub fn velocity<const D: usize>(fields: &Fields<D>, kernel: &Smoothing<D>, x: &[f64], axis: usize) -> f64 {
    fluid_value(fields, kernel, x, |j| f64::from(fields.velocity[j][axis]))
}

/// The height [m] of the free surface above `foot` along `axis` (upwards), scanned up to
/// `top` (the coordinate along `axis` where the line ends): see the module documentation.
pub fn level<const D: usize>(
    fields: &Fields<D>,
    kernel: &Smoothing<D>,
    foot: &[f64],
    axis: usize,
    top: f64,
) -> f64 {
    let h = f64::from(kernel.h);
    // The particles near the line, once: within h of it across the axis.
    let near: Vec<usize> = (0..fields.len())
        .filter(|&j| {
            let across: f64 = (0..D)
                .filter(|&k| k != axis)
                .map(|k| (foot[k] - f64::from(fields.position[j][k])).powi(2))
                .sum();
            let along = f64::from(fields.position[j][axis]);
            across < h * h && along > foot[axis] - h && along < top + h
        })
        .collect();
    let sum_at = |height: f64| -> f64 {
        let mut x = foot.to_vec();
        x[axis] = foot[axis] + height;
        let h2 = h * h;
        near.iter()
            .map(|&j| {
                let r2: f64 = (0..D)
                    .map(|k| (x[k] - f64::from(fields.position[j][k])).powi(2))
                    .sum();
                if r2 >= h2 {
                    return 0.0;
                }
                let volume = f64::from(fields.mass[j]) / f64::from(fields.density[j]);
                let w = volume * f64::from(kernel.w(r2 as Real));
                if w.is_finite() { w } else { 0.0 }
            })
            .sum()
    };
    let step = h / 8.0;
    let length = top - foot[axis];
    let mut below = sum_at(0.0);
    if below.is_nan() || below < LEVEL_THRESHOLD {
        return 0.0;
    }
    let mut height = 0.0;
    while height < length {
        let next = (height + step).min(length);
        let above = sum_at(next);
        if above.is_nan() || above < LEVEL_THRESHOLD {
            // Linear between the two steps.
            let fraction = (below - LEVEL_THRESHOLD) / (below - above.max(0.0));
            return height + (next - height) * fraction.clamp(0.0, 1.0);
        }
        below = above;
        height = next;
    }
    length
}

/// The volume flux through the section centred on `centre`, normal to `axis`, of extents `size`
/// along the other axes in increasing order (see the module documentation).
pub fn flow_rate<const D: usize>(
    fields: &Fields<D>,
    kernel: &Smoothing<D>,
    centre: &[f64],
    axis: usize,
    size: &[f64],
) -> f64 {
    let h = f64::from(kernel.h);
    let across: Vec<usize> = (0..D).filter(|&k| k != axis).collect();
    if size.len() != across.len() {
        return f64::NAN;
    }
    // The particles within h of the section's plane (and of its extent).
    let near: Vec<usize> = (0..fields.len())
        .filter(|&j| {
            let x = &fields.position[j];
            (f64::from(x[axis]) - centre[axis]).abs() < h
                && across
                    .iter()
                    .zip(size)
                    .all(|(&k, &w)| (f64::from(x[k]) - centre[k]).abs() < w / 2.0 + h)
        })
        .collect();
    let counts: Vec<usize> = size
        .iter()
        .map(|w| (w / (h / 4.0)).ceil().max(1.0) as usize)
        .collect();
    let cell: Vec<f64> = size.iter().zip(&counts).map(|(w, n)| w / *n as f64).collect();
    let area: f64 = cell.iter().product();
    let h2 = h * h;
    let mut flux = 0.0;
    let total: usize = counts.iter().product();
    for index in 0..total {
        let mut x = centre.to_vec();
        let mut rest = index;
        for (a, &k) in across.iter().enumerate() {
            let i = rest % counts[a];
            rest /= counts[a];
            x[k] = centre[k] - size[a] / 2.0 + (i as f64 + 0.5) * cell[a];
        }
        let (mut all, mut fluid, mut moving) = (0.0, 0.0, 0.0);
        for &j in &near {
            let r2: f64 = (0..D)
                .map(|k| (x[k] - f64::from(fields.position[j][k])).powi(2))
                .sum();
            if r2 >= h2 {
                continue;
            }
            let volume = f64::from(fields.mass[j]) / f64::from(fields.density[j]);
            let w = volume * f64::from(kernel.w(r2 as Real));
            if !(w.is_finite() && w > 0.0) {
                continue;
            }
            all += w;
            if fields.kind[j] == FLUID {
                fluid += w;
                moving += w * f64::from(fields.velocity[j][axis]);
            }
        }
        if fluid > 0.0 {
            flux += moving / fluid.max(SHEPARD_MIN) * all.min(1.0) * area;
        }
    }
    flux
}

/// The largest spacing \[in units of `h`\] between the points at which a sensor's face is
/// sampled ([`face_average`]).
pub const FACE_SPACING: f64 = 0.25;

/// Nodes and weights of the 2-point Gauss–Legendre rule on `[-1, 1]` (exact for cubics).
const GAUSS2: [(f64, f64); 2] = [(-0.577_350_269_189_625_8, 1.0), (0.577_350_269_189_625_8, 1.0)];

/// The mean of `value` over a sensor's face: the segment (2D) or disc (3D) of `diameter`
/// centred on `centre`, in the plane normal to axis `normal`, sampled at points at most
/// `spacing` apart.
///
/// 2D: the segment is cut into cells no longer than `spacing`, each integrated by the
/// 2-point Gauss rule. 3D: in polar coordinates about the centre, rings no wider than
/// `spacing` (2-point Gauss in the radius, weight `r dr`), each sampled at
/// `max(4, ⌈2π r / spacing⌉)` equally spaced angles. Both are exact for a pressure
/// quadratic across the face (the disc mean of `a x²` is `a R²/4`), so the reading differs from
/// the centre's only by the field's curvature.
pub fn face_average<const D: usize>(
    centre: &[f64],
    normal: usize,
    diameter: f64,
    spacing: f64,
    value: impl Fn(&[f64]) -> f64,
) -> f64 {
    let across: Vec<usize> = (0..D).filter(|&k| k != normal).collect();
    let radius = diameter / 2.0;
    let at = |offsets: &[f64]| -> f64 {
        let mut x = centre.to_vec();
        for (&k, o) in across.iter().zip(offsets) {
            x[k] += o;
        }
        value(&x)
    };
    if D == 2 {
        let cells = (diameter / spacing).ceil().max(1.0) as usize;
        let width = diameter / cells as f64;
        let mut sum = 0.0;
        for i in 0..cells {
            let mid = -radius + (i as f64 + 0.5) * width;
            for (node, weight) in GAUSS2 {
                sum += weight * width / 2.0 * at(&[mid + node * width / 2.0]);
            }
        }
        return sum / diameter;
    }
    let rings = (radius / spacing).ceil().max(1.0) as usize;
    let width = radius / rings as f64;
    let (mut sum, mut area) = (0.0, 0.0);
    for i in 0..rings {
        let mid = (i as f64 + 0.5) * width;
        for (node, weight) in GAUSS2 {
            let r = mid + node * width / 2.0;
            let angles = ((2.0 * std::f64::consts::PI * r / spacing).ceil() as usize).max(4);
            let ring: f64 = (0..angles)
                .map(|a| {
                    let phi = 2.0 * std::f64::consts::PI * a as f64 / angles as f64;
                    at(&[r * phi.cos(), r * phi.sin()])
                })
                .sum::<f64>()
                / angles as f64;
            let w = weight * width / 2.0 * r;
            sum += w * ring;
            area += w;
        }
    }
    sum / area
}
