//! A validated floating solid (`[[solid]] floating`, `scene::schema::FloatingFile`) and its
//! rigid body: mass properties from the solid's shape, overridden where the scene says.

use crate::boundary::contact::WallContact;
use crate::boundary::rigid_body::{Freedom, MassProperties, Mooring, RigidBody};
use crate::geometry::Volume;
use nalgebra::{Matrix3, Vector3};

/// Cells per particle spacing, per axis, of the lattice that samples a floating solid's shape
/// for its mass properties (`MassProperties::of_cells`): a box whose sides are whole spacings
/// is then sampled exactly.
pub const MASS_CELLS_PER_SPACING: f64 = 4.0;

/// How much of the body there is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BodyAmount {
    /// Uniform density [kg/m³].
    Density(f64),
    /// Total mass [kg] (2D: [kg/m]), spread uniformly over the shape.
    Mass(f64),
}

/// A floating solid as the scene gives it (`scene::schema::FloatingFile`), validated.
#[derive(Clone, Debug, PartialEq)]
pub struct Floating {
    /// Density or mass.
    pub amount: BodyAmount,
    /// Centre of mass [m] (3 entries, z = 0 in 2D), if given.
    pub centre_of_mass: Option<Vector3<f64>>,
    /// Principal moments about x, y, z [kg m²] (2D: only z is used), if given.
    pub inertia: Option<Vector3<f64>>,
    /// What the body may do.
    pub freedom: Freedom,
    /// Mooring lines (3-vectors, z = 0 in 2D).
    pub moorings: Vec<Mooring>,
    /// How it meets the fixed solids.
    pub contact: WallContact,
}

impl Floating {
    /// The shape `volume`, bounded by `min`..`max` [m], at unit density, sampled on a lattice
    /// of `spacing / MASS_CELLS_PER_SPACING` ([`MassProperties::of_cells`]) in dimension `dim`:
    /// its `mass` is the shape's volume [m³] (2D: area [m²]). `None` when the lattice finds no
    /// point inside.
    pub fn shape_properties(
        volume: &Volume,
        min: &[f64],
        max: &[f64],
        spacing: f64,
        dim: usize,
    ) -> Option<MassProperties> {
        let s = spacing / MASS_CELLS_PER_SPACING;
        let n: Vec<i64> = (0..dim)
            .map(|k| ((max[k] - min[k]) / s).ceil().max(1.0) as i64)
            .collect();
        let mut points = Vec::new();
        let mut visit = |idx: &[i64]| {
            points.push(Vector3::from_fn(|k, _| {
                if k < dim {
                    min[k] + (idx[k] as f64 + 0.5) * s
                } else {
                    0.0
                }
            }));
        };
        match dim {
            2 => volume.lattice_inside::<2>([min[0], min[1]], [n[0], n[1]], s, |i| visit(i)),
            _ => volume.lattice_inside::<3>([min[0], min[1], min[2]], [n[0], n[1], n[2]], s, |i| visit(i)),
        }
        let cell = s.powi(dim as i32);
        MassProperties::of_cells(&points, cell, 1.0, dim)
    }

    /// The body's mean density [kg/m³] on a shape of `volume` [m³] (2D: m²).
    pub fn mean_density(&self, volume: f64) -> f64 {
        match self.amount {
            BodyAmount::Density(rho) => rho,
            BodyAmount::Mass(m) => m / volume,
        }
    }

    /// The rigid body of this floating solid of shape `volume`, bounded by `min`..`max` [m], in a
    /// scene of particle spacing `spacing` [m] and dimension `dim`: the shape's properties
    /// ([`Floating::shape_properties`]) at the body's density, then the scene's overrides.
    /// Gravity is zero here: the run sets it at each stage. `None` when the lattice finds no
    /// point inside.
    pub fn rigid_body(
        &self,
        volume: &Volume,
        min: &[f64],
        max: &[f64],
        spacing: f64,
        dim: usize,
    ) -> Option<RigidBody> {
        Some(self.rigid_body_of(&Self::shape_properties(volume, min, max, spacing, dim)?))
    }

    /// The rigid body of this floating solid on its shape's unit-density properties `sampled`
    /// ([`Floating::shape_properties`]).
    pub fn rigid_body_of(&self, sampled: &MassProperties) -> RigidBody {
        let density = self.mean_density(sampled.mass);
        let mut mass = MassProperties {
            mass: sampled.mass * density,
            centre: sampled.centre,
            inertia: sampled.inertia * density,
        };
        if let Some(c) = self.centre_of_mass {
            mass.centre = c;
        }
        if let Some(i) = self.inertia {
            mass.inertia = Matrix3::from_diagonal(&i);
        }
        RigidBody {
            mass,
            freedom: self.freedom.clone(),
            moorings: self.moorings.clone(),
            gravity: Vector3::zeros(),
            contact: self.contact,
        }
    }
}

/// The rigid body of each floating solid (`scene::floating`), `None` for the others, in scene
/// order.
pub fn rigid_bodies(scene: &crate::scene::Scene) -> Vec<Option<RigidBody>> {
    scene
        .solids
        .iter()
        .map(|s| {
            let f = s.floating.as_ref()?;
            f.rigid_body(
                &s.volume,
                &s.region.min,
                &s.region.max,
                scene.spacing,
                scene.dimension,
            )
        })
        .collect()
}
