//! Every CUDA kernel of `kernels/`, run on the CPU through the host shim (`backend::cuda::shim`),
//! against the rayon stage it mirrors, on random inputs. These run everywhere, GPU or not.
#![cfg(feature = "cuda")]

use sph::backend::Backend;
use sph::backend::cpu::CpuBackend;
use sph::backend::cuda::shim;
use sph::backend::params::StepParams;
use sph::fields::{FLUID, Fields};
use sph::math::Vector;

/// Parameters with a water-like state, support `h` [m].
fn params<const D: usize>(h: f32) -> StepParams<D> {
    StepParams {
        h,
        rho0: 1000.0,
        c2: 40.0 * 40.0,
        mu: 1.0e-3,
        alpha: 0.05,
        c: 40.0,
        pressure_gradient_scale: 1.0,
        gravity: Vector::zeros(),
        domain_min: Vector::repeat(-1.0),
        domain_max: Vector::repeat(1.0),
    }
}

/// A small deterministic generator (xorshift), so failures reproduce.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

#[test]
fn equation_of_state_matches_the_cpu_stage() {
    let mut rng = Rng(0x9e3779b97f4a7c15);
    let mut f = Fields::<3>::default();
    for k in 0..1000u32 {
        let kind = if k % 7 == 0 { 1 } else { FLUID };
        f.push(Vector::zeros(), Vector::zeros(), 1.0, 990.0 + 20.0 * rng.next(), kind);
    }
    let p = params::<3>(0.1);
    let mut cpu = f.clone();
    CpuBackend::<3>::new().equation_of_state(&mut cpu, &p);
    let mut pressure = f.pressure.clone();
    // SAFETY: every slice has n = f.len() items.
    unsafe {
        shim::sph_shim_equation_of_state_3(
            f.len() as u32,
            &p,
            f.density.as_ptr(),
            f.kind.as_ptr(),
            pressure.as_mut_ptr(),
        );
    }
    assert_eq!(pressure, cpu.pressure, "same f32 formula, bitwise equal");
    assert!(cpu.pressure.iter().any(|&x| x > 0.0) && cpu.pressure.iter().any(|&x| x == 0.0));
}
