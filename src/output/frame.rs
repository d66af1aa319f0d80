//! One output frame: the per-particle state [`super::vtu::write_vtu`] writes, borrowed from the
//! solver's fields ([`Frame`]) or copied for a subset of the particles ([`FrameSubset`]).

use nalgebra::SVector;

use super::OutputError;

/// One output frame: borrowed per-particle state at simulated time `time`.
///
/// All slices must have the same length (the number of particles).
#[derive(Debug, Clone, Copy)]
pub struct Frame<'a, const D: usize> {
    /// Simulated time of the frame, in seconds (stored as the VTK `TimeValue`
    /// field).
    pub time: f64,
    /// Particle positions, in metres.
    pub position: &'a [SVector<f32, D>],
    /// Particle velocities, in metres per second.
    pub velocity: &'a [SVector<f32, D>],
    /// Particle densities, in kg/m^D.
    pub density: &'a [f32],
    /// Particle pressures, in Pa (force per unit length in 2D).
    pub pressure: &'a [f32],
    /// Particle kind: 0 = fluid, k > 0 = the k-th named solid.
    pub kind: &'a [u32],
    /// Stable particle id: the particle's index in the initial layout, the same in every frame
    /// of a run whatever order the particles are stored in (`Fields::id`).
    pub id: &'a [u32],
}

impl<const D: usize> Frame<'_, D> {
    /// Number of particles, after checking that all slices have the same
    /// length as `position`.
    pub fn checked_len(&self) -> Result<usize, OutputError> {
        let n = self.position.len();
        let fields = [
            ("velocity", self.velocity.len()),
            ("density", self.density.len()),
            ("pressure", self.pressure.len()),
            ("kind", self.kind.len()),
            ("id", self.id.len()),
        ];
        for (field, found) in fields {
            if found != n {
                return Err(OutputError::LengthMismatch {
                    field,
                    expected: n,
                    found,
                });
            }
        }
        Ok(n)
    }

    /// An owned copy of the fluid particles (`kind` 0) of this frame, ids kept.
    pub fn fluid(&self) -> FrameSubset<D> {
        let keep: Vec<usize> = (0..self.kind.len()).filter(|&i| self.kind[i] == 0).collect();
        fn pick<T: Copy>(v: &[T], keep: &[usize]) -> Vec<T> {
            keep.iter().filter_map(|&i| v.get(i).copied()).collect()
        }
        FrameSubset {
            time: self.time,
            position: pick(self.position, &keep),
            velocity: pick(self.velocity, &keep),
            density: pick(self.density, &keep),
            pressure: pick(self.pressure, &keep),
            kind: pick(self.kind, &keep),
            id: pick(self.id, &keep),
        }
    }
}

/// Owned particle state of part of a [`Frame`] (from [`Frame::fluid`]); same fields and units.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameSubset<const D: usize> {
    /// Simulated time [s].
    pub time: f64,
    /// Positions [m].
    pub position: Vec<SVector<f32, D>>,
    /// Velocities [m/s].
    pub velocity: Vec<SVector<f32, D>>,
    /// Densities [kg/m^D].
    pub density: Vec<f32>,
    /// Pressures [Pa].
    pub pressure: Vec<f32>,
    /// Kinds.
    pub kind: Vec<u32>,
    /// Stable ids.
    pub id: Vec<u32>,
}

impl<const D: usize> FrameSubset<D> {
    /// The subset as a [`Frame`] to write.
    pub fn frame(&self) -> Frame<'_, D> {
        Frame {
            time: self.time,
            position: &self.position,
            velocity: &self.velocity,
            density: &self.density,
            pressure: &self.pressure,
            kind: &self.kind,
            id: &self.id,
        }
    }
}
