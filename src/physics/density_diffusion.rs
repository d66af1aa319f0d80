//! The continuity equation with density diffusion (the `density_diffusion` effect of `wcsph`):
//!
//! `dρ_i/dt = Σ_j m_j (u_i − u_j)·∇_i W_ij + D_i`, with
//! `D_i = 2 δ h_s c0 Σ_j^fluid ρ_ji^T (x_ji·∇_i W_ij) / |x_ij|² · m_j/ρ_j`,
//! `ρ_ji^T = (ρ_j − ρ_i) − ρ_ji^H`, `ρ_ji^H = ρ0 g·x_ji / c0²`, `x_ji = x_j − x_i`.
//!
//! References: [MC09] Molteni & Colagrossi, Comput. Phys. Commun. 180 (2009) 861–872, the
//! diffusive term; [A10] Antuono, Colagrossi, Marrone & Molteni, Comput. Phys. Commun. 181
//! (2010) 532–549, δ-SPH; [F19] Fourtakas, Dominguez, Vacondio & Rogers, Comput. Fluids 190
//! (2019) 346–361: the hydrostatic part `ρ_ji^H` taken out of the diffused difference
//! ("DDT Fourtakas" of DualSPHysics).
//!
//! Why [F19]'s form: a resting column has `ρ_j − ρ_i = ρ_ji^H ≠ 0` between heights, so
//! [MC09]'s term (`ρ_ji` alone) diffuses the hydrostatic profile away and the column sinks at
//! the bottom and swells at the top; [F19] diffuses only the departure from hydrostatics, which
//! is zero at rest (tests below). [A10]'s renormalised gradient does the same at the cost of a
//! second pass; [F19] needs none.
//!
//! Sign: `∇_i W_ij = W'(r) x_ij / r` with `W' < 0`, so `x_ji·∇_i W_ij = −r W'(r) > 0`, and
//! `D_i = δ h_s c0 ∇²ρ` in Brookshaw's SPH Laplacian: a particle denser than its neighbours
//! loses density ([A10] and [F19] write it with `x_ji`).
//!
//! `ρ_ji^H` is [F19]'s `ρ0 [(1 + ρ0 g z_ji / B)^(1/γ) − 1]` for this solver's equation of state
//! (19), linear: `γ = 1`, `B = ρ0 c0²`, so `ρ0 g z_ji / c0²`, here with the gravity vector
//! (`z_ji` along `−g`: `|g| z_ji = g·x_ji`).
//!
//! `h_s`: [F19] writes `h` for the smoothing length of a kernel of support `2h`; this code's
//! `h` is the support radius, so `h_s = h/2` keeps `δ` at its published meaning (0.1 typical).
//! `∇W` is the gradient of the density kernel (18) ([`density_kernel_gradient`]): the
//! continuity sum is then the time derivative of the summation it replaces.

use super::density::{DensityWeight, density_kernel_gradient};
use crate::math::{Real, Vector};
use crate::smoothing::Smoothing;

/// What the continuity sum of particle `i` needs besides its neighbours.
#[derive(Clone, Copy, Debug)]
pub struct DiffusionCoefficients<const D: usize> {
    /// `2 δ h_s c0` [m²/s], `h_s = h/2` (module doc).
    pub strength: Real,
    /// `ρ0 g / c0²` [kg/m³ per m]: the hydrostatic density gradient, `ρ_ji^H = this · x_ji`.
    pub hydrostatic_gradient: Vector<D>,
}

impl<const D: usize> DiffusionCoefficients<D> {
    /// From `δ` (dimensionless), the support radius `h` [m], `c0²` [m²/s²], `ρ0` [kg/m³] and
    /// gravity `g` [m/s²] (at the stage's time, so it follows a ramp).
    pub fn new(delta: Real, h: Real, c2: Real, rho0: Real, gravity: &Vector<D>) -> Self {
        Self {
            strength: 2.0 * delta * 0.5 * h * c2.sqrt(),
            hydrostatic_gradient: gravity * (rho0 / c2),
        }
    }
}

/// `m_j (u_i − u_j)·∇_i W_ij` [kg/(m^D s)]: neighbour `j`'s share of the velocity divergence
/// term of the continuity equation, at `x = x_i − x_j` [m], `r = |x|`.
#[inline(always)]
pub fn continuity_term<const D: usize>(
    kernel: &Smoothing<D>,
    weight: DensityWeight,
    m_j: Real,
    u_ij: &Vector<D>,
    x: &Vector<D>,
    r: Real,
) -> Real {
    m_j * u_ij.dot(&density_kernel_gradient(kernel, weight, x, r))
}

/// [F19]: fluid neighbour `j`'s share of `D_i` [kg/(m^D s)], at `x = x_i − x_j` [m],
/// `r = |x| > 0`, densities `rho_i`, `rho_j` [kg/m³], mass `m_j` [kg] (module doc).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn diffusion_term<const D: usize>(
    kernel: &Smoothing<D>,
    weight: DensityWeight,
    c: &DiffusionCoefficients<D>,
    rho_i: Real,
    rho_j: Real,
    m_j: Real,
    x: &Vector<D>,
    r: Real,
) -> Real {
    // x_ji = −x.
    let hydrostatic = -c.hydrostatic_gradient.dot(x);
    let excess = (rho_j - rho_i) - hydrostatic;
    let grad = density_kernel_gradient(kernel, weight, x, r);
    c.strength * excess * (-x.dot(&grad)) / (r * r) * (m_j / rho_j)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::density::DensityWeight;

    /// `D_i` of the centre particle of a square lattice with densities `rho(x)`; `surface`: the
    /// lattice ends at the centre's row (no neighbours above, a free surface).
    fn diffusion_at_centre(
        rho: impl Fn(Vector<2>) -> Real,
        c: &DiffusionCoefficients<2>,
        surface: bool,
    ) -> Real {
        let dx = 0.01;
        let kernel = Smoothing::<2>::new(2.0 * dx).expect("kernel");
        let m = 1000.0 * dx * dx;
        let xi = Vector::<2>::zeros();
        let mut sum = 0.0;
        for a in -3..=3 {
            for b in -3..=if surface { 0 } else { 3 } {
                let xj = Vector::<2>::new(a as Real * dx, b as Real * dx);
                let x = xi - xj;
                let r = x.norm();
                if r > 0.0 && r < 2.0 * dx {
                    let m_j = m * rho(xj) / 1000.0;
                    sum += diffusion_term(&kernel, DensityWeight::POLY6, c, rho(xi), rho(xj), m_j, &x, r);
                }
            }
        }
        sum
    }

    #[test]
    fn a_hydrostatic_profile_does_not_diffuse() {
        let g = Vector::<2>::new(0.0, -9.81);
        let c = DiffusionCoefficients::new(0.1, 0.02, 35.0 * 35.0, 1000.0, &g);
        // ρ = ρ0 + ρ0 g (H − y)/c², H = 0.1 m: the column's density 0.08 % above ρ0 at y = 0.
        let rho = |x: Vector<2>| 1000.0 + 1000.0 * 9.81 * (0.1 - x.y) / (35.0 * 35.0);
        // Rounding: each pair's excess is a difference of f32 densities near 1000 (ulp 6e-5)
        // minus the hydrostatic one, ~1e-4 kg/m³, times 2 δ h_s c0 |∇W|/r V_j ~ 300 per pair:
        // ~0.03 a pair, under 1 for the ~12 pairs. One dx of the hydrostatic difference
        // (0.08 kg/m³) unbalanced at the surface gives ~100 (the plain form below).
        for surface in [false, true] {
            let d = diffusion_at_centre(rho, &c, surface);
            assert!(
                d.abs() < 1.0,
                "hydrostatic column diffuses (surface {surface}): {d}"
            );
        }
        // Molteni & Colagrossi's form (no hydrostatic part) keeps the interior, whose profile is
        // linear, but not the top row, where the kernel is cut: it sinks the surface.
        let plain = DiffusionCoefficients {
            hydrostatic_gradient: Vector::zeros(),
            ..c
        };
        let top = diffusion_at_centre(rho, &plain, true);
        assert!(top.abs() > 10.0, "plain form at the surface: {top}");
    }

    #[test]
    fn a_density_bump_diffuses_down() {
        let c = DiffusionCoefficients::new(0.1, 0.02, 35.0 * 35.0, 1000.0, &Vector::<2>::zeros());
        // The centre 1 kg/m³ above its neighbours: it must lose density, at the rate of the
        // Laplacian, D ≈ δ h_s c0 ∇²ρ ~ 0.1 · 0.01 · 35 · 1 / dx² = 350 kg/m³/s in order.
        let rho = |x: Vector<2>| if x.norm() == 0.0 { 1001.0 } else { 1000.0 };
        let d = diffusion_at_centre(rho, &c, false);
        assert!(d < -35.0 && d > -3500.0, "bump rate {d}");
    }
}
