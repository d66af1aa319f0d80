//! The force stage's optional per-pair terms, generated from `kernels/pair_terms.table`
//! (`build/pair_terms.rs`): [`PairTerm`], the coefficients' slot in `StepParams`
//! ([`PairCoefficients`]), the CPU's sum [`add_pair_terms`] and its monomorphised dispatch
//! (`with_pair_terms!`), the scene file's keys (`with_pair_term_keys!`). A term's physics lives
//! in `physics/` and its device twin in `kernels/pair_forces.cuh`; everything between is read
//! from the table, so no other file names a term.

use super::params::StepParams;
use crate::math::{Real, Vector};

include!(concat!(env!("OUT_DIR"), "/pair_terms.rs"));

/// The check of a pair term's coefficient in a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoefficientRule {
    /// `>= 0`.
    NonNegative,
    /// `> 0`.
    Positive,
}

impl PairTerm {
    /// The term whose effect (and `[fluid]` key) is `name`.
    pub fn from_name(name: &str) -> Option<PairTerm> {
        PairTerm::ALL.into_iter().find(|t| t.name() == name)
    }

    /// The term's bit in [`PairTerms::bits`].
    pub fn bit(self) -> u32 {
        1 << self as u32
    }
}

/// A set of pair terms (the force stage's, `ForceTerms::pair`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PairTerms(u32);

impl PairTerms {
    /// No optional pair term: the pressure force alone.
    pub const NONE: PairTerms = PairTerms(0);

    /// This set with `term`.
    pub fn with(self, term: PairTerm) -> PairTerms {
        PairTerms(self.0 | term.bit())
    }

    /// This set without `term`.
    pub fn without(self, term: PairTerm) -> PairTerms {
        PairTerms(self.0 & !term.bit())
    }

    /// Whether `term` is in the set.
    pub fn contains(self, term: PairTerm) -> bool {
        self.0 & term.bit() != 0
    }

    /// Bit `k` for `PairTerm::ALL[k]`: the `TERMS` of [`add_pair_terms`] and the `{terms}`
    /// index of the generated kernel families (`kernels/launch.table`).
    pub fn bits(self) -> u32 {
        self.0
    }

    /// The number of sets, `2^PAIR_TERM_COUNT`.
    pub const SETS: usize = 1 << PAIR_TERM_COUNT;

    /// The set with these bits (`bits < SETS`; higher bits are dropped).
    pub fn from_bits(bits: u32) -> PairTerms {
        PairTerms(bits & (PairTerms::SETS as u32 - 1))
    }

    /// The terms of the set, in table order.
    pub fn iter(self) -> impl Iterator<Item = PairTerm> {
        PairTerm::ALL.into_iter().filter(move |t| self.contains(*t))
    }
}

/// The pair terms a run switches on, each with its coefficient (the scene's `[fluid]` value).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairTermSettings([Option<f64>; PAIR_TERM_COUNT]);

impl PairTermSettings {
    /// No pair term.
    pub fn none() -> PairTermSettings {
        PairTermSettings::default()
    }

    /// These settings with `term` on with `coefficient`.
    pub fn with(mut self, term: PairTerm, coefficient: f64) -> PairTermSettings {
        self.0[term as usize] = Some(coefficient);
        self
    }

    /// `term`'s coefficient, `None` when it is off.
    pub fn get(&self, term: PairTerm) -> Option<f64> {
        self.0[term as usize]
    }

    /// The terms that are on.
    pub fn terms(&self) -> PairTerms {
        PairTerm::ALL
            .into_iter()
            .filter(|t| self.get(*t).is_some())
            .fold(PairTerms::NONE, PairTerms::with)
    }

    /// The terms that are on with their coefficients, in table order.
    pub fn iter(&self) -> impl Iterator<Item = (PairTerm, f64)> + '_ {
        PairTerm::ALL
            .into_iter()
            .filter_map(|t| self.get(t).map(|c| (t, c)))
    }

    /// The coefficients for `StepParams` (a term that is off keeps 0, never read).
    pub fn coefficients(&self) -> PairCoefficients {
        let mut c = PairCoefficients::default();
        for (term, value) in self.iter() {
            c.set(term, value as Real);
        }
        c
    }

    /// The kinematic viscosity [m²/s] the terms that are on amount to together, for the
    /// explicit step's viscous limit (each term's `step_viscosity`, summed in table order).
    pub fn step_viscosity(&self, medium: &crate::physics::pair::ViscousMedium) -> f64 {
        self.iter()
            .fold(0.0, |sum, (term, c)| sum + term.step_viscosity(c, medium))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_term_has_its_own_name_and_bit() {
        for (k, term) in PairTerm::ALL.into_iter().enumerate() {
            assert_eq!(PairTerm::from_name(term.name()), Some(term));
            assert_eq!(term.bit(), 1 << k, "bits in table order");
            assert!(!term.label().is_empty() && !term.equation().is_empty());
        }
        assert_eq!(PairTerm::from_name("no_such_term"), None);
    }

    #[test]
    fn coefficients_are_one_float_per_term_in_table_order() {
        // `$OUT_DIR/pair_coefficients.cuh` declares the same floats in table order, so the
        // device reads each term's coefficient where the host wrote it.
        assert_eq!(std::mem::size_of::<PairCoefficients>(), PAIR_TERM_COUNT * 4);
        let settings = PairTerm::ALL
            .into_iter()
            .enumerate()
            .fold(PairTermSettings::none(), |s, (k, t)| s.with(t, k as f64 + 1.5));
        let c = settings.coefficients();
        // SAFETY: `#[repr(C)]` struct of `PAIR_TERM_COUNT` `f32`s.
        let floats: [f32; PAIR_TERM_COUNT] = unsafe { std::mem::transmute(c) };
        for (k, value) in floats.into_iter().enumerate() {
            assert_eq!(value, k as f32 + 1.5);
        }
    }

    #[test]
    fn term_sets_round_trip_through_their_bits() {
        for bits in 0..PairTerms::SETS as u32 {
            let set = PairTerms::from_bits(bits);
            assert_eq!(set.bits(), bits);
            let rebuilt = set.iter().fold(PairTerms::NONE, PairTerms::with);
            assert_eq!(rebuilt, set);
            for term in PairTerm::ALL {
                assert_eq!(set.contains(term), bits & term.bit() != 0);
                assert!(!set.without(term).contains(term));
            }
        }
        let settings = PairTermSettings::none().with(PairTerm::Viscosity, 0.0);
        assert_eq!(
            settings.terms(),
            PairTerms::NONE.with(PairTerm::Viscosity),
            "a term is on by its effect, not by its value"
        );
    }

    #[test]
    fn the_step_viscosity_sums_the_terms_that_are_on() {
        let medium = crate::physics::pair::ViscousMedium {
            sound_speed: 20.0,
            h: 0.02,
            dimension: 2,
            lightest_rho0: 1000.0,
            viscosity_scale: 0.5,
        };
        let none = PairTermSettings::none();
        assert_eq!(none.step_viscosity(&medium), 0.0);
        let mu = none.with(PairTerm::Viscosity, 2.0);
        assert_eq!(mu.step_viscosity(&medium), 2.0 / 1000.0 * 0.5);
        let both = mu.with(PairTerm::ArtificialViscosity, 0.1);
        let alpha = 0.1 * 20.0 * 0.5 * 0.02 / (2.0 * 4.0);
        assert!((both.step_viscosity(&medium) - (2.0 / 1000.0 * 0.5 + alpha)).abs() < 1e-15);
    }
}
