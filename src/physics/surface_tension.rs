//! Surface tension by cohesion and curvature forces, [AAT13] Akinci, Akinci & Teschner,
//! "Versatile surface tension and adhesion for SPH fluids", ACM TOG 32(6) 182 (2013), the model
//! `fluid.surface_tension_model = "akinci"` (the default is `physics::surface_stress`: this
//! model's bulk pressure jams small drops, tests/physics/surface_tension.rs):
//!
//! - eq. (1)–(2) cohesion `F_coh = −γ m_i m_j C(|x_ij|) x_ij/|x_ij|` with their spline `C`;
//! - eq. (3) normals `n_i = h Σ_j (m_j/ρ_j) ∇W(x_ij)` (poly6 gradient (20), the density kernel);
//! - eq. (4) curvature `F_curv = −γ m_i (n_i − n_j)`;
//! - eq. (5) `F_ij = K_ij (F_coh + F_curv)` with `K_ij = 2ρ0/(ρ_i + ρ_j)`.
//!
//! Fluid neighbours only: adhesion to solids ([AAT13] eqs. 6–7) is not implemented, so a solid
//! neither attracts nor wets the fluid.
//!
//! **Direction of `n`.** `∇W(x_ij)` is the gradient with respect to `x_i`, as in the published
//! implementations (SPlisHSPlasH `SurfaceTension_Akinci2013`, TrixiParticles): it points from `i`
//! towards `j`, so at a free surface `n` points *into* the fluid (the gradient of the colour
//! field). With this sign the curvature term adds a positive amount to the mechanical surface
//! tension of a flat interface ([`surface_tension_per_gamma`]); the opposite sign would subtract.
//!
//! **`γ` is not `σ`.** `γ` multiplies two terms of different units (`F_coh/γ` [kg² m^−D] and
//! `F_curv/γ` [kg]), so its value means nothing until the model's surface tension is measured.
//! [`surface_tension_per_gamma`] measures it: the mechanical surface tension (Kirkwood–Buff /
//! Irving–Kirkwood, `σ = ∫ (p_N − p_T) dz`) of a flat slab of the initial lattice, free surfaces
//! included, so `ρ_i`, `n_i` and `K_ij` are the discrete ones the solver will see, as
//! `physics::lattice` calibrates `κ` and the mass. The scene gives `σ` [N/m] and the solver uses
//! `γ = σ / (σ per unit γ)` ([`gamma_for_surface_tension`]).
//!
//! **2D normalisation of `C`.** The published 3D constant `32/(π h⁹)` does not make `C`
//! integrate to one: `∫ C dV = 79/336` (4π ∫₀ʰ c(r) r² dr with `c` the bracket of eq. 2, whose
//! integral is `79 h⁹/43008`). The 2D constant keeps that integral: `2π K₂ ∫₀ʰ c(r) r dr =
//! 2π K₂ · 209 h⁸/71680 = 79/336`, so `K₂ = 25280/(627 π h⁸)`. The choice only sets the ratio of
//! the cohesion and curvature terms; `σ` is calibrated either way.
//!
//! References: [AAT13] as above; [KB49] Kirkwood & Buff, J. Chem. Phys. 17, 338 (1949), the
//! mechanical surface tension of a flat interface.

use crate::math::{Real, Vector};
use crate::smoothing::Smoothing;

/// `∫ C dV` over the support, the same in 2D and 3D (module doc): 79/336.
pub const COHESION_INTEGRAL: f64 = 79.0 / 336.0;

/// Normalisation `K` of [AAT13] eq. (2) times `h^(D+6)`: `32/π` in 3D (published) and
/// `25280/(627 π)` in 2D (module doc).
pub fn cohesion_normalisation(dim: usize) -> f64 {
    if dim == 2 {
        25280.0 / (627.0 * std::f64::consts::PI)
    } else {
        32.0 / std::f64::consts::PI
    }
}

/// [AAT13] eq. (2): the cohesion spline `C(r)` [1/m^D] for support `h` [m]:
/// `K (h − r)³ r³` for `h/2 < r ≤ h`, `K (2 (h − r)³ r³ − h⁶/64)` for `0 < r ≤ h/2` (negative:
/// repulsive at short range), else 0, with `K` = [`cohesion_normalisation`]`/h^(D+6)`.
#[inline(always)]
pub fn cohesion_kernel<const D: usize>(r: Real, h: Real) -> Real {
    if r > h || r <= 0.0 {
        return 0.0;
    }
    let k = (cohesion_normalisation(D) / f64::from(h).powi(D as i32 + 6)) as Real;
    let s = (h - r) * (h - r) * (h - r) * r * r * r;
    if 2.0 * r > h {
        k * s
    } else {
        let h3 = h * h * h;
        k * (2.0 * s - h3 * h3 / 64.0)
    }
}

/// [AAT13] eq. (3), one neighbour's share of the normal: `(m_j/ρ_j) ∇W(x_ij)` [1/m] (poly6
/// gradient (20)); the normal is `h` times the sum over fluid neighbours (dimensionless).
#[inline(always)]
pub fn normal_term<const D: usize>(
    kernel: &Smoothing<D>,
    m_j: Real,
    rho_j: Real,
    d: &Vector<D>,
) -> Vector<D> {
    kernel.grad_w(d) * (m_j / rho_j)
}

/// [AAT13] eqs. (1)–(5) as the acceleration [m/s²] of fluid particle `i` from fluid neighbour
/// `j` at offset `d = x_i − x_j` [m], `|d| = r > 0`: `F_ij/m_i = −γ K_ij (m_j C(r) d/r +
/// n_i − n_j)` with `K_ij = 2ρ0/(ρ_i + ρ_j)`. `gamma` is [AAT13]'s `γ` in the units that make
/// each term a force (module doc); masses [kg], densities [kg/m³], normals dimensionless.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn surface_tension_acceleration<const D: usize>(
    gamma: Real,
    rho0: Real,
    h: Real,
    m_j: Real,
    rho_i: Real,
    rho_j: Real,
    n_i: &Vector<D>,
    n_j: &Vector<D>,
    d: &Vector<D>,
    r: Real,
) -> Vector<D> {
    let k_ij = 2.0 * rho0 / (rho_i + rho_j);
    let cohesion = d * (m_j * cohesion_kernel::<D>(r, h) / r);
    (cohesion + (n_i - n_j)) * (-gamma * k_ij)
}

/// The mechanical surface tension [N/m] (2D: [N], per unit depth as every 2D force) of the model
/// with `γ = 1`, measured on a flat slab of the initial lattice (spacing `dx` [m], kernel
/// `kernel`, rest density `rho0` [kg/m³], every particle of mass `mass` [kg]).
///
/// [KB49]: for pair forces `F_ij` (on `i` from `j`, here antisymmetric for equal masses),
/// `∫ (p_N − p_T) dz = (1/A) Σ_pairs (z_ij F_ij,z − x_ij F_ij,x)` over a slab of cross-section
/// `A`; the slab has two interfaces, so `σ` is half of it. The slab is periodic along the face
/// (`x`, and `y` in 3D) and `4 ceil(h/dx) + 2` layers thick, so its middle is bulk; the density
/// of each layer and its normal are summed over the lattice, and `K_ij` follows, so the surface
/// layers' missing neighbours count as they will in a run. Summed in f64.
///
/// Not included: the pressure (16) and viscous forces (the pressure of the relaxed interface is
/// not known before a run), and the relaxation of the surface layers (tests/physics/surface_tension.rs
/// measures what that leaves: the drops' jump is 0.58–1.26 σ/R).
///
/// Caveat: the curvature term has no kernel weight, so it jumps at `r = h`; a lattice offset at
/// exactly `h` counts when `r < h` holds in the arithmetic used. At `h = 2 dx` with `h` an f32
/// (0.002 f32 is 2 dx (1 + 5e-8) for dx = 1 mm), the `2 dx` offsets count and the curvature part
/// is 0.0051 instead of 0.0034 of the 0.0367 per unit γ (2D, dx = 1 mm, ρ0 = 1000).
pub fn surface_tension_per_gamma<const D: usize>(
    kernel: &Smoothing<D>,
    dx: f64,
    rho0: f64,
    mass: f64,
) -> f64 {
    let h = f64::from(kernel.h);
    let FlatSlab {
        n,
        layers,
        tangential,
        density,
        normal,
        ..
    } = flat_slab(kernel, dx, mass, rho0);
    let neighbours = |l: i64| (l - n).max(0)..=(l + n).min(layers - 1);
    let c = |r: f64| f64::from(cohesion_kernel::<D>(r as Real, kernel.h));
    let mut sum = 0.0;
    for l in 0..layers {
        for lj in neighbours(l) {
            let z = (l - lj) as f64 * dx;
            let k_ij = 2.0 * rho0 / (density[l as usize] + density[lj as usize]);
            for &(x, t2) in &tangential {
                let r = (z * z + t2).sqrt();
                if r <= 0.0 || r >= h {
                    continue;
                }
                // Force on i per unit γ: −K_ij (m² C(r) x_ij/r + m (n_i − n_j)), normals along z.
                let coh = mass * mass * c(r) / r;
                let fz = -k_ij * (coh * z + mass * (normal[l as usize] - normal[lj as usize]));
                let fx = -k_ij * coh * x;
                // Each pair is visited from both ends: half each.
                sum += 0.5 * (z * fz - x * fx);
            }
        }
    }
    // Per column of cross-section dx^(D−1), two interfaces.
    sum / dx.powi(D as i32 - 1) / 2.0
}

/// A flat slab of the initial lattice, periodic along its faces, `4 ceil(h/dx) + 2` layers
/// thick so that its middle is bulk: per layer the density (18) and the `z` component of the
/// [AAT13] normal (3) (`h Σ (m/ρ_j) ∇W`, positive into the fluid at the lower face), summed in
/// f64 over the lattice offsets within `h` (`tangential`: each offset along the face with the
/// first component and the squared length). Shared by the calibrations of both surface-tension
/// models ([`surface_tension_per_gamma`],
/// `physics::continuum_surface_force::surface_delta_per_area`).
pub(crate) struct FlatSlab {
    /// `ceil(h/dx)`: layers within reach of a layer on each side.
    pub n: i64,
    /// Number of layers.
    pub layers: i64,
    /// Offsets along the face: `(first component, squared length)` [m, m²].
    pub tangential: Vec<(f64, f64)>,
    /// Density (18) of each layer [kg/m³].
    pub density: Vec<f64>,
    /// `z` component of the normal (3) of each layer (dimensionless).
    pub normal: Vec<f64>,
    /// The same with the rest volume `m/ρ0` for every neighbour, `h ∇(ρ/ρ0)`: the continuum
    /// surface force's normal (`physics::continuum_surface_force`).
    pub rest_normal: Vec<f64>,
}

/// The [`FlatSlab`] of spacing `dx` [m] for `kernel`, every particle of mass `mass` [kg] and rest
/// density `rho0` [kg/m³].
pub(crate) fn flat_slab<const D: usize>(kernel: &Smoothing<D>, dx: f64, mass: f64, rho0: f64) -> FlatSlab {
    let h = f64::from(kernel.h);
    let n = (h / dx).ceil() as i64;
    let layers = 4 * n + 2;
    // Offsets along the face: (2n + 1)^(D − 1) of them, `t` = the first tangential component.
    let tangential: Vec<(f64, f64)> = {
        let mut v = Vec::new();
        for a in -n..=n {
            if D == 2 {
                v.push((a as f64 * dx, (a as f64 * dx).powi(2)));
            } else {
                for b in -n..=n {
                    v.push((a as f64 * dx, ((a * a + b * b) as f64) * dx * dx));
                }
            }
        }
        v
    };
    let neighbours = |l: i64| (l - n).max(0)..=(l + n).min(layers - 1);
    // Density (18) and the normal's z component (3) per layer.
    let w = |r2: f64| f64::from(kernel.w(r2 as Real));
    let grad_poly6 = |r2: f64| {
        // ∇W = −6 K (h² − r²)² x; the factor of x.
        if r2 >= h * h {
            0.0
        } else {
            -6.0 * w(0.0) / h.powi(6) * (h * h - r2).powi(2)
        }
    };
    let density: Vec<f64> = (0..layers)
        .map(|l| {
            neighbours(l)
                .flat_map(|lj| {
                    let z = (l - lj) as f64 * dx;
                    tangential.iter().map(move |&(_, t2)| z * z + t2)
                })
                .map(|r2| mass * w(r2))
                .sum()
        })
        .collect();
    let normal_with = |volume: &dyn Fn(usize) -> f64| -> Vec<f64> {
        (0..layers)
            .map(|l| {
                let mut s = 0.0;
                for lj in neighbours(l) {
                    let z = (l - lj) as f64 * dx;
                    for &(_, t2) in &tangential {
                        s += volume(lj as usize) * grad_poly6(z * z + t2) * z;
                    }
                }
                h * s
            })
            .collect()
    };
    let normal = normal_with(&|lj| mass / density[lj]);
    let rest_normal = normal_with(&|_| mass / rho0);
    FlatSlab {
        n,
        layers,
        tangential,
        density,
        normal,
        rest_normal,
    }
}

/// `γ` [AAT13] that gives the surface tension `sigma` [N/m] (2D: [N]) on the lattice of
/// spacing `dx` [m]: `σ / σ(γ = 1)` ([`surface_tension_per_gamma`]).
pub fn gamma_for_surface_tension<const D: usize>(
    kernel: &Smoothing<D>,
    dx: f64,
    rho0: f64,
    mass: f64,
    sigma: f64,
) -> f64 {
    sigma / surface_tension_per_gamma(kernel, dx, rho0, mass)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::lattice::lattice_mass;
    use nalgebra::{Vector2, Vector3};

    /// Midpoint quadrature of `∫ C dV` over the support, f64.
    fn cohesion_integral<const D: usize>(h: Real) -> f64 {
        let steps = 200_000;
        let dr = f64::from(h) / steps as f64;
        (0..steps)
            .map(|k| {
                let r = (k as f64 + 0.5) * dr;
                let shell = if D == 2 {
                    2.0 * std::f64::consts::PI * r
                } else {
                    4.0 * std::f64::consts::PI * r * r
                };
                f64::from(cohesion_kernel::<D>(r as Real, h)) * shell * dr
            })
            .sum()
    }

    #[test]
    fn cohesion_kernel_integrates_to_79_over_336_in_2d_and_3d() {
        for h in [0.02, 0.5, 1.0] {
            let two = cohesion_integral::<2>(h);
            let three = cohesion_integral::<3>(h);
            // f32 kernel values summed in f64: 1e-5 relative.
            assert!((two / COHESION_INTEGRAL - 1.0).abs() < 1e-5, "2D h = {h}: {two}");
            assert!(
                (three / COHESION_INTEGRAL - 1.0).abs() < 1e-5,
                "3D h = {h}: {three}"
            );
        }
    }

    #[test]
    fn cohesion_kernel_is_repulsive_inside_h_over_2_and_continuous_there() {
        let h = 1.0;
        assert!(cohesion_kernel::<3>(0.1, h) < 0.0);
        assert!(cohesion_kernel::<3>(0.7, h) > 0.0);
        assert_eq!(cohesion_kernel::<2>(1.0001, h), 0.0);
        // At h/2 both branches give K h⁶/64.
        let k = cohesion_normalisation(3) as Real;
        let at = cohesion_kernel::<3>(0.5, h);
        assert!((at - k / 64.0).abs() < 1e-6 * k, "{at}");
        assert!((cohesion_kernel::<3>(0.500_001, h) - at).abs() < 1e-5 * k);
    }

    #[test]
    fn a_pair_feels_equal_and_opposite_forces() {
        // Equal masses (every particle of a run has the lattice mass): F_ij = −F_ji exactly.
        let (gamma, rho0, h, m) = (0.7, 1000.0, 0.02, 0.4);
        let (x_i, x_j) = (
            Vector3::new(0.003, -0.001, 0.002),
            Vector3::new(-0.004, 0.006, 0.001),
        );
        let (n_i, n_j) = (Vector3::new(0.2, -0.5, 0.1), Vector3::new(-0.3, 0.05, 0.4));
        let (rho_i, rho_j) = (990.0, 1013.0);
        let d = x_i - x_j;
        let r = d.norm();
        let a_ij = surface_tension_acceleration(gamma, rho0, h, m, rho_i, rho_j, &n_i, &n_j, &d, r);
        let a_ji = surface_tension_acceleration(gamma, rho0, h, m, rho_j, rho_i, &n_j, &n_i, &(-d), r);
        assert_eq!(a_ij * m + a_ji * m, Vector3::zeros());
        assert!(a_ij.norm() > 0.0);
    }

    #[test]
    fn the_normal_of_a_flat_face_points_into_the_fluid_with_magnitude_one_at_h_2dx() {
        // A half-plane y ≤ 0 of the 2D lattice: the top particle's normal, h Σ (m/ρ0) ∇W, with
        // the bulk density ρ0 for every neighbour.
        let (dx, rho0) = (0.01, 1000.0);
        let kernel = Smoothing::<2>::new(0.02).expect("2D");
        let m = lattice_mass(&kernel, dx, rho0) as Real;
        let mut n = Vector2::zeros();
        for a in -2i32..=2 {
            for b in -2i32..=0 {
                let d = -Vector2::new(a as Real, b as Real) * dx as Real;
                n += normal_term(&kernel, m, rho0 as Real, &d);
            }
        }
        n *= kernel.h;
        assert!(n.x.abs() < 1e-6, "{n:?}");
        // Into the fluid (−y), |n| = 1.000 at h = 2 dx: measured on this lattice, f32.
        assert!(n.y < 0.0, "{n:?}");
        assert!((n.y + 1.0).abs() < 1e-4, "{n:?}");
    }

    #[test]
    fn the_calibrated_surface_tension_is_positive_and_scales_with_gamma() {
        for dx in [0.005, 0.01] {
            let kernel = Smoothing::<2>::new((2.0 * dx) as Real).expect("2D");
            let m = lattice_mass(&kernel, dx, 1000.0);
            let per_gamma = surface_tension_per_gamma(&kernel, dx, 1000.0, m);
            assert!(per_gamma > 0.0, "{per_gamma}");
            let gamma = gamma_for_surface_tension(&kernel, dx, 1000.0, m, 0.072);
            assert!((gamma * per_gamma / 0.072 - 1.0).abs() < 1e-12);
            let kernel = Smoothing::<3>::new((2.0 * dx) as Real).expect("3D");
            let m = lattice_mass(&kernel, dx, 1000.0);
            assert!(surface_tension_per_gamma(&kernel, dx, 1000.0, m) > 0.0);
        }
    }
}
