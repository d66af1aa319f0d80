//! Constants calibrated on the initial particle lattice, so that a fluid at rest on the lattice
//! starts in exact discrete equilibrium.
//!
//! The kernels (20)–(22) integrate exactly, but their sums over a lattice of spacing `dx` with
//! `h ≈ 2 dx` differ from the integrals by a few percent (poly6) up to 11 % (the spiky gradient's
//! first moment in 2D). Both are computed here in f64 by summing over lattice offsets.

use crate::math::Real;
use crate::smoothing::Smoothing;

/// Calls `f(offset²)` for every lattice offset `k dx`, `k ∈ [−n, n]^D`, `n = ceil(h/dx)`.
fn for_each_lattice_offset<const D: usize>(h: f64, dx: f64, mut f: impl FnMut(f64)) {
    let n = (h / dx).ceil() as i64;
    let mut idx = [-n; D];
    loop {
        f(idx.iter().map(|&k| (k as f64 * dx).powi(2)).sum());
        let mut axis = 0;
        loop {
            if axis == D {
                return;
            }
            idx[axis] += 1;
            if idx[axis] <= n {
                break;
            }
            idx[axis] = -n;
            axis += 1;
        }
    }
}

/// Mass [kg] (per unit depth in 2D) that gives an interior particle of a square/cubic lattice of
/// spacing `dx` [m] exactly the density `rho0` [kg/m³] under eq. (18): `m = ρ0 / Σ_lattice W`
/// rather than `ρ0 dx^D`, which would start every scene with a spurious pressure.
pub fn lattice_mass<const D: usize>(kernel: &Smoothing<D>, dx: f64, rho0: f64) -> f64 {
    let mut sum = 0.0f64;
    for_each_lattice_offset::<D>(f64::from(kernel.h), dx, |r2| {
        sum += f64::from(kernel.w(r2 as Real))
    });
    rho0 / sum
}

/// First moment of the spiky gradient (21) on the lattice,
/// `κ = −(1/D) Σ_j V_j x_ij · ∇W(x_ij)` with `V_j = m/ρ0` the lattice particle volume [m^D].
///
/// The SPH gradient of a linear field `p` is `κ ∇p` on the lattice, so the pressure force (16)
/// is divided by `κ` to make a hydrostatic column balance gravity at the exact pressure
/// `ρ0 g (H − z)` (κ ≈ 0.89 at h = 2dx in 2D, 0.96 in 3D; κ → 1 as h/dx grows).
pub fn lattice_gradient_moment<const D: usize>(kernel: &Smoothing<D>, dx: f64, rho0: f64) -> f64 {
    let volume = lattice_mass(kernel, dx, rho0) / rho0;
    let mut sum = 0.0f64;
    for_each_lattice_offset::<D>(f64::from(kernel.h), dx, |r2| {
        let r = r2.sqrt();
        let h = f64::from(kernel.h);
        if r > 0.0 && r < h {
            // −x·∇W = −r dW/dr for the spiky kernel: r · 3K (h − r)², with K from W(0) = K h³.
            let k = f64::from(kernel.w_spiky(0.0)) / h.powi(3);
            sum += volume * r * 3.0 * k * (h - r).powi(2);
        }
    });
    sum / D as f64
}

/// Second moment of the viscosity kernel's Laplacian (22) on the lattice,
/// `λ = Σ_{j≠i} V_j r_ij² ∇²W^visc(r_ij) / (2D)` with `V_j = m/ρ0` the lattice particle volume
/// [m^D]; dimensionless.
///
/// The SPH Laplacian of eq. (17), `Σ_j V_j (u_j − u_i) ∇²W^visc(r_ij)`, applied to a quadratic
/// field on the lattice is `λ ∇²u` (the continuum integral `∫ r² ∇²W dV = 2D ∫ W dV` makes it
/// `∇²u` exactly; the linear part cancels by symmetry), so the viscous force (17) is divided by
/// `λ` to give the fluid the scene's viscosity on the lattice, as the pressure force (16) is
/// divided by `κ` ([`lattice_gradient_moment`]). Measured: λ = 0.85 at h = 2dx in 2D (0.95 at
/// 3dx, 0.98 at 4dx); the missing 15 % made the Poiseuille profile 1.17 times too curved
/// (`tests/physics/poiseuille.rs`). Deviation (docs/method.md): the paper uses (17) unscaled.
pub fn lattice_laplacian_moment<const D: usize>(kernel: &Smoothing<D>, dx: f64, rho0: f64) -> f64 {
    let volume = lattice_mass(kernel, dx, rho0) / rho0;
    let mut sum = 0.0f64;
    for_each_lattice_offset::<D>(f64::from(kernel.h), dx, |r2| {
        let r = r2.sqrt();
        if r > 0.0 {
            sum += volume * r2 * f64::from(kernel.laplacian_w_viscosity(r as Real));
        }
    });
    sum / (2 * D) as f64
}

/// The factor `c = Σ_lattice W_poly6 / Σ_lattice W_spiky` that makes the spiky density of the
/// `corrected` solver, `Σ_j m c W_spiky` (`physics::density`), sum exactly `ρ0` on the lattice
/// with the lattice mass of [`lattice_mass`] (0.797 at h = 2dx in 2D, 0.817 in 3D).
pub fn lattice_spiky_scale<const D: usize>(kernel: &Smoothing<D>, dx: f64) -> f64 {
    let (mut poly6, mut spiky) = (0.0f64, 0.0f64);
    for_each_lattice_offset::<D>(f64::from(kernel.h), dx, |r2| {
        poly6 += f64::from(kernel.w(r2 as Real));
        spiky += f64::from(kernel.w_spiky(r2.sqrt() as Real));
    });
    poly6 / spiky
}

/// The step scale of the position correction (PAPER.md note 5), `K = ρ0² / (2 m² S)` with
/// `S = Σ_j ∇W_ρ(x_ij) · ∇W^press(x_ij)/κ` over a full lattice neighbourhood (the gradient of
/// the density kernel of (18) dotted with the scaled spiky gradient of the force (16)).
/// `weight` is the density kernel's (`physics::density::density_kernel`).
///
/// Derivation (the PCISPH argument of Solenthaler & Pajarola 2009): give particle `i` the
/// correction pressure `δp_i` and move it and its neighbours by eq. (23),
/// `Δx = τ² a^press`. On the lattice (`ρ ≈ ρ0`, `Σ_j ∇W_ij = 0`) the displacements it causes
/// change its summed density (18) by `Δρ_i = −2 τ² m² δp_i S / ρ0²`. Choosing
/// `δp_i = (K/τ²) (ρ_i − ρ0)` therefore removes the error of an isolated particle in one sweep,
/// whatever `τ`: the literal `δp = C² (ρ − ρ0)` is this with `C² τ² = K`, which overshoots and
/// diverges once `τ ≫ sqrt(K)/C`. The solver uses `ω K/τ²` with a relaxation `ω ≤ 1`, because
/// neighbours that are corrected at the same time (Jacobi sweep) add up. Units: `K` [m²], so
/// `K/τ²` [m²/s²] plays the role of `C²` in (19).
pub fn correction_stiffness<const D: usize>(
    kernel: &Smoothing<D>,
    dx: f64,
    rho0: f64,
    kappa: f64,
    weight: crate::physics::density::DensityWeight,
) -> f64 {
    let mass = lattice_mass(kernel, dx, rho0);
    let h = f64::from(kernel.h);
    let mut s = 0.0f64;
    for_each_lattice_offset::<D>(h, dx, |r2| {
        let r = r2.sqrt();
        if r > 0.0 && r < h {
            let mut x = crate::math::Vector::<D>::zeros();
            x[0] = r as Real;
            let gs = kernel.grad_w_spiky(&x, r as Real);
            let g_rho = crate::physics::density::density_kernel_gradient(kernel, weight, &x, r as Real);
            s += f64::from(g_rho.dot(&gs)) / kappa;
        }
    });
    rho0 * rho0 / (2.0 * mass * mass * s)
}
