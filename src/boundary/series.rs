//! A prescribed displacement from a time series (`motion = { kind = "series", file = ..., ... }`):
//! a piston driven by a wave maker's stroke signal, sampled in a CSV file.
//!
//! The samples `(t_i, s_i)` (time [s], displacement [m] along the unit `direction`) are joined
//! by the natural cubic spline (zero second derivative at both ends; Press et al., *Numerical
//! Recipes*, 3rd ed., §3.3, eqs. 3.3.3–3.3.7): on `[t_i, t_{i+1}]`, `h = t_{i+1} − t_i`,
//! `a = (t_{i+1} − t)/h`, `b = 1 − a`,
//!
//! ```text
//! s   = a s_i + b s_{i+1} + ((a³ − a) M_i + (b³ − b) M_{i+1}) h²/6
//! s'  = (s_{i+1} − s_i)/h − (3a² − 1) h M_i / 6 + (3b² − 1) h M_{i+1} / 6
//! s'' = a M_i + b M_{i+1}
//! ```
//!
//! with `M` the spline's second derivatives, so displacement, velocity and acceleration are
//! continuous between samples (the wall acceleration enters the wall pressure, [A12] eq. 27).
//! Before the first sample the solid stays at `s_0`, after the last at `s_n`, at rest: a series
//! should start and end at rest, or the velocity jumps there.

use super::motion::Profile;

/// A displacement time series along a unit direction (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct DisplacementSeries {
    /// The file the samples came from, for messages.
    pub file: String,
    /// Sample times `t_i` [s], strictly increasing, at least 2.
    pub time: Vec<f64>,
    /// Displacements `s_i` [m].
    pub displacement: Vec<f64>,
    /// Unit direction `n` of the displacement, one entry per axis.
    pub direction: Vec<f64>,
    /// The natural spline's second derivatives `M_i` [m/s²].
    second: Vec<f64>,
}

impl DisplacementSeries {
    /// The series of `time` [s] and `displacement` [m] samples along the unit `direction`.
    ///
    /// # Errors
    /// A message when there are fewer than 2 samples, a value is not finite, or the times do
    /// not increase strictly.
    pub fn new(
        file: &str,
        time: Vec<f64>,
        displacement: Vec<f64>,
        direction: Vec<f64>,
    ) -> Result<Self, String> {
        if time.len() < 2 || time.len() != displacement.len() {
            return Err(format!("needs at least 2 samples, found {}", time.len()));
        }
        if let Some(i) = (0..time.len()).find(|&i| !(time[i].is_finite() && displacement[i].is_finite())) {
            return Err(format!("sample {} is not finite", i + 1));
        }
        if let Some(i) = (1..time.len()).find(|&i| time[i] <= time[i - 1]) {
            return Err(format!(
                "times must increase: sample {} at {} s follows {} s",
                i + 1,
                time[i],
                time[i - 1]
            ));
        }
        let second = natural_spline(&time, &displacement);
        Ok(DisplacementSeries {
            file: file.to_string(),
            time,
            displacement,
            direction,
            second,
        })
    }

    /// Parses CSV text: a header line, then one `t, s` pair a line (comma separated; blank
    /// lines and lines starting with `#` skipped).
    ///
    /// # Errors
    /// A message naming the line that is not two numbers.
    pub fn parse(text: &str) -> Result<(Vec<f64>, Vec<f64>), String> {
        let (mut time, mut displacement) = (Vec::new(), Vec::new());
        let mut header = true;
        for (n, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            if std::mem::take(&mut header) {
                continue;
            }
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            let pair = match cells.as_slice() {
                [t, s] => t.parse::<f64>().ok().zip(s.parse::<f64>().ok()),
                _ => None,
            };
            let Some((t, s)) = pair else {
                return Err(format!(
                    "line {}: expected two numbers `t_s, displacement_m`, found {line:?}",
                    n + 1
                ));
            };
            time.push(t);
            displacement.push(s);
        }
        Ok((time, displacement))
    }

    /// `s(t)`, `s'(t)`, `s''(t)` (module doc); held at the ends.
    pub fn profile(&self, t: f64) -> Profile {
        let n = self.time.len() - 1;
        if t <= self.time[0] || t >= self.time[n] {
            let value = if t <= self.time[0] {
                self.displacement[0]
            } else {
                self.displacement[n]
            };
            return Profile {
                value,
                rate: 0.0,
                curvature: 0.0,
            };
        }
        // The interval holding t: the last sample at or before it.
        let i = self.time.partition_point(|&ti| ti <= t) - 1;
        let (t0, t1) = (self.time[i], self.time[i + 1]);
        let (s0, s1) = (self.displacement[i], self.displacement[i + 1]);
        let (m0, m1) = (self.second[i], self.second[i + 1]);
        let h = t1 - t0;
        let a = (t1 - t) / h;
        let b = 1.0 - a;
        Profile {
            value: a * s0 + b * s1 + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6.0,
            rate: (s1 - s0) / h - (3.0 * a * a - 1.0) * h * m0 / 6.0 + (3.0 * b * b - 1.0) * h * m1 / 6.0,
            curvature: a * m0 + b * m1,
        }
    }

    /// Upper bounds of `|s|` [m] and `|s'|` [m/s] over all times, from the spline sampled at 64
    /// points an interval, raised by 1 % (the time step and the swept-box check read them; the
    /// sampling misses at most `h² |s''| / 8192` of a peak).
    pub fn bounds(&self) -> (f64, f64) {
        let (mut reach, mut speed) = (0.0f64, 0.0f64);
        for w in self.time.windows(2) {
            for j in 0..=64 {
                let p = self.profile(w[0] + (w[1] - w[0]) * f64::from(j) / 64.0);
                reach = reach.max(p.value.abs());
                speed = speed.max(p.rate.abs());
            }
        }
        (1.01 * reach, 1.01 * speed)
    }
}

/// The second derivatives `M_i` of the natural cubic spline through `(t_i, s_i)` (Numerical
/// Recipes eq. 3.3.7 with `M_0 = M_n = 0`), by the tridiagonal (Thomas) algorithm.
fn natural_spline(t: &[f64], s: &[f64]) -> Vec<f64> {
    let n = t.len();
    let mut m = vec![0.0; n];
    if n < 3 {
        return m;
    }
    // Rows i = 1..n-1: h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (Δ_i − Δ_{i-1}).
    let (mut diag, mut rhs) = (vec![0.0; n], vec![0.0; n]);
    let mut upper = vec![0.0; n];
    for i in 1..n - 1 {
        let (h0, h1) = (t[i] - t[i - 1], t[i + 1] - t[i]);
        diag[i] = 2.0 * (h0 + h1);
        upper[i] = h1;
        rhs[i] = 6.0 * ((s[i + 1] - s[i]) / h1 - (s[i] - s[i - 1]) / h0);
        if i > 1 {
            let w = h0 / diag[i - 1];
            diag[i] -= w * upper[i - 1];
            rhs[i] -= w * rhs[i - 1];
        }
    }
    for i in (1..n - 1).rev() {
        m[i] = (rhs[i] - upper[i] * m[i + 1]) / diag[i];
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples of `A sin(ωt)` every 20 ms: the spline's value, rate and curvature match the
    /// sine's to the interpolation error (O(h⁴), O(h³), O(h²) relative: 1e-5, 1e-3, 3e-2
    /// here), away from the natural ends; outside the samples the solid rests at the ends.
    #[test]
    fn spline_of_a_sampled_sine_follows_the_sine() {
        let (a, w) = (0.02, 5.7);
        let time: Vec<f64> = (0..=250).map(|i| f64::from(i) * 0.02).collect();
        let s: Vec<f64> = time.iter().map(|t| a * (w * t).sin()).collect();
        let series = DisplacementSeries::new("test", time, s, vec![1.0, 0.0]).expect("valid");
        for i in 0..300 {
            let t = 1.0 + f64::from(i) * 0.01;
            let p = series.profile(t);
            assert!((p.value - a * (w * t).sin()).abs() < 1e-5 * a, "s at {t}");
            assert!((p.rate - a * w * (w * t).cos()).abs() < 1e-3 * a * w, "s' at {t}");
            assert!(
                (p.curvature + a * w * w * (w * t).sin()).abs() < 3e-2 * a * w * w,
                "s'' at {t}"
            );
        }
        let end = series.profile(9.0);
        assert_eq!((end.rate, end.curvature), (0.0, 0.0));
        assert_eq!(end.value, series.displacement[250]);
        let (reach, speed) = series.bounds();
        assert!(reach >= a && reach < 1.02 * a, "{reach}");
        assert!(speed >= 0.999 * a * w && speed < 1.02 * a * w, "{speed}");
    }

    /// A bad file is a message naming the line; too few samples and times that do not increase
    /// are refused.
    #[test]
    fn bad_series_are_refused_with_the_reason() {
        let e = DisplacementSeries::parse("t_s,x_m\n0,0\n0.1,oops\n").expect_err("bad line");
        assert!(e.starts_with("line 3:"), "{e}");
        let (t, s) = DisplacementSeries::parse("t_s,x_m\n# comment\n0, 0\n\n0.1, 0.01\n").expect("valid");
        assert_eq!((t, s), (vec![0.0, 0.1], vec![0.0, 0.01]));
        let one = DisplacementSeries::new("f", vec![0.0], vec![0.0], vec![1.0]).expect_err("one sample");
        assert!(one.contains("at least 2"), "{one}");
        let back =
            DisplacementSeries::new("f", vec![0.0, 0.2, 0.1], vec![0.0; 3], vec![1.0]).expect_err("back");
        assert!(back.contains("must increase"), "{back}");
    }
}
