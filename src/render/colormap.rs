//! The colour map of rendered frames (viridis) and the fixed value range it spans.
//!
//! Viridis (van der Walt & Smith, matplotlib 2015) is perceptually uniform and stays readable
//! in grey scale and for colour-blind readers; no grey lies on it, so solids (drawn grey, as
//! in the paper's Figs. 2–3) stand apart from the fluid in every frame.

/// Viridis at nine equally spaced stops (matplotlib's table at 0, 1/8, …, 1), as sRGB.
const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [72, 40, 120],
    [62, 73, 137],
    [49, 104, 142],
    [38, 130, 142],
    [31, 158, 137],
    [53, 183, 121],
    [110, 206, 88],
    [253, 231, 37],
];

/// Colours of solid particles (walls, obstacles): greys, one per named solid in turn, so that
/// an obstacle stands out against the tank behind it.
const SOLID_GREYS: [[u8; 3]; 4] = [[165, 165, 165], [105, 105, 105], [200, 200, 200], [135, 135, 135]];

/// The grey of the particles of solid `kind` (1 = the scene's first solid).
pub fn solid_grey(kind: u32) -> [u8; 3] {
    SOLID_GREYS[(kind.max(1) as usize - 1) % SOLID_GREYS.len()]
}

/// The viridis colour at `s` ∈ [0, 1] (clamped; NaN maps to 0), linearly interpolated
/// between the stops.
pub fn viridis(s: f64) -> [u8; 3] {
    let s = if s.is_nan() { 0.0 } else { s.clamp(0.0, 1.0) };
    let x = s * (VIRIDIS.len() - 1) as f64;
    let k = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - k as f64;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    std::array::from_fn(|c| (f64::from(a[c]) + f * (f64::from(b[c]) - f64::from(a[c]))).round() as u8)
}

/// A value range `[low, high]` mapped onto the colour map, in the field's unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColorRange {
    /// Value drawn at the bottom of the colour bar.
    pub low: f64,
    /// Value drawn at the top of the colour bar.
    pub high: f64,
}

impl ColorRange {
    /// The range `[low, high]`; an empty or reversed span is widened around its centre so that
    /// every value still maps to a colour (a fluid at rest has one speed, 0).
    pub fn new(low: f64, high: f64) -> Self {
        let (low, high) = if low <= high { (low, high) } else { (high, low) };
        if high - low > 1e-12 * low.abs().max(high.abs()) && high > low {
            return ColorRange { low, high };
        }
        let pad = if low == 0.0 { 1.0 } else { 0.01 * low.abs() };
        ColorRange {
            low: low - pad,
            high: high + pad,
        }
    }

    /// Position of `value` on the bar, 0 at `low` and 1 at `high` (not clamped).
    pub fn fraction(&self, value: f64) -> f64 {
        (value - self.low) / (self.high - self.low)
    }

    /// Colour of `value` (values outside the range take the end colours).
    pub fn color(&self, value: f64) -> [u8; 3] {
        viridis(self.fraction(value))
    }

    /// About `count` round tick values inside the range (steps of 1, 2 or 5 × 10^k).
    pub fn ticks(&self, count: usize) -> Vec<f64> {
        let span = self.high - self.low;
        let raw = span / count.max(1) as f64;
        let magnitude = 10f64.powf(raw.log10().floor());
        let step = [1.0, 2.0, 5.0, 10.0]
            .iter()
            .map(|m| m * magnitude)
            .find(|s| *s >= raw)
            .unwrap_or(10.0 * magnitude);
        let first = (self.low / step).ceil() as i64;
        let last = (self.high / step).floor() as i64;
        (first..=last).map(|k| k as f64 * step).collect()
    }
}

/// The low and high quantiles (`q` and `1 − q`) of the finite `values`, or `None` when there are
/// none. Used per frame so that a handful of splashing particles do not stretch the colour bar.
pub fn quantile_range(values: &mut [f64], q: f64) -> Option<(f64, f64)> {
    let mut finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() {
        return None;
    }
    let last = finite.len() - 1;
    let lo = ((q * last as f64).round() as usize).min(last);
    let hi = (((1.0 - q) * last as f64).round() as usize).min(last);
    let low = *finite.select_nth_unstable_by(lo, f64::total_cmp).1;
    let high = *finite.select_nth_unstable_by(hi, f64::total_cmp).1;
    Some((low, high))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_ends_are_the_table_ends_and_clamp() {
        assert_eq!(viridis(0.0), VIRIDIS[0]);
        assert_eq!(viridis(1.0), VIRIDIS[8]);
        assert_eq!(viridis(-3.0), VIRIDIS[0]);
        assert_eq!(viridis(7.0), VIRIDIS[8]);
        assert_eq!(viridis(f64::NAN), VIRIDIS[0]);
        assert_eq!(viridis(0.5), VIRIDIS[4]);
        // Halfway between stops 0 and 1.
        assert_eq!(viridis(1.0 / 16.0), [70, 21, 102]);
    }

    #[test]
    fn ticks_are_round_and_inside() {
        let r = ColorRange::new(0.0, 2.3);
        assert_eq!(r.ticks(5), vec![0.0, 0.5, 1.0, 1.5, 2.0]);
        let r = ColorRange::new(-1234.0, 5678.0);
        assert_eq!(r.ticks(5), vec![0.0, 2000.0, 4000.0]);
        assert_eq!(
            r.ticks(10),
            vec![-1000.0, 0.0, 1000.0, 2000.0, 3000.0, 4000.0, 5000.0]
        );
    }

    #[test]
    fn empty_range_is_widened() {
        let r = ColorRange::new(0.0, 0.0);
        assert!(r.low < 0.0 && r.high > 0.0);
        let r = ColorRange::new(1000.0, 1000.0);
        assert!(r.low < 1000.0 && r.high > 1000.0);
        assert_eq!(ColorRange::new(2.0, 1.0), ColorRange { low: 1.0, high: 2.0 });
    }

    #[test]
    fn quantiles_drop_outliers() {
        let mut v: Vec<f64> = (0..1000).map(f64::from).collect();
        v[3] = 1e9;
        v.push(f64::NAN);
        let (lo, hi) = quantile_range(&mut v, 0.005).unwrap();
        assert!(lo <= 6.0 && hi < 1000.0, "{lo} {hi}");
        assert_eq!(quantile_range(&mut [f64::NAN], 0.01), None);
    }
}
