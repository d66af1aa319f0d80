//! The velocity solve's mixing by reference (`solver::anderson`): the window of differences by
//! particle id, and how far the backends' f64 Gram matrix may be from this one.

use crate::correction_reference::{EPS, rest};
use sph::fields::{FLUID, Fields};
use sph::model::params::StepParams;
use sph::physics::correction::pressure_increment;
use sph::solver::anderson::{AndersonState, WINDOW};

/// The mixing's reference (`solver::anderson`): the window's differences by id, the previous
/// iterate with its `f = g(P) − P`, and bounds of how far the backends' Gram matrix may be from
/// this one (their f64 sums of the same exact products in another order: at most
/// `2 (n − 1) 2⁻⁵³ Σ|terms|` apart).
pub(super) struct Mixing {
    pub(super) state: AndersonState,
    dp: Vec<Vec<f32>>,
    df: Vec<Vec<f32>>,
    gram_error: [[f64; WINDOW]; WINDOW],
    previous: Vec<f32>,
    previous_f: Vec<f32>,
}

/// Bound of two f64 sums of `n` terms in different orders, relative to `Σ|terms|`.
pub(super) fn order64(n: usize) -> f64 {
    2.0 * n as f64 * f64::EPSILON / 2.0
}

impl Mixing {
    pub(super) fn new(n: usize) -> Self {
        Self {
            state: AndersonState::default(),
            dp: vec![vec![0.0; n]; WINDOW],
            df: vec![vec![0.0; n]; WINDOW],
            gram_error: [[0.0; WINDOW]; WINDOW],
            previous: Vec::new(),
            previous_f: Vec::new(),
        }
    }

    /// `Σ a_i b_i` in f64 and its order bound.
    fn dot(a: &[f32], b: &[f32]) -> (f64, f64) {
        let (mut sum, mut abs) = (0.0f64, 0.0f64);
        for (&x, &y) in a.iter().zip(b) {
            let t = f64::from(x) * f64::from(y);
            sum += t;
            abs += t.abs();
        }
        (sum, order64(a.len()) * abs)
    }

    /// One sweep on `f` (id order: the pressure `P`, the predicted density): `f = g(P) − P`
    /// (`pressure_increment`, 0 for solids), the newest differences and the window's `γ`, then
    /// fluid `max(P + f − Σ γ_l (ΔP_l + Δf_l), 0)` in f32 in slot order. Returns the mixed
    /// pressures, each one's tolerance, and the plain projected Jacobi iterate `max(P + f, 0)`.
    /// The tolerance: `δγ ≤ |G⁻¹| (e_rhs + E_G |γ|)` to first order (the columns of `G⁻¹` from
    /// `AndersonState::coefficients` of unit vectors, with its Tikhonov term), plus one f32
    /// rounding of `γ`, times `|ΔP_l + Δf_l|`; and the roundings of the `3 held + 1` f32
    /// operations, of the magnitudes they add.
    pub(super) fn mix<const D: usize>(
        &mut self,
        f: &Fields<D>,
        p: &StepParams<D>,
        k: f32,
    ) -> (Vec<f32>, Vec<f64>, Vec<f32>) {
        let n = f.len();
        let fluid = |i: usize| f.kind[i] == FLUID;
        let r: Vec<f32> = (0..n)
            .map(|i| {
                if fluid(i) {
                    pressure_increment(f.density[i], rest(f, p, i), f.pressure[i], k)
                } else {
                    0.0
                }
            })
            .collect();
        let state = &mut self.state;
        if state.has_previous {
            let s = state.next;
            for i in 0..n {
                self.dp[s][i] = f.pressure[i] - self.previous[i];
                self.df[s][i] = r[i] - self.previous_f[i];
            }
            let valid = (state.held + 1).min(WINDOW);
            let mut row = [0.0; WINDOW];
            for l in 0..valid {
                let (dot, error) = Self::dot(&self.df[s], &self.df[l]);
                row[l] = dot;
                self.gram_error[s][l] = error;
                self.gram_error[l][s] = error;
            }
            state.push(&row);
        }
        let held = state.held;
        let (mut rhs, mut rhs_error) = ([0.0; WINDOW], [0.0; WINDOW]);
        for l in 0..held {
            (rhs[l], rhs_error[l]) = Self::dot(&self.df[l], &r);
        }
        let gamma64 = state.coefficients(&rhs);
        let mut dgamma = [0.0f64; WINDOW];
        for l in 0..held {
            let mut unit = [0.0; WINDOW];
            unit[l] = 1.0;
            let column = state.coefficients(&unit);
            let e = rhs_error[l]
                + (0..held)
                    .map(|m| self.gram_error[l][m] * gamma64[m].abs())
                    .sum::<f64>();
            for (d, c) in dgamma.iter_mut().zip(column) {
                *d += c.abs() * e;
            }
        }
        let gamma = gamma64.map(|g| g as f32);
        state.has_previous = true;
        let (mut mixed, mut tol, mut jacobi) = (f.pressure.clone(), vec![0.0f64; n], f.pressure.clone());
        for i in (0..n).filter(|&i| fluid(i)) {
            let mut m = f.pressure[i] + r[i];
            let mut magnitude = f64::from(f.pressure[i].abs() + r[i].abs());
            jacobi[i] = m.max(0.0);
            for l in 0..held {
                let (a, b) = (self.dp[l][i], self.df[l][i]);
                m -= gamma[l] * (a + b);
                let size = f64::from(a.abs() + b.abs());
                magnitude += f64::from(gamma[l]).abs() * size;
                tol[i] += (dgamma[l] + EPS * gamma64[l].abs()) * size;
            }
            mixed[i] = m.max(0.0);
            tol[i] += (3 * held + 2) as f64 * EPS * magnitude;
        }
        self.previous.clone_from(&f.pressure);
        self.previous_f = r;
        (mixed, tol, jacobi)
    }
}
