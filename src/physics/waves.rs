//! Linear (Airy) water waves and first-order wave-maker theory, for the piston wave maker
//! (`boundary::motion::Piston`) and the checks of a wave flume.
//!
//! - The linear dispersion relation `ω² = g k tanh(k d)` [DD91] eq. (4.20), with `ω = 2π/T`
//!   [rad/s], `g` [m/s²], `k = 2π/L` [1/m] and the still-water depth `d` [m], solved for `k` by
//!   Newton's method ([`wavenumber`]).
//! - The piston's transfer function (Biésel): the ratio of the far-field wave height `H` [m]
//!   to the piston's stroke `S` [m] (its full excursion, twice the amplitude),
//!   `H/S = 2 (cosh 2kd − 1) / (sinh 2kd + 2kd)` [DD91] eq. (6.20) ([`piston_height_per_stroke`]).
//! - The flap's transfer function ([DD91] §6.2), `S` the stroke at the still-water level, for a
//!   flap hinged at the bed and, by the same integral, at a height `l` above (or below) it
//!   ([`flap_height_per_stroke`]).
//!
//! [DD91] Dean & Dalrymple, *Water Wave Mechanics for Engineers and Scientists*, World
//! Scientific (1991), chapters 4 and 6.

/// The wavenumber `k` [1/m] of linear waves of angular frequency `omega` [rad/s] on water
/// `depth` [m] deep under gravity `g` [m/s²]: the root of `F(k) = g k tanh(k d) − ω² = 0`
/// ([DD91] eq. 4.20).
///
/// Newton's method from the deep-water root `k₀ = ω²/g` when that is the shallower guess
/// (`k₀ d ≥ 1`), else from the shallow-water root `ω/√(g d)`: `F` is increasing and convex in
/// `k` for `k > 0`, so from any start above the root the iterates fall monotonically onto it,
/// and both starts lie above it (`tanh x < 1` and `tanh x < x`). Stops when the step is below
/// `1e-14 k`; in double precision this takes fewer than ten iterations for any `k d`. Inputs
/// must be positive and finite (the caller validates them).
pub fn wavenumber(omega: f64, depth: f64, g: f64) -> f64 {
    let deep = omega * omega / g;
    let shallow = omega / (g * depth).sqrt();
    let mut k = deep.max(shallow);
    for _ in 0..100 {
        let t = (k * depth).tanh();
        let f = g * k * t - omega * omega;
        // F'(k) = g tanh(kd) + g k d sech²(kd).
        let df = g * t + g * k * depth * (1.0 - t * t);
        let step = f / df;
        k -= step;
        if step.abs() <= 1e-14 * k {
            break;
        }
    }
    k
}

/// Biésel's transfer function of a piston wave maker ([DD91] eq. 6.20): the height `H` [m] of
/// the progressive wave it makes per metre of stroke `S` (full excursion),
/// `H/S = 2 (cosh 2kd − 1) / (sinh 2kd + 2kd)`, for `k d` [dimensionless] > 0. It rises from
/// `k d` in shallow water (`H/S → kd`) to 2 in deep water. Evaluated as the same ratio divided
/// through by `sinh 2kd`, `2 tanh kd / (1 + 2kd/sinh 2kd)`, which stays finite where `cosh`
/// overflows (`k d` above about 355) and keeps `kd` where `cosh 2kd − 1` rounds to 0.
pub fn piston_height_per_stroke(kd: f64) -> f64 {
    let x = 2.0 * kd;
    2.0 * kd.tanh() / (1.0 + x / x.sinh())
}

/// The transfer function of a flap wave maker ([DD91] §6.2): the far-field wave height `H` [m]
/// per metre of stroke `S` at the still-water level, for `k d` > 0 and the hinge at the height
/// `l = q d` above the bed (`q < 1`; `q < 0`: below the bed, the flap spans the whole depth).
/// The first-order progressive wave of a paddle with the horizontal stroke profile `S(z)` is
/// `H = 4 sinh kd / (sinh 2kd + 2kd) ∫_{−d}^{0} (S(z)/S) k cosh k(d + z) dz · S` ([DD91] §6.2,
/// the piston's eq. 6.20 with `S(z) = S`); for the flap `S(z) = S (1 + z/(d − l))` above the
/// hinge and 0 below, which integrates to
///
/// ```text
/// H/S = 4 sinh kd / (sinh 2kd + 2kd) · (sinh kd − (cosh kd − cosh(k max(l, 0))) / (k (d − l)))
/// ```
///
/// At `l = 0` this is the bed-hinged flap of [DD91] §6.2,
/// `H/S = 4 (sinh kd / kd) (kd sinh kd − cosh kd + 1) / (sinh 2kd + 2kd)`, which rises from
/// `kd/2` in shallow water to 2 in deep water; as `l → −∞` it tends to the piston's.
///
/// Evaluated divided through by `sinh 2kd = 2 sinh kd cosh kd`, with `1 − cosh a/cosh kd`
/// (`a = k max(l, 0)`) as `2 sinh((kd + a)/2) sinh((kd − a)/2)/cosh kd` (no cancellation in
/// shallow water) or, past `k d = 300` where those overflow, as `1 − e^(a − kd) (1 +
/// e^(−2a))/(1 + e^(−2kd))`: finite for any `k d > 0`.
pub fn flap_height_per_stroke(kd: f64, q: f64) -> f64 {
    let lever = kd * (1.0 - q);
    let a = kd * q.max(0.0);
    let one_minus_cosh_ratio = if kd < 300.0 {
        2.0 * (0.5 * (kd + a)).sinh() * (0.5 * (kd - a)).sinh() / kd.cosh()
    } else {
        1.0 - (a - kd).exp() * (1.0 + (-2.0 * a).exp()) / (1.0 + (-2.0 * kd).exp())
    };
    let integral_per_cosh = kd.tanh() - one_minus_cosh_ratio / lever;
    2.0 * integral_per_cosh / (1.0 + 2.0 * kd / (2.0 * kd).sinh())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The root satisfies the dispersion relation to 1e-12 relative, from shallow (kd = 0.05)
    /// to deep water (kd = 20), and has the two limits: `ω ≈ k √(g d)` and `ω² ≈ g k`.
    #[test]
    fn wavenumber_solves_the_dispersion_relation_in_any_depth() {
        let g: f64 = 9.81;
        for &kd in &[0.05, 0.3, 1.0, 1.3, 3.0, 20.0] {
            let d: f64 = 0.4;
            let k_true = kd / d;
            let omega = (g * k_true * (k_true * d).tanh()).sqrt();
            let k = wavenumber(omega, d, g);
            assert!(
                (k - k_true).abs() <= 1e-12 * k_true,
                "kd = {kd}: k = {k}, expected {k_true}"
            );
        }
        let (d, omega) = (0.4, 0.05);
        let shallow = omega / (g * d).sqrt();
        assert!((wavenumber(omega, d, g) / shallow - 1.0).abs() < 1e-3);
        let omega = 60.0;
        assert!((wavenumber(omega, d, g) / (omega * omega / g) - 1.0).abs() < 1e-12);
    }

    /// [DD91] Fig. 6.5: `H/S = kd` in shallow water, 2 in deep water; at kd = 1.2 the formula
    /// gives 1.1586 (evaluated by hand: 2 (cosh 2.4 − 1) / (sinh 2.4 + 2.4)).
    #[test]
    fn piston_transfer_function_has_its_limits() {
        assert!((piston_height_per_stroke(1e-3) / 1e-3 - 1.0).abs() < 1e-3);
        assert!((piston_height_per_stroke(30.0) - 2.0).abs() < 1e-9);
        let x: f64 = 2.4;
        let by_hand = 2.0 * (x.cosh() - 1.0) / (x.sinh() + x);
        assert!((piston_height_per_stroke(1.2) - by_hand).abs() < 1e-14);
        assert!((by_hand - 1.1586).abs() < 1e-4, "{by_hand}");
        // Finite at the extremes a scene can ask for (a period of 1e-9 s or 1e30 s).
        assert_eq!(piston_height_per_stroke(1e6), 2.0);
        assert!((piston_height_per_stroke(1e-30) / 1e-30 - 1.0).abs() < 1e-12);
    }

    /// The bed-hinged flap: `H/S → kd/2` in shallow water (the integral's leading term, to
    /// O(kd²)), → 2 in deep water (as `2 − 2/kd`), and the closed form of [DD91] §6.2 at
    /// kd = 1.2 (0.6401 by hand: 4 (sinh 1.2/1.2)(1.2 sinh 1.2 − cosh 1.2 + 1)/(sinh 2.4 + 2.4));
    /// a hinge far below the bed gives the piston's, and one halfway up less than the bed's.
    #[test]
    fn flap_transfer_function_has_its_limits() {
        let kd = 1e-3;
        assert!((flap_height_per_stroke(kd, 0.0) / (kd / 2.0) - 1.0).abs() < 1e-5);
        assert!((flap_height_per_stroke(200.0, 0.0) - (2.0 - 2.0 / 200.0)).abs() < 1e-4);
        let x: f64 = 1.2;
        let closed = 4.0 * (x.sinh() / x) * (x * x.sinh() - x.cosh() + 1.0) / ((2.0 * x).sinh() + 2.0 * x);
        assert!((flap_height_per_stroke(x, 0.0) - closed).abs() < 1e-14);
        assert!((closed - 0.6401).abs() < 1e-4, "{closed}");
        let far = flap_height_per_stroke(x, -1e7);
        assert!((far / piston_height_per_stroke(x) - 1.0).abs() < 1e-6, "{far}");
        assert!(flap_height_per_stroke(x, 0.5) < closed);
        // Finite at the extremes: deep water tends to 2 (minus 2/kd), shallow to kd/2.
        assert!((flap_height_per_stroke(1e6, 0.0) - 2.0).abs() < 1e-5);
        assert!((flap_height_per_stroke(1e6, 0.5) - 2.0).abs() < 1e-5);
        assert!((flap_height_per_stroke(1e-20, 0.0) / 5e-21 - 1.0).abs() < 1e-3);
    }
}
