//! `[periodic]`: periodic boundaries (`crate::periodic`).

use serde::Deserialize;

/// `[periodic]`: the domain is one period along the listed axes; a particle leaving one face
/// enters at the other, and particles near a face see those near the opposite face.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PeriodicFile {
    /// The periodic axes, `"x"`, `"y"` or `"z"`: each at most once, within `dimension`. The
    /// period is the domain's extent along the axis, a whole number of particle spacings and at
    /// least 3 smoothing lengths.
    pub axes: Vec<AxisName>,
}

/// A coordinate axis named in a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AxisName {
    /// Axis 0.
    X,
    /// Axis 1.
    Y,
    /// Axis 2 (3D only).
    Z,
}

impl AxisName {
    /// The axis index.
    pub fn index(self) -> usize {
        match self {
            AxisName::X => 0,
            AxisName::Y => 1,
            AxisName::Z => 2,
        }
    }
}
