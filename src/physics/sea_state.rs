//! Irregular and focused sea states as sums of linear (Airy) wave components, the targets of
//! the wave makers' sea signals (`boundary::sea_maker`).
//!
//! A band `[f_min, f_max]` [Hz] of a JONSWAP spectrum (`physics::jonswap`, Goda's form) is cut
//! into `N` lines `Δf = (f_max − f_min)/N` apart; each line's frequency is the midpoint of its
//! slice rounded to a whole multiple of `Δf` (a shift below `Δf/2`), so the sum repeats after
//! `T_rep = 1/Δf` and its components are orthogonal over that time. The target elevation at
//! the distance `x` [m] from the paddle's mean position is
//!
//! ```text
//! η(x, t) = Σ_i a_i cos(ω_i t − k_i x − φ_i),   ω_i = 2π f_i,   ω_i² = g k_i tanh(k_i d)
//! ```
//!
//! ([DD91] eq. 4.20 for `k_i`), with, for the two kinds:
//!
//! - irregular: `a_i = √(2 S(f_i) Δf)` (the random-phase model, [G00] §2.3), `φ_i = 2π u_i`,
//!   `u_i` uniform from `pcg32` of the scene's seed (`physics::pcg`, stream [`PHASE_STREAM`]),
//!   drawn in order of frequency. The band's `H_m0 = 4 √(Σ a_i²/2)` is the spectrum's within
//!   the band: below the scene's `H_s` by the energy outside it and the lines' sampling of `S` (the
//!   default 0.5 to 3 `f_p` at γ = 3.3 and 128 lines: `m_0` 1.0 % low, `H_m0` 0.5 %);
//! - focused (NewWave, [TAB91] Tromans, Anaturk & Hagemeijer 1991): `a_i = A S(f_i) / Σ_j S(f_j)`
//!   and `φ_i = ω_i t_f − k_i x_f`, so every crest meets at `(x_f, t_f)`, where `η = Σ a_i = A`,
//!   the largest elevation `x_f` sees (`|η| ≤ Σ a_i`).
//!
//! [DD91] Dean & Dalrymple, *Water Wave Mechanics for Engineers and Scientists* (1991).
//! [G00] Y. Goda, *Random Seas and Design of Maritime Structures*, 2nd ed. (2000).
//! [TAB91] P. S. Tromans, A. R. Anaturk, P. Hagemeijer, "A new model for the kinematics of
//! large ocean waves — application as a design wave", Proc. 1st ISOPE (1991).

use super::jonswap::Jonswap;
use super::pcg::Pcg32;
use super::waves::wavenumber;
use std::f64::consts::TAU;

/// The `pcg32` stream the irregular sea's phases are drawn from (the reference demo's 54).
pub const PHASE_STREAM: u64 = 54;

/// The discrete band of a JONSWAP spectrum (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    /// Peak period `T_p` [s], > 0.
    pub peak_period: f64,
    /// Peak enhancement `γ`, >= 1.
    pub gamma: f64,
    /// Number of lines `N`.
    pub components: usize,
    /// Lower end `f_min` [Hz], in (0, f_p).
    pub f_min: f64,
    /// Upper end `f_max` [Hz], above `f_p`.
    pub f_max: f64,
}

impl Band {
    /// The line spacing `Δf` [Hz].
    pub fn spacing(&self) -> f64 {
        (self.f_max - self.f_min) / self.components as f64
    }

    /// The lines' frequencies `f_i` [Hz]: the slices' midpoints rounded to whole multiples of
    /// `Δf` (module doc).
    pub fn frequencies(&self) -> Vec<f64> {
        let df = self.spacing();
        let first = (self.f_min / df + 0.5).round().max(1.0);
        (0..self.components).map(|i| (first + i as f64) * df).collect()
    }

    /// The time `T_rep = 1/Δf` [s] after which the sum repeats.
    pub fn repeat_period(&self) -> f64 {
        1.0 / self.spacing()
    }

    /// The spectrum's shape at the lines: `S(f_i)` [m²/Hz] for `H_s` [m].
    fn densities(&self, significant_height: f64) -> Vec<f64> {
        let s = Jonswap {
            significant_height,
            peak_period: self.peak_period,
            gamma: self.gamma,
        };
        s.densities(&self.frequencies())
    }
}

/// A sea state a wave maker makes (module doc).
#[derive(Clone, Debug, PartialEq)]
pub enum Sea {
    /// Random phases from a seed.
    Irregular {
        /// Significant height `H_s` [m], > 0.
        significant_height: f64,
        /// The spectrum's band.
        band: Band,
        /// The seed of the phases.
        seed: u64,
    },
    /// A focused group (NewWave).
    Focused {
        /// The linear crest `A` [m] at the focus, > 0.
        amplitude: f64,
        /// `x_f` [m], the focus' distance from the paddle's mean position, > 0.
        focus_position: f64,
        /// `t_f` [s], the time of the focus.
        focus_time: f64,
        /// The spectrum's band.
        band: Band,
    },
}

/// The components of a sea on water `d` deep: `η(x, t) = Σ a_i cos(ω_i t − k_i x − φ_i)`.
#[derive(Clone, Debug, PartialEq)]
pub struct WaveComponents {
    /// Frequencies `f_i` [Hz].
    pub frequency: Vec<f64>,
    /// Amplitudes `a_i` [m].
    pub amplitude: Vec<f64>,
    /// Phases `φ_i` [rad].
    pub phase: Vec<f64>,
    /// Wavenumbers `k_i` [1/m] by the dispersion relation.
    pub wavenumber: Vec<f64>,
}

impl Sea {
    /// The spectrum's band.
    pub fn band(&self) -> &Band {
        match self {
            Sea::Irregular { band, .. } | Sea::Focused { band, .. } => band,
        }
    }

    /// The components on water `depth` [m] deep under gravity `g` [m/s²] (module doc).
    pub fn components(&self, depth: f64, g: f64) -> WaveComponents {
        let band = self.band();
        let frequency = band.frequencies();
        let wavenumber: Vec<f64> = frequency.iter().map(|f| wavenumber(TAU * f, depth, g)).collect();
        let (amplitude, phase) = match self {
            Sea::Irregular {
                significant_height,
                seed,
                ..
            } => {
                let df = band.spacing();
                let a = band
                    .densities(*significant_height)
                    .iter()
                    .map(|s| (2.0 * s * df).sqrt())
                    .collect();
                let mut rng = Pcg32::new(*seed, PHASE_STREAM);
                let phase = frequency.iter().map(|_| TAU * rng.next_f64()).collect();
                (a, phase)
            }
            Sea::Focused {
                amplitude,
                focus_position,
                focus_time,
                ..
            } => {
                let s = band.densities(1.0);
                let total: f64 = s.iter().sum();
                let a = s.iter().map(|s| amplitude * s / total).collect();
                let phase = frequency
                    .iter()
                    .zip(&wavenumber)
                    .map(|(f, k)| TAU * f * focus_time - k * focus_position)
                    .collect();
                (a, phase)
            }
        };
        WaveComponents {
            frequency,
            amplitude,
            phase,
            wavenumber,
        }
    }
}

impl WaveComponents {
    /// The linear elevation `η(x, t)` [m] at the distance `x` [m] from the paddle's mean
    /// position at time `t` [s] (module doc), without the wave maker's ramp.
    pub fn elevation(&self, x: f64, t: f64) -> f64 {
        (0..self.frequency.len())
            .map(|i| {
                let w = TAU * self.frequency[i];
                self.amplitude[i] * (w * t - self.wavenumber[i] * x - self.phase[i]).cos()
            })
            .sum()
    }

    /// The zeroth moment `m_0 = Σ a_i²/2` [m²] of the discrete spectrum.
    pub fn m0(&self) -> f64 {
        self.amplitude.iter().map(|a| 0.5 * a * a).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn band() -> Band {
        Band {
            peak_period: 1.1,
            gamma: 3.3,
            components: 128,
            f_min: 0.5 / 1.1,
            f_max: 3.0 / 1.1,
        }
    }

    /// The lines are whole multiples of `Δf` inside `[f_min − Δf/2, f_max]`, so the sum
    /// repeats after `1/Δf` (to rounding, 1e-9 m on an elevation of order 0.01 m).
    #[test]
    fn the_band_repeats_after_one_over_its_spacing() {
        let b = band();
        let (f, df) = (b.frequencies(), b.spacing());
        assert_eq!(f.len(), 128);
        assert!(f[0] >= b.f_min - 0.5 * df && f[127] <= b.f_max + 1e-12);
        for w in f.windows(2) {
            assert!((w[1] - w[0] - df).abs() < 1e-12);
        }
        let sea = Sea::Irregular {
            significant_height: 0.04,
            band: b.clone(),
            seed: 3,
        };
        let c = sea.components(0.3, 9.81);
        for t in [0.3, 1.7, 5.0] {
            let (now, later) = (c.elevation(0.7, t), c.elevation(0.7, t + b.repeat_period()));
            assert!((now - later).abs() < 1e-9, "{now} vs {later}");
        }
    }

    /// The elevation at `x` sampled `M = 2048` times over one repeat `1/Δf` (more than twice
    /// the highest line's index, 154, so the discrete means of `cos²` and of the cross terms
    /// are exactly 1/2 and 0: the samples' variance is the discrete `m_0` to rounding).
    fn sampled_m0(c: &WaveComponents, x: f64, repeat: f64) -> f64 {
        let m = 2048;
        let eta: Vec<f64> = (0..m)
            .map(|j| c.elevation(x, repeat * j as f64 / m as f64))
            .collect();
        let mean = eta.iter().sum::<f64>() / m as f64;
        eta.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / m as f64
    }

    /// The irregular sea's target elevation, at the paddle and 1 m down the flume, has
    /// `4 √m_0` within 1 % of the scene's `H_s`. `m_0` is the variance of the generated
    /// elevation over one repeat, so the test covers the amplitudes `√(2 S Δf)` and the sum;
    /// it falls short of `H_s` by the spectrum outside the band (measured: 0.039799 m, 0.50 %
    /// low). The samples agree with the discrete `Σ a_i²/2` to 1e-9.
    #[test]
    fn irregular_sea_has_the_significant_height() {
        let sea = Sea::Irregular {
            significant_height: 0.04,
            band: band(),
            seed: 11,
        };
        let c = sea.components(0.3, 9.81);
        for x in [0.0, 1.0] {
            let m0 = sampled_m0(&c, x, band().repeat_period());
            let hs = 4.0 * m0.sqrt();
            eprintln!(
                "H_m0 at x = {x} m: {hs:.6} m (target 0.04 m, discrete {:.6})",
                4.0 * c.m0().sqrt()
            );
            assert!((hs / 0.04 - 1.0).abs() < 0.01, "H_m0 = {hs}");
            assert!((m0 / c.m0() - 1.0).abs() < 1e-9, "{m0} vs {}", c.m0());
        }
    }

    /// The same seed gives bitwise the same components; another seed other phases (every
    /// one of the 128: equal f64 draws from two seeds would be a 2⁻⁵³ coincidence) with the
    /// same amplitudes; the phases fill [0, 2π).
    #[test]
    fn a_seed_fixes_the_phases() {
        let sea = |seed| Sea::Irregular {
            significant_height: 0.04,
            band: band(),
            seed,
        };
        let (a, b, other) = (
            sea(5).components(0.3, 9.81),
            sea(5).components(0.3, 9.81),
            sea(6).components(0.3, 9.81),
        );
        assert_eq!(a, b);
        let bits = |c: &WaveComponents| c.phase.iter().map(|p| p.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a), bits(&b));
        assert_eq!(a.amplitude, other.amplitude);
        assert!(a.phase.iter().zip(&other.phase).all(|(p, q)| p != q));
        assert!(a.phase.iter().all(|p| (0.0..TAU).contains(p)));
    }

    /// The focused group's linear crest at `(x_f, t_f)` is `A` to rounding (1e-12 relative),
    /// and no time over a whole repeat around it (sampled every 5 ms) nor a nearby place at
    /// `t_f` rises higher: the focus is the maximum.
    #[test]
    fn focused_group_peaks_at_the_focus() {
        let (a, x_f, t_f) = (0.05, 2.0, 12.0);
        let sea = Sea::Focused {
            amplitude: a,
            focus_position: x_f,
            focus_time: t_f,
            band: band(),
        };
        let c = sea.components(0.3, 9.81);
        let crest = c.elevation(x_f, t_f);
        assert!((crest / a - 1.0).abs() < 1e-12, "crest {crest}");
        let repeat = band().repeat_period();
        let n = (repeat / 0.005) as usize;
        let highest = (0..n)
            .map(|j| c.elevation(x_f, t_f - 0.5 * repeat + j as f64 * 0.005))
            .fold(f64::MIN, f64::max);
        assert!(
            highest <= crest * (1.0 + 1e-12),
            "{highest} above the crest {crest}"
        );
        for dx in [-0.3, -0.05, 0.05, 0.3] {
            assert!(c.elevation(x_f + dx, t_f) < crest);
        }
        // The group is compact: half a repeat away the surface is a small fraction of A.
        assert!(c.elevation(x_f, t_f + 0.5 * repeat).abs() < 0.2 * a);
    }
}
