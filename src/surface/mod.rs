//! Free-surface reconstruction for visualisation (section 4 of the paper, eq. (25)).
//!
//! The fluid's surface is an isosurface of the colour field of eq. (25),
//! `F(x_g) = sqrt( Σ_j (1 − r_gj/h)² )` over the particles `j` with `r_gj = |x_g − x_j| < h`,
//! sampled on an Eulerian grid of nodes ([`field`]). The grid is sparse: only blocks of nodes
//! within `h` (plus one node) of a particle exist, so the cost grows with the number of
//! particles, never with the empty volume of the domain. The isosurface is extracted by
//! marching cubes in 3D ([`marching_cubes`]) and marching squares in 2D
//! ([`marching_squares`]), welded into one indexed mesh ([`mesh`]) whose vertex normals are
//! `−∇F/|∇F|` (pointing out of the fluid).
//!
//! # Iso level
//! Each particle stands for a cell of volume `dx^D` of the fluid, so the fluid body is the union
//! of those cells and its surface lies half a spacing outside the outer particle centres. Away
//! from the surface, the lattice sum of eq. (25) at a node averages (over the node's position
//! relative to the lattice) to the continuum value
//! `F_int² = (1/dx^D) ∫_{|r|<h} (1 − r/h)² dV` = `π h²/(6 dx²)` in 2D, `2π h³/(15 dx³)` in 3D.
//! On a flat boundary of that union body exactly half of the kernel ball lies inside, so there
//! `F² = F_int²/2`. The iso level is therefore `F_iso = F_int/√2` ([`iso_level`]): it puts a flat
//! surface half a spacing outside the outer particle centres, independent of `h/dx`. On a
//! curved surface of radius `R` the level sits about `h²/(10 R)` inside the union body (less than
//! half the kernel ball is inside there); on a 20-particle sphere with `h = 2 dx` that is
//! 0.04 dx, a volume error near 1 %. Measured in `tests/surface.rs`. The level exceeds the
//! value 1 that F reaches at a lone particle (for h > 1.69 dx in 3D, h > 1.96 dx in 2D), so
//! isolated spray particles are not drawn; clusters of a few particles are.
//!
//! References: [P] the seed paper, eq. (25); [LC87] Lorensen & Cline 1987 (marching cubes);
//! [NH91] Nielson & Hamann 1991 (the asymptotic decider on ambiguous faces).

pub mod field;
pub mod marching_cubes;
pub mod marching_squares;
pub mod mesh;

use crate::math::{Real, Vector};

pub use field::SparseField;
pub use mesh::SurfaceMesh;

/// Errors of the surface reconstruction.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SurfaceError {
    /// A particle position is NaN or infinite.
    #[error("particle {particle} has a non-finite position")]
    NonFinitePosition {
        /// Index of the particle in the input.
        particle: usize,
    },
    /// A length parameter is not a positive finite number.
    #[error("surface parameter `{name}` must be a positive finite length, got {value}")]
    BadParameter {
        /// Parameter name (`spacing`, `smoothing_length`, `cell_size`).
        name: &'static str,
        /// The rejected value [m].
        value: f64,
    },
    /// Positions too far from the origin, in grid cells, for 64-bit node indices.
    #[error(
        "particle {particle} lies {cells:.3e} grid cells from the origin, beyond what node indices can address"
    )]
    OutOfRange {
        /// Index of the particle in the input.
        particle: usize,
        /// Distance from the origin in grid cells.
        cells: f64,
    },
    /// Only 2D (marching squares) and 3D (marching cubes) surfaces exist.
    #[error("surface reconstruction supports 2 or 3 dimensions, not {0}")]
    UnsupportedDimension(usize),
}

/// Parameters of one reconstruction, all lengths in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceParams {
    /// Particle spacing dx of the scene [m]: the lattice the fluid was generated on.
    pub spacing: f64,
    /// Kernel support h of eq. (25) [m].
    pub smoothing_length: f64,
    /// Distance between grid nodes [m]; [`SurfaceParams::new`] takes `dx/2`, which resolves a
    /// sphere of 20 particles across to well under 1 % in volume.
    pub cell_size: f64,
    /// Iso level of F (dimensionless); [`SurfaceParams::new`] takes [`iso_level`].
    pub iso: f64,
}

impl SurfaceParams {
    /// Default parameters for a scene with spacing `spacing` [m] and support `smoothing_length`
    /// [m]: nodes every `spacing/2`, iso level [`iso_level`] (`D` = 2 or 3).
    pub fn new<const D: usize>(spacing: f64, smoothing_length: f64) -> Self {
        SurfaceParams {
            spacing,
            smoothing_length,
            cell_size: 0.5 * spacing,
            iso: iso_level(D, spacing, smoothing_length),
        }
    }

    /// Checks that every length is positive and finite and the iso level positive.
    pub fn validate(&self) -> Result<(), SurfaceError> {
        for (name, value) in [
            ("spacing", self.spacing),
            ("smoothing_length", self.smoothing_length),
            ("cell_size", self.cell_size),
            ("iso", self.iso),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(SurfaceError::BadParameter { name, value });
            }
        }
        Ok(())
    }
}

/// Square of the interior value of eq. (25) on a lattice of spacing `dx` [m] with support `h`
/// [m] (dimensionless): `F_int² = (1/dx^D) ∫_{|r|<h} (1 − r/h)² dV`, the average of the lattice sum
/// over the node's offset: `π h²/(6 dx²)` in 2D, `2π h³/(15 dx³)` in 3D.
pub fn interior_value_squared(dim: usize, dx: f64, h: f64) -> f64 {
    let q = h / dx;
    match dim {
        2 => std::f64::consts::PI * q * q / 6.0,
        _ => 2.0 * std::f64::consts::PI * q * q * q / 15.0,
    }
}

/// Iso level of eq. (25)'s F (dimensionless): `F_int/√2`, the value F takes on a flat boundary of
/// the union of the particles' `dx^D` cells, half a spacing outside the outer centres (see the
/// module documentation for the reasoning).
pub fn iso_level(dim: usize, dx: f64, h: f64) -> f64 {
    (0.5 * interior_value_squared(dim, dx, h)).sqrt()
}

/// Reconstructs the free surface of the particles at `positions` [m]: eq. (25) on a sparse grid,
/// then marching cubes (3D, triangles) or marching squares (2D, segments), welded, with outward
/// unit normals from `−∇F`. Pass only fluid particles. No particles give an empty mesh.
pub fn reconstruct<const D: usize>(
    positions: &[Vector<D>],
    params: &SurfaceParams,
) -> Result<SurfaceMesh<D>, SurfaceError> {
    if D != 2 && D != 3 {
        return Err(SurfaceError::UnsupportedDimension(D));
    }
    params.validate()?;
    let field = SparseField::<D>::build(positions, params.smoothing_length, params.cell_size)?;
    let iso = params.iso as Real;
    let mut mesh = if D == 3 {
        mesh::weld(marching_cubes::extract(&field, iso))
    } else {
        mesh::weld(marching_squares::extract(&field, iso))
    };
    mesh.normals = mesh::vertex_normals(&field, &mesh);
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn surface_iso_level_is_half_the_interior_square() {
        // 2D, h = 2 dx: F_int² = π·4/6; 3D: 2π·8/15.
        assert!((iso_level(2, 0.01, 0.02).powi(2) - std::f64::consts::PI * 4.0 / 12.0).abs() < 1e-12);
        assert!((iso_level(3, 0.01, 0.02).powi(2) - std::f64::consts::PI * 8.0 / 15.0).abs() < 1e-12);
    }

    #[test]
    fn surface_of_no_particles_is_empty_and_bad_parameters_are_named() {
        let params = SurfaceParams::new::<3>(0.01, 0.02);
        assert!(reconstruct::<3>(&[], &params).unwrap().is_empty());
        let bad = SurfaceParams {
            cell_size: 0.0,
            ..params
        };
        assert_eq!(
            reconstruct::<3>(&[Vector::<3>::zeros()], &bad).unwrap_err(),
            SurfaceError::BadParameter {
                name: "cell_size",
                value: 0.0
            }
        );
        let nan = SurfaceParams {
            smoothing_length: f64::NAN,
            ..params
        };
        assert!(matches!(
            reconstruct::<3>(&[], &nan),
            Err(SurfaceError::BadParameter {
                name: "smoothing_length",
                ..
            })
        ));
    }

    #[test]
    fn surface_drops_a_lone_particle_and_closes_around_a_small_cluster() {
        let params = SurfaceParams::new::<3>(0.01, 0.02);
        // F ≤ 1 around a lone particle, below F_iso ≈ 1.29 for h = 2 dx: spray is not drawn.
        assert!(
            reconstruct(&[Vector::<3>::new(0.3, -0.2, 0.1)], &params)
                .unwrap()
                .is_empty()
        );
        let centre = Vector::<3>::new(0.3, -0.2, 0.1);
        let cluster: Vec<Vector<3>> = (0..27)
            .map(|i| {
                centre
                    + Vector::<3>::new(
                        (i % 3) as Real - 1.0,
                        ((i / 3) % 3) as Real - 1.0,
                        (i / 9) as Real - 1.0,
                    ) * 0.01
            })
            .collect();
        let mesh = reconstruct(&cluster, &params).unwrap();
        assert!(!mesh.is_empty());
        assert_eq!(mesh.open_facets(), 0);
        assert!(mesh.enclosed_measure() > 0.0);
        for (x, n) in mesh.positions.iter().zip(&mesh.normals) {
            assert!((x - centre).dot(n) > 0.0, "normal {n:?} at {x:?}");
        }
    }
}
