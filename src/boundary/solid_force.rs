//! Force exerted by the fluid on a solid particle: the reaction to the pair forces (16)–(17).

use crate::math::{Real, Vector, to_xyz};
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

/// Cross product `a × b` of two three-component vectors.
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// One solid particle's share of its solid's load (`backend::SolidLoad`): the force `f_s` [N]
/// and its moment about the origin `x_s × f_s` [N m], in f64 (the solid's sums run in f64).
/// In 2D (z = 0) the moment is `x f_y − y f_x` in the z slot, per metre of depth [N m/m].
#[inline(always)]
pub fn particle_load<const D: usize>(x_s: &Vector<D>, f_s: &Vector<D>) -> [f64; 6] {
    let (x, f) = (to_xyz(x_s), to_xyz(f_s));
    let m = cross(x, f);
    [f[0], f[1], f[2], m[0], m[1], m[2]]
}

/// Moment [N m] (2D: [N m/m]) of a solid's load about the point `p` [m] (`dimension` entries,
/// z = 0 in 2D): `M_P = M_O − P × F`, from the moment `M_O` about the origin and the force `F`
/// of `load` (`backend::SolidLoad`), since `Σ (x_s − P) × f_s = Σ x_s × f_s − P × Σ f_s`.
pub fn moment_about(load: &[f64; 6], p: &[f64]) -> [f64; 3] {
    let mut point = [0.0; 3];
    for (c, v) in point.iter_mut().zip(p) {
        *c = *v;
    }
    let arm = cross(point, [load[0], load[1], load[2]]);
    [load[3] - arm[0], load[4] - arm[1], load[5] - arm[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `M_P = M_O − P × F` against the moment summed about `P` directly, for two particles'
    /// loads in 3D and in 2D; the numbers are small integers, so the f64 sums are exact.
    #[test]
    fn moment_about_a_point_is_the_origin_moment_less_p_cross_f() {
        let particles = [
            ([1.0, 2.0, -1.0], [3.0, -1.0, 2.0]),
            ([-2.0, 0.5, 4.0], [0.5, 2.0, -3.0]),
        ];
        let p = [0.5, -1.0, 2.0];
        let mut load = [0.0; 6];
        let mut direct = [0.0; 3];
        for (x, f) in particles {
            let l = particle_load::<3>(&Vector::<3>::from(x), &Vector::<3>::from(f));
            for k in 0..6 {
                load[k] += l[k];
            }
            let arm = [
                f64::from(x[0]) - p[0],
                f64::from(x[1]) - p[1],
                f64::from(x[2]) - p[2],
            ];
            let m = cross(arm, [f[0], f[1], f[2]].map(f64::from));
            for k in 0..3 {
                direct[k] += m[k];
            }
        }
        assert_eq!(moment_about(&load, &p), direct);
        // 2D: the z moment only, `(x − P_x) f_y − (y − P_y) f_x`.
        let l = particle_load::<2>(&Vector::<2>::new(1.0, 2.0), &Vector::<2>::new(3.0, -1.0));
        assert_eq!(
            moment_about(&l, &[0.5, -1.0]),
            [0.0, 0.0, -(1.0 - 0.5) - (2.0 + 1.0) * 3.0]
        );
    }
}
