//! Eq. (18): density by summation, `ρ_i = Σ_j m_j W_ρ(|x_i − x_j|, h)`.
//!
//! Which kernel `W_ρ` is summed depends on the solver ([`DensityKernel`], `StepParams::density_kernel`):
//! - `wcsph`: the poly6 kernel (20), as the paper prints it.
//! - `corrected`: the spiky kernel (21) times the lattice factor `c = Σ W_poly6 / Σ W_spiky`
//!   ([`crate::physics::lattice::lattice_spiky_scale`]), so a particle of the initial lattice
//!   still sums exactly `ρ0` with the same lattice mass. Deviation from (18), and why: the
//!   correction (23) moves particles along the spiky gradient, the kernel of the pressure force
//!   (16), while (24) measures the poly6 sum. The sweep's operator, "density change per
//!   pressure increment", is then `J_poly6 · G_spiky`, which is not symmetric and has modes of
//!   either sign: measured on `scenes/hard/rest_3d.toml`, stages grew from a residual of 2e-4 to
//!   1e-3 and stalled at the 1,000-sweep cap while particles drifted sideways, and the first step
//!   gained 0.37 % of |E0| (kinetic plus potential energy). Summing the kernel whose gradient
//!   moves the particles makes the operator `G Gᵀ`-like (positive): every stage of that scene
//!   converges in at most 78 sweeps and the energy never rises (`tests/hard_cases/suite.rs`). The
//!   other single-kernel choice, poly6 for (16) too, pairs particles in 3D (its gradient
//!   vanishes at `r = 0`; the column collapsed by step 20); the spiky kernel `(h − r)³` is
//!   positive definite in 2D and 3D (Askey), so it does not pair (Dehnen & Aly 2012).

use crate::math::{Real, Vector};
use crate::smoothing::Smoothing;

/// The kernel `W_ρ` of the density sum (18), chosen by the solver (module doc). `#[repr(u32)]`
/// as a field of `StepParams`; `kernels/sph.cuh` names the same values `SPH_DENSITY_*`.
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DensityKernel {
    /// Poly6 (20): `wcsph`.
    Poly6 = 0,
    /// The spiky kernel (21) times the lattice factor `c` of [`DensityWeight::spiky_scale`]:
    /// `corrected`.
    ScaledSpiky = 1,
}

/// The kernel of eq. (18) with its factor: what [`density_kernel`] evaluates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DensityWeight {
    /// Which kernel.
    pub kernel: DensityKernel,
    /// The factor `c` of `c W_spiky` (`physics::lattice::lattice_spiky_scale`), dimensionless;
    /// unused with poly6.
    pub spiky_scale: Real,
}

impl DensityWeight {
    /// Poly6 (20).
    pub const POLY6: Self = Self {
        kernel: DensityKernel::Poly6,
        spiky_scale: 1.0,
    };

    /// `scale · W_spiky` (21).
    pub fn spiky(scale: Real) -> Self {
        Self {
            kernel: DensityKernel::ScaledSpiky,
            spiky_scale: scale,
        }
    }
}

/// The kernel of eq. (18) [1/m^D] at squared distance `r2` [m²]: poly6 (20) or
/// `c · W_spiky(r)` (21), as `weight` says (module doc).
#[inline(always)]
pub fn density_kernel<const D: usize>(kernel: &Smoothing<D>, weight: DensityWeight, r2: Real) -> Real {
    match weight.kernel {
        DensityKernel::ScaledSpiky => weight.spiky_scale * kernel.w_spiky(r2.sqrt()),
        DensityKernel::Poly6 => kernel.w(r2),
    }
}

/// Gradient [1/m^(D+1)] of [`density_kernel`] with respect to `x_i`, at `x = x_i − x_j` [m],
/// `r = |x|`: the continuity sum `dρ_i/dt = Σ_j m_j (u_i − u_j)·∇W_ρ` of the velocity solve
/// (`solver::step`) differentiates the sum (18) the correction measures.
#[inline(always)]
pub fn density_kernel_gradient<const D: usize>(
    kernel: &Smoothing<D>,
    weight: DensityWeight,
    x: &Vector<D>,
    r: Real,
) -> Vector<D> {
    match weight.kernel {
        DensityKernel::ScaledSpiky => kernel.grad_w_spiky(x, r) * weight.spiky_scale,
        DensityKernel::Poly6 => kernel.grad_w(x),
    }
}

/// Density ratio `ρ/ρ0` below which the velocity solve takes a particle for one at the free
/// surface (or in a splash): it has lost neighbours, and its sum (18) is low because of the
/// missing ones, not because it is expanded. After the position correction an interior particle
/// that carries pressure sits within δ of ρ0 (δ = 1e-4 by default, 1e-3 recommended), far above
/// this ratio; one expanded by more than 2 % (no pressure) is treated as a surface particle.
pub const SURFACE_DENSITY_RATIO: Real = 0.98;

/// The density [kg/m³] from which the velocity solve (`solver::step`) predicts `ρ* = base +
/// τ dρ/dt`, given the particle's density (18) `rho` after the position correction and its rest
/// density `rho0` [kg/m³]. Inside the fluid, `ρ0`: every compression counts, which makes the
/// interior's velocity divergence-free and damps the column's standing wave (docs/method.md,
/// "The velocity solve"). At the free surface (`rho < SURFACE_DENSITY_RATIO ρ0`), its own
/// density: a surface particle may close up until its sum reaches ρ0. With `ρ0` there too, the
/// 2D dam-break front runs 11.1 % ahead of the experiment, against 5.6 % with this rule. Twin
/// of `velocity_solve_base` in
/// `kernels/sph.cuh`.
#[inline(always)]
pub fn velocity_solve_base(rho: Real, rho0: Real) -> Real {
    if rho >= SURFACE_DENSITY_RATIO * rho0 {
        rho0
    } else {
        rho
    }
}

/// Eq. (18): contribution of neighbour `j` (mass `m_j` [kg]) at squared distance `r2` [m²] to
/// the density of particle `i` [kg/m³], with the kernel [`density_kernel`]. The sum includes
/// `j = i` (`r = 0`).
#[inline(always)]
pub fn density_term<const D: usize>(
    kernel: &Smoothing<D>,
    weight: DensityWeight,
    m_j: Real,
    r2: Real,
) -> Real {
    m_j * density_kernel(kernel, weight, r2)
}
