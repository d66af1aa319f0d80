//! Fluid phases of different rest densities (the `multiphase` effect): the number-density form
//! of Hu & Adams 2006 ([HA06]: X. Y. Hu, N. A. Adams, "A multi-phase SPH method for
//! macroscopic and mesoscopic flows", J. Comput. Phys. 213 (2006) 844–861).
//!
//! Each particle carries its phase's rest density `ρ0_i` (`Fields::rest_density`) and a mass
//! `m_i` that gives its phase `ρ0_i` on the initial lattice (`physics::lattice::lattice_mass`).
//!
//! - Density: [HA06] replace the mass sum (18) by the particle number density
//!   `σ_i = Σ_j W_ij` [1/m^D] and `ρ_i = m_i σ_i`. Eq. (18) at a particle next to the interface
//!   sums the other phase's masses, so a light particle there reads a density between the two
//!   phases (with half its neighbours across, `(ρ0_j − ρ0_i)/(2 ρ0_i)`: a 12.5 % compression
//!   for oil 800 on water 1000, far above any δ) and its pressure (19) jumps; `m_i σ_i` depends only on where the neighbours are, not on their phase.
//! - Equation of state: (19) per particle with its own `ρ0_i` and one `C` for every phase:
//!   the relative compression of a phase under a pressure change `Δp` is `Δp/(ρ0_i C²)`, and the
//!   hydrostatic `Δp` in a phase scales with `ρ0_i`, so one `C` keeps every phase's density error
//!   at the same `g H / C²`, and the acoustic time step `h/C` is unchanged.
//! - Pressure force: [HA06]'s volume form `m_i a_i = −Σ_j (p_i V_i² + p_j V_j²) ∇W_ij` with
//!   `V = m/ρ = 1/σ` [m^D]. The symmetric form (16), `a_i = −Σ_j m_j (p_i/ρ_i² + p_j/ρ_j²) ∇W_ij`,
//!   weights each neighbour by `m_j/ρ_i²`: across an interface of density ratio `r` a uniform
//!   pressure `p` gives a light particle the spurious acceleration `(r − 1) p/ρ_i` times the
//!   one-sided gradient sum (about `1/dx`), because `Σ_j V_j ∇W_ij ≈ 0` holds for volumes, not
//!   for `m_j/ρ_i`. The volume form makes a uniform pressure exert no force whatever the phases
//!   (for equal volumes, which the lattice masses give). For a single phase it equals (16) up to
//!   rounding. Pair forces stay antisymmetric, so momentum is conserved.
//!   Measured on the two-layer tank (`tests/physics/multiphase.rs`, wcsph, dx = 5 mm, worst slab
//!   pressure against the piecewise hydrostatic profile, % of the bottom pressure): volume form
//!   1.63 / 1.64 / 1.27 % for ρ_top = 800 / 500 / 250 on 1000; (16) with the same number density
//!   1.70 / 2.42 / 2.52 %, and its water particles crossed the interface by 0.12–0.14 dx, while
//!   with the volume form they stayed 0.2–0.5 dx below it. So (16) is adequate at 800/1000 but
//!   degrades with the ratio; the volume form is used for every ratio. The viscous (17) and
//!   artificial viscosity terms keep their single-phase forms (Morris's `m_j/(ρ_i ρ_j)` weights
//!   already use each particle's own density).
//! - Position correction (eqs. 23–24): the increment and the compression measure use `ρ0_i`; the
//!   step scale `K = ρ0²/(2 m² S)` (`physics::lattice::correction_stiffness`) is the same for
//!   every phase because the lattice mass is proportional to `ρ0` (`m/ρ0` is one lattice volume).

use crate::math::{Real, Vector};
use crate::smoothing::Smoothing;

/// How many fluid phases a run has: the plan's choice between the single-phase stages and their
/// [HA06] variants (`StepParams::phases`, `kernels/sph.cuh`'s `SPH_PHASES_*`). `u32` values as in
/// the kernels.
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Phases {
    /// One fluid of the scene's rest density `ρ0`: eqs. (16), (18), (19) as written.
    #[default]
    Single = 0,
    /// The `multiphase` effect: each particle's own rest density `Fields::rest_density`, the
    /// number density and the volume-form pressure force of [HA06].
    Multi = 1,
}

impl Phases {
    /// Rest density `ρ0_i` [kg/m³] of particle `i`: the scene's `rho0` for one phase, else the
    /// particle's own from `rest_density` (`Fields::rest_density`, which `Simulation::with_phases`
    /// fills for every particle).
    #[inline(always)]
    pub fn rest_density(self, rest_density: &[Real], i: usize, rho0: Real) -> Real {
        match self {
            Phases::Single => rho0,
            Phases::Multi => rest_density[i],
        }
    }
}

/// [HA06] number density: contribution of a neighbour at squared distance `r2` [m²] to
/// `σ_i = Σ_j W_ij` [1/m^D] (the sum includes `j = i`), with the density kernel of (18)
/// (`physics::density::density_kernel` with `weight`).
#[inline(always)]
pub fn number_density_term<const D: usize>(
    kernel: &Smoothing<D>,
    weight: crate::physics::density::DensityWeight,
    r2: Real,
) -> Real {
    crate::physics::density::density_kernel(kernel, weight, r2)
}

/// [HA06] density from the number density: `ρ_i = m_i σ_i` [kg/m³], mass `m_i` [kg] (per unit
/// depth in 2D), `sigma` [1/m^D].
#[inline(always)]
pub fn density(m_i: Real, sigma: Real) -> Real {
    m_i * sigma
}

/// [HA06] pressure-force factor of one particle, `p V² = p (m/ρ)²` [Pa m^(2D)] (per unit depth
/// in 2D): pressure [Pa], mass [kg], density [kg/m³]. Computed once per particle, as
/// `physics::pressure::pressure_term` is for (16).
#[inline(always)]
pub fn pressure_term(p: Real, m: Real, rho: Real) -> Real {
    let v = m / rho;
    p * v * v
}

/// [HA06] pressure acceleration [m/s²] of particle `i` (mass `m_i` [kg]) due to neighbour `j`,
/// `−(Q_i + Q_j) ∇W_ij / m_i` with `Q = p V²` ([`pressure_term`]) and `grad_w` the (scaled)
/// spiky gradient [1/m^(D+1)]. Multiplied by `m_i` the pair force is antisymmetric in `i, j`.
#[inline(always)]
pub fn pressure_acceleration<const D: usize>(
    q_i: Real,
    q_j: Real,
    m_i: Real,
    grad_w: &Vector<D>,
) -> Vector<D> {
    grad_w * (-(q_i + q_j) / m_i)
}

/// The density a solid particle of mass `m_w` [kg] reads with the number density: `m_w σ_w`
/// [kg/m³], for the summed branch of the weakly compressible wall model
/// (`WallModel::ExtrapolatedOrSummed`). Eq. (18) there would count a heavy phase's masses as a
/// compression of the wall and push the heavy fluid away from it.
#[inline(always)]
pub fn wall_density(m_w: Real, sigma: Real) -> Real {
    density(m_w, sigma)
}

/// Buoyant acceleration [m/s²] (upwards positive, along `−g`) of a body of density `rho_b`
/// [kg/m³] at rest in a fluid of density `rho_f` [kg/m³] under gravity `g` [m/s²], with
/// added-mass coefficient `c_a` (dimensionless): `a = g (ρ_f − ρ_b)/(ρ_b + C_a ρ_f)`.
///
/// The body's momentum `(ρ_b + C_a ρ_f) V a = (ρ_f − ρ_b) V g` at the start of the motion, when
/// drag is still zero (Batchelor 1967, §6.4: `C_a = 1/2` for a sphere; 1 for a circular
/// cylinder, the 2D disc). Used by the tests as the early-time reference.
pub fn buoyant_acceleration(g: f64, rho_f: f64, rho_b: f64, c_a: f64) -> f64 {
    g * (rho_f - rho_b) / (rho_b + c_a * rho_f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::lattice::{lattice_mass, lattice_spiky_scale};

    #[test]
    fn uniform_pressure_exerts_no_force_across_a_lattice_interface() {
        // A 2D lattice, heavy below y < 0, light above; the centre particle sits at the
        // interface. With the volume form a uniform pressure gives zero net acceleration.
        let dx = 0.01f64;
        let kernel = Smoothing::<2>::new((2.0 * dx) as Real).expect("2D");
        let (rho_l, rho_h): (Real, Real) = (500.0, 1000.0);
        let (m_l, m_h) = (
            lattice_mass(&kernel, dx, f64::from(rho_l)) as Real,
            lattice_mass(&kernel, dx, f64::from(rho_h)) as Real,
        );
        let p = 1.0e4 as Real;
        let mut a_volume = Vector::<2>::zeros();
        let mut a_symmetric = Vector::<2>::zeros();
        for i in -3i32..=3 {
            for j in -3i32..=3 {
                if i == 0 && j == 0 {
                    continue;
                }
                let d = Vector::<2>::new(-(i as Real) * dx as Real, -(j as Real) * dx as Real);
                let r = d.norm();
                let grad = kernel.grad_w_spiky(&d, r);
                let (m_j, rho_j) = if j < 0 { (m_h, rho_h) } else { (m_l, rho_l) };
                a_volume += pressure_acceleration(
                    pressure_term(p, m_l, rho_l),
                    pressure_term(p, m_j, rho_j),
                    m_l,
                    &grad,
                );
                a_symmetric +=
                    crate::physics::pressure::pressure_acceleration(p, rho_l, p, rho_j, m_j, &grad);
            }
        }
        // Relative to the one-sided push p/(ρ dx) = 2000 m/s²: rounding only for the volume form.
        let scale = p / (rho_l * dx as Real);
        assert!(a_volume.norm() < 1e-5 * scale, "{a_volume:?}");
        assert!(a_symmetric.norm() > 0.1 * scale, "{a_symmetric:?}");
    }

    #[test]
    fn number_density_gives_each_phase_its_rest_density_on_the_lattice() {
        for (dx, ratio) in [(0.01f64, 2.0f64), (0.02, 1.5)] {
            let kernel = Smoothing::<2>::new((ratio * dx) as Real).expect("2D");
            let n = (ratio).ceil() as i32 + 1;
            // Both density kernels: poly6 (wcsph) and the scaled spiky one (corrected).
            for weight in [
                crate::physics::density::DensityWeight::POLY6,
                crate::physics::density::DensityWeight::spiky(lattice_spiky_scale(&kernel, dx) as Real),
            ] {
                let mut sigma = 0.0 as Real;
                for i in -n..=n {
                    for j in -n..=n {
                        let r2 = ((i * i + j * j) as f64 * dx * dx) as Real;
                        sigma += number_density_term(&kernel, weight, r2);
                    }
                }
                for rho0 in [500.0, 800.0, 1000.0, 2000.0] {
                    let m = lattice_mass(&kernel, dx, rho0) as Real;
                    let rho = density(m, sigma);
                    assert!(
                        ((f64::from(rho) - rho0) / rho0).abs() < 1e-5,
                        "dx {dx}, rho0 {rho0}, {weight:?}: {rho}"
                    );
                }
            }
        }
    }

    #[test]
    fn buoyant_acceleration_of_a_disc() {
        // Half as dense as water, C_a = 1: g (1000 − 500)/(500 + 1000) = g/3, upwards.
        assert!((buoyant_acceleration(9.81, 1000.0, 500.0, 1.0) - 9.81 / 3.0).abs() < 1e-12);
        assert!(buoyant_acceleration(9.81, 1000.0, 2000.0, 1.0) < 0.0);
    }
}
