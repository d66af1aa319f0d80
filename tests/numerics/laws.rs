//! Laws of the smoothing kernels of eqs. (20)–(22) (`sph::smoothing`), in 2D and 3D: unit
//! integral, the viscosity Laplacian's second moment, positivity, symmetry, odd gradients,
//! compact support, finiteness at coincident particles, and gradients that match finite
//! differences of the kernel values.

use proptest::prelude::*;
use sph::math::{Real, Vector};
use sph::smoothing::{R_MIN_FRACTION, Smoothing};
use std::f64::consts::PI;

/// Tolerance of every normalisation law (unit integral, second moment), relative.
const NORMALISATION_TOL: f64 = 1.0e-3;

/// Smallest and largest support radius drawn by the property tests [m].
const H_MIN: f64 = 1.0e-3;
const H_MAX: f64 = 10.0;

fn kernel<const D: usize>(h: Real) -> Smoothing<D> {
    Smoothing::<D>::new(h).expect("2D and 3D are supported")
}

/// Surface of the unit sphere in `d` dimensions: 2π in 2D, 4π in 3D.
fn unit_sphere_surface(d: usize) -> f64 {
    match d {
        2 => 2.0 * PI,
        3 => 4.0 * PI,
        _ => unreachable!("only 2D and 3D kernels exist"),
    }
}

/// Nodes and weights of `n`-point Gauss–Legendre quadrature on [−1, 1] (Newton on `P_n`).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-15 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Composite Gauss–Legendre quadrature of `f` over `[a, b]`: `panels` equal panels of 8 nodes.
fn integrate(f: impl Fn(f64) -> f64, a: f64, b: f64, panels: usize) -> f64 {
    let rule = gauss_legendre(8);
    let width = (b - a) / panels as f64;
    (0..panels)
        .map(|p| {
            let mid = a + (p as f64 + 0.5) * width;
            rule.iter()
                .map(|&(x, w)| w * f(mid + 0.5 * width * x))
                .sum::<f64>()
                * 0.5
                * width
        })
        .sum()
}

/// Radial quadrature `∫₀ʰ S_d r^(d−1) W(r) dr` of a radial kernel `w(r)` (f32 values, f64 sum).
///
/// The panels break at `R_MIN_FRACTION·h`, where the singular kernels stop following their
/// formula (PAPER.md note 4), so each panel integrates a smooth function.
fn radial_integral<const D: usize>(h: Real, w: impl Fn(Real) -> Real) -> f64 {
    let (hd, d) = (f64::from(h), D as i32);
    let f = |r: f64| unit_sphere_surface(D) * r.powi(d - 1) * f64::from(w(r as Real));
    let core = f64::from(R_MIN_FRACTION) * hd;
    integrate(f, 0.0, core, 4) + integrate(f, core, hd, 64)
}

/// `∫₀^ε S_d r^(d−1) W(r) dr` of eq. (22) as written (no clamp), with `ε = R_MIN_FRACTION·h`:
/// the part of the unit integral that the clamped kernel (note 4) does not represent.
fn viscosity_core_exact<const D: usize>(h: f64) -> f64 {
    let e = f64::from(R_MIN_FRACTION) * h;
    match D {
        // K = 10/(3π h²); ∫ 2π r (−r³/2h³ + r²/h² + h/2r − 1) dr
        2 => {
            let k = 10.0 / (3.0 * PI * h * h);
            2.0 * PI
                * k
                * (-e.powi(5) / (10.0 * h.powi(3)) + e.powi(4) / (4.0 * h * h) + h * e / 2.0 - e * e / 2.0)
        }
        // K = 15/(2π h³); ∫ 4π r² (…) dr
        3 => {
            let k = 15.0 / (2.0 * PI * h.powi(3));
            4.0 * PI
                * k
                * (-e.powi(6) / (12.0 * h.powi(3)) + e.powi(5) / (5.0 * h * h) + h * e * e / 4.0
                    - e.powi(3) / 3.0)
        }
        _ => unreachable!("only 2D and 3D kernels exist"),
    }
}

/// The integrals of eqs. (20)–(22) over their support, by radial quadrature of the f32 kernels.
/// The viscosity kernel's integral takes the core `[0, R_MIN·h]` from the formula (see
/// [`viscosity_core_exact`]), so it proves the normalisation constant of (22).
fn kernel_integrals<const D: usize>(h: Real) -> [(&'static str, f64); 3] {
    let k = kernel::<D>(h);
    let core = f64::from(R_MIN_FRACTION) * f64::from(h);
    let poly6 = radial_integral::<D>(h, |r| k.w(r * r));
    let spiky = radial_integral::<D>(h, |r| k.w_spiky(r));
    let d = D as i32;
    let visc_outer = integrate(
        |r| unit_sphere_surface(D) * r.powi(d - 1) * f64::from(k.w_viscosity(r as Real)),
        core,
        f64::from(h),
        64,
    );
    let viscosity = visc_outer + viscosity_core_exact::<D>(f64::from(h));
    [("poly6", poly6), ("spiky", spiky), ("viscosity", viscosity)]
}

fn assert_unit_integrals<const D: usize>(h: Real) -> Result<(), TestCaseError> {
    for (name, integral) in kernel_integrals::<D>(h) {
        prop_assert!(
            (integral - 1.0).abs() < NORMALISATION_TOL,
            "{D}D {name} kernel, h = {h}: ∫W dV = {integral}"
        );
    }
    Ok(())
}

/// `∫ r² ∇²W dV` of the viscosity kernel's Laplacian, by radial quadrature.
fn viscosity_laplacian_second_moment<const D: usize>(h: Real) -> f64 {
    let k = kernel::<D>(h);
    radial_integral::<D>(h, |r| r * r * k.laplacian_w_viscosity(r))
}

/// Midpoint rule of `∫ W(|x|) dV` on an `n^D` Cartesian grid over `[−h, h]^D`.
fn cartesian_integral<const D: usize>(h: Real, n: usize, w: impl Fn(&Vector<D>) -> Real) -> f64 {
    let hd = f64::from(h);
    let dx = 2.0 * hd / n as f64;
    let cells = n.pow(D as u32);
    let mut sum = 0.0;
    for c in 0..cells {
        let mut x = Vector::<D>::zeros();
        let mut t = c;
        for k in 0..D {
            x[k] = (-hd + (((t % n) as f64) + 0.5) * dx) as Real;
            t /= n;
        }
        sum += f64::from(w(&x));
    }
    sum * dx.powi(D as i32)
}

/// A unit vector from components in [−1, 1]; `None` when they are too short to normalise.
fn unit<const D: usize>(c: &[f64]) -> Option<[f64; D]> {
    let n = c[..D].iter().map(|v| v * v).sum::<f64>().sqrt();
    if n < 0.1 {
        return None;
    }
    let mut u = [0.0; D];
    for k in 0..D {
        u[k] = c[k] / n;
    }
    Some(u)
}

fn vector<const D: usize>(c: &[f64; D]) -> Vector<D> {
    Vector::<D>::from_iterator(c.iter().map(|&v| v as Real))
}

/// Every kernel value, gradient and Laplacian at offset `x`, `r = |x|`, flattened.
fn all_values<const D: usize>(k: &Smoothing<D>, x: &Vector<D>, r: Real) -> Vec<(&'static str, Real)> {
    let mut v = vec![
        ("w", k.w(r * r)),
        ("laplacian_w", k.laplacian_w(r * r)),
        ("w_spiky", k.w_spiky(r)),
        ("laplacian_w_spiky", k.laplacian_w_spiky(r)),
        ("w_viscosity", k.w_viscosity(r)),
        ("laplacian_w_viscosity", k.laplacian_w_viscosity(r)),
    ];
    for (name, g) in [
        ("grad_w", k.grad_w(x)),
        ("grad_w_spiky", k.grad_w_spiky(x, r)),
        ("grad_w_viscosity", k.grad_w_viscosity(x, r)),
    ] {
        v.extend(g.iter().map(|&c| (name, c)));
    }
    v
}

fn h_strategy() -> impl Strategy<Value = f64> {
    // Log-uniform over [H_MIN, H_MAX], so every decade is exercised.
    (H_MIN.ln()..=H_MAX.ln()).prop_map(f64::exp)
}

fn direction() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(-1.0f64..=1.0, 3)
}

/// `h` as [`Real`], its kernel, and the point `x` at `q h` along `c` with its mirror `−x`;
/// `None` when `c` gives no direction.
fn mirrored<const D: usize>(h: f64, c: &[f64], q: f64) -> Option<(Real, Smoothing<D>, Vector<D>, Vector<D>)> {
    let u = unit::<D>(c)?;
    let h = h as Real;
    let x = vector::<D>(&u.map(|v| v * q * f64::from(h)));
    Some((h, kernel::<D>(h), x, -x))
}

fn symmetric_and_positive<const D: usize>(h: f64, c: &[f64], q: f64) -> Result<(), TestCaseError> {
    let Some((h, k, x, minus)) = mirrored::<D>(h, c, q) else {
        return Ok(());
    };
    let (r, rm) = (x.norm(), minus.norm());
    for (name, a, b) in [
        ("w", k.w(x.norm_squared()), k.w(minus.norm_squared())),
        ("w_spiky", k.w_spiky(r), k.w_spiky(rm)),
        ("w_viscosity", k.w_viscosity(r), k.w_viscosity(rm)),
    ] {
        prop_assert!(a >= 0.0, "{D}D {name}({x:?}) = {a} < 0, h = {h}");
        prop_assert_eq!(a, b, "{}D {}: W(x) ≠ W(−x) at x = {:?}", D, name, x);
    }
    Ok(())
}

fn gradients_are_odd<const D: usize>(h: f64, c: &[f64], q: f64) -> Result<(), TestCaseError> {
    let Some((h, k, x, minus)) = mirrored::<D>(h, c, q) else {
        return Ok(());
    };
    let (r, rm) = (x.norm(), minus.norm());
    for (name, g, gm) in [
        ("grad_w", k.grad_w(&x), k.grad_w(&minus)),
        ("grad_w_spiky", k.grad_w_spiky(&x, r), k.grad_w_spiky(&minus, rm)),
        (
            "grad_w_viscosity",
            k.grad_w_viscosity(&x, r),
            k.grad_w_viscosity(&minus, rm),
        ),
    ] {
        prop_assert_eq!(
            gm,
            -g,
            "{}D {}: ∇W(−x) ≠ −∇W(x) at x = {:?}, h = {}",
            D,
            name,
            x,
            h
        );
    }
    Ok(())
}

fn zero_outside_support<const D: usize>(h: f64, c: &[f64], q: f64) -> Result<(), TestCaseError> {
    let Some(u) = unit::<D>(c) else { return Ok(()) };
    let h = h as Real;
    let k = kernel::<D>(h);
    // r = h exactly, on an axis so that |x| = h and |x|² = h² hold in f32.
    for axis in 0..D {
        for sign in [1.0, -1.0] {
            let mut x = Vector::<D>::zeros();
            x[axis] = sign * h;
            prop_assert_eq!(x.norm(), h);
            prop_assert_eq!(x.norm_squared(), k.h2);
            for (name, v) in all_values(&k, &x, h) {
                prop_assert_eq!(v, 0.0, "{}D {} at r = h = {}", D, name, h);
            }
        }
    }
    // Random r > h (q ≥ 1 + 1e-5: tens of ulps beyond h).
    let x = vector::<D>(&u.map(|v| v * q * f64::from(h)));
    let r = x.norm();
    prop_assume!(r > h && x.norm_squared() > k.h2);
    for (name, v) in all_values(&k, &x, r) {
        prop_assert_eq!(v, 0.0, "{}D {} at r = {} > h = {}", D, name, r, h);
    }
    Ok(())
}

fn finite_near_zero<const D: usize>(h: f64, c: &[f64], q: f64) -> Result<(), TestCaseError> {
    let h = h as Real;
    let k = kernel::<D>(h);
    let z = Vector::<D>::zeros();
    for (name, v) in all_values(&k, &z, 0.0) {
        prop_assert!(v.is_finite(), "{D}D {name} at r = 0 is {v}, h = {h}");
    }
    let Some(u) = unit::<D>(c) else { return Ok(()) };
    let x = vector::<D>(&u.map(|v| v * q * f64::from(h)));
    let r = x.norm();
    for (name, v) in all_values(&k, &x, r) {
        prop_assert!(
            v.is_finite(),
            "{D}D {name} at r = {r} (x = {x:?}) is {v}, h = {h}"
        );
    }
    Ok(())
}

/// Central differences of the f32 kernel values along each axis, positions and `r` in f64.
fn finite_difference<const D: usize>(x: &[f64; D], step: f64, w: impl Fn(f64) -> f64) -> [f64; D] {
    let mut g = [0.0; D];
    for k in 0..D {
        let radius = |s: f64| {
            let mut y = *x;
            y[k] += s;
            y.iter().map(|v| v * v).sum::<f64>().sqrt()
        };
        g[k] = (w(radius(step)) - w(radius(-step))) / (2.0 * step);
    }
    g
}

/// Each analytic gradient component is within `2e-3·|∇W| + 1e-4·W(0)/h` of the finite
/// difference; the second term is the scale of the gradient, for components near zero.
fn gradients_match_finite_differences<const D: usize>(
    h: f64,
    c: &[f64],
    q: f64,
) -> Result<(), TestCaseError> {
    let Some(u) = unit::<D>(c) else { return Ok(()) };
    let hr = h as Real;
    let h = f64::from(hr);
    let k = kernel::<D>(hr);
    let x64 = u.map(|v| v * q * h);
    let x = vector::<D>(&x64);
    let r = x.norm();
    let step = 1.0e-3 * h;
    let poly6 = finite_difference(&x64, step, |r| f64::from(k.w((r * r) as Real)));
    let spiky = finite_difference(&x64, step, |r| f64::from(k.w_spiky(r as Real)));
    let visc = finite_difference(&x64, step, |r| f64::from(k.w_viscosity(r as Real)));
    let cases = [
        ("grad_w", k.grad_w(&x), poly6, f64::from(k.w(0.0))),
        (
            "grad_w_spiky",
            k.grad_w_spiky(&x, r),
            spiky,
            f64::from(k.w_spiky(0.0)),
        ),
        (
            "grad_w_viscosity",
            k.grad_w_viscosity(&x, r),
            visc,
            f64::from(k.w_viscosity(0.05 * hr)),
        ),
    ];
    for (name, g, fd, w0) in cases {
        let norm = f64::from(g.norm());
        for axis in 0..D {
            let err = (f64::from(g[axis]) - fd[axis]).abs();
            let tol = 2.0e-3 * norm + 1.0e-4 * w0 / h;
            prop_assert!(
                err <= tol,
                "{D}D {name}, h = {h}, x = {x64:?}: analytic {} vs finite difference {} (|err| {err:e} > {tol:e})",
                g[axis],
                fd[axis]
            );
        }
    }
    Ok(())
}

proptest! {
    #[test]
    fn kernels_integrate_to_one_in_2d(h in h_strategy()) {
        assert_unit_integrals::<2>(h as Real)?;
    }

    #[test]
    fn kernels_integrate_to_one_in_3d(h in h_strategy()) {
        assert_unit_integrals::<3>(h as Real)?;
    }

    #[test]
    fn viscosity_laplacian_has_second_moment_2d_in_2d(h in h_strategy()) {
        let m = viscosity_laplacian_second_moment::<2>(h as Real);
        prop_assert!((m / 4.0 - 1.0).abs() < NORMALISATION_TOL, "h = {h}: ∫ r² ∇²W dA = {m}, want 4");
    }

    #[test]
    fn viscosity_laplacian_has_second_moment_2d_in_3d(h in h_strategy()) {
        let m = viscosity_laplacian_second_moment::<3>(h as Real);
        prop_assert!((m / 6.0 - 1.0).abs() < NORMALISATION_TOL, "h = {h}: ∫ r² ∇²W dV = {m}, want 6");
    }
}

/// Runs each check as two property tests, in 2D and in 3D, on a random `h`, direction `c` and
/// `q` in its range, so a check is written once for both dimensions.
macro_rules! in_2d_and_3d {
    ($($check:ident, $q:expr => $name_2d:ident, $name_3d:ident;)*) => {
        proptest! {
            $(
                #[test]
                fn $name_2d(h in h_strategy(), c in direction(), q in $q) {
                    $check::<2>(h, &c, q)?;
                }

                #[test]
                fn $name_3d(h in h_strategy(), c in direction(), q in $q) {
                    $check::<3>(h, &c, q)?;
                }
            )*
        }
    };
}

in_2d_and_3d! {
    symmetric_and_positive, 0.0f64..1.5
        => kernels_are_non_negative_and_even_in_2d, kernels_are_non_negative_and_even_in_3d;
    gradients_are_odd, 0.0f64..1.5 => gradients_are_odd_in_2d, gradients_are_odd_in_3d;
    zero_outside_support, 1.00001f64..100.0
        => kernels_vanish_at_and_beyond_support_in_2d, kernels_vanish_at_and_beyond_support_in_3d;
    finite_near_zero, 0.0f64..=1.0e-6
        => kernels_are_finite_near_coincidence_in_2d, kernels_are_finite_near_coincidence_in_3d;
    gradients_match_finite_differences, 0.05f64..0.9
        => gradients_match_finite_differences_in_2d, gradients_match_finite_differences_in_3d;
}

/// The Cartesian (vector-form) integral of poly6 and spiky, by the midpoint rule.
fn assert_cartesian_unit_integrals<const D: usize>(n: usize) {
    let h: Real = 0.37;
    let k = kernel::<D>(h);
    let poly6 = cartesian_integral::<D>(h, n, |x| k.w(x.norm_squared()));
    let spiky = cartesian_integral::<D>(h, n, |x| k.w_spiky(x.norm()));
    for (name, integral) in [("poly6", poly6), ("spiky", spiky)] {
        assert!(
            (integral - 1.0).abs() < NORMALISATION_TOL,
            "{D}D {name}: Cartesian midpoint ∫W dV = {integral}"
        );
    }
}

#[test]
fn kernels_integrate_to_one_on_a_cartesian_grid_in_2d() {
    assert_cartesian_unit_integrals::<2>(400);
}

#[test]
fn kernels_integrate_to_one_on_a_cartesian_grid_in_3d() {
    assert_cartesian_unit_integrals::<3>(120);
}

/// The kernels as implemented, clamp included (note 4): the clamp removes the mass
/// `π K h ε / 2` (2D) or `π K h ε² / 3` (3D) of the `h/2r` singularity inside `ε = R_MIN·h`.
/// This pins the clamp's deficit, so a change of `R_MIN_FRACTION` or of the clamp shows here.
#[test]
fn clamped_viscosity_kernel_misses_only_the_core_mass() {
    fn check<const D: usize>(h: Real) {
        let k = kernel::<D>(h);
        let clamped = radial_integral::<D>(h, |r| k.w_viscosity(r));
        let eps = f64::from(R_MIN_FRACTION);
        let deficit = match D {
            2 => PI * 10.0 / (3.0 * PI) * eps / 2.0,
            _ => PI * 15.0 / (2.0 * PI) * eps * eps / 3.0,
        };
        let expected = 1.0 - deficit;
        assert!(
            (clamped - expected).abs() < 1.0e-5,
            "{D}D clamped viscosity kernel, h = {h}: ∫W dV = {clamped}, expected {expected}"
        );
    }
    for h in [1.0e-3, 0.02, 1.0, 10.0] {
        check::<2>(h);
        check::<3>(h);
    }
}
