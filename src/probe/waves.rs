//! Regular waves read from wave-gauge records: each gauge's first harmonic at the wave maker's
//! frequency, the crest-to-trough height, and the separation of an incident and a reflected
//! wave, whose ratio is the reflection coefficient of what the waves meet (a damping zone, a
//! beach, a structure). Used by `sph waves RUN_DIR` and the flume tests.
//!
//! Each gauge's record `η(t)` [m] over a window of whole periods is fitted by least squares with
//! `η(t) = a cos ωt + b sin ωt + c` at the wave's `ω`: its complex amplitude `Z = a − i b`
//! (`η = Re(Z e^{iωt})`). The incident and reflected waves are separated as in the least-squares
//! method of Mansard & Funke (1980), `Z(x) = A_I e^{−ikx} + A_R e^{ikx}` over all gauges, here
//! with the waves' spatial decay `κ` [1/m] (the numerical dissipation of an SPH flume, which the
//! constant-amplitude method reads as reflection): `Z(x) = A_I e^{−(ik+κ)x} + A_R e^{(ik+κ)x}`,
//! `k` and `κ` by a grid search, `A_I`, `A_R` by linear least squares. The reflection coefficient
//! at `x` is `K_r(x) = |A_R e^{(ik+κ)x}| / |A_I e^{−(ik+κ)x}|`.
//!
//! With two gauges the decaying fit is not determined (four unknowns, four data); then `κ = 0`
//! and `k` is the one given, the two-gauge method of Goda & Suzuki (1976).
//!
//! References: E. P. D. Mansard, E. R. Funke, "The measurement of incident and reflected spectra
//! using a least squares method", Proc. 17th ICCE, 154–172 (1980). Y. Goda, Y. Suzuki,
//! "Estimation of incident and reflected waves in random wave experiments", Proc. 15th ICCE,
//! 828–845 (1976).

use nalgebra::Complex;

/// A gauge record's first harmonic at `ω`: `η(t) ≈ Re(Z e^{iωt}) + c`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Harmonic {
    /// `Z` [m]: `|Z|` the amplitude, `2|Z|` the height of the harmonic.
    pub amplitude: Complex<f64>,
    /// `c` [m], the record's mean.
    pub mean: f64,
}

/// The least-squares [`Harmonic`] of `samples` `(t [s], η [m])` at `omega` [rad/s] over the
/// samples with `t` in `[t0, t1)`; `None` with fewer than three samples there or samples that do
/// not determine it (all at one phase).
pub fn harmonic(samples: &[(f64, f64)], omega: f64, (t0, t1): (f64, f64)) -> Option<Harmonic> {
    // Normal equations of the basis (cos ωt, sin ωt, 1).
    let mut m = nalgebra::Matrix3::<f64>::zeros();
    let mut r = nalgebra::Vector3::<f64>::zeros();
    let mut count = 0;
    for &(t, eta) in samples.iter().filter(|(t, _)| *t >= t0 && *t < t1) {
        let basis = nalgebra::Vector3::new((omega * t).cos(), (omega * t).sin(), 1.0);
        r += basis * eta;
        m += basis * basis.transpose();
        count += 1;
    }
    if count < 3 {
        return None;
    }
    let x = m.lu().solve(&r)?;
    x.iter().all(|v| v.is_finite()).then(|| Harmonic {
        amplitude: Complex::new(x[0], -x[1]),
        mean: x[2],
    })
}

/// The mean crest-to-trough height [m] over the whole periods `period` [s] from `t0` within
/// `[t0, t1)`; `None` when the window holds no whole period with samples (or the count is not
/// finite).
pub fn crest_to_trough(samples: &[(f64, f64)], period: f64, (t0, t1): (f64, f64)) -> Option<f64> {
    let n = ((t1 - t0) / period).floor();
    if !n.is_finite() || n < 1.0 {
        return None;
    }
    let heights: Vec<f64> = (0..n as usize)
        .filter_map(|j| {
            let (a, b) = (t0 + j as f64 * period, t0 + (j + 1) as f64 * period);
            let window = samples.iter().filter(|(t, _)| *t >= a && *t < b).map(|s| s.1);
            let (lo, hi) = window.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
            (hi >= lo).then_some(hi - lo)
        })
        .collect();
    (!heights.is_empty()).then(|| heights.iter().sum::<f64>() / heights.len() as f64)
}

/// An incident and a reflected wave decaying along their way: `Z(x) = A_I e^{−(ik+κ)x} +
/// A_R e^{(ik+κ)x}` (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoWaves {
    /// Wavenumber `k` [1/m].
    pub k: f64,
    /// Spatial decay `κ` [1/m] (0 with two gauges).
    pub kappa: f64,
    /// `A_I` [m] at `x = 0`.
    pub incident: Complex<f64>,
    /// `A_R` [m] at `x = 0`.
    pub reflected: Complex<f64>,
    /// The residual's norm over the data's (0 with two gauges).
    pub misfit: f64,
}

impl TwoWaves {
    /// `K_r(x) = |A_R(x)| / |A_I(x)|` at `x` [m].
    pub fn reflection_at(&self, x: f64) -> f64 {
        self.reflected_height_at(x) / self.incident_height_at(x)
    }

    /// `2 |A_I(x)|` [m], the incident wave's height at `x` [m].
    pub fn incident_height_at(&self, x: f64) -> f64 {
        2.0 * self.incident.norm() * (-self.kappa * x).exp()
    }

    /// `2 |A_R(x)|` [m], the reflected wave's height at `x` [m].
    pub fn reflected_height_at(&self, x: f64) -> f64 {
        2.0 * self.reflected.norm() * (self.kappa * x).exp()
    }
}

/// The search of [`two_waves`]: `k` within ±15 % of the guess in steps of 0.25 %, `κ` in
/// `[0, 1]` 1/m in steps of 0.01 1/m (a coarse SPH flume decays by 0.2–0.4 1/m).
const K_STEPS: usize = 120;
const KAPPA_STEPS: usize = 100;

/// The least-squares [`TwoWaves`] of the complex amplitudes `z` [m] at the gauge positions `x`
/// [m] along the wave's way: with three gauges or more, `k` and `κ` searched around `k_guess`
/// [1/m] (the dispersion relation's); with two, `κ = 0`, `k = k_guess`. `None` with fewer than
/// two gauges, or gauges the fit cannot separate (two gauges half a wavelength apart).
pub fn two_waves(z: &[Complex<f64>], x: &[f64], k_guess: f64) -> Option<TwoWaves> {
    if z.len() < 2 || z.len() != x.len() {
        return None;
    }
    let norm = z.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
    let fit = |k: f64, kappa: f64| -> Option<TwoWaves> {
        // Columns e^{s(ik+κ)x}, s = −1, 1; normal equations M^H M a = M^H z.
        let col = |x: f64, s: f64| Complex::new(s * kappa * x, s * k * x).exp();
        let (mut g11, mut g12, mut g22) = (Complex::<f64>::ZERO, Complex::<f64>::ZERO, Complex::<f64>::ZERO);
        let (mut r1, mut r2) = (Complex::<f64>::ZERO, Complex::<f64>::ZERO);
        for (&zj, &xj) in z.iter().zip(x) {
            let (c1, c2) = (col(xj, -1.0), col(xj, 1.0));
            g11 += c1.conj() * c1;
            g12 += c1.conj() * c2;
            g22 += c2.conj() * c2;
            r1 += c1.conj() * zj;
            r2 += c2.conj() * zj;
        }
        let det = g11 * g22 - g12 * g12.conj();
        if det.norm() <= 1e-12 * (g11.norm() * g22.norm()) {
            return None;
        }
        let incident = (g22 * r1 - g12 * r2) / det;
        let reflected = (g11 * r2 - g12.conj() * r1) / det;
        let residual = z
            .iter()
            .zip(x)
            .map(|(&zj, &xj)| (zj - incident * col(xj, -1.0) - reflected * col(xj, 1.0)).norm_sqr())
            .sum::<f64>()
            .sqrt();
        Some(TwoWaves {
            k,
            kappa,
            incident,
            reflected,
            misfit: if norm > 0.0 { residual / norm } else { 0.0 },
        })
    };
    if z.len() == 2 {
        return fit(k_guess, 0.0).map(|w| TwoWaves { misfit: 0.0, ..w });
    }
    let mut best: Option<TwoWaves> = None;
    for i in 0..=K_STEPS {
        let k = k_guess * (0.85 + 0.3 * i as f64 / K_STEPS as f64);
        for j in 0..=KAPPA_STEPS {
            let kappa = j as f64 / KAPPA_STEPS as f64;
            if let Some(w) = fit(k, kappa)
                && best.is_none_or(|b| w.misfit < b.misfit)
            {
                best = Some(w);
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A decaying incident wave and a reflection of known `K_r`, sampled as gauges would record
    /// them: the fit gives back `k`, `κ`, the heights and `K_r`.
    #[test]
    fn the_analysis_recovers_a_known_decaying_pattern() {
        let (k, kappa, a, kr_at, x_z): (f64, f64, f64, f64, f64) = (4.0, 0.3, 0.02, 0.2, 3.0);
        let omega = 5.7;
        let incident = Complex::new(a, 0.0);
        // K_r at x_z: |A_R| e^{κ x_z} = K_r |A_I| e^{−κ x_z}.
        let reflected = Complex::from_polar(kr_at * a * (-2.0 * kappa * x_z).exp(), 0.7);
        let gauges = [0.5, 0.9, 1.3, 1.7, 2.1, 2.5];
        let period = std::f64::consts::TAU / omega;
        let records: Vec<Vec<(f64, f64)>> = gauges
            .iter()
            .map(|&x| {
                let z = incident * Complex::new(-kappa * x, -k * x).exp()
                    + reflected * Complex::new(kappa * x, k * x).exp();
                (0..2000)
                    .map(|n| {
                        let t = n as f64 * 0.005;
                        (t, 0.3 + (z * Complex::new(0.0, omega * t).exp()).re)
                    })
                    .collect()
            })
            .collect();
        let window = (2.0, 2.0 + 4.0 * period);
        let z: Vec<Complex<f64>> = records
            .iter()
            .map(|r| {
                let h = harmonic(r, omega, window).expect("a harmonic");
                assert!((h.mean - 0.3).abs() < 1e-9, "mean {}", h.mean);
                h.amplitude
            })
            .collect();
        let fit = two_waves(&z, &gauges, 4.1).expect("a fit");
        // The grid holds k = 4.1 (0.85 + 0.3 i/120) within 0.25 % and κ to 0.01.
        assert!((fit.k - k).abs() < 0.0025 * 4.1 + 1e-9, "k {}", fit.k);
        assert!((fit.kappa - kappa).abs() < 1e-9, "κ {}", fit.kappa);
        assert!(
            (fit.reflection_at(x_z) / kr_at - 1.0).abs() < 0.02,
            "K_r {}",
            fit.reflection_at(x_z)
        );
        assert!((fit.incident_height_at(0.0) / (2.0 * a) - 1.0).abs() < 0.02);
        // A pure sine's crest-to-trough is 2 |Z| (sampled at 1/250 of the period: to 1e-4).
        let h = crest_to_trough(&records[0], period, window).expect("whole periods");
        assert!((h / (2.0 * z[0].norm()) - 1.0).abs() < 1e-3, "{h}");

        // Two gauges: κ = 0 and the given k (Goda & Suzuki); exact for a pattern without decay.
        let plain: Vec<Complex<f64>> = [0.5, 0.9]
            .iter()
            .map(|&x| incident * Complex::new(0.0, -k * x).exp() + reflected * Complex::new(0.0, k * x).exp())
            .collect();
        let fit = two_waves(&plain, &[0.5, 0.9], k).expect("a fit");
        assert!((fit.reflected - reflected).norm() < 1e-12 && (fit.incident - incident).norm() < 1e-12);
        // Half a wavelength apart two gauges cannot separate the waves.
        assert!(two_waves(&plain, &[0.5, 0.5 + std::f64::consts::PI / k], k).is_none());
        assert!(two_waves(&plain[..1], &[0.5], k).is_none());
        assert!(harmonic(&records[0][..2], omega, (0.0, 1.0)).is_none());
        assert!(crest_to_trough(&records[0], period, (2.0, 2.0 + 0.5 * period)).is_none());
    }
}
