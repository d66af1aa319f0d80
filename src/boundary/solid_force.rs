//! Force exerted by the fluid on a solid particle: the reaction to the pair forces (16)–(17).

use crate::math::{Real, Vector};
use crate::model::params::StepParams;
use crate::physics::{
    artificial_viscosity::artificial_viscous_acceleration, pressure::pressure_acceleration,
    viscosity::viscous_acceleration,
};

/// Force [N] (per unit depth [N/m] in 2D) on solid particle `s` from fluid particle `f`:
/// `m_s` times the pair accelerations of (16), (17) and, when on, the artificial viscosity,
/// evaluated from the solid's side. This is exactly minus the force that `s` exerts on `f`
/// (every pair term is antisymmetric), so the fluid's momentum change equals the walls' impulse.
///
/// `solid` and `fluid` are `[m, p, ρ]` ([kg], [Pa], [kg/m³]); `offset = x_s − x_f` [m];
/// `velocity = [u_s, u_f]` the solid's and the fluid's velocities [m/s] (`u_s` is zero for a
/// fixed solid and `d'(t)` for a moving one, `boundary::motion`: the artificial viscosity sees
/// the relative velocity, as the fluid's own force stage does); `viscous_u_s` [m/s] the velocity
/// the solid carries in the viscous term (17), the no-slip `Fields::wall_velocity` where the
/// scene has it ([A12] eqs. 22–23), else `u_s`: the fluid's force stage uses the same one, so
/// the pair stays antisymmetric; `grad_w` the (scaled) spiky gradient at `offset`;
/// `laplacian_w` the viscosity-kernel Laplacian; (17) is scaled by `params.viscosity_scale`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn force_on_solid<const D: usize>(
    params: &StepParams<D>,
    solid: [Real; 3],
    fluid: [Real; 3],
    offset: &Vector<D>,
    velocity: [&Vector<D>; 2],
    viscous_u_s: &Vector<D>,
    grad_w: &Vector<D>,
    laplacian_w: Real,
) -> Vector<D> {
    let [m_s, p_s, rho_s] = solid;
    let [m_f, p_f, rho_f] = fluid;
    let [u_s, u_f] = velocity;
    let mut a = pressure_acceleration(p_s, rho_s, p_f, rho_f, m_f, grad_w);
    if params.mu > 0.0 {
        let mu = params.mu * params.viscosity_scale;
        a += viscous_acceleration(mu, viscous_u_s, u_f, rho_s, rho_f, m_f, laplacian_w);
    }
    if params.alpha > 0.0 {
        let u_sf = u_s - u_f;
        a += artificial_viscous_acceleration(
            params.alpha,
            params.c,
            params.h,
            offset,
            &u_sf,
            rho_s,
            rho_f,
            m_f,
            grad_w,
        );
    }
    a * m_s
}
