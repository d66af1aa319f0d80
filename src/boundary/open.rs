//! Open boundaries: an inflow of prescribed velocity and an outflow, by buffer layers of
//! particles created and removed ([LBQ09] Lastiwka, Basa & Quinlan 2009; [F12] Federico et al.
//! 2012). docs/effects.md, "Open boundaries", gives the reasons for each choice.
//!
//! An open boundary is a plane across a channel, its normal along a coordinate axis and
//! pointing into the fluid, and a section: the part of the plane between `min` and `max`. Its
//! buffer is the box behind the section, `depth` deep. Membership is geometric: a fluid particle
//! is a buffer particle while it lies in that box, so no field marks it. Once a step, at the
//! step's start, on the host ([`update`]):
//! - inflow: every buffer particle gets the prescribed velocity `u(x)` (uniform, or parabolic
//!   across the section, [`Profile`]); a particle that crossed the plane is fluid. Each column of
//!   the buffer (one spacing wide across the section) gets a new particle one spacing behind its
//!   rearmost one as soon as that fits in the buffer, so the buffer stays full and the fluid
//!   gains one lattice particle per column each time the column has moved one spacing: a mass
//!   flux `ρ0 u·n` per unit area of the section, below `level` where one is given;
//! - outflow: a free exit. The buffer's particles move as the fluid does, and a particle past the
//!   buffer's far side is removed. The buffer's rear, short of neighbours, sums a density below
//!   `ρ0` and so has zero pressure (19): the fluid leaves against zero pressure, and a fluid that
//!   gains mass pushes harder through the exit. (Setting the buffer's velocities to the mean of
//!   the fluid just upstream, [F12]'s zero gradient, leaves nothing to restore the balance:
//!   measured on `scenes/open_channel_2d.toml`, its buffer slowed to 0.16 m/s against the
//!   inflow's 0.2 and compressed by 2 % within 2.5 s.)
//!
//! During the step buffer particles are fluid particles of every stage: their density is the
//! summation (18) and their pressure (19), so the fluid next to the plane has a full kernel
//! support of particles at the lattice spacing.
//!
//! References: [LBQ09] M. Lastiwka, M. Basa, N. J. Quinlan, "Permeable and non-reflecting
//! boundary conditions in SPH", Int. J. Numer. Meth. Fluids 61, 709–724 (2009).
//! [F12] I. Federico, S. Marrone, A. Colagrossi, F. Aristodemo, M. Antuono, "Simulating 2D
//! open-channel flows through an SPH model", Eur. J. Mech. B/Fluids 34, 35–46 (2012).

use crate::fields::{FLUID, Fields};
use crate::math::{Real, Vector};

/// The velocity profile of an inflow across its section.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Profile {
    /// The same velocity everywhere on the section.
    #[default]
    Uniform,
    /// `u(s) = 6 s (1 − s) U` along each axis across the section, `s` the fraction of the
    /// wetted width (up to `level` on the vertical axis): plane Poiseuille flow of mean `U`.
    Parabolic,
}

impl Profile {
    /// The name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Profile::Uniform => "uniform",
            Profile::Parabolic => "parabolic",
        }
    }
}

/// What crosses an open boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Flow<const D: usize> {
    /// Fluid enters with the mean velocity `velocity` [m/s] (its normal component positive)
    /// distributed by `profile`, below `level` [m] on the last axis where given.
    Inflow {
        /// Mean velocity over the wetted section [m/s].
        velocity: Vector<D>,
        /// Its distribution across the section.
        profile: Profile,
        /// Height of the free surface at the inflow [m] (the last axis); `None`: the whole section.
        level: Option<Real>,
        /// Time `T` [s] over which the velocity rises from zero as `(1 − cos(π t/T))/2` (a start
        /// without a water hammer, its acceleration zero at both ends); `None`: the full
        /// velocity from the start.
        ramp: Option<f64>,
    },
    /// Fluid leaves freely, against the zero pressure of the buffer's rear.
    Outflow,
}

/// One open boundary (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OpenBoundary<const D: usize> {
    /// Inflow or outflow.
    pub flow: Flow<D>,
    /// The axis of the normal.
    pub axis: usize,
    /// `+1` when the normal into the fluid is `+e_axis`, `−1` when it is `−e_axis`.
    pub inward: Real,
    /// Lower corner of the section [m]; its `axis` component is the plane's coordinate.
    pub min: Vector<D>,
    /// Upper corner of the section [m]; its `axis` component is the plane's coordinate.
    pub max: Vector<D>,
    /// Depth of the buffer behind the plane [m] (`layers · dx`).
    pub depth: Real,
}

/// What every created particle starts from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Template {
    /// Lattice spacing `dx` [m].
    pub spacing: Real,
    /// Particle mass [kg] ([kg/m] in 2D): the lattice mass of every fluid particle.
    pub mass: Real,
    /// Rest density `ρ0` [kg/m³]: a new particle's density when its column is empty.
    pub rho0: Real,
}

/// What one [`update`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Update {
    /// Particles created behind an inflow.
    pub created: u64,
    /// Particles removed past an outflow (or, in a backflow, past an inflow's buffer).
    pub removed: u64,
}

impl<const D: usize> OpenBoundary<D> {
    /// Signed distance [m] of `x` from the plane, positive in the fluid, negative in the buffer.
    pub fn inward_distance(&self, x: &Vector<D>) -> Real {
        self.inward * (x[self.axis] - self.min[self.axis])
    }

    /// Whether `x` lies across the section (its coordinates off the normal axis within it).
    pub fn across(&self, x: &Vector<D>) -> bool {
        (0..D)
            .filter(|&k| k != self.axis)
            .all(|k| x[k] >= self.min[k] && x[k] <= self.max[k])
    }

    /// Whether `x` is in the buffer: across the section, behind the plane, within `depth`.
    pub fn in_buffer(&self, x: &Vector<D>) -> bool {
        let d = self.inward_distance(x);
        (-self.depth..0.0).contains(&d) && self.across(x)
    }

    /// Columns along each axis across the section (1 along the normal): the section's width
    /// over `dx`, rounded, at least 1.
    fn columns(&self, dx: Real) -> [usize; D] {
        std::array::from_fn(|k| {
            if k == self.axis {
                1
            } else {
                ((self.max[k] - self.min[k]) / dx).round().max(1.0) as usize
            }
        })
    }

    /// The column of `x` (flattened, the first axis fastest).
    fn column_of(&self, x: &Vector<D>, columns: &[usize; D]) -> usize {
        let mut c = 0;
        for k in (0..D).rev() {
            let w = (self.max[k] - self.min[k]) / columns[k] as Real;
            let i = if k == self.axis || w <= 0.0 {
                0
            } else {
                (((x[k] - self.min[k]) / w).floor().max(0.0) as usize).min(columns[k] - 1)
            };
            c = c * columns[k] + i;
        }
        c
    }

    /// The centre of column `c` on the plane.
    fn column_centre(&self, mut c: usize, columns: &[usize; D]) -> Vector<D> {
        let mut x = self.min;
        for k in 0..D {
            let i = c % columns[k];
            c /= columns[k];
            if k != self.axis {
                let w = (self.max[k] - self.min[k]) / columns[k] as Real;
                x[k] = self.min[k] + (i as Real + 0.5) * w;
            }
        }
        x
    }

    /// The inflow's velocity at `x` [m/s] and time `time` [s] (`Profile`, times the ramp's
    /// `(1 − cos(π t/T))/2` before `T`); zero for an outflow.
    pub fn inflow_velocity(&self, x: &Vector<D>, time: f64) -> Vector<D> {
        let Flow::Inflow {
            velocity,
            profile,
            level,
            ramp,
        } = self.flow
        else {
            return Vector::zeros();
        };
        let velocity = match ramp {
            Some(t) if time < t => velocity * (0.5 * (1.0 - (std::f64::consts::PI * time / t).cos())) as Real,
            _ => velocity,
        };
        match profile {
            Profile::Uniform => velocity,
            Profile::Parabolic => {
                let mut factor = 1.0;
                for k in (0..D).filter(|&k| k != self.axis) {
                    let top = match level {
                        Some(l) if k == D - 1 => l.min(self.max[k]),
                        _ => self.max[k],
                    };
                    let s = ((x[k] - self.min[k]) / (top - self.min[k])).clamp(0.0, 1.0);
                    factor *= 6.0 * s * (1.0 - s);
                }
                velocity * factor
            }
        }
    }

    /// Whether the inflow fills column centre `x` (below its level, if any).
    fn wetted(&self, x: &Vector<D>) -> bool {
        match self.flow {
            Flow::Inflow { level: Some(l), .. } => x[D - 1] <= l,
            _ => true,
        }
    }
}

/// How the particles of [`update`]'s fields take part: all of them (a whole simulation,
/// [`Whole`]), or one rank's share of a run split across ranks, where the fields also hold
/// ghosts (copies of other ranks' particles) and every decision must be the same on every rank.
pub trait Share<const D: usize> {
    /// Whether particle `i` is this share's own (not a ghost).
    fn counts(&self, i: usize) -> bool;
    /// Whether a particle created at `x` [m] belongs to this share.
    fn owns(&self, x: &Vector<D>) -> bool;
    /// Replaces each of `values` by its largest over the shares.
    fn max(&mut self, values: &mut [f64]);
    /// Replaces each of `values` by its sum over the shares.
    fn sum(&mut self, values: &mut [f64]);
}

/// Every particle, one share: nothing to combine.
pub struct Whole;

impl<const D: usize> Share<D> for Whole {
    fn counts(&self, _: usize) -> bool {
        true
    }
    fn owns(&self, _: &Vector<D>) -> bool {
        true
    }
    fn max(&mut self, _: &mut [f64]) {}
    fn sum(&mut self, _: &mut [f64]) {}
}

/// The open boundaries' update at a step's start (module doc) on a whole simulation: removes
/// the fluid particles past a buffer's far side, sets the inflow buffers' velocities, and fills
/// each inflow column. Kept particles keep their order; created ones are appended, boundary by
/// boundary and column by column, with new ids above every id present, so the result depends
/// only on `fields` and the time `time` [s] (an inflow's ramp).
pub fn update<const D: usize>(
    fields: &mut Fields<D>,
    boundaries: &[OpenBoundary<D>],
    t: &Template,
    time: f64,
) -> Update {
    update_share(fields, boundaries, t, time, &mut Whole)
}

/// [`update`] on one share of a split run. Each column's rearmost particle is the nearest over
/// every share's own particles (a largest `-d`, then the sum of the density and pressure of
/// the shares that hold it, divided by their count); every share computes the same created
/// particles with the same ids (above the largest id of any share) and keeps those it owns.
/// The counts returned are over all shares.
pub fn update_share<const D: usize>(
    fields: &mut Fields<D>,
    boundaries: &[OpenBoundary<D>],
    t: &Template,
    time: f64,
    share: &mut dyn Share<D>,
) -> Update {
    let mut top = [fields.id.iter().max().map_or(-1.0, |&m| f64::from(m))];
    share.max(&mut top);
    let mut next_id = (top[0] + 1.0) as u32;
    let past = |x: &Vector<D>| {
        boundaries
            .iter()
            .any(|b| b.across(x) && b.inward_distance(x) < -b.depth)
    };
    // A share removes its own particles only (a ghost goes with its owner's next halo), so
    // that it changes its particles only when the count over the shares says so.
    let gone = |i: usize| fields.kind[i] == FLUID && past(&fields.position[i]) && share.counts(i);
    let mut removed = [(0..fields.len()).filter(|&i| gone(i)).count() as f64];
    let kept: Vec<u32> = (0..fields.len())
        .filter(|&i| !gone(i))
        .map(|i| i as u32)
        .collect();
    // Which particles are this share's own, in the order after the removal (created ones are).
    let mut own: Vec<bool> = kept.iter().map(|&i| share.counts(i as usize)).collect();
    if kept.len() < fields.len() {
        fields.keep(&kept);
    }
    share.sum(&mut removed);
    let mut created = 0;
    for b in boundaries {
        // An outflow is a free exit: its buffer's particles move as the fluid's, and those past
        // its far side were removed above (module doc).
        if b.flow == Flow::Outflow {
            continue;
        }
        let columns = b.columns(t.spacing);
        let count: usize = columns.iter().product();
        // Each column's rearmost particle (distance, index), the fluid just ahead of the
        // plane included, so an empty buffer fills on from the fluid.
        let mut rear: Vec<Option<(Real, usize)>> = vec![None; count];
        for i in 0..fields.len() {
            if fields.kind[i] != FLUID {
                continue;
            }
            let x = fields.position[i];
            let d = b.inward_distance(&x);
            if d >= -b.depth && d < t.spacing && b.across(&x) {
                if d < 0.0 {
                    fields.velocity[i] = b.inflow_velocity(&x, time);
                }
                let r = &mut rear[b.column_of(&x, &columns)];
                if own[i] && r.is_none_or(|(dr, _)| d < dr) {
                    *r = Some((d, i));
                }
            }
        }
        // The nearest over the shares, and its density and pressure.
        let mut nearest: Vec<f64> = rear
            .iter()
            .map(|r| r.map_or(f64::NEG_INFINITY, |(d, _)| -f64::from(d)))
            .collect();
        share.max(&mut nearest);
        let mut source = vec![0.0; 3 * count];
        for (c, r) in rear.iter().enumerate() {
            if let Some((d, i)) = *r
                && -f64::from(d) == nearest[c]
            {
                source[3 * c] = f64::from(fields.density[i]);
                source[3 * c + 1] = f64::from(fields.pressure[i]);
                source[3 * c + 2] = 1.0;
            }
        }
        share.sum(&mut source);
        for (c, &near) in nearest.iter().enumerate() {
            let centre = b.column_centre(c, &columns);
            if !b.wetted(&centre) {
                continue;
            }
            let (mut d, density, pressure) = if near == f64::NEG_INFINITY {
                (0.5 * t.spacing, t.rho0, 0.0)
            } else {
                let n = source[3 * c + 2];
                (
                    -near as Real,
                    (source[3 * c] / n) as Real,
                    (source[3 * c + 1] / n) as Real,
                )
            };
            while d - t.spacing >= -b.depth {
                d -= t.spacing;
                let mut x = centre;
                x[b.axis] = b.min[b.axis] + d * b.inward;
                if share.owns(&x) {
                    let u = b.inflow_velocity(&x, time);
                    fields.push_created(x, u, t.mass, density, pressure, next_id, t.rho0);
                    own.push(true);
                }
                next_id += 1;
                created += 1;
            }
        }
    }
    Update {
        created,
        removed: removed[0] as u64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inflow(level: Option<Real>, profile: Profile) -> OpenBoundary<2> {
        OpenBoundary {
            flow: Flow::Inflow {
                velocity: Vector::<2>::new(0.5, 0.0),
                profile,
                level,
                ramp: None,
            },
            axis: 0,
            inward: 1.0,
            min: Vector::<2>::new(0.0, 0.0),
            max: Vector::<2>::new(0.0, 0.1),
            depth: 0.04,
        }
    }

    const T: Template = Template {
        spacing: 0.01,
        mass: 0.1,
        rho0: 1000.0,
    };

    #[test]
    fn an_empty_inflow_buffer_fills_with_whole_layers_below_the_level() {
        let mut f = Fields::<2>::default();
        let u = update(&mut f, &[inflow(Some(0.05), Profile::Uniform)], &T, 0.0);
        // 5 wetted columns of 10 (centres 0.005..0.045 below 0.05), 4 layers of 0.04 m.
        assert_eq!(
            u,
            Update {
                created: 20,
                removed: 0
            }
        );
        assert!(
            f.position
                .iter()
                .all(|x| x[0] < 0.0 && x[0] >= -0.04 && x[1] < 0.05)
        );
        let again = update(&mut f, &[inflow(Some(0.05), Profile::Uniform)], &T, 0.0);
        assert_eq!(again, Update::default(), "a full buffer gains nothing");
    }

    #[test]
    fn the_parabolic_profile_has_the_mean_velocity() {
        let b = inflow(None, Profile::Parabolic);
        let n = 1000;
        let mean: f64 = (0..n)
            .map(|i| {
                let y = (i as Real + 0.5) / n as Real * 0.1;
                f64::from(b.inflow_velocity(&Vector::<2>::new(-0.005, y), 0.0)[0])
            })
            .sum::<f64>()
            / n as f64;
        // The midpoint sum of 6 s (1 − s) over n cells is 1 − 1/(2 n²).
        assert!((mean - 0.5).abs() < 1e-5, "mean {mean}");
    }
}
