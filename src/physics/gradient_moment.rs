//! The first moment `κ` of the spiky gradient (21) measured on the particles as they stand: the
//! factor the pressure force (16) divides by (`StepParams::pressure_gradient_scale = 1/κ`).
//!
//! The SPH gradient of a linear field `p` at particle `i` is `κ_i ∇p`, with
//! `κ_i = −(1/D) Σ_j V_j x_ij · ∇W(x_ij)` and `V_j = m_j/ρ_j` (the scalar part of Bonet & Lok's
//! 1999 gradient correction, [BL99] Comput. Methods Appl. Mech. Engrg. 180, eq. 43). On the
//! initial square lattice it is `physics::lattice::lattice_gradient_moment` (0.874 at `h = 2 dx`
//! in 2D), but fluid at rest does not stay on the lattice: in the resting tank of
//! `tests/physics/basics.rs` the particles settle into an arrangement whose `κ` is 0.848, and a
//! force divided by the lattice's 0.874 holds the water up with a pressure 3 % above
//! `ρ0 g (H − z)`. Measured (`GradientMoment::Measured`), `κ` is the mean of `κ_i` over the
//! owned fluid particles with full kernel support, those whose Shepard sum
//! `Σ_j V_j W(x_ij)` (poly6, eq. 20, the particle itself included) is at least
//! [`FULL_SUPPORT`]: a particle at the free surface lacks neighbours on one side and its
//! `κ_i` says so, not how the fluid is arranged.

use crate::math::{Real, Vector};
use crate::smoothing::Smoothing;

/// Least Shepard sum of a particle whose neighbourhood counts as full (dimensionless). On the
/// lattice at `h = 2 dx` the free surface's row sums about 0.75 and the row below it 1.0; the
/// fluid's interior reads 0.99–1.02 as it moves.
pub const FULL_SUPPORT: f64 = 0.95;

/// The step `κ` is rounded to, 2⁻¹⁶ (1.5e-5, about 2e-5 of `κ`). Why: the per-particle sums
/// are f32 and add in another order on another backend or rank count, so the mean differs in its
/// last digits; unrounded, that difference scales the pressure of every particle at once, and
/// the `corrected` solver's sweep count amplifies it (measured on `scenes/dam_break_wall_2d.toml`,
/// CPU against the CUDA backend on the host shim: positions 2.0e-3 dx apart after the first
/// step, against 4.8e-5 with a fixed `κ`). The mean moves by about 1e-5 a stage as the fluid
/// moves, so the rounding costs nothing the measurement could resolve.
pub const KAPPA_QUANTUM: f64 = 1.0 / 65536.0;

/// Neighbour `j`'s share of particle `i`'s sums, `[V_j W(x_ij), −V_j x_ij · ∇W(x_ij) / D]`
/// (dimensionless), with `d = x_i − x_j` [m], `r2 = |d|²` [m²] and `volume = m_j/ρ_j` [m^D]
/// (2D: per unit depth). `j = i` adds `V_i W(0)` to the Shepard sum and nothing to the moment.
#[inline(always)]
pub fn moment_terms<const D: usize>(
    kernel: &Smoothing<D>,
    d: &Vector<D>,
    r2: Real,
    volume: Real,
) -> [Real; 2] {
    let shepard = volume * kernel.w(r2);
    let moment = -volume * d.dot(&kernel.grad_w_spiky(d, r2.sqrt())) / D as Real;
    [shepard, moment]
}

/// What the `gradient_moment` stage sums over the owned fluid particles with full support.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MomentSums {
    /// `Σ κ_i` (dimensionless).
    pub moment: f64,
    /// How many particles entered.
    pub count: f64,
}

impl MomentSums {
    /// The particle's `[shepard, moment]` sums entered if its support is full.
    pub fn of_particle(sums: [Real; 2]) -> Self {
        if f64::from(sums[0]) >= FULL_SUPPORT && sums[1].is_finite() {
            MomentSums {
                moment: f64::from(sums[1]),
                count: 1.0,
            }
        } else {
            MomentSums::default()
        }
    }

    /// The mean `κ` rounded to a multiple of [`KAPPA_QUANTUM`], or `None` when no particle had
    /// full support (a film one particle thick, a spray): the step then keeps the last `κ` (the
    /// lattice's before the first measurement).
    pub fn kappa(&self) -> Option<f64> {
        (self.count > 0.0 && self.moment > 0.0)
            .then(|| (self.moment / self.count / KAPPA_QUANTUM).round() * KAPPA_QUANTUM)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::lattice::{lattice_gradient_moment, lattice_mass};

    /// On the square lattice the measured moment of an interior particle is the lattice's.
    #[test]
    fn an_interior_lattice_particle_measures_the_lattice_moment() {
        let (dx, rho0) = (0.01f64, 1000.0f64);
        let kernel = Smoothing::<2>::new((2.0 * dx) as Real).expect("2D");
        let volume = (lattice_mass(&kernel, dx, rho0) / rho0) as Real;
        let mut sums = [0.0f32; 2];
        for a in -3i32..=3 {
            for b in -3i32..=3 {
                let d = Vector::<2>::new(a as Real * dx as Real, b as Real * dx as Real);
                let t = moment_terms(&kernel, &d, d.norm_squared(), volume);
                sums[0] += t[0];
                sums[1] += t[1];
            }
        }
        let kappa = lattice_gradient_moment(&kernel, dx, rho0);
        assert!((f64::from(sums[0]) - 1.0).abs() < 1e-5, "shepard {}", sums[0]);
        assert!(
            (f64::from(sums[1]) - kappa).abs() < 1e-5 * kappa,
            "{} vs {kappa}",
            sums[1]
        );
        let m = MomentSums::of_particle(sums);
        assert_eq!(m.count, 1.0);
        // A surface particle (its upper rows missing) does not enter.
        let mut top = [0.0f32; 2];
        for a in -3i32..=3 {
            for b in -3i32..=0 {
                let d = Vector::<2>::new(a as Real * dx as Real, b as Real * dx as Real);
                let t = moment_terms(&kernel, &d, d.norm_squared(), volume);
                top[0] += t[0];
                top[1] += t[1];
            }
        }
        assert!(f64::from(top[0]) < FULL_SUPPORT, "surface shepard {}", top[0]);
        assert_eq!(MomentSums::of_particle(top).count, 0.0);
        assert_eq!(MomentSums::default().kappa(), None);
    }
}
