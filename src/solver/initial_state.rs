//! The fluid's initial pressure (`fluid.initial_state = "hydrostatic"`, `scene::initial_state`):
//! what each solver makes of a pressure field at `t = 0`.

use super::{SetupError, Simulation};
use crate::fields::FLUID;
use crate::math::Real;
use crate::physics::eos;

impl<const D: usize> Simulation<D> {
    /// Gives each fluid particle (in the order given to [`Simulation::new`]) the initial
    /// pressure `pressure[k]` [Pa], before the first step.
    ///
    /// - `wcsph`: density from the inverted equation of state (19), `ρ = ρ0 + p / C²`, and mass
    ///   `m ρ / ρ0` at the lattice spacing (as DualSPHysics: spacing kept, denser particles
    ///   heavier). Why the mass: wcsph sums its density (18) every step, and the sum of the
    ///   lattice mass over an unchanged lattice is `ρ0` whatever density a particle was given;
    ///   with masses in proportion to `ρ`, an interior sum over a lattice reproduces the linear
    ///   hydrostatic profile (the lattice sum of `ρ_j W_ij` is `ρ_i` for `ρ` linear in `x`), so
    ///   the column starts at its hydrostatic compression instead of falling into it.
    /// - `corrected`: density and mass unchanged, pressure `p`. Its density is the sum the
    ///   correction (23)–(24) drives to `ρ0`: heavier particles would read as compressed and be
    ///   pushed apart by the start-up settle. Its pressure is not a function of density but the
    ///   correction's, carried from stage to stage (`solver::step`), so the column's weight is
    ///   held from the first force stage on.
    ///
    /// # Errors
    /// [`SetupError::Invalid`] when the count differs from the fluid particles', a pressure is
    /// negative or not finite, the simulation has stepped or a device holds the fields, or the
    /// fluid has several phases (a column of several densities is not one profile).
    pub fn with_initial_pressure(mut self, pressure: &[f64]) -> Result<Self, SetupError> {
        let invalid = |reason: String| SetupError::Invalid {
            key: "fluid.initial_state",
            reason,
        };
        if pressure.len() != self.fluid_count {
            return Err(invalid(format!(
                "{} pressures for {} fluid particles",
                pressure.len(),
                self.fluid_count
            )));
        }
        if self.clock.step != 0 || self.settled {
            return Err(invalid(
                "the initial state must be given before the first step".into(),
            ));
        }
        if self.backend.holds_state() {
            return Err(invalid(
                "the initial state must be given before `use_backend`".into(),
            ));
        }
        if self.multiphase() {
            return Err(invalid("not supported with several fluid phases".into()));
        }
        if let Some(bad) = pressure.iter().find(|p| !(p.is_finite() && **p >= 0.0)) {
            return Err(invalid(format!(
                "a pressure must be non-negative and finite, got {bad}"
            )));
        }
        let (rho0, c2) = (
            self.config.rho0,
            self.config.sound_speed * self.config.sound_speed,
        );
        let corrected = self.config.correction.is_some();
        let f = &mut self.fields;
        for i in 0..f.len() {
            if f.kind[i] != FLUID {
                continue;
            }
            // Before the first step particle i has id i (`Fields::push`).
            let p = pressure[f.id[i] as usize];
            f.pressure[i] = p as Real;
            if corrected {
                f.acting_pressure[i] = p as Real;
            } else {
                let rho = f64::from(eos::density_from_pressure(p as Real, rho0 as Real, c2 as Real));
                f.density[i] = rho as Real;
                f.mass[i] = (f64::from(f.mass[i]) * rho / rho0) as Real;
            }
        }
        self.fields_stale = false;
        self.density_fresh = false;
        Ok(self)
    }
}
