//! Surface tension as a surface stress, the conservative form of the continuum surface force:
//! [LNSZZ94] Lafaurie, Nardone, Scardovelli, Zaleski & Zanetti, "Modelling merging and
//! fragmentation in multiphase flows with SURFER", J. Comput. Phys. 113, 134 (1994) (their
//! "continuum surface stress"); in SPH, with a colour function of two phases, [HA06] Hu & Adams,
//! J. Comput. Phys. 213, 844 (2006). The capillary stress
//!
//! `T = σ' δ (I − N̂ N̂ᵀ)`,  `δ = |∇c|`,  `N̂ = ∇c/|∇c|`,
//!
//! is a tension `σ' δ` along the surface and nothing across it, with `c = Σ_j (m_j/ρ0_j) W` the
//! colour field of the fluid (1 in the bulk, 0 in the void; `Fields::normal` holds `h ∇c`, the
//! [AAT13] normal (3) with rest volumes, written by the `surface_normals` stage). Its divergence
//! is the continuum surface force `σκ δ N̂` plus tangential terms that vanish for uniform `σ`
//! ([BKZ92] Brackbill, Kothe & Zemach, J. Comput. Phys. 100, 335 (1992)); no curvature is
//! computed. It enters the momentum equation as a pair force, like the pressure in (16):
//!
//! `a_i += Σ_j m_j/(ρ0_i ρ0_j) (T_i + T_j)·∇W(x_ij) t_ij`
//!
//! with the spiky gradient and `1/κ` of (16) (`StepParams::pressure_gradient_scale`) and `t_ij`
//! Monaghan's artificial stress ([`ARTIFICIAL_STRESS`]). The pair forces are equal and opposite
//! (momentum is conserved to round-off), and a drop's core is held by the operator that holds
//! its pressure: the core's EOS pressure (19) is the Laplace pressure `σκ` (the bulk has
//! `∇c = 0` and carries no stress of its own, unlike [AAT13]'s pair cohesion,
//! `physics::surface_tension`). The rest volumes `m/ρ0` weigh the pairs, not `m/ρ`: the
//! surface layer's summed density (18) is 0.6–0.7 ρ0 and changes with its packing, and with
//! `1/ρ²` the tension would change with it (measured: 0.87–0.96 σ/R instead of 1.00–1.03).
//!
//! **Surface weight.** In a disordered bulk `|h ∇c|` is not 0 (0.13–0.16 on a lattice jittered
//! by 0.2 dx), and a tension there would act as a negative pressure. `δ` is therefore
//! weighted by a ramp of `|h∇c|` from 0 at [`SURFACE_RAMP`]`.0` to 1 at [`SURFACE_RAMP`]`.1`: a
//! flat face of the lattice has 1.0 in its outer layer and below 1e-6 in the next (h = 2 dx).
//!
//! **`σ'`, the calibration.** In the continuum `∫ σ' δ dz = σ'` across a surface. With particles
//! on one side only the discrete sum falls short, so [`surface_tension_per_unit_stress`]
//! measures the mechanical surface tension of the discrete model on a flat slab of the initial
//! lattice (Kirkwood–Buff, as `physics::surface_tension::surface_tension_per_gamma` does for
//! [AAT13]: `(1/2A) Σ_pairs (z F_z − x F_x)` per interface) with `σ' = 1`, and the solver uses
//! `σ' = σ / that` ([`calibrated_stress`]).
//!
//! Fluid neighbours only: a solid neither attracts nor wets the fluid, and a fluid face on a
//! wall carries the tension of a free surface there.
//!
//! References: as above; [AAT13] Akinci, Akinci & Teschner, ACM TOG 32(6) 182 (2013), eq. (3).

use crate::math::{Real, Vector};
use crate::physics::surface_tension::flat_slab;
use crate::smoothing::Smoothing;

/// `ε` of Monaghan's artificial stress against the tensile instability ([M00a] Monaghan,
/// "SPH without a tensile instability", J. Comput. Phys. 159, 290 (2000)): a tension pulls
/// neighbours together with a force that grows as they approach, so without a counter-stress
/// the surface layer clumps into pairs and sprays (its density is below `ρ0`, where the clamped
/// (19) gives no pressure to resist). Each pair's stress term is multiplied by
/// `1 − ε (W(r)/W(dx))^n` ([`tensile_factor`]): `1 − ε` at the initial spacing, repulsive below
/// about 0.75 dx (h = 2 dx). `n = 4` as in [M00a].
///
/// `ε = 0.2`, measured (tests/physics/surface_tension.rs, the 2D drop of R = 11.3 dx, core pressure over
/// t = 0.5–1 s): at 0.15 the surface layer still clumps (the outline's spread grows to 0.34 by
/// 1 s, the core holds 0.53 σ/R); at 0.2 the core holds 1.03 σ/R; at 0.25 0.92 σ/R and at 0.3
/// 0.79 σ/R. The counter-stress is a compressive stress along the surface, and the surface
/// layer of a drop that was a square is compressed along it (a circle has `√π/2` = 0.89 of the
/// perimeter of a square of its area, and the outer layer's particles do not all leave it), so a
/// larger `ε` takes more of the tension than the flat-lattice calibration counts: the smallest
/// stable `ε` is the choice.
pub const ARTIFICIAL_STRESS: Real = 0.2;

/// `1 − ε (W(r)/W(dx))^n` for the kernel values `w_r = W(r)` and `w_dx = W(dx)` (eq. 20, `dx`
/// the initial spacing), `ε` = [`ARTIFICIAL_STRESS`], `n = 4` (`q⁴` as `(q²)²`, as the kernel).
#[inline(always)]
pub fn tensile_factor(w_r: Real, w_dx: Real) -> Real {
    let q = w_r / w_dx;
    let q2 = q * q;
    1.0 - ARTIFICIAL_STRESS * (q2 * q2)
}

/// `|h ∇c|` below which a particle carries no tension and at and above which it carries all
/// of it; linear between (module doc).
pub const SURFACE_RAMP: (Real, Real) = (0.2, 0.5);

/// The ramp weight of a particle whose normal has length `len = |h ∇c|` (module doc).
#[inline(always)]
pub fn surface_weight(len: Real) -> Real {
    ((len - SURFACE_RAMP.0) / (SURFACE_RAMP.1 - SURFACE_RAMP.0)).clamp(0.0, 1.0)
}

/// `T x` for a particle of normal `n = h ∇c`, applied to the vector `x`: `(σ'/h) w(|n|) (|n| x −
/// n (n·x)/|n|)` [N/m² times the unit of `x`], `sigma` = `σ'` [N/m] (2D: [N]), `h` [m]. Zero off
/// the surface.
#[inline(always)]
pub fn stress_along<const D: usize>(sigma: Real, h: Real, n: &Vector<D>, x: &Vector<D>) -> Vector<D> {
    let len = n.norm();
    let w = surface_weight(len);
    if w == 0.0 {
        return Vector::zeros();
    }
    (x * len - n * (n.dot(x) / len)) * (sigma * w / h)
}

/// The acceleration [m/s²] of particle `i` from fluid neighbour `j`: `m_j/(ρ0_i ρ0_j) (T_i +
/// T_j)·∇W · t`, with `grad_w` the scaled spiky gradient of (16) at `x_ij` [1/m^(D+1)], `t` the
/// [`tensile_factor`] of the pair, `m_j` [kg], rest densities [kg/m³], normals `h ∇c`
/// (dimensionless), `sigma` = `σ'` [N/m], `h` [m]. The rest volumes `m/ρ0`, not `m/ρ`, weigh the
/// pair: the surface layer's summed density is 0.6–0.7 ρ0 and moves with its packing, and
/// `1/ρ²` would make the tension follow it (module doc).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn surface_stress_acceleration<const D: usize>(
    sigma: Real,
    h: Real,
    m_j: Real,
    rho0_i: Real,
    rho0_j: Real,
    n_i: &Vector<D>,
    n_j: &Vector<D>,
    grad_w: &Vector<D>,
    tensile: Real,
) -> Vector<D> {
    (stress_along(sigma, h, n_i, grad_w) + stress_along(sigma, h, n_j, grad_w))
        * (m_j * tensile / (rho0_i * rho0_j))
}

/// The mechanical surface tension [N/m] (2D: [N]) of the model with `σ' = 1`, on a flat slab of
/// the initial lattice (spacing `dx` [m], every particle of mass `mass` [kg], rest density
/// `rho0` [kg/m³]): [KB49] `(1/2A) Σ_pairs (z F_z − x F_x)` per interface, with the slab's own
/// densities (18) and normals, the spiky gradient times `grad_scale` (`1/κ` of (16)). The
/// pressure is zero on the unrelaxed slab (clamped (19)) and does not enter. Summed in f64.
pub fn surface_tension_per_unit_stress<const D: usize>(
    kernel: &Smoothing<D>,
    dx: f64,
    mass: f64,
    rho0: f64,
    grad_scale: f64,
) -> f64 {
    let slab = flat_slab(kernel, dx, mass, rho0);
    let h = f64::from(kernel.h);
    let n = slab.n;
    // Tension per layer over ρ0²: `w(|n|) |n| / (h ρ0²)` (σ' = 1); T is tangential only.
    let tension: Vec<f64> = (0..slab.layers as usize)
        .map(|l| {
            let len = slab.rest_normal[l].abs();
            f64::from(surface_weight(len as Real)) * len / (h * rho0 * rho0)
        })
        .collect();
    // The spiky gradient's factor of x: −3 K (h − r)²/r.
    let spiky = |r: f64| {
        let mut x = Vector::<D>::zeros();
        x[0] = r as Real;
        f64::from(kernel.grad_w_spiky(&x, r as Real)[0]) / r * grad_scale
    };
    let w_dx = kernel.w((dx * dx) as Real);
    let mut sum = 0.0;
    for l in 0..slab.layers {
        for lj in (l - n).max(0)..=(l + n).min(slab.layers - 1) {
            let z = (l - lj) as f64 * dx;
            let t = tension[l as usize] + tension[lj as usize];
            for &(x, t2) in &slab.tangential {
                let r = (z * z + t2).sqrt();
                if r <= 0.0 || r >= h {
                    continue;
                }
                // F_x on i = m² (T_i + T_j)_xx/ρ0² ∂W/∂x t; F_z = 0 (no stress across).
                let tensile = f64::from(tensile_factor(kernel.w((r * r) as Real), w_dx));
                let fx = mass * mass * t * spiky(r) * x * tensile;
                sum += 0.5 * (-x * fx);
            }
        }
    }
    sum / dx.powi(D as i32 - 1) / 2.0
}

/// `σ'` [N/m] (2D: [N]) that gives the surface tension `sigma` on the lattice of spacing `dx`
/// ([`surface_tension_per_unit_stress`]).
pub fn calibrated_stress<const D: usize>(
    kernel: &Smoothing<D>,
    dx: f64,
    mass: f64,
    rho0: f64,
    grad_scale: f64,
    sigma: f64,
) -> f64 {
    sigma / surface_tension_per_unit_stress(kernel, dx, mass, rho0, grad_scale)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::lattice::{lattice_gradient_moment, lattice_mass};
    use nalgebra::Vector2;

    #[test]
    fn the_stress_is_a_tension_along_the_surface_only() {
        let (sigma, h) = (0.1, 0.02);
        let n = Vector2::new(0.0, -0.9);
        // Along the surface: tension σ' |n| / h (full weight at |n| = 0.9); across: nothing.
        let along = stress_along(sigma, h, &n, &Vector2::new(1.0, 0.0));
        let across = stress_along(sigma, h, &n, &Vector2::new(0.0, 1.0));
        assert!((along.x - sigma * 0.9 / h).abs() < 1e-6 * along.x, "{along:?}");
        assert!(along.y.abs() < 1e-12 && across.norm() < 1e-12, "{across:?}");
        // Off the surface: none.
        let bulk = stress_along(sigma, h, &Vector2::new(0.15, 0.0), &Vector2::new(0.0, 1.0));
        assert_eq!(bulk, Vector2::zeros());
    }

    #[test]
    fn a_pair_feels_equal_and_opposite_forces() {
        let kernel = Smoothing::<2>::new(0.02).expect("2D");
        let d = Vector2::new(0.004, -0.007);
        let g = kernel.grad_w_spiky(&d, d.norm());
        let (n_i, n_j) = (Vector2::new(0.6, -0.7), Vector2::new(-0.3, 0.9));
        let m = 0.4;
        let a_ij = surface_stress_acceleration(0.1, 0.02, m, 800.0, 1000.0, &n_i, &n_j, &g, 0.7);
        let a_ji = surface_stress_acceleration(0.1, 0.02, m, 1000.0, 800.0, &n_j, &n_i, &(-g), 0.7);
        assert!((a_ij + a_ji).norm() < 1e-6 * a_ij.norm(), "{a_ij:?} {a_ji:?}");
        assert!(a_ij.norm() > 0.0);
    }

    #[test]
    fn on_a_flat_face_only_the_outer_layer_carries_tension() {
        // h = 2 dx: the rest-volume colour gradient is 1 in the outer layer and vanishes in the
        // next (the module doc's claim), so the ramp gives the second layer no tension.
        let dx = 0.001;
        let kernel = Smoothing::<2>::new((2.0 * dx) as Real).expect("2D");
        let slab = flat_slab(&kernel, dx, lattice_mass(&kernel, dx, 1000.0), 1000.0);
        assert!(
            (slab.rest_normal[0] - 1.0).abs() < 1e-3,
            "{:?}",
            &slab.rest_normal[..3]
        );
        assert!(slab.rest_normal[1].abs() < 1e-6, "{:?}", &slab.rest_normal[..3]);
        assert_eq!(surface_weight(slab.rest_normal[1] as Real), 0.0);
        assert_eq!(surface_weight(slab.rest_normal[0] as Real), 1.0);
    }

    #[test]
    fn the_calibration_is_positive_and_depends_on_dx_over_h_only() {
        let per_unit = |dx: f64| {
            let kernel = Smoothing::<2>::new((2.0 * dx) as Real).expect("2D");
            let m = lattice_mass(&kernel, dx, 1000.0);
            let scale = 1.0 / lattice_gradient_moment(&kernel, dx, 1000.0);
            // σ per unit σ' is dimensionless: the same at any dx for h = 2 dx.
            surface_tension_per_unit_stress(&kernel, dx, m, 1000.0, scale)
        };
        let (a, b) = (per_unit(0.01), per_unit(0.001));
        assert!(a > 0.1 && a < 2.0, "{a}");
        assert!((a / b - 1.0).abs() < 1e-4, "{a} {b}");
    }
}
