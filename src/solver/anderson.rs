//! Anderson acceleration of the velocity solve's fixed-point map (Walker & Ni, SIAM J. Numer.
//! Anal. 49 (2011), "Anderson acceleration for fixed-point iterations"): the host side, shared by
//! both backends. The backends hold the vectors and compute the dot products; this module keeps
//! the window's Gram matrix and solves the small least-squares problem for the mixing
//! coefficients.
//!
//! The map is one projected Jacobi sweep of the velocity solve, `g(P) = max(P + k r(P), 0)`
//! (`physics::correction::pressure_increment`), with `f = g(P) − P`. With the window's
//! differences `ΔP_j`, `Δf_j` of consecutive iterates, the next iterate is
//! `P⁺ = max(P + f − Σ_j γ_j (ΔP_j + Δf_j), 0)` with `γ = argmin ‖f − Σ_j γ_j Δf_j‖₂`. On a
//! linear map this is GMRES in disguise; the projection keeps `P ≥ 0` (note 6).
//!
//! Why: the heavy-ball sweeps it replaces converge at their momentum's rate `√β ≈ 0.95` per
//! sweep (about 45 sweeps per decade), a long-wave limit of any Jacobi-type iteration on a tall
//! column; a Krylov-type method adapts to the spectrum the residual actually holds.

/// Most differences the acceleration remembers. Why 6: measured on the 2D dam break (see
/// docs/performance.md, "The velocity solve"); more costs memory (`2 × WINDOW` floats per
/// particle) for little gain.
pub const WINDOW: usize = 6;

/// The host's side of the acceleration: which ring slots hold differences and their Gram matrix
/// `G_jl = Δf_j·Δf_l`.
#[derive(Clone, Debug, Default)]
pub struct AndersonState {
    /// Differences held (≤ `WINDOW`).
    pub held: usize,
    /// The ring slot the next difference goes to.
    pub next: usize,
    /// Whether the previous iterate and its `f` are stored.
    pub has_previous: bool,
    gram: [[f64; WINDOW]; WINDOW],
}

impl AndersonState {
    /// Forgets every iterate (a new solve).
    pub fn reset(&mut self) {
        *self = Self::default();
    }

    /// Records the difference just written to slot `self.next`, whose dot products with the
    /// slots' differences are `dots[l] = Δf_new·Δf_l` (its own at `dots[self.next]`), and
    /// advances the ring.
    pub fn push(&mut self, dots: &[f64; WINDOW]) {
        let s = self.next;
        for l in 0..WINDOW {
            self.gram[s][l] = dots[l];
            self.gram[l][s] = dots[l];
        }
        self.held = (self.held + 1).min(WINDOW);
        self.next = (s + 1) % WINDOW;
    }

    /// The mixing coefficients `γ` (one per slot, zero for empty slots) from `rhs[l] = Δf_l·f`:
    /// the normal equations `G γ = rhs` with a small Tikhonov term (the differences become
    /// nearly dependent as the solve converges), solved by Gaussian elimination in f64.
    pub fn coefficients(&self, rhs: &[f64; WINDOW]) -> [f64; WINDOW] {
        let m = self.held;
        let mut gamma = [0.0; WINDOW];
        if m == 0 {
            return gamma;
        }
        let trace: f64 = (0..m).map(|j| self.gram[j][j]).sum();
        if !trace.is_finite() || trace <= 0.0 {
            return gamma;
        }
        let lambda = 1e-10 * trace / m as f64;
        let mut a = [[0.0f64; WINDOW + 1]; WINDOW];
        for j in 0..m {
            for l in 0..m {
                a[j][l] = self.gram[j][l] + if j == l { lambda } else { 0.0 };
            }
            a[j][m] = rhs[j];
        }
        for c in 0..m {
            let pivot = (c..m)
                .max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))
                .unwrap_or(c);
            a.swap(c, pivot);
            if a[c][c].abs() < f64::MIN_POSITIVE {
                return [0.0; WINDOW];
            }
            for r in c + 1..m {
                let factor = a[r][c] / a[c][c];
                for k in c..=m {
                    a[r][k] -= factor * a[c][k];
                }
            }
        }
        for c in (0..m).rev() {
            let mut s = a[c][m];
            for k in c + 1..m {
                s -= a[c][k] * gamma[k];
            }
            gamma[c] = s / a[c][c];
        }
        if gamma[..m].iter().all(|g| g.is_finite()) {
            gamma
        } else {
            [0.0; WINDOW]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a linear map `g(x) = x + (b − A x)` with SPD `A` (n = 3), Anderson with a window of at
    /// least n reaches the solution in at most n + 1 iterations (it is GMRES).
    #[test]
    fn solves_a_small_linear_system_in_n_plus_one_iterations() {
        let a = [[4.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 2.0]];
        let b = [1.0, 2.0, 3.0];
        let scale = 0.25;
        let residual = |x: &[f64; 3]| -> [f64; 3] {
            let mut f = [0.0; 3];
            for i in 0..3 {
                f[i] = scale * (b[i] - (0..3).map(|k| a[i][k] * x[k]).sum::<f64>());
            }
            f
        };
        let dot = |u: &[f64; 3], v: &[f64; 3]| (0..3).map(|i| u[i] * v[i]).sum::<f64>();
        let mut state = AndersonState::default();
        let mut x = [0.0; 3];
        let mut dx = [[0.0; 3]; WINDOW];
        let mut df = [[0.0; 3]; WINDOW];
        let (mut x_prev, mut f_prev) = ([0.0; 3], [0.0; 3]);
        let mut last = f64::INFINITY;
        for _ in 0..5 {
            let f = residual(&x);
            last = dot(&f, &f).sqrt();
            if state.has_previous {
                let s = state.next;
                for i in 0..3 {
                    dx[s][i] = x[i] - x_prev[i];
                    df[s][i] = f[i] - f_prev[i];
                }
                let mut dots = [0.0; WINDOW];
                for l in 0..WINDOW {
                    dots[l] = dot(&df[s], &df[l]);
                }
                state.push(&dots);
            }
            let mut rhs = [0.0; WINDOW];
            for l in 0..state.held {
                rhs[l] = dot(&df[l], &f);
            }
            let gamma = state.coefficients(&rhs);
            x_prev = x;
            f_prev = f;
            state.has_previous = true;
            for i in 0..3 {
                x[i] += f[i]
                    - (0..state.held)
                        .map(|l| gamma[l] * (dx[l][i] + df[l][i]))
                        .sum::<f64>();
            }
        }
        assert!(last < 1e-9, "residual {last:e} after 5 iterations");
    }
}
