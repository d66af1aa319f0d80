//! Random particle sets for the decomposition tests.

use sph::fields::Fields;
use sph::math::Vector;
use sph::physics::pcg::Pcg32;

/// Uniform draws in [0, 1) from the library's PCG32, so that the tests need no seed.
pub struct Rng(Pcg32);

impl Rng {
    /// The generator of `seed`.
    pub fn new(seed: u64) -> Self {
        Self(Pcg32::new(seed, 0))
    }

    /// A uniform draw in [0, 1).
    pub fn next(&mut self) -> f32 {
        self.0.next_f64() as f32
    }
}

/// `n` particles in the box [0, 2] x [0, 1] (x [0, 0.5] in 3D), with every field holding
/// distinct bits (velocity, mass, density, pressure, the step-start copies and the acting
/// pressure), so that a field swapped or dropped in transit shows; ids 0..n.
pub fn random_fields<const D: usize>(n: usize, seed: u64) -> Fields<D> {
    let mut rng = Rng::new(seed);
    let mut fields = Fields::with_capacity(n);
    let extent = [2.0, 1.0, 0.5];
    for k in 0..n {
        let x = Vector::<D>::from_fn(|c, _| extent[c] * rng.next());
        let u = Vector::<D>::from_fn(|_, _| rng.next() - 0.5);
        fields.push(x, u, 1.0 + rng.next(), 1000.0 + rng.next(), (k % 3) as u32);
        fields.pressure[k] = 100.0 * rng.next();
    }
    fields.position_start = fields.position.iter().map(|x| x * 0.5).collect();
    fields.velocity_start = fields.velocity.iter().map(|u| u * 2.0).collect();
    fields.acting_pressure = fields.pressure.iter().map(|p| p + 1.0).collect();
    fields
}

/// The particles `range` of `fields` (ids kept), as a rank's share before any migration.
pub fn slice<const D: usize>(fields: &Fields<D>, range: std::ops::Range<usize>) -> Fields<D> {
    let kept: Vec<u32> = range.map(|k| k as u32).collect();
    let mut part = fields.clone();
    part.keep(&kept);
    part
}
