//! Smoothing kernels of Müller et al. (2003), eqs. (20)–(22) of the paper, in 2D and 3D.
//!
//! All kernels have compact support of radius `h` (PAPER.md note 1: the kernel formulas use
//! support `h`, so the neighbour grid's cell size equals `h`).
//!
//! Normalisations (PAPER.md note 3; each is proved by the quadrature tests in `tests/numerics/laws.rs`):
//!
//! | kernel | 3D | 2D |
//! |---|---|---|
//! | poly6 (20) `K (h²−r²)³` | `315/(64π h⁹)` | `4/(π h⁸)` |
//! | spiky (21) `K (h−r)³` | `15/(π h⁶)` | `10/(π h⁵)` |
//! | viscosity (22) `K (−r³/2h³ + r²/h² + h/2r − 1)` | `15/(2π h³)` | `10/(3π h²)` |
//! | viscosity Laplacian `L (h−r)` | `45/(π h⁶)` | `40/(π h⁵)` |
//!
//! The 2D constants come from `∫ W dA = 1` over the disc of radius `h`. The viscosity kernel's
//! Laplacian is not the Laplacian of its 2D form (that one is singular at 0); instead, as in 3D,
//! we use `L (h − r)` with `L` fixed by the second-moment condition `∫ r² ∇²W dV = 2d`, which is
//! what makes (17) a consistent approximation of `μ∇²u`. In 3D that condition gives Müller's
//! `45/(π h⁶)` exactly; in 2D it gives `40/(π h⁵)`.
//!
//! Deviation (PAPER.md note 2): (22) is used with Müller's sign, `−r³/(2h³)`.
//! Deviation (PAPER.md note 4): the spiky gradient's magnitude, the singular viscosity kernel, its
//! gradient and the spiky Laplacian evaluate `r` no smaller than [`R_MIN_FRACTION`]`·h`, so
//! coincident particles never produce NaN or infinity; at `r = 0` the spiky gradient has no
//! direction and returns zero. The pair loops never pass it a coincident pair: [`pair_offset`]
//! gives a pair closer than [`COINCIDENT_FRACTION`]`·h` a fixed antisymmetric direction, so two
//! particles started at the same spot (or driven onto it) push each other apart.
//!
//! References: [P] seed paper, eqs. (14), (20)–(22); [M03] M. Müller, D. Charypar, M. Gross,
//! "Particle-based fluid simulation for interactive applications", SCA 2003.

use crate::math::{Real, Vector};
use std::f64::consts::PI;

/// Smallest distance, as a fraction of `h`, at which the singular kernels are evaluated (note 4).
pub const R_MIN_FRACTION: Real = 1.0e-3;

/// Pairs closer than this fraction of `h` count as coincident and get [`pair_offset`]'s
/// direction. Far below any distance the flow produces (1e-3 of `dx` at `h = 2dx` would already
/// mean a particle on top of another), far above f32 underflow of `r²`.
pub const COINCIDENT_FRACTION: Real = 1.0e-6;

/// The offset `x_i − x_j` [m] and its squared length [m²] that a pair loop uses for particles
/// of ids `id_i ≠ id_j` (`Fields::id`) at `d = x_i − x_j`, `r2 = |d|²`: `(d, r2)` itself, or,
/// when `r2 < (ε h)²` with `ε =` [`COINCIDENT_FRACTION`], the offset of length `ε h` along axis
/// `(id_i + id_j) mod D` with the sign of `id_i − id_j`. A particle with itself (`id_i = id_j`)
/// is left alone.
///
/// Why: coincident particles have no direction, so the spiky gradient gives them no pressure
/// force, and two particles at the same spot feel the same forces from everyone else: they would
/// never separate and the corrected solver could not bring their density to `ρ0`. The rule is
/// antisymmetric under `i ↔ j` (same axis, opposite sign), so every pair force stays
/// antisymmetric and momentum is conserved. From ids, not indices, so a pair takes the same
/// direction in any particle order: on both backends (the CUDA kernels use its twin
/// `pair_offset`, `kernels/sph.cuh`) and on any number of ranks (a ghost carries its owner's id).
#[inline(always)]
pub fn pair_offset<const D: usize>(
    d: Vector<D>,
    r2: Real,
    id_i: u32,
    id_j: u32,
    h: Real,
) -> (Vector<D>, Real) {
    let e = COINCIDENT_FRACTION * h;
    if id_i == id_j || r2 >= e * e {
        return (d, r2);
    }
    let mut offset = Vector::<D>::zeros();
    offset[((u64::from(id_i) + u64::from(id_j)) % D as u64) as usize] = if id_i > id_j { e } else { -e };
    (offset, e * e)
}

/// The three kernels of the paper for one support radius `h` and dimension `D`, with their
/// normalisation constants precomputed. Construct with [`Smoothing::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Smoothing<const D: usize> {
    /// Support radius `h` [m].
    pub h: Real,
    /// `h²` [m²].
    pub h2: Real,
    poly6: Real,
    spiky: Real,
    visc: Real,
    visc_laplacian: Real,
}

/// The dimension is not 2 or 3.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("unsupported dimension {0}: only 2 and 3 are supported")]
pub struct UnsupportedDimension(pub usize);

impl<const D: usize> Smoothing<D> {
    /// Whether every normalisation constant is a normal f32 number (neither overflowed to
    /// infinity nor flushed towards 0). False for a support radius far from 1 m, whose
    /// `h^-(D+6)` leaves f32's range: below about 5e-5 m or above about 1e4 m in 3D. Scene
    /// validation refuses such a radius (`scene::magnitude`).
    pub fn constants_are_normal(&self) -> bool {
        [self.poly6, self.spiky, self.visc, self.visc_laplacian]
            .iter()
            .all(|c| c.is_normal())
    }

    /// Kernels with support radius `h` [m] in dimension `D` (2 or 3).
    pub fn new(h: Real) -> Result<Self, UnsupportedDimension> {
        let hd = f64::from(h);
        let (poly6, spiky, visc, visc_laplacian) = match D {
            2 => (
                4.0 / (PI * hd.powi(8)),
                10.0 / (PI * hd.powi(5)),
                10.0 / (3.0 * PI * hd.powi(2)),
                40.0 / (PI * hd.powi(5)),
            ),
            3 => (
                315.0 / (64.0 * PI * hd.powi(9)),
                15.0 / (PI * hd.powi(6)),
                15.0 / (2.0 * PI * hd.powi(3)),
                45.0 / (PI * hd.powi(6)),
            ),
            d => return Err(UnsupportedDimension(d)),
        };
        Ok(Self {
            h,
            h2: h * h,
            poly6: poly6 as Real,
            spiky: spiky as Real,
            visc: visc as Real,
            visc_laplacian: visc_laplacian as Real,
        })
    }

    /// Eq. (20): poly6 kernel `W = K (h² − r²)³` for `r ≤ h`, else 0; argument `r²` [m²],
    /// result [1/m^D]. Used for density (18).
    #[inline(always)]
    pub fn w(&self, r2: Real) -> Real {
        if r2 >= self.h2 {
            return 0.0;
        }
        let q = self.h2 - r2;
        self.poly6 * q * q * q
    }

    /// Gradient of eq. (20): `∇W = −6K (h² − r²)² x`, `x = x_i − x_j` [m]; result [1/m^(D+1)].
    #[inline(always)]
    pub fn grad_w(&self, x: &Vector<D>) -> Vector<D> {
        let r2 = x.norm_squared();
        if r2 >= self.h2 {
            return Vector::zeros();
        }
        let q = self.h2 - r2;
        x * (-6.0 * self.poly6 * q * q)
    }

    /// Laplacian of eq. (20): `∇²W = K (h² − r²)(24 r² − 6d (h² − r²))`; argument `r²` [m²].
    #[inline(always)]
    pub fn laplacian_w(&self, r2: Real) -> Real {
        if r2 >= self.h2 {
            return 0.0;
        }
        let q = self.h2 - r2;
        self.poly6 * q * (24.0 * r2 - 6.0 * D as Real * q)
    }

    /// Eq. (21): spiky kernel `W = K (h − r)³` for `r ≤ h`, else 0; argument `r` [m].
    #[inline(always)]
    pub fn w_spiky(&self, r: Real) -> Real {
        if r >= self.h {
            return 0.0;
        }
        let q = self.h - r;
        self.spiky * q * q * q
    }

    /// Gradient of eq. (21), used by the pressure force (16): `∇W = −3K (h − r)² x/r`,
    /// `x = x_i − x_j` [m], `r = |x|`; the magnitude is taken at `r` no smaller than
    /// `R_MIN_FRACTION·h` (note 4: closer pairs keep the near-peak repulsion along `x/r` instead
    /// of losing it), zero at `r = 0` (no direction) and outside the support.
    #[inline(always)]
    pub fn grad_w_spiky(&self, x: &Vector<D>, r: Real) -> Vector<D> {
        if r >= self.h || r <= 0.0 {
            return Vector::zeros();
        }
        let q = self.h - r.max(R_MIN_FRACTION * self.h);
        x * (-3.0 * self.spiky * q * q / r)
    }

    /// Laplacian of eq. (21): `K (6 (h − r) − 3(d − 1)(h − r)²/r)`, with `r ≥ R_MIN_FRACTION·h`.
    /// Not used by the solver (the spiky kernel only enters through its gradient).
    #[inline(always)]
    pub fn laplacian_w_spiky(&self, r: Real) -> Real {
        if r >= self.h {
            return 0.0;
        }
        let r = r.max(R_MIN_FRACTION * self.h);
        let q = self.h - r;
        self.spiky * (6.0 * q - 3.0 * (D as Real - 1.0) * q * q / r)
    }

    /// Eq. (22), Müller's sign (note 2): `W = K (−r³/(2h³) + r²/h² + h/(2r) − 1)`, `r ≥ R_MIN·h`.
    #[inline(always)]
    pub fn w_viscosity(&self, r: Real) -> Real {
        if r >= self.h {
            return 0.0;
        }
        let r = r.max(R_MIN_FRACTION * self.h);
        let (h, q) = (self.h, r / self.h);
        self.visc * (-0.5 * q * q * q + q * q + 0.5 * h / r - 1.0)
    }

    /// Gradient of eq. (22): `K (−3r/(2h³) + 2/h² − h/(2r³)) x`, `r ≥ R_MIN·h`.
    #[inline(always)]
    pub fn grad_w_viscosity(&self, x: &Vector<D>, r: Real) -> Vector<D> {
        if r >= self.h {
            return Vector::zeros();
        }
        let r = r.max(R_MIN_FRACTION * self.h);
        let h = self.h;
        x * (self.visc * (-1.5 * r / (h * h * h) + 2.0 / (h * h) - 0.5 * h / (r * r * r)))
    }

    /// Laplacian of the viscosity kernel, the only part of (22) that enters (17):
    /// `∇²W = L (h − r)` for `r ≤ h`; argument `r` [m], result [1/m^(D+2)].
    #[inline(always)]
    pub fn laplacian_w_viscosity(&self, r: Real) -> Real {
        if r >= self.h {
            return 0.0;
        }
        self.visc_laplacian * (self.h - r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_two_and_three_dimensions_are_supported() {
        assert!(Smoothing::<2>::new(0.1).is_ok());
        assert!(Smoothing::<3>::new(0.1).is_ok());
        assert_eq!(Smoothing::<4>::new(0.1), Err(UnsupportedDimension(4)));
    }

    #[test]
    fn coincident_particles_give_finite_values() {
        let k = Smoothing::<3>::new(0.02).expect("3D");
        let z = Vector::<3>::zeros();
        assert!(k.w(0.0).is_finite());
        assert_eq!(k.grad_w_spiky(&z, 0.0), z);
        assert!(k.w_viscosity(0.0).is_finite());
        assert!(k.grad_w_viscosity(&z, 0.0).iter().all(|c| c.is_finite()));
        assert!(k.laplacian_w_spiky(0.0).is_finite());
        assert!(k.laplacian_w_viscosity(0.0).is_finite());
    }

    #[test]
    fn coincident_pairs_get_an_antisymmetric_direction() {
        let h = 0.02;
        let k = Smoothing::<3>::new(h).expect("3D");
        let z = Vector::<3>::zeros();
        let (d_ij, r2) = pair_offset(z, 0.0, 7, 4, h);
        let (d_ji, _) = pair_offset(z, 0.0, 4, 7, h);
        assert_eq!(d_ij, -d_ji);
        assert_eq!(d_ij, Vector::<3>::new(0.0, 0.0, COINCIDENT_FRACTION * h));
        let g = k.grad_w_spiky(&d_ij, r2.sqrt());
        // The repulsion of a pair at R_MIN_FRACTION·h, pushing i (the larger index) along +z.
        let peak = 3.0 * k.spiky * (h - R_MIN_FRACTION * h).powi(2);
        assert!((g[2] + peak).abs() <= 1e-5 * peak, "{g:?} vs {peak}");
        // A particle with itself and a pair further apart are left alone.
        assert_eq!(pair_offset(z, 0.0, 3, 3, h), (z, 0.0));
        let d = Vector::<3>::new(1e-6, 0.0, 0.0);
        assert_eq!(pair_offset(d, 1e-12, 1, 2, h), (d, 1e-12));
    }
}
