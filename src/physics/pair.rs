//! What an optional pair term of the force stage sees (`kernels/pair_terms.table`): the pair
//! [`Pair`], the same for the fluid's own force stage and for the reaction on a solid
//! (`boundary::solid_force`), and the medium its step limit is computed for
//! ([`ViscousMedium`]).

use crate::math::{Real, Vector};
use crate::smoothing::Smoothing;

/// Particle `i` and its neighbour `j` as every optional pair term sees them (twin of `Pair` in
/// `kernels/pair_forces.cuh`).
pub struct Pair<'a, const D: usize> {
    /// `x_i − x_j` [m].
    pub x_ij: &'a Vector<D>,
    /// `|x_ij|` [m].
    pub r: Real,
    /// Velocity of `i` [m/s].
    pub u_i: &'a Vector<D>,
    /// Velocity of `j` [m/s].
    pub u_j: &'a Vector<D>,
    /// The velocity of `i` in the viscous term (17): a solid carries its no-slip velocity
    /// ([A12] eqs. 22–23) where the scene has one [m/s].
    pub viscous_u_i: &'a Vector<D>,
    /// The velocity of `j` in the viscous term (17) [m/s].
    pub viscous_u_j: &'a Vector<D>,
    /// Density of `i` [kg/m³].
    pub rho_i: Real,
    /// Density of `j` [kg/m³].
    pub rho_j: Real,
    /// Mass of `j` [kg].
    pub m_j: Real,
    /// The scaled spiky gradient `∇W(x_ij)` of the pressure force (16) [1/m^(D+1)].
    pub grad_w: &'a Vector<D>,
    /// The kernels for the step's `h`.
    pub kernel: &'a Smoothing<D>,
    /// Whether one of the two is a solid particle (a fluid–wall pair).
    pub wall: bool,
}

/// What a term's step viscosity depends on (`PairTerm::step_viscosity`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViscousMedium {
    /// Sound speed `C` [m/s].
    pub sound_speed: f64,
    /// Kernel support radius `h` [m].
    pub h: f64,
    /// Number of dimensions.
    pub dimension: usize,
    /// The smallest rest density of the fluid's phases [kg/m³] (the largest `μ/ρ0`).
    pub lightest_rho0: f64,
    /// `1/λ`, the scale of the viscous force (17) (`StepParams::viscosity_scale`).
    pub viscosity_scale: f64,
}
