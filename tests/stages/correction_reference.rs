//! Brute-force references of the position correction (eqs. 19, 23, 24 with [A12] at the walls)
//! shared by `correction` and `velocity_solve`: the loop's error, the pressure increments of
//! fluid and walls, the displacements, and the states they start from.

use crate::setup::{DX, RHO0, Under, in_id_order, neighbours};
use nalgebra::SVector;
use sph::backend::{Backend, CorrectionError};
use sph::fields::{FLUID, Fields};
use sph::model::params::StepParams;
use sph::physics::correction::{self, MOMENTUM};
use sph::physics::lattice::correction_stiffness;
use sph::physics::multiphase::{self, Phases};
use sph::physics::pressure::{pressure_acceleration_from_terms, pressure_term};

/// f32's machine epsilon: one f32 operation rounds within `EPS/2` of its value.
pub(super) const EPS: f64 = f32::EPSILON as f64;
/// Rest density of the lighter phase with [`Phases::Multi`] [kg/m³].
pub(super) const RHO0_LIGHT: f32 = 800.0;
/// f64 vectors of the references.
pub(super) type V64<const D: usize> = SVector<f64, D>;

/// The correction's stiffness `ω K/τ²` [m²/s²] as the driver forms it (`ω = 0.5`).
pub(super) fn stiffness<const D: usize>(p: &StepParams<D>, tau: f32) -> f32 {
    let kappa = 1.0 / f64::from(p.pressure_gradient_scale);
    let k = correction_stiffness(
        &p.smoothing(),
        f64::from(DX),
        f64::from(RHO0),
        kappa,
        p.density_weight(),
    );
    (0.5 * k / f64::from(tau * tau)) as f32
}

/// [HA06] two phases: the fluid in the left half of `setup::scene`'s block becomes the lighter
/// phase (its own rest density, mass and density scaled by `RHO0_LIGHT/ρ0`); solids keep ρ0.
pub(super) fn two_phases<const D: usize>(f: &mut Fields<D>, p: &mut StepParams<D>) {
    let middle = if D == 2 { 12.0 * DX } else { 5.0 * DX };
    p.phases = Phases::Multi;
    f.rest_density = (0..f.len())
        .map(|i| {
            if f.kind[i] == FLUID && f.position[i][0] < middle {
                RHO0_LIGHT
            } else {
                RHO0
            }
        })
        .collect();
    for i in 0..f.len() {
        let ratio = f.rest_density[i] / RHO0;
        f.mass[i] *= ratio;
        f.density[i] *= ratio;
    }
}

/// The backend's state in id order (the CPU backend works on `f` itself).
pub(super) fn snapshot<const D: usize>(b: &mut dyn Backend<D>, f: &mut Fields<D>) -> Fields<D> {
    b.download(f).expect("download");
    in_id_order(f)
}

/// Eq. (24) with note 6 by brute force over the fluid of `f`: the largest
/// `correction::compression` and `correction::residual`, each particle against its own ρ0 with
/// several phases. A NaN wins the maximum: the residual stays NaN (`correction::residual`),
/// the compression drops it (`correction::compression` is `max(e, 0)`).
pub(super) fn reference_error<const D: usize>(f: &Fields<D>, p: &StepParams<D>) -> CorrectionError {
    let max = |a: f64, b: f64| {
        if a.is_nan() || b.is_nan() {
            f64::NAN
        } else {
            a.max(b)
        }
    };
    let (mut compression, mut residual) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for i in (0..f.len()).filter(|&i| f.kind[i] == FLUID) {
        let rho0 = p.phases.rest_density(&f.rest_density, i, p.rho0);
        compression = max(compression, correction::compression(f.density[i], rho0));
        residual = max(residual, correction::residual(f.density[i], rho0, f.pressure[i]));
    }
    CorrectionError {
        compression: compression.max(0.0),
        residual: if residual.is_nan() {
            residual
        } else {
            residual.max(0.0)
        },
    }
}

/// `got` against `want`, bitwise: the CPU returns the f64 maxima; the CUDA backend's go through
/// an f32 atomic (`kernels/correction.cu`), so `want` rounded to f32 (rounding is monotone: the
/// maximum of the rounded values is the rounded maximum).
pub(super) fn check_error(under: Under, label: &str, got: CorrectionError, want: CorrectionError) {
    let round = |x: f64| {
        if under == Under::Cpu {
            x
        } else {
            f64::from(x as f32)
        }
    };
    for (what, g, w) in [
        ("compression", got.compression, want.compression),
        ("residual", got.residual, want.residual),
    ] {
        assert!(
            g.to_bits() == round(w).to_bits() || (g.is_nan() && w.is_nan()),
            "{under:?} {label}: {what} {g:e} against {w:e}"
        );
    }
}

/// Eq. (19) inside the correction for fluid particle `i` of `f`: `δp` with the heavy-ball term
/// `m = β δp_prev` where `previous` is given.
pub(super) fn fluid_increment<const D: usize>(
    f: &Fields<D>,
    phases: Phases,
    p: &StepParams<D>,
    k: f32,
    i: usize,
    previous: Option<f32>,
) -> f32 {
    let m = previous.map_or(0.0, |d| MOMENTUM * d);
    let rho0 = phases.rest_density(&f.rest_density, i, p.rho0);
    correction::pressure_increment(f.density[i], rho0, f.pressure[i] + m, k) + m
}

/// [A12] eq. (27) without gravity for solid `w` of `f`: `Σ δp_f W / Σ W` over its fluid
/// neighbours (brute force, poly6 weights) and `Σ |δp_f| W / Σ W`, in f64; zeros without any.
pub(super) fn wall_increment<const D: usize>(
    f: &Fields<D>,
    p: &StepParams<D>,
    dp: &[f32],
    w: usize,
) -> (f64, f64) {
    let kernel = p.smoothing();
    let (mut sum, mut abs, mut weight) = (0.0f64, 0.0f64, 0.0f64);
    for (j, _, r) in neighbours(f, p.h, w) {
        if f.kind[j] == FLUID {
            let wt = f64::from(kernel.w(r * r));
            sum += f64::from(dp[j]) * wt;
            abs += f64::from(dp[j]).abs() * wt;
            weight += wt;
        }
    }
    if weight > 0.0 {
        (sum / weight, abs / weight)
    } else {
        (0.0, 0.0)
    }
}

/// Eq. (23) by brute force for every fluid particle of `f`: `Δx_i = τ² Σ_j a_ij`, the pressure
/// force (16) of the increments `dp` with the densities `density`, or with `Phases::Multi` its
/// [HA06] volume form, summed in f64 from the f32 pair terms; and the scale of the backends' f32
/// sum, `τ² Σ_j (|a_ij| + |∂a_ij/∂δp_j| dp_error_j)` (`dp_error`: how far the backend's `δp_j`
/// may be from `dp_j`). Zero for solids. `solids: false` leaves the solid neighbours out (for
/// the checks that their terms show).
#[allow(clippy::too_many_arguments)]
pub(super) fn reference_displacements<const D: usize>(
    f: &Fields<D>,
    p: &StepParams<D>,
    phases: Phases,
    density: &[f32],
    dp: &[f32],
    dp_error: &[f64],
    tau: f32,
    solids: bool,
) -> Vec<(V64<D>, f64)> {
    let kernel = p.smoothing();
    let tau2 = f64::from(tau * tau);
    (0..f.len())
        .map(|i| {
            let (mut dx, mut scale) = (V64::<D>::zeros(), 0.0f64);
            if f.kind[i] != FLUID {
                return (dx, scale);
            }
            for (j, d, r) in neighbours(f, p.h, i) {
                if !solids && f.kind[j] != FLUID {
                    continue;
                }
                let grad = kernel.grad_w_spiky(&d, r) * p.pressure_gradient_scale;
                let (a, per_dp_j) = if phases == Phases::Multi {
                    let q = |k: usize| multiphase::pressure_term(dp[k], f.mass[k], density[k]);
                    let v_j = f64::from(f.mass[j] / density[j]);
                    let a = multiphase::pressure_acceleration(q(i), q(j), f.mass[i], &grad);
                    (a, v_j * v_j / f64::from(f.mass[i]))
                } else {
                    let (q_i, q_j) = (pressure_term(dp[i], density[i]), pressure_term(dp[j], density[j]));
                    let rho_j = f64::from(density[j]);
                    let a = pressure_acceleration_from_terms(q_i, q_j, f.mass[j], &grad);
                    (a, f64::from(f.mass[j]) / (rho_j * rho_j))
                };
                dx += a.cast::<f64>();
                scale += f64::from(a.norm()) + per_dp_j * f64::from(grad.norm()) * dp_error[j];
            }
            (dx * tau2, scale * tau2)
        })
        .collect()
}

/// Rest density `ρ0_i` of particle `i` of `f` [kg/m³].
pub(super) fn rest<const D: usize>(f: &Fields<D>, p: &StepParams<D>, i: usize) -> f32 {
    p.phases.rest_density(&f.rest_density, i, p.rho0)
}
