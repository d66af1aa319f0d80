//! The `[[open_boundary]]` tables as deserialized, before validation
//! (`scene::validate::open`); the model is `boundary::open`.

use crate::boundary::open::Profile;
use serde::Deserialize;

/// `open_boundary.kind`: which way the fluid crosses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OpenBoundaryKind {
    /// Fluid enters at a prescribed velocity.
    Inflow,
    /// Fluid leaves freely.
    Outflow,
}

impl OpenBoundaryKind {
    /// The name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            OpenBoundaryKind::Inflow => "inflow",
            OpenBoundaryKind::Outflow => "outflow",
        }
    }
}

/// `[[open_boundary]]`: an inflow or outflow plane (`boundary::open`). `min` and `max` \[m\]
/// are the corners of its section, equal along the normal's axis (the plane); `normal` points
/// into the fluid along a coordinate axis; `layers` is the buffer's depth in spacings (default
/// `⌈2 h/dx⌉ + 1`, at least `⌈h/dx⌉`); an inflow needs `velocity` \[m/s\] (the mean over the
/// wetted section, pointing into the fluid) and may set `profile` (`"uniform"`, default, or
/// `"parabolic"`), `level` \[m\] (the free surface's height on the last axis) and `ramp` \[s\]
/// (the velocity's rise time from zero, `(1 − cos(π t/T))/2`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OpenBoundaryFile {
    /// `"inflow"` or `"outflow"`.
    pub kind: OpenBoundaryKind,
    /// Lower corner of the section \[m\], `dimension` entries.
    pub min: Vec<f64>,
    /// Upper corner of the section \[m\], `dimension` entries.
    pub max: Vec<f64>,
    /// Direction into the fluid, along a coordinate axis (any length but zero).
    pub normal: Vec<f64>,
    /// Buffer depth in particle spacings (signed so that bad values reach validation).
    pub layers: Option<i64>,
    /// Inflow: mean velocity over the wetted section \[m/s\].
    pub velocity: Option<Vec<f64>>,
    /// Inflow: the velocity's distribution across the section.
    pub profile: Option<Profile>,
    /// Inflow: height of the free surface \[m\] on the last axis; absent: the whole section.
    pub level: Option<f64>,
    /// Inflow: time \[s\] over which the velocity rises from zero as `(1 − cos(π t/T))/2`, > 0;
    /// absent: none.
    pub ramp: Option<f64>,
}
