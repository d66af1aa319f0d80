//! Force exerted by the fluid on a solid particle: the reaction to the pair forces (16)–(17).

use crate::math::{Real, Vector};
use crate::model::pair_terms::add_pair_terms;
use crate::model::params::StepParams;
use crate::physics::{pair::Pair, pressure::pressure_acceleration};

/// Force [N] (per unit depth [N/m] in 2D) on solid particle `s` from fluid particle `f`:
/// `m_s` times the pair accelerations of (16) and of the optional pair terms of `TERMS`
/// (`model::pair_terms`, in table order), evaluated from the solid's side. This is exactly
/// minus the force that `s` exerts on `f` (every pair term is antisymmetric), so the fluid's
/// momentum change equals the walls' impulse.
///
/// `p_s`, `p_f` are the pressures [Pa]; `m_s` [kg]; in `pair`, `i` is the solid and `j` the
/// fluid particle: `x_ij = x_s − x_f` [m], `u_i` the solid's velocity (zero for a fixed solid and
/// `d'(t)` for a moving one, `boundary::motion`: the artificial viscosity sees the relative
/// velocity, as the fluid's own force stage does), `viscous_u_i` the velocity the solid carries in
/// the viscous term (17), the no-slip `Fields::wall_velocity` where the scene has it ([A12] eqs.
/// 22–23), else `u_s`: the fluid's force stage uses the same one, so the pair stays
/// antisymmetric.
#[inline(always)]
pub fn force_on_solid<const D: usize, const TERMS: u32>(
    params: &StepParams<D>,
    m_s: Real,
    [p_s, p_f]: [Real; 2],
    pair: &Pair<'_, D>,
) -> Vector<D> {
    let mut a = pressure_acceleration(p_s, pair.rho_i, p_f, pair.rho_j, pair.m_j, pair.grad_w);
    add_pair_terms::<D, TERMS>(&mut a, params, pair);
    a * m_s
}
