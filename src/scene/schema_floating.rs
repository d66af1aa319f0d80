//! The scene file's keys of a floating solid (`[[solid]] floating`), as deserialized, before
//! validation (`scene::validate::floating`).

use serde::Deserialize;

/// `[[solid]] floating = { density = ρ_b }` (or `mass = M`): a rigid body that the fluid's
/// forces and moments move (`solver::floating`), with gravity. Optional keys:
/// `centre_of_mass = [..]` \[m\] and `inertia` \[kg m²\] (2D: `I_zz` per metre of depth \[kg m\],
/// a number; 3D: the principal moments about x, y, z, 3 entries) override the values from the
/// solid's shape at uniform density; `fixed = ["x", "rz", ..]` holds degrees of freedom
/// (`x`, `y`, `z` translation, `rx`, `ry`, `rz` rotation; 2D has `x`, `y`, `rz`) or
/// `hinge = { point = [..], axis = [..] }` lets it turn about a fixed axis only (2D: about z
/// through `point`, no `axis`); `moorings = [{ anchor, fairlead, stiffness, rest_length }]`,
/// taut-only linear springs (`boundary::rigid_body::Mooring`); `contact`, how it meets the
/// fixed solids ([`ContactFile`]).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FloatingFile {
    /// Uniform density \[kg/m³\], > 0; or `mass`.
    pub density: Option<f64>,
    /// Mass \[kg\] (2D: per metre of depth \[kg/m\]), > 0; or `density`.
    pub mass: Option<f64>,
    /// Centre of mass \[m\], `dimension` entries; default the shape's centroid.
    pub centre_of_mass: Option<Vec<f64>>,
    /// Inertia about the centre of mass: 2D one number \[kg m\], 3D three principal moments
    /// \[kg m²\]; default from the shape.
    pub inertia: Option<super::NumberOrVector>,
    /// Held degrees of freedom (`x`, `y`, `z`, `rx`, `ry`, `rz`); default none.
    pub fixed: Option<Vec<String>>,
    /// Turn about a fixed axis only.
    pub hinge: Option<HingeFile>,
    /// Mooring lines.
    pub moorings: Option<Vec<MooringFile>>,
    /// Contact with the fixed solids; default the spring–dashpot with its default parameters.
    pub contact: Option<ContactFile>,
}

/// `contact = { kind = "spring_dashpot", restitution = e, friction = μ }` or
/// `{ kind = "none" }` (`boundary::contact`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactFile {
    /// `"spring_dashpot"` (default) or `"none"`.
    pub kind: Option<String>,
    /// Restitution coefficient in (0, 1]; default 0.5.
    pub restitution: Option<f64>,
    /// Coulomb friction coefficient ≥ 0; default 0.5.
    pub friction: Option<f64>,
}

/// `hinge = { point = [..], axis = [..] }`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HingeFile {
    /// A point on the axis \[m\], `dimension` entries.
    pub point: Vec<f64>,
    /// 3D: the axis direction (3 entries, not zero); 2D: absent (z).
    pub axis: Option<Vec<f64>>,
}

/// One mooring line: `{ anchor = [..], fairlead = [..], stiffness = k, rest_length = L0 }`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MooringFile {
    /// The fixed anchor \[m\].
    pub anchor: Vec<f64>,
    /// The line's point on the body at `t = 0` \[m\].
    pub fairlead: Vec<f64>,
    /// Stiffness \[N/m\] (2D: per metre of depth), >= 0.
    pub stiffness: f64,
    /// Rest length \[m\], >= 0.
    pub rest_length: f64,
}
