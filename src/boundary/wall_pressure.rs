//! Pressure of solid particles, extrapolated from the fluid ([A12] eq. 27).

use crate::math::{Real, Vector};

/// Running sums over the fluid neighbours `f` of one solid particle `w`.
#[derive(Clone, Copy, Debug)]
pub struct WallPressureSums<const D: usize> {
    /// `Σ_f W_wf` [1/m^D].
    pub weight: Real,
    /// `Σ_f p_f W_wf` [Pa/m^D].
    pub pressure: Real,
    /// `Σ_f ρ_f (x_w − x_f) W_wf` [kg/m^(2+D)... ] (density times offset, weighted).
    pub density_offset: Vector<D>,
}

impl<const D: usize> Default for WallPressureSums<D> {
    fn default() -> Self {
        Self {
            weight: 0.0,
            pressure: 0.0,
            density_offset: Vector::zeros(),
        }
    }
}

impl<const D: usize> WallPressureSums<D> {
    /// Adds fluid neighbour `f` with pressure `p_f` [Pa], density `rho_f` [kg/m³], offset
    /// `x_w − x_f` [m] and poly6 weight `w` (eq. 20).
    #[inline(always)]
    pub fn add(&mut self, p_f: Real, rho_f: Real, offset: &Vector<D>, w: Real) {
        self.weight += w;
        self.pressure += p_f * w;
        self.density_offset += offset * (rho_f * w);
    }

    /// [A12] eq. (27): `p_w = (Σ p_f W + (g − a_w)·Σ ρ_f (x_w − x_f) W) / Σ W` [Pa], clamped at
    /// zero as the fluid's own pressure (19) is; zero without fluid neighbours. `body` is the
    /// body acceleration `g − a_w` [m/s²]: gravity for a wall at rest, minus the wall's own
    /// acceleration `a_w = d''(t)` for a moving one (`boundary::motion`): in the wall's frame the
    /// fluid feels `g − a_w`, and that is what holds the fluid's pressure gradient against it.
    #[inline(always)]
    pub fn pressure(&self, body: &Vector<D>) -> Real {
        if self.weight <= 0.0 {
            return 0.0;
        }
        ((self.pressure + body.dot(&self.density_offset)) / self.weight).max(0.0)
    }

    /// The position correction's wall increment: eq. (27) of the fluid increments without the
    /// body term (gravity acts in the force stage, not in the sweeps) and of either sign,
    /// `δp_w = Σ δp_f W / Σ W` [Pa]; zero without fluid neighbours. The caller keeps the wall's
    /// accumulated pressure non-negative (`CpuBackend::correction_pressure`). The zero body
    /// term stays in the sum so that a non-finite density propagates as in [`Self::pressure`].
    #[inline(always)]
    pub fn increment(&self) -> Real {
        if self.weight <= 0.0 {
            return 0.0;
        }
        (self.pressure + Vector::<D>::zeros().dot(&self.density_offset)) / self.weight
    }
}
