//! The fluid's initial state (`fluid.initial_state`): uniform (every particle at `ρ0`, no
//! pressure) or hydrostatic (each particle at the pressure of a resting column).
//!
//! The hydrostatic pressure of a particle at height `z` (along `−g`) under a free surface at
//! height `H` is `p = ρ0 |g| (H − z)` [Pa]. `H` is read from the generated particles, not from a
//! shape: the particles are binned by their position across gravity (one bin per lattice column,
//! `dx` wide), and a column's surface lies half a spacing above its highest particle. So any
//! fluid shape gets the surface its particles have. What the solver makes of the pressure (a
//! density by the inverted equation of state, a mass, or a carried pressure) is
//! `Simulation::with_initial_pressure`.

use crate::math::Vector;
use serde::Deserialize;
use std::collections::HashMap;

/// The fluid's initial state (`fluid.initial_state`, in `snake_case`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InitialState {
    /// Every fluid particle at the rest density `ρ0` with no pressure: a column first compresses
    /// under its own weight.
    #[default]
    Uniform,
    /// Every fluid particle at the pressure of a resting column under the scene's gravity,
    /// [`hydrostatic_pressure`].
    Hydrostatic,
}

impl InitialState {
    /// The name used in scene files (`"uniform"`, `"hydrostatic"`).
    pub fn name(self) -> &'static str {
        match self {
            InitialState::Uniform => "uniform",
            InitialState::Hydrostatic => "hydrostatic",
        }
    }
}

/// The hydrostatic pressure `p_i = ρ0 |g| (H_i − z_i)` [Pa] of each fluid particle at `position`
/// [m] (module doc), for gravity `gravity` [m/s²], rest density `rho0` [kg/m³] and lattice
/// spacing `spacing` [m]. `z` is the height along `−g`; `H_i` the highest `z` of the particles
/// in `i`'s column plus `spacing / 2`. Columns are the positions across gravity rounded to the
/// lattice of the first particle, so particles of one lattice share a column exactly (for
/// gravity along an axis); without gravity every pressure is zero.
pub fn hydrostatic_pressure<const D: usize>(
    position: &[Vector<D>],
    gravity: &[f64],
    rho0: f64,
    spacing: f64,
) -> Vec<f64> {
    let g: [f64; D] = std::array::from_fn(|k| gravity.get(k).copied().unwrap_or(0.0));
    let g_norm = g.iter().map(|c| c * c).sum::<f64>().sqrt();
    if position.is_empty() || g_norm == 0.0 || !g_norm.is_finite() {
        return vec![0.0; position.len()];
    }
    let up: [f64; D] = std::array::from_fn(|k| -g[k] / g_norm);
    let origin: [f64; D] = std::array::from_fn(|k| f64::from(position[0][k]));
    // Height along `up` and the lattice column across it, both from the first particle.
    let place = |x: &Vector<D>| {
        let d: [f64; D] = std::array::from_fn(|k| f64::from(x[k]) - origin[k]);
        let z: f64 = (0..D).map(|k| d[k] * up[k]).sum();
        let column: [i64; D] = std::array::from_fn(|k| ((d[k] - z * up[k]) / spacing).round() as i64);
        (z, column)
    };
    let mut top: HashMap<[i64; D], f64> = HashMap::new();
    for x in position {
        let (z, column) = place(x);
        let t = top.entry(column).or_insert(z);
        *t = t.max(z);
    }
    position
        .iter()
        .map(|x| {
            let (z, column) = place(x);
            let surface = top[&column] + 0.5 * spacing;
            rho0 * g_norm * (surface - z)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_column_carries_rho_g_depth_below_a_surface_half_a_spacing_up() {
        // Two columns of heights 4 and 2 spacings, lattice points at (i + 1/2) dx.
        let dx = 0.1;
        let mut x = Vec::new();
        for (i, n) in [(0, 4), (1, 2)] {
            for j in 0..n {
                x.push(Vector::<2>::new(
                    ((i as f64 + 0.5) * dx) as f32,
                    ((j as f64 + 0.5) * dx) as f32,
                ));
            }
        }
        let p = hydrostatic_pressure(&x, &[0.0, -9.81], 1000.0, dx);
        let expected = |n: usize, j: usize| 1000.0 * 9.81 * (n as f64 - j as f64 - 0.5) * dx;
        // f32 positions of 0.1-scale numbers: about 1e-7 relative, on depths of 0.05–0.35 m.
        let tol = 1e-3;
        for j in 0..4 {
            assert!(
                (p[j] - expected(4, j)).abs() < tol,
                "{} vs {}",
                p[j],
                expected(4, j)
            );
        }
        for j in 0..2 {
            assert!((p[4 + j] - expected(2, j)).abs() < tol);
        }
    }

    #[test]
    fn sideways_gravity_measures_depth_along_itself() {
        // Gravity along +x: the "surface" is the smallest x of each row, at x_min − dx/2.
        let dx = 0.5;
        let x: Vec<Vector<2>> = (0..3)
            .map(|i| Vector::<2>::new(i as f32 * 0.5 + 0.25, 0.25))
            .collect();
        let p = hydrostatic_pressure(&x, &[2.0, 0.0], 1.0, dx);
        for (i, pi) in p.iter().enumerate() {
            assert!((pi - 2.0 * (i as f64 + 0.5) * dx).abs() < 1e-6, "{i}: {pi}");
        }
    }

    #[test]
    fn without_gravity_nothing_is_pressed() {
        let x = vec![Vector::<3>::zeros(); 3];
        assert_eq!(
            hydrostatic_pressure(&x, &[0.0, 0.0, 0.0], 1000.0, 0.1),
            vec![0.0; 3]
        );
    }
}
