//! The time-integration stages, `integrate` (symplectic Euler), `store_step_start` and
//! `rk_stage` (one Shu–Osher stage of SSP-RK3), on every backend. Per particle, without sums: the
//! same f32 operations in the same order as the reference here, so compared bitwise. Fluid
//! moves; solids keep their position and velocity.

use crate::setup::{Rng, Under, backends, by_id, in_id_order, scene};
use sph::backend::Backend;
use sph::fields::{FLUID, Fields};
use sph::math::Vector;

/// Time step [s].
const DT: f32 = 1.3e-3;
/// The Shu–Osher coefficients `(a, b)` of SSP-RK3's three stages.
const STAGES: [(f32, f32); 3] = [(0.0, 1.0), (0.75, 0.25), (1.0 / 3.0, 2.0 / 3.0)];

/// What the reference of one step carries: the fields (id order) and the step start.
#[derive(Clone)]
struct State<const D: usize> {
    position: Vec<Vector<D>>,
    velocity: Vec<Vector<D>>,
    position_start: Vec<Vector<D>>,
    velocity_start: Vec<Vector<D>>,
}

impl<const D: usize> State<D> {
    /// Symplectic Euler for fluid: `u += a dt`, then `x += u dt` with the new `u`.
    fn integrate(&mut self, f: &Fields<D>, dt: f32) {
        for i in (0..f.len()).filter(|&i| f.kind[i] == FLUID) {
            self.velocity[i] += f.acceleration[i] * dt;
            self.position[i] += self.velocity[i] * dt;
        }
    }

    /// `x^n`, `u^n` of every particle.
    fn store_step_start(&mut self) {
        self.position_start.clone_from(&self.position);
        self.velocity_start.clone_from(&self.velocity);
    }

    /// For fluid `x ← a x^n + b (x + dt u)`, `u ← a u^n + b (u + dt acc)`, both Euler steps from
    /// the stage's own `x`, `u`.
    fn rk_stage(&mut self, f: &Fields<D>, dt: f32, a: f32, b: f32) {
        for i in (0..f.len()).filter(|&i| f.kind[i] == FLUID) {
            let x_euler = self.position[i] + self.velocity[i] * dt;
            let u_euler = self.velocity[i] + f.acceleration[i] * dt;
            self.position[i] = self.position_start[i] * a + x_euler * b;
            self.velocity[i] = self.velocity_start[i] * a + u_euler * b;
        }
    }
}

/// Runs the first `steps` of the sequence `integrate`, `store_step_start`, then the three RK
/// stages on `b`.
fn run_prefix<const D: usize>(b: &mut dyn Backend<D>, f: &mut Fields<D>, steps: usize) {
    for step in 0..steps {
        match step {
            0 => b.integrate(f, DT),
            1 => b.store_step_start(f),
            s => {
                let (a, w) = STAGES[s - 2];
                b.rk_stage(f, DT, a, w);
            }
        }
    }
}

/// `v` compared bitwise, per particle id.
fn assert_bitwise<const D: usize>(under: Under, what: &str, got: &[Vector<D>], want: &[Vector<D>]) {
    for (id, (g, w)) in got.iter().zip(want).enumerate() {
        let (g, w) = (g.map(f32::to_bits), w.map(f32::to_bits));
        assert_eq!(g, w, "{under:?} {D}D {what}: particle {id}");
    }
}

fn check_integration<const D: usize>(seed: u64) {
    let (mut f, p) = scene::<D>(seed);
    let mut rng = Rng(seed ^ 0xabcd);
    for a in f.acceleration.iter_mut() {
        *a = Vector::from_fn(|_, _| rng.sym(30.0));
    }
    let reference = in_id_order(&f);
    let start = State {
        position: reference.position.clone(),
        velocity: reference.velocity.clone(),
        position_start: Vec::new(),
        velocity_start: Vec::new(),
    };
    // The reference after each prefix of the sequence.
    let mut states = vec![start.clone()];
    let mut s = start.clone();
    for step in 0..2 + STAGES.len() {
        match step {
            0 => s.integrate(&reference, DT),
            1 => s.store_step_start(),
            k => {
                let (a, b) = STAGES[k - 2];
                // The step start counts: a stage with a ≠ 0 is not the Euler stage.
                let mut euler = s.clone();
                euler.rk_stage(&reference, DT, 0.0, 1.0);
                s.rk_stage(&reference, DT, a, b);
                assert!(a == 0.0 || euler.position != s.position, "{D}D stage ({a}, {b})");
            }
        }
        states.push(s.clone());
    }
    let fluid = |id: usize| reference.kind[id] == FLUID;
    for id in 0..reference.len() {
        let moved = s.position[id] != reference.position[id] && s.velocity[id] != reference.velocity[id];
        assert_eq!(moved, fluid(id), "{D}D particle {id}: fluid only moves");
    }

    for under in backends() {
        for steps in 1..states.len() {
            let (out, ()) = under.run(&f, &p, |b, f| run_prefix(b, f, steps));
            let want = &states[steps];
            let what = format!("after {steps} stages");
            assert_bitwise(
                under,
                &format!("{what}: position"),
                &by_id(&out, &out.position),
                &want.position,
            );
            assert_bitwise(
                under,
                &format!("{what}: velocity"),
                &by_id(&out, &out.velocity),
                &want.velocity,
            );
            // The CPU keeps the step start in `Fields`; the CUDA backend keeps it on the device
            // only (its `download` leaves none), where the RK stages above read it.
            if steps >= 2 && !out.position_start.is_empty() {
                let got = by_id(&out, &out.position_start);
                assert_bitwise(
                    under,
                    &format!("{what}: position start"),
                    &got,
                    &want.position_start,
                );
                let got = by_id(&out, &out.velocity_start);
                assert_bitwise(
                    under,
                    &format!("{what}: velocity start"),
                    &got,
                    &want.velocity_start,
                );
            }
        }
        eprintln!("{under:?} {D}D integrate, store_step_start, 3 RK stages: bitwise equal");
    }
}

#[test]
fn integration_stages_are_the_f32_formulas_bitwise() {
    check_integration::<2>(0x2468_ace0_1357_9bdf);
    check_integration::<3>(0x1357_9bdf_2468_ace0);
}
