//! What every stage test shares: the backends under test, a random particle set with walls, the
//! brute-force neighbour search of the references, and comparisons per particle id.

use sph::backend::Backend;
use sph::backend::cpu::CpuBackend;
use sph::boundary::motion::SolidReference;
use sph::fields::{FLUID, Fields};
use sph::math::Vector;
use sph::model::pair_terms::{PairTerm, PairTermSettings, PairTerms};
use sph::model::params::StepParams;
use sph::model::{ForceTerms, SurfaceTensionModel};
use sph::physics::density::DensityKernel;
use sph::physics::lattice::lattice_spiky_scale;
use sph::physics::multiphase::Phases;

/// Relative tolerance of a neighbour sum against the sum of its terms' magnitudes. Two orders of
/// an f32 sum of N terms `t_j` differ by at most `2 (N − 1) u Σ|t_j|` (`u = 2⁻²⁴`); a support of
/// `h = 2 dx` holds about 13 neighbours in 2D and 34 in 3D, so 1e-5 bounds every case with room
/// (N up to ~80), while a missing or wrong term, which moves the sum by a whole term, fails it.
pub const SUM_ORDER: f64 = 1.0e-5;

/// Lattice spacing [m]; the support is `h = 2 dx`.
pub const DX: f32 = 0.01;
/// Rest density [kg/m³].
pub const RHO0: f32 = 1000.0;
/// Number of solids in [`scene`] (floor = 1, left wall = 2).
pub const SOLIDS: usize = 2;

/// A backend under test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Under {
    /// The rayon CPU backend.
    Cpu,
    /// The CUDA backend on the host shim.
    Shim,
    /// The CUDA backend on the first GPU.
    Gpu,
}

/// Every backend this build and machine can run (the GPU probed once per test binary).
pub fn backends() -> Vec<Under> {
    static GPU: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let mut all = vec![Under::Cpu];
    if cfg!(feature = "cuda") {
        all.push(Under::Shim);
        let gpu = *GPU.get_or_init(|| match sph::backend::cuda::probe() {
            Ok(()) => true,
            Err(e) => {
                let required = std::env::var("SPH_REQUIRE_GPU").is_ok_and(|v| v == "1");
                assert!(!required, "SPH_REQUIRE_GPU=1 but {e}");
                eprintln!("SKIPPED stages on a GPU: {e}");
                false
            }
        });
        if gpu {
            all.push(Under::Gpu);
        }
    }
    all
}

impl Under {
    /// The backend, holding a copy of `fields` where it keeps its own.
    pub fn start<const D: usize>(
        self,
        fields: &Fields<D>,
        params: &StepParams<D>,
    ) -> Box<dyn Backend<D> + Send> {
        match self {
            Under::Cpu => Box::new(CpuBackend::<D>::new()),
            #[cfg(feature = "cuda")]
            Under::Shim => sph::backend::cuda::shim::Shim::backend(fields, params).expect("the shim starts"),
            #[cfg(not(feature = "cuda"))]
            Under::Shim => unreachable!("backends() lists the shim only with the cuda feature"),
            Under::Gpu => sph::backend::cuda::create(fields, params, 0).expect("the GPU backend starts"),
        }
    }

    /// Runs `stage` on a fresh backend holding `fields`, after `sort_by_cell` (every neighbour
    /// stage needs the grid); returns the fields as the backend leaves them (in its order) and
    /// what the stage returned.
    pub fn run<const D: usize, R>(
        self,
        fields: &Fields<D>,
        params: &StepParams<D>,
        stage: impl FnOnce(&mut dyn Backend<D>, &mut Fields<D>) -> R,
    ) -> (Fields<D>, R) {
        let mut f = fields.clone();
        let mut backend = self.start(&f, params);
        backend.sort_by_cell(&mut f, params).expect("finite positions");
        let out = stage(backend.as_mut(), &mut f);
        backend.download(&mut f).expect("download");
        assert!(backend.take_error().is_none(), "{self:?}: no device error");
        (f, out)
    }
}

/// A small deterministic generator (xorshift), so failures reproduce.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in `[0, 1)`.
    pub fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in `[-a, a)`.
    pub fn sym(&mut self, a: f32) -> f32 {
        a * (2.0 * self.next() - 1.0)
    }

    /// Uniform index in `0..n`.
    pub fn below(&mut self, n: usize) -> usize {
        ((f64::from(self.next()) * n as f64) as usize).min(n - 1)
    }
}

/// Fluid lattice size per axis.
fn fluid_counts<const D: usize>() -> [i32; 3] {
    if D == 2 { [24, 16, 1] } else { [10, 8, 8] }
}

/// The velocity of solid `kind` (each wall moves rigidly) [m/s].
pub fn wall_velocity_of<const D: usize>(kind: u32) -> Vector<D> {
    Vector::from_fn(|k, _| [0.4, -0.25, 0.1][k] * if kind == 1 { 1.0 } else { -0.7 })
}

/// A jittered fluid block (random velocities up to 1 m/s, densities within 1 % of ρ0,
/// pressures up to 2 kPa with a quarter of the fluid at zero) on a floor (solid 1, two layers)
/// beside a left wall (solid 2, two layers), each wall moving rigidly, and random no-slip wall
/// velocities ([A12] eqs. 22–23) on every particle. Strong viscosity and artificial viscosity,
/// gravity, a rotating frame off every axis and a gradient scale ≠ 1, so that every term shows
/// above the tolerances. The storage order is shuffled and the ids permuted, so no backend sums
/// in the order the reference does.
pub fn scene<const D: usize>(seed: u64) -> (Fields<D>, StepParams<D>) {
    let mut rng = Rng(seed);
    let n = fluid_counts::<D>();
    let lo = [-2, -2, 0];
    let mut particles: Vec<(Vector<D>, Vector<D>, u32)> = Vec::new();
    let total: i32 = (0..D).map(|k| n[k] - lo[k]).product();
    for c in 0..total {
        let mut idx = [0i32; 3];
        let mut rest = c;
        for k in 0..D {
            let extent = n[k] - lo[k];
            idx[k] = lo[k] + rest % extent;
            rest /= extent;
        }
        let kind = if idx[1] < 0 {
            1
        } else if idx[0] < 0 {
            2
        } else {
            FLUID
        };
        let mut x = Vector::<D>::from_fn(|k, _| (idx[k] as f32 + 0.5) * DX);
        let u = if kind == FLUID {
            for k in 0..D {
                x[k] += rng.sym(0.15 * DX);
            }
            Vector::from_fn(|_, _| rng.sym(1.0))
        } else {
            wall_velocity_of(kind)
        };
        particles.push((x, u, kind));
    }
    for i in (1..particles.len()).rev() {
        particles.swap(i, rng.below(i + 1));
    }
    let mass = RHO0 * DX.powi(D as i32);
    let mut f = Fields::<D>::default();
    for (x, u, kind) in particles {
        f.push(x, u, mass, RHO0 * (1.0 + rng.sym(0.01)), kind);
        let p = if kind == FLUID && rng.next() < 0.25 {
            0.0
        } else {
            2000.0 * rng.next()
        };
        *f.pressure.last_mut().expect("just pushed") = p;
        *f.acceleration.last_mut().expect("just pushed") = Vector::from_fn(|_, _| rng.sym(10.0));
    }
    for i in (1..f.len()).rev() {
        f.id.swap(i, rng.below(i + 1));
    }
    f.wall_velocity = (0..f.len())
        .map(|_| Vector::from_fn(|_, _| rng.sym(1.0)))
        .collect();
    let mut gravity = Vector::<D>::zeros();
    gravity[1] = -9.81;
    let p = StepParams {
        h: 2.0 * DX,
        rho0: RHO0,
        c2: 40.0 * 40.0,
        pair: PairTermSettings::none()
            .with(PairTerm::Viscosity, 1.0)
            .with(PairTerm::ArtificialViscosity, 0.3)
            .coefficients(),
        c: 40.0,
        pressure_gradient_scale: 1.05,
        gravity,
        domain_min: Vector::from_fn(|k, _| (lo[k] as f32 - 1.0) * DX),
        domain_max: Vector::from_fn(|k, _| (n[k] as f32 + 6.0) * DX),
        // Off every axis, so that both the in-plane and the out-of-plane part act in 2D.
        angular_velocity: [1.5, -2.0, 7.0],
        rotation_centre: Vector::from_fn(|k, _| 0.02 * (k as f32 + 1.0)),
        viscosity_scale: 1.17,
        surface_tension_gamma: 0.0,
        surface_tension_sigma: 0.0,
        spacing: DX,
        density_spiky_scale: 0.0,
        density_kernel: DensityKernel::Poly6,
        surface_tension_model: SurfaceTensionModel::SurfaceStress,
        rotating_frame: 1,
        phases: Phases::Single,
        density_diffusion: 0.0,
        artificial_viscosity_wall_factor: 1.0,
        periodic: sph::periodic::PeriodicAxes::NONE,
    };
    (f, p)
}

/// Adds particles the grid must still place: a cluster across the domain's upper face on axis
/// 0, and far clusters of fluid and of solid 1 outside it. They go at random storage places,
/// with fresh ids.
pub fn add_strays<const D: usize>(f: &mut Fields<D>, p: &StepParams<D>, seed: u64) {
    let mut rng = Rng(seed);
    let mass = f.mass[0];
    let mut across = (p.domain_min + p.domain_max) * 0.5;
    across[0] = p.domain_max[0];
    let mut strays: Vec<(Vector<D>, u32)> = (0..40)
        .map(|_| (across + Vector::from_fn(|_, _| rng.sym(2.0 * p.h)), FLUID))
        .collect();
    for (offset, kind) in [(-0.5, FLUID), (0.6, 1)] {
        let c = Vector::<D>::repeat(offset);
        strays.extend((0..12).map(|_| (c + Vector::from_fn(|_, _| rng.sym(0.6 * p.h)), kind)));
    }
    let wall = !f.wall_velocity.is_empty();
    for (x, kind) in strays {
        let u = Vector::from_fn(|_, _| rng.sym(1.0));
        f.push(x, u, mass, RHO0 * (1.0 + rng.sym(0.01)), kind);
        *f.pressure.last_mut().expect("just pushed") = 2000.0 * rng.next();
        if wall {
            f.wall_velocity.push(Vector::from_fn(|_, _| rng.sym(1.0)));
        }
        // Moved to a random place, keeping every field's entries together.
        let last = f.len() - 1;
        let at = rng.below(f.len());
        swap_particles(f, at, last);
    }
}

/// Swaps particles `a` and `b` in every allocated field.
pub fn swap_particles<const D: usize>(f: &mut Fields<D>, a: usize, b: usize) {
    f.position.swap(a, b);
    f.velocity.swap(a, b);
    f.acceleration.swap(a, b);
    f.density.swap(a, b);
    f.pressure.swap(a, b);
    f.mass.swap(a, b);
    f.kind.swap(a, b);
    f.id.swap(a, b);
    for v in [
        &mut f.position_start,
        &mut f.velocity_start,
        &mut f.wall_velocity,
        &mut f.normal,
    ] {
        if !v.is_empty() {
            v.swap(a, b);
        }
    }
    if !f.rest_density.is_empty() {
        f.rest_density.swap(a, b);
    }
}

/// Sets the kernel of (18): poly6, or the spiky one scaled for the lattice
/// (`physics::lattice::lattice_spiky_scale`).
pub fn use_density_kernel<const D: usize>(p: &mut StepParams<D>, kernel: DensityKernel) {
    p.density_kernel = kernel;
    p.density_spiky_scale = match kernel {
        DensityKernel::Poly6 => 0.0,
        DensityKernel::ScaledSpiky => lattice_spiky_scale(&p.smoothing(), f64::from(DX)) as f32,
    };
}

/// Makes `phases` the plan's; with [`Phases::Multi`] ([HA06]) every third particle by id
/// (solids too) is eight times lighter, as in a light layer: its rest density and mass, and
/// with `densities` its density too.
pub fn use_phases<const D: usize>(f: &mut Fields<D>, p: &mut StepParams<D>, phases: Phases, densities: bool) {
    p.phases = phases;
    if phases == Phases::Multi {
        f.rest_density = (0..f.len())
            .map(|i| if f.id[i] % 3 == 0 { RHO0 / 8.0 } else { RHO0 })
            .collect();
        for i in 0..f.len() {
            let ratio = f.rest_density[i] / RHO0;
            f.mass[i] *= ratio;
            if densities {
                f.density[i] *= ratio;
            }
        }
    }
}

/// Every term set: each set of pair terms, without and with the rotating frame.
pub fn all_force_terms() -> impl Iterator<Item = ForceTerms> {
    (0..2 * PairTerms::SETS).map(|k| ForceTerms {
        pair: PairTerms::from_bits((k % PairTerms::SETS) as u32),
        rotating_frame: k >= PairTerms::SETS,
    })
}

/// `at[id]` = the storage index of particle `id`.
pub fn index_of_id<const D: usize>(f: &Fields<D>) -> Vec<usize> {
    let mut at = vec![usize::MAX; f.len()];
    for (i, &id) in f.id.iter().enumerate() {
        at[id as usize] = i;
    }
    at
}

/// `values` (one per particle of `f`, in `f`'s order) in id order.
pub fn by_id<const D: usize, T: Copy>(f: &Fields<D>, values: &[T]) -> Vec<T> {
    index_of_id(f).into_iter().map(|i| values[i]).collect()
}

/// `f` with every field in id order (particle `id` at index `id`), so that a backend's output
/// and the reference line up.
pub fn in_id_order<const D: usize>(f: &Fields<D>) -> Fields<D> {
    let at = index_of_id(f);
    let pick_vec = |v: &Vec<Vector<D>>| {
        if v.is_empty() {
            Vec::new()
        } else {
            at.iter().map(|&i| v[i]).collect()
        }
    };
    let pick = |v: &Vec<f32>| {
        if v.is_empty() {
            Vec::new()
        } else {
            at.iter().map(|&i| v[i]).collect()
        }
    };
    let mut out = f.clone();
    out.position = pick_vec(&f.position);
    out.velocity = pick_vec(&f.velocity);
    out.acceleration = pick_vec(&f.acceleration);
    out.position_start = pick_vec(&f.position_start);
    out.velocity_start = pick_vec(&f.velocity_start);
    out.wall_velocity = pick_vec(&f.wall_velocity);
    out.normal = pick_vec(&f.normal);
    out.density = pick(&f.density);
    out.pressure = pick(&f.pressure);
    out.mass = pick(&f.mass);
    out.rest_density = pick(&f.rest_density);
    out.density_rate = pick(&f.density_rate);
    out.density_start = pick(&f.density_start);
    out.acting_pressure = pick(&f.acting_pressure);
    out.kind = at.iter().map(|&i| f.kind[i]).collect();
    out.id = at.iter().map(|&i| f.id[i]).collect();
    out
}

/// The particles `j ≠ i` of `f` within `h` of particle `i` (brute force), with `x_i − x_j`
/// and its length.
pub fn neighbours<const D: usize>(f: &Fields<D>, h: f32, i: usize) -> Vec<(usize, Vector<D>, f32)> {
    (0..f.len())
        .filter(|&j| j != i)
        .filter_map(|j| {
            let d = f.position[i] - f.position[j];
            let r2 = d.norm_squared();
            (r2 < h * h).then(|| (j, d, r2.sqrt()))
        })
        .collect()
}

/// `|v|` as f64.
pub fn norm<const D: usize>(v: &Vector<D>) -> f64 {
    f64::from(v.norm())
}

/// Asserts `|got − want| ≤ tol` per component, naming the backend, what and which particle.
pub fn assert_close<const D: usize>(
    under: Under,
    what: &str,
    id: usize,
    got: &Vector<D>,
    want: &Vector<D>,
    tol: f64,
) {
    for k in 0..D {
        let diff = f64::from(got[k] - want[k]).abs();
        assert!(
            diff <= tol,
            "{under:?} {D}D {what}: particle {id} axis {k}: got {} want {} (tolerance {tol:.3e})",
            got[k],
            want[k]
        );
    }
}

/// The scene with ids as `Simulation` lays them out (fluid first, then the solids; storage stays
/// shuffled), and the solids' reference positions: their positions, jittered by 0.3 dx.
pub fn solid_scene<const D: usize>(seed: u64) -> (Fields<D>, StepParams<D>, SolidReference<D>) {
    let (mut f, p) = scene::<D>(seed);
    add_strays(&mut f, &p, seed ^ 0x5151);
    let mut order: Vec<usize> = (0..f.len()).collect();
    order.sort_by_key(|&i| (f.kind[i] != FLUID, f.id[i]));
    for (new, &i) in order.iter().enumerate() {
        f.id[i] = new as u32;
    }
    let first_id = f.kind.iter().filter(|&&k| k == FLUID).count() as u32;
    let mut rng = Rng(seed ^ 0x5eed);
    let r = in_id_order(&f);
    let reference = SolidReference::<D> {
        first_id,
        position: (first_id as usize..r.len())
            .map(|id| r.position[id] + Vector::from_fn(|_, _| rng.sym(0.3 * DX)))
            .collect(),
    };
    (f, p, reference)
}
