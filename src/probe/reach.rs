//! Which particles a probe's reading depends on, so that a run split across ranks gathers only
//! those on rank 0 (`run::record`), not every particle.
//!
//! Every interpolating probe sums kernel weights, zero at and beyond the support `h`, over the
//! particles within `h` of a point, a sensor's face, a gauge's line or a section; the box that
//! holds those (widened by `h` and a little slack) is the probe's reach. A particle outside it
//! adds an exact zero to every sum, so the reading from the particles in the reach, kept in
//! their order, is the reading from all of them bit for bit. A front needs only the fluid
//! particle furthest along its axis; a force or moment probe reads no particles.

use super::{ProbeLog, ProbeSpace};
use crate::fields::{FLUID, Fields};
use crate::math::Vector;
use crate::scene::{Probe, ProbeKind, Sensor};

/// Relative slack on `h` in the reach's box: the interpolations test `r² < h²` in f64 on f32
/// positions; this keeps a particle they count inside the box whatever the rounding.
const SLACK: f64 = 1e-6;

/// What a probe's reading depends on.
#[derive(Clone, Debug, PartialEq)]
pub enum Reach {
    /// No particle (a force or a moment: the step's loads).
    Nothing,
    /// The particles inside a box [m].
    Inside {
        /// Lower corner, `D` entries.
        lo: Vec<f64>,
        /// Upper corner, `D` entries.
        hi: Vec<f64>,
    },
    /// The fluid particle furthest along an axis (a front).
    Furthest {
        /// The front's axis.
        axis: usize,
    },
}

/// The reach of `probe` in a `D`-dimensional run with `space`'s kernel and domain.
pub fn reach<const D: usize>(probe: &Probe, space: &ProbeSpace) -> Reach {
    let h = space.h * (1.0 + SLACK);
    let Some(point) = probe.point.as_deref().filter(|p| p.len() == D) else {
        return match probe.kind {
            ProbeKind::Front => Reach::Furthest {
                axis: probe.axis.min(D - 1),
            },
            _ => Reach::Nothing,
        };
    };
    let around = |half: &[f64]| Reach::Inside {
        lo: point.iter().zip(half).map(|(x, w)| x - w).collect(),
        hi: point.iter().zip(half).map(|(x, w)| x + w).collect(),
    };
    let axis = probe.axis.min(D - 1);
    match probe.kind {
        ProbeKind::Pressure => match probe.sensor {
            Sensor::Point => around(&[h; D]),
            Sensor::Face { diameter, .. } => around(&[diameter / 2.0 + h; D]),
        },
        ProbeKind::Velocity => around(&[h; D]),
        ProbeKind::FlowRate => {
            let size = probe.size.as_deref().unwrap_or(&[]);
            let mut across = size.iter();
            let half: Vec<f64> = (0..D)
                .map(|k| {
                    if k == axis {
                        h
                    } else {
                        across.next().map_or(h, |w| w / 2.0 + h)
                    }
                })
                .collect();
            around(&half)
        }
        ProbeKind::Level => {
            let top = space.domain_max.get(axis).copied().unwrap_or(point[axis]);
            let mut lo: Vec<f64> = point.iter().map(|x| x - h).collect();
            let mut hi: Vec<f64> = point.iter().map(|x| x + h).collect();
            hi[axis] = top.max(point[axis]) + h;
            lo[axis] = point[axis] - h;
            Reach::Inside { lo, hi }
        }
        ProbeKind::Front => Reach::Furthest { axis },
        ProbeKind::Force | ProbeKind::Moment => Reach::Nothing,
    }
}

/// The indices (increasing) of the particles of `fields` that any of `probes` reads.
pub fn particles_read<const D: usize>(probes: &[Probe], space: &ProbeSpace, fields: &Fields<D>) -> Vec<u32> {
    let mut read = vec![false; fields.len()];
    for probe in probes {
        match reach::<D>(probe, space) {
            Reach::Nothing => {}
            Reach::Inside { lo, hi } => {
                let inside = |x: &Vector<D>| (0..D).all(|k| (lo[k]..=hi[k]).contains(&f64::from(x[k])));
                for (i, x) in fields.position.iter().enumerate() {
                    read[i] |= inside(x);
                }
            }
            Reach::Furthest { axis } => {
                let furthest = (0..fields.len())
                    .filter(|&i| fields.kind[i] == FLUID)
                    .max_by(|&a, &b| fields.position[a][axis].total_cmp(&fields.position[b][axis]));
                if let Some(i) = furthest {
                    read[i] = true;
                }
            }
        }
    }
    (0..fields.len() as u32).filter(|&i| read[i as usize]).collect()
}

impl ProbeLog {
    /// The indices (increasing) of the particles of `fields` these probes read ([`reach`]).
    pub fn particles_read<const D: usize>(&self, fields: &Fields<D>) -> Vec<u32> {
        particles_read(&self.probes, &self.space, fields)
    }
}
