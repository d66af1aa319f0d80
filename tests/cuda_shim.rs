//! Every CUDA kernel of `kernels/`, run on the CPU through the host shim (`backend::cuda::shim`),
//! against the rayon stage it mirrors, on random inputs. These run everywhere, GPU or not.
#![cfg(feature = "cuda")]

use sph::backend::cpu::CpuBackend;
use sph::backend::cuda::grid::GridGeometry;
use sph::backend::cuda::shim;
use sph::backend::params::StepParams;
use sph::backend::{Backend, WallModel};
use sph::fields::{FLUID, Fields};
use sph::grid::neighbours_naive;
use sph::math::{Real, Vector};
use sph::physics::density::DensityWeight;

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
        angular_velocity: [0.0; 3],
        rotation_centre: Vector::zeros(),
        viscosity_scale: 1.0,
        surface_tension_gamma: 0.0,
        surface_tension_sigma: 0.0,
        spacing: 0.0,
        density_spiky_scale: 0.0,
        density_kernel: sph::physics::density::DensityKernel::Poly6,
        surface_tension_model: sph::backend::SurfaceTensionModel::SurfaceStress,
        rotating_frame: 0,
        phases: sph::physics::multiphase::Phases::Single,
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

    /// Uniform in `[-a, a)`.
    fn sym(&mut self, a: f32) -> f32 {
        a * (2.0 * self.next() - 1.0)
    }

    /// Uniform index in `0..n`.
    fn below(&mut self, n: usize) -> usize {
        ((self.next() as f64 * n as f64) as usize).min(n - 1)
    }
}

#[test]
fn equation_of_state_matches_the_cpu_stage() {
    let mut rng = Rng(0x9e3779b97f4a7c15);
    let mut f = Fields::<3>::default();
    for k in 0..1000u32 {
        let kind = if k % 7 == 0 { 1 } else { FLUID };
        f.push(
            Vector::zeros(),
            Vector::zeros(),
            1.0,
            990.0 + 20.0 * rng.next(),
            kind,
        );
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
    assert!(cpu.pressure.iter().any(|&x| x > 0.0) && cpu.pressure.contains(&0.0));
}

// ---------------------------------------------------------------------------------------------
// Neighbour-side kernels: sort_by_cell, density, wall_pressure, wall_velocity, and the candidate
// loop itself.

/// The shim's neighbour-side launchers of one dimension, so one test body serves 2D and 3D.
struct Kernels<const D: usize> {
    cell_hash: unsafe extern "C" fn(u32, *const GridGeometry<D>, *const f32, *mut u32, *mut u32),
    scan_chunks: unsafe extern "C" fn(u32, u32, *const u32, *mut u32, *mut u32),
    scan_chunk_sums: unsafe extern "C" fn(u32, *mut u32),
    scan_add: unsafe extern "C" fn(u32, u32, *mut u32, *const u32),
    scatter: unsafe extern "C" fn(u32, *const u32, *const u32, *mut u32, *mut u32),
    order_cells: unsafe extern "C" fn(u32, *const u32, *const u32, *mut u32),
    gather_vec: unsafe extern "C" fn(u32, *const u32, *const f32, *mut f32),
    gather_f32: unsafe extern "C" fn(u32, *const u32, *const f32, *mut f32),
    gather_u32: unsafe extern "C" fn(u32, *const u32, *const u32, *mut u32),
    density: unsafe extern "C" fn(
        u32,
        *const StepParams<D>,
        *const GridGeometry<D>,
        *const u32,
        *const u32,
        *const f32,
        *const f32,
        *const u32,
        *mut f32,
    ),
    wall_pressure: unsafe extern "C" fn(
        u32,
        *const StepParams<D>,
        *const GridGeometry<D>,
        *const u32,
        *const u32,
        *const f32,
        *const f32,
        *const u32,
        *const f32,
        i32,
        *mut f32,
        *mut f32,
    ),
    wall_velocity: unsafe extern "C" fn(
        u32,
        *const StepParams<D>,
        *const GridGeometry<D>,
        *const u32,
        *const u32,
        *const f32,
        *const f32,
        *const u32,
        *mut f32,
    ),
    neighbour_list: unsafe extern "C" fn(
        u32,
        f32,
        *const GridGeometry<D>,
        *const u32,
        *const u32,
        *const f32,
        u32,
        *mut u32,
        *mut u32,
    ),
}

const KERNELS_2: Kernels<2> = Kernels {
    cell_hash: shim::sph_shim_cell_hash_2,
    scan_chunks: shim::sph_shim_scan_chunks_2,
    scan_chunk_sums: shim::sph_shim_scan_chunk_sums_2,
    scan_add: shim::sph_shim_scan_add_2,
    scatter: shim::sph_shim_scatter_2,
    order_cells: shim::sph_shim_order_cells_2,
    gather_vec: shim::sph_shim_gather_vec_2,
    gather_f32: shim::sph_shim_gather_f32_2,
    gather_u32: shim::sph_shim_gather_u32_2,
    density: shim::sph_shim_density_2,
    wall_pressure: shim::sph_shim_wall_pressure_2,
    wall_velocity: shim::sph_shim_wall_velocity_2,
    neighbour_list: shim::sph_shim_neighbour_list_2,
};

const KERNELS_3: Kernels<3> = Kernels {
    cell_hash: shim::sph_shim_cell_hash_3,
    scan_chunks: shim::sph_shim_scan_chunks_3,
    scan_chunk_sums: shim::sph_shim_scan_chunk_sums_3,
    scan_add: shim::sph_shim_scan_add_3,
    scatter: shim::sph_shim_scatter_3,
    order_cells: shim::sph_shim_order_cells_3,
    gather_vec: shim::sph_shim_gather_vec_3,
    gather_f32: shim::sph_shim_gather_f32_3,
    gather_u32: shim::sph_shim_gather_u32_3,
    density: shim::sph_shim_density_3,
    wall_pressure: shim::sph_shim_wall_pressure_3,
    wall_velocity: shim::sph_shim_wall_velocity_3,
    neighbour_list: shim::sph_shim_neighbour_list_3,
};

/// A vector field as the kernels see it: `D` floats per particle.
fn flat<const D: usize>(v: &[Vector<D>]) -> *const f32 {
    v.as_ptr().cast::<f32>()
}

fn flat_mut<const D: usize>(v: &mut [Vector<D>]) -> *mut f32 {
    v.as_mut_ptr().cast::<f32>()
}

/// Chunk of the device scan in `sort_on_shim` (several chunks on the test grids).
const SCAN_CHUNK: u32 = 32;

/// The dense grid's state after `sort_on_shim`, as the stage kernels read it.
struct DeviceGrid<const D: usize> {
    geometry: GridGeometry<D>,
    /// First particle of each cell, `ncell + 1` entries.
    cell_start: Vec<u32>,
    /// Cell key of each particle, in sorted order.
    cell_key: Vec<u32>,
}

impl<const D: usize> Kernels<D> {
    /// Exclusive scan of `counts` (`m` entries) into a new vector, as the host runs it.
    fn exclusive_scan(&self, counts: &[u32], chunk: u32) -> Vec<u32> {
        let m = counts.len() as u32;
        let chunks = m.div_ceil(chunk);
        let mut out = vec![u32::MAX; counts.len()];
        let mut chunk_sums = vec![u32::MAX; chunks as usize];
        // SAFETY: `counts` and `out` have m entries, `chunk_sums` ceil(m / chunk).
        unsafe {
            (self.scan_chunks)(
                m,
                chunk,
                counts.as_ptr(),
                out.as_mut_ptr(),
                chunk_sums.as_mut_ptr(),
            );
            (self.scan_chunk_sums)(chunks, chunk_sums.as_mut_ptr());
            (self.scan_add)(m, chunk, out.as_mut_ptr(), chunk_sums.as_ptr());
        }
        out
    }

    /// Stage `sort_by_cell` through the shim, launched as the CUDA backend does: hash, count,
    /// scan, scatter, order each cell by id, then gather every field and the keys.
    fn sort_on_shim(&self, f: &mut Fields<D>, geometry: GridGeometry<D>) -> DeviceGrid<D> {
        let n = f.len();
        let ncell = geometry.cell_count();
        let mut key = vec![0u32; n];
        let mut cell_count = vec![0u32; ncell + 1];
        // SAFETY: positions have n * D floats, key n entries, cell_count ncell + 1.
        unsafe {
            (self.cell_hash)(
                n as u32,
                &geometry,
                flat(&f.position),
                key.as_mut_ptr(),
                cell_count.as_mut_ptr(),
            );
        }
        let cell_start = self.exclusive_scan(&cell_count, SCAN_CHUNK);
        assert_eq!(
            cell_start[ncell] as usize, n,
            "the last cell_start is the particle count"
        );
        let mut cell_fill = vec![0u32; ncell];
        let mut perm = vec![u32::MAX; n];
        // SAFETY: key and perm have n entries, cell_start ncell + 1, cell_fill ncell.
        unsafe {
            (self.scatter)(
                n as u32,
                key.as_ptr(),
                cell_start.as_ptr(),
                cell_fill.as_mut_ptr(),
                perm.as_mut_ptr(),
            );
            (self.order_cells)(
                ncell as u32,
                cell_start.as_ptr(),
                f.id.as_ptr(),
                perm.as_mut_ptr(),
            );
        }
        let vec_field = |src: &Vec<Vector<D>>| {
            let mut dst = vec![Vector::<D>::zeros(); n];
            // SAFETY: perm, src and dst have n items; perm holds indices < n (checked by callers).
            unsafe { (self.gather_vec)(n as u32, perm.as_ptr(), flat(src), flat_mut(&mut dst)) };
            dst
        };
        let f32_field = |src: &Vec<Real>| {
            let mut dst = vec![0.0; n];
            // SAFETY: as above.
            unsafe { (self.gather_f32)(n as u32, perm.as_ptr(), src.as_ptr(), dst.as_mut_ptr()) };
            dst
        };
        let u32_field = |src: &Vec<u32>| {
            let mut dst = vec![0; n];
            // SAFETY: as above.
            unsafe { (self.gather_u32)(n as u32, perm.as_ptr(), src.as_ptr(), dst.as_mut_ptr()) };
            dst
        };
        f.position = vec_field(&f.position);
        f.velocity = vec_field(&f.velocity);
        f.acceleration = vec_field(&f.acceleration);
        f.density = f32_field(&f.density);
        f.pressure = f32_field(&f.pressure);
        f.mass = f32_field(&f.mass);
        f.kind = u32_field(&f.kind);
        f.id = u32_field(&f.id);
        if !f.wall_velocity.is_empty() {
            f.wall_velocity = vec_field(&f.wall_velocity);
        }
        DeviceGrid {
            geometry,
            cell_start,
            cell_key: u32_field(&key),
        }
    }

    /// Stage `density` through the shim on sorted fields.
    fn density(&self, f: &mut Fields<D>, p: &StepParams<D>, grid: &DeviceGrid<D>) {
        // SAFETY: every field has n items, the grid is the one the fields were sorted with.
        unsafe {
            (self.density)(
                f.len() as u32,
                p,
                &grid.geometry,
                grid.cell_start.as_ptr(),
                grid.cell_key.as_ptr(),
                flat(&f.position),
                f.mass.as_ptr(),
                f.kind.as_ptr(),
                f.density.as_mut_ptr(),
            );
        }
    }

    /// Stage `wall_pressure` through the shim on sorted fields; `wall_acc` holds each solid's
    /// acceleration (the device's buffer: zeros for walls at rest).
    fn wall_pressure(
        &self,
        f: &mut Fields<D>,
        p: &StepParams<D>,
        grid: &DeviceGrid<D>,
        model: WallModel,
        wall_acc: &[Vector<D>],
    ) {
        let flag = i32::from(model == WallModel::ExtrapolatedOrSummed);
        // SAFETY: as in `density`.
        unsafe {
            (self.wall_pressure)(
                f.len() as u32,
                p,
                &grid.geometry,
                grid.cell_start.as_ptr(),
                grid.cell_key.as_ptr(),
                flat(&f.position),
                f.mass.as_ptr(),
                f.kind.as_ptr(),
                flat(wall_acc),
                flag,
                f.pressure.as_mut_ptr(),
                f.density.as_mut_ptr(),
            );
        }
    }

    /// Stage `wall_velocity` through the shim on sorted fields (`f.wall_velocity` allocated).
    fn wall_velocity(&self, f: &mut Fields<D>, p: &StepParams<D>, grid: &DeviceGrid<D>) {
        assert_eq!(
            f.wall_velocity.len(),
            f.len(),
            "the device buffer holds n vectors"
        );
        // SAFETY: as in `density`.
        unsafe {
            (self.wall_velocity)(
                f.len() as u32,
                p,
                &grid.geometry,
                grid.cell_start.as_ptr(),
                grid.cell_key.as_ptr(),
                flat(&f.position),
                flat(&f.velocity),
                f.kind.as_ptr(),
                flat_mut(&mut f.wall_velocity),
            );
        }
    }

    /// Each particle's neighbours (`r < h`) as the kernels' candidate loop finds them, ascending.
    fn neighbour_lists(&self, position: &[Vector<D>], h: f32, grid: &DeviceGrid<D>) -> Vec<Vec<usize>> {
        const MAX: usize = 512;
        let n = position.len();
        let mut count = vec![0u32; n];
        let mut list = vec![u32::MAX; n * MAX];
        // SAFETY: positions and count have n items, list n * MAX.
        unsafe {
            (self.neighbour_list)(
                n as u32,
                h,
                &grid.geometry,
                grid.cell_start.as_ptr(),
                grid.cell_key.as_ptr(),
                flat(position),
                MAX as u32,
                count.as_mut_ptr(),
                list.as_mut_ptr(),
            );
        }
        (0..n)
            .map(|i| {
                let c = count[i] as usize;
                assert!(
                    c <= MAX,
                    "particle {i} has {c} neighbours, more than the test's list holds"
                );
                let mut l: Vec<usize> = list[i * MAX..i * MAX + c].iter().map(|&j| j as usize).collect();
                l.sort_unstable();
                l
            })
            .collect()
    }
}

/// A test state: fluid jittered on a lattice of spacing `dx` with `h = 2 dx`, under gravity,
/// with two solids (a floor and a side wall, exact lattices, partly outside the domain) and a
/// few particles outside the domain box: a fluid blob across the upper x face, a fluid and a
/// solid cluster far outside. Pushed in random order so the sort has work to do, with ids a
/// random permutation of the storage order.
struct Setup<const D: usize> {
    fields: Fields<D>,
    params: StepParams<D>,
    geometry: GridGeometry<D>,
}

fn setup<const D: usize>(seed: u64) -> Setup<D> {
    let mut rng = Rng(seed);
    let dx: f32 = if D == 2 { 0.02 } else { 0.05 };
    let h = 2.0 * dx;
    let rho0 = 1000.0;
    let mass = rho0 * dx.powi(D as i32);
    let mut p = params::<D>(h);
    p.gravity[1] = -9.81;
    p.domain_min = Vector::repeat(0.0);
    p.domain_max = Vector::repeat(1.0);
    // Lattice counts: fluid block, walls (3 layers) under and beside it.
    let fluid_n: [usize; 3] = if D == 2 { [25, 20, 1] } else { [10, 8, 9] };
    let wall_n = if D == 2 { 30 } else { 13 };
    let base = 2.0 * dx; // fluid starts here; walls at base - (l + 1) dx, the last one below 0
    let mut particles: Vec<(Vector<D>, u32)> = Vec::new();
    let lattice = |c: [usize; 3]| {
        let mut x = Vector::<D>::zeros();
        for k in 0..D {
            x[k] = base + c[k] as f32 * dx;
        }
        x
    };
    for a in 0..fluid_n[0] {
        for b in 0..fluid_n[1] {
            for c in 0..fluid_n[2] {
                let mut x = lattice([a, b, c]);
                for k in 0..D {
                    x[k] += rng.sym(0.25 * dx);
                }
                particles.push((x, FLUID));
            }
        }
    }
    let depth = if D == 2 { 1 } else { wall_n };
    for l in 0..3 {
        for a in 0..wall_n {
            for c in 0..depth {
                // Floor (solid 1): axis 1 below the fluid; side wall (solid 2): axis 0.
                let mut floor = lattice([a, 0, c]);
                floor[0] -= 3.0 * dx;
                floor[1] = base - (l + 1) as f32 * dx;
                particles.push((floor, 1));
                let mut side = lattice([0, a, c]);
                side[0] = base - (l + 1) as f32 * dx;
                particles.push((side, 2));
            }
        }
    }
    // Outside the domain: across the upper x face, and two clusters far away.
    let mut centre = Vector::<D>::repeat(0.3);
    centre[0] = 1.0;
    for _ in 0..40 {
        let x = centre + Vector::from_fn(|_, _| rng.sym(2.0 * h));
        particles.push((x, FLUID));
    }
    for (offset, kind) in [(-3.0, FLUID), (2.5, 1)] {
        let c = Vector::<D>::repeat(offset);
        for _ in 0..12 {
            particles.push((c + Vector::from_fn(|_, _| rng.sym(0.6 * h)), kind));
        }
    }
    // Random order (Fisher-Yates).
    for i in (1..particles.len()).rev() {
        particles.swap(i, rng.below(i + 1));
    }
    let mut fields = Fields::<D>::default();
    for (x, kind) in particles {
        let u = Vector::from_fn(|_, _| rng.sym(1.0));
        fields.push(x, u, mass, rho0 + rng.sym(30.0), kind);
    }
    // Ids as after earlier sorts: not the storage order, so the CPU (storage order within a
    // cell) and the shim (id order) sum in different orders.
    for i in (1..fields.len()).rev() {
        fields.id.swap(i, rng.below(i + 1));
    }
    // Every field distinct per particle, so the gathers are checked field by field.
    for i in 0..fields.len() {
        fields.acceleration[i] = Vector::from_fn(|_, _| rng.sym(10.0));
        fields.pressure[i] = sph::physics::eos::pressure(fields.density[i], rho0, p.c2);
    }
    let geometry = GridGeometry::new(&p.domain_min, &p.domain_max, h).expect("a small valid domain");
    Setup {
        fields,
        params: p,
        geometry,
    }
}

/// Cell coordinates of `x` in the dense grid, as `cell_of` in `kernels/sph.cuh` computes them.
fn cell_of<const D: usize>(g: &GridGeometry<D>, x: &Vector<D>) -> u32 {
    let mut key = 0u32;
    for k in (0..D).rev() {
        let f = ((x[k] - g.origin[k]) * g.inv_cell).floor();
        let hi = g.dims[k] as i64 - 2;
        let c = if f.is_nan() || f < 1.0 {
            1
        } else {
            (f as i64).min(hi)
        };
        key = key * g.dims[k] + c as u32;
    }
    key
}

/// Bit patterns of a particle's fields, to compare particles exactly.
fn particle_bits<const D: usize>(f: &Fields<D>, i: usize) -> Vec<u32> {
    let mut v = vec![f.id[i], f.kind[i]];
    for x in [&f.position[i], &f.velocity[i], &f.acceleration[i]] {
        v.extend(x.iter().map(|c| c.to_bits()));
    }
    v.extend([f.density[i], f.pressure[i], f.mass[i]].map(f32::to_bits));
    v
}

fn check_sort<const D: usize>(k: &Kernels<D>, seed: u64) {
    let s = setup::<D>(seed);
    let mut f = s.fields.clone();
    let grid = k.sort_on_shim(&mut f, s.geometry);
    let n = f.len();
    assert!(
        f.id.windows(2).any(|w| w[0] > w[1]),
        "the input order is not already sorted"
    );
    // The same particles: ids are a permutation, each carrying all its input fields.
    let mut input = vec![usize::MAX; n];
    for i in 0..n {
        input[s.fields.id[i] as usize] = i;
    }
    let mut seen = vec![false; n];
    for i in 0..n {
        let id = f.id[i] as usize;
        assert!(!seen[id], "id {id} twice");
        seen[id] = true;
        assert_eq!(
            particle_bits(&f, i),
            particle_bits(&s.fields, input[id]),
            "particle {id}'s fields"
        );
    }
    // Cell ranges: ascending, each particle in its own cell, ids ascending within a cell.
    let ncell = s.geometry.cell_count();
    assert_eq!(grid.cell_start.len(), ncell + 1);
    assert_eq!((grid.cell_start[0], grid.cell_start[ncell]), (0, n as u32));
    assert!(
        grid.cell_start.windows(2).all(|w| w[0] <= w[1]),
        "cell_start ascending"
    );
    let mut occupied = 0;
    for c in 0..ncell {
        let range = grid.cell_start[c] as usize..grid.cell_start[c + 1] as usize;
        occupied += usize::from(!range.is_empty());
        for i in range.clone() {
            assert_eq!(grid.cell_key[i] as usize, c, "cell_key of particle {i}");
            assert_eq!(
                cell_of(&s.geometry, &f.position[i]) as usize,
                c,
                "particle {i} lies in cell {c}"
            );
        }
        assert!(
            f.id[range].windows(2).all(|w| w[0] < w[1]),
            "ids ascending in cell {c}"
        );
    }
    assert!(occupied > 20, "the particles spread over many cells ({occupied})");
}

#[test]
fn sort_by_cell_on_the_shim_orders_particles_by_cell_then_id() {
    check_sort(&KERNELS_2, 0x2545f4914f6cdd1d);
    check_sort(&KERNELS_3, 0x9e3779b97f4a7c15);
}

#[test]
fn scan_on_the_shim_is_an_exclusive_prefix_sum_for_any_chunk() {
    let mut rng = Rng(0xd1b54a32d192ed03);
    for m in [1usize, 2, 31, 32, 33, 257, 1000] {
        let counts: Vec<u32> = (0..m).map(|_| rng.below(5) as u32).collect();
        let expected: Vec<u32> = counts
            .iter()
            .scan(0u32, |s, &c| {
                let e = *s;
                *s += c;
                Some(e)
            })
            .collect();
        for chunk in [1u32, 3, 32, 256, m as u32, 2 * m as u32] {
            assert_eq!(
                KERNELS_2.exclusive_scan(&counts, chunk),
                expected,
                "m = {m}, chunk = {chunk}"
            );
        }
    }
}

/// `|a − b| ≤ max(rel · max(|a|, |b|), abs)`, as `tests/common/tol.rs` of STYLE.md.
fn close(a: f32, b: f32, rel: f32, abs: f32) -> bool {
    (a - b).abs() <= (rel * a.abs().max(b.abs())).max(abs)
}

/// `value` of every particle of `f`, indexed by id.
fn by_id<const D: usize, T: Copy>(f: &Fields<D>, value: &[T]) -> Vec<T> {
    let mut index = vec![usize::MAX; f.len()];
    for i in 0..f.len() {
        index[f.id[i] as usize] = i;
    }
    index.iter().map(|&i| value[i]).collect()
}

/// Largest relative difference `|a − b| / max(|a|, |b|)` over particles where `pick(id)`.
fn max_rel_diff(a: &[f32], b: &[f32], pick: impl Fn(usize) -> bool) -> f32 {
    (0..a.len())
        .filter(|&i| pick(i))
        .map(|i| {
            let m = a[i].abs().max(b[i].abs());
            if m == 0.0 { 0.0 } else { (a[i] - b[i]).abs() / m }
        })
        .fold(0.0, f32::max)
}

/// Eq. (18) in f32 on both sides with the same terms `m_j W_ij` (same operations, so the same
/// bits), summed in another order (CPU: sparse-grid rows in input order; shim: cells by id). For
/// n ≤ ~60 positive terms each sum is within (n − 1) · 2⁻²⁴ ≈ 3.6e-6 of the exact one, so the
/// two agree to 1e-5 relative.
const DENSITY_REL: f32 = 1.0e-5;

fn check_density<const D: usize>(k: &Kernels<D>, seed: u64) {
    // Both kernels of (18): poly6 (wcsph) and the corrected solver's scaled spiky kernel.
    for weight in [DensityWeight::POLY6, DensityWeight::spiky(0.82)] {
        check_density_with(k, seed, weight);
    }
}

fn check_density_with<const D: usize>(k: &Kernels<D>, seed: u64, weight: DensityWeight) {
    let mut s = setup::<D>(seed);
    s.params.density_kernel = weight.kernel;
    s.params.density_spiky_scale = weight.spiky_scale;
    let mut cpu_fields = s.fields.clone();
    let mut cpu = CpuBackend::<D>::new();
    cpu.sort_by_cell(&mut cpu_fields, s.params.h)
        .expect("finite positions");
    cpu.density(&mut cpu_fields, &s.params);
    let mut f = s.fields.clone();
    let grid = k.sort_on_shim(&mut f, s.geometry);
    k.density(&mut f, &s.params, &grid);
    let (a, b) = (by_id(&cpu_fields, &cpu_fields.density), by_id(&f, &f.density));
    let (kind, input) = (
        by_id(&s.fields, &s.fields.kind),
        by_id(&s.fields, &s.fields.density),
    );
    let fluid = |id: usize| kind[id] == FLUID;
    for id in 0..a.len() {
        if fluid(id) {
            assert!(
                close(a[id], b[id], DENSITY_REL, 0.0),
                "density of {id} ({weight:?}): cpu {} shim {}",
                a[id],
                b[id]
            );
        } else {
            assert_eq!(b[id], input[id], "solid {id}'s density is untouched");
        }
    }
    // Not a trivial state: interior particles have ~ rest density, some fluid is isolated.
    let max = a.iter().copied().fold(0.0, f32::max);
    assert!(max > 0.8 * s.params.rho0, "max density {max}");
    eprintln!(
        "density D={D}, {weight:?}: max relative difference {:.2e}",
        max_rel_diff(&a, &b, fluid)
    );
}

#[test]
fn density_on_the_shim_matches_the_cpu_stage() {
    check_density(&KERNELS_2, 0x2545f4914f6cdd1d);
    check_density(&KERNELS_3, 0x9e3779b97f4a7c15);
}

/// [A12] eq. (27) in f32, terms identical on both sides, summed in another order (see
/// `DENSITY_REL`), so each sum is within 2 (n − 1) 2⁻²⁴ ≤ 1e-5 of the sum of its terms' absolute
/// values. That bounds the extrapolated pressure's difference by 1e-5 (p_max + ρ_max |g| h) (the
/// weighted means of |p_f| and ρ_f |x_w − x_f| over the same weights), and eq. (19) of the
/// summed density by 1e-5 C² ρ_max; the density ρ0 + p / C² adds one rounding of ρ0.
/// Accelerations [m/s²] of the setup's two solids (floor, side wall) for the moving-wall case of
/// `wall_pressure` ([A12] eq. 27 with `g − a_w`); several g, so that the term moves the pressure
/// of pressed walls well beyond the tolerance (which the `C² ρ` term of the summed model sets).
fn wall_accelerations<const D: usize>() -> Vec<Vector<D>> {
    let mut floor = Vector::<D>::zeros();
    let mut side = Vector::<D>::zeros();
    floor[0] = 30.0;
    floor[1] = -60.0;
    side[0] = -80.0;
    side[1] = 25.0;
    vec![floor, side]
}

fn wall_tolerance<const D: usize>(s: &Setup<D>) -> (f32, f32) {
    let p_max = s.fields.pressure.iter().copied().fold(0.0, f32::max);
    let rho_max = 1.1 * s.params.rho0; // summed densities near the walls stay below
    // The largest body acceleration |g − a_w| of either case.
    let g = wall_accelerations::<D>()
        .iter()
        .map(|a| (s.params.gravity - a).norm())
        .fold(s.params.gravity.norm(), f32::max);
    let p = 1.0e-5 * (p_max + rho_max * g * s.params.h + s.params.c2 * rho_max);
    (p, p / s.params.c2 + s.params.rho0 * f32::EPSILON)
}

fn check_wall_pressure<const D: usize>(k: &Kernels<D>, seed: u64) {
    let s = setup::<D>(seed);
    let (p_abs, rho_abs) = wall_tolerance(&s);
    let kind = by_id(&s.fields, &s.fields.kind);
    let (input_p, input_rho) = (
        by_id(&s.fields, &s.fields.pressure),
        by_id(&s.fields, &s.fields.density),
    );
    let solid = |id: usize| kind[id] != FLUID;
    let mut results = Vec::new();
    let mut moving_results = Vec::new();
    let cases = [
        (WallModel::ExtrapolatedOrSummed, false),
        (WallModel::Extrapolated, false),
        (WallModel::ExtrapolatedOrSummed, true),
        (WallModel::Extrapolated, true),
    ];
    for (model, moving) in cases {
        // At rest the CPU gets no accelerations and the device its buffer of zeros.
        let (cpu_acc, shim_acc) = if moving {
            (wall_accelerations::<D>(), wall_accelerations::<D>())
        } else {
            (Vec::new(), vec![Vector::<D>::zeros(); 2])
        };
        let mut cpu_fields = s.fields.clone();
        let mut cpu = CpuBackend::<D>::new();
        cpu.sort_by_cell(&mut cpu_fields, s.params.h)
            .expect("finite positions");
        cpu.wall_pressure(&mut cpu_fields, &s.params, model, &cpu_acc);
        let mut f = s.fields.clone();
        let grid = k.sort_on_shim(&mut f, s.geometry);
        k.wall_pressure(&mut f, &s.params, &grid, model, &shim_acc);
        let cpu_p = by_id(&cpu_fields, &cpu_fields.pressure);
        let (p, rho) = (by_id(&f, &f.pressure), by_id(&f, &f.density));
        let cpu_rho = by_id(&cpu_fields, &cpu_fields.density);
        let mut max_abs: [f32; 2] = [0.0; 2];
        for id in 0..p.len() {
            if solid(id) {
                assert!(
                    close(p[id], cpu_p[id], 1.0e-5, p_abs),
                    "{model:?} p of {id}: cpu {} shim {}",
                    cpu_p[id],
                    p[id]
                );
                assert!(
                    close(rho[id], cpu_rho[id], 1.0e-5, rho_abs),
                    "{model:?} density of {id}: cpu {} shim {}",
                    cpu_rho[id],
                    rho[id]
                );
                max_abs[0] = max_abs[0].max((p[id] - cpu_p[id]).abs());
                max_abs[1] = max_abs[1].max((rho[id] - cpu_rho[id]).abs());
            } else {
                assert_eq!(p[id], input_p[id], "fluid {id}'s pressure is untouched");
                assert_eq!(rho[id], input_rho[id], "fluid {id}'s density is untouched");
            }
        }
        eprintln!(
            "wall_pressure D={D} {model:?} moving={moving}: max |dp| {:.2e} Pa (tolerance {p_abs:.2e}), \
             max |drho| {:.2e} kg/m3, max relative dp {:.2e}",
            max_abs[0],
            max_abs[1],
            max_rel_diff(&p, &cpu_p, solid)
        );
        if moving {
            moving_results.push(p);
        } else {
            results.push(p);
        }
    }
    // The wall acceleration is in the kernel: walls next to the fluid change by far more than
    // the tolerance.
    let changed = (0..results[1].len())
        .filter(|&id| solid(id) && (moving_results[1][id] - results[1][id]).abs() > 10.0 * p_abs)
        .count();
    assert!(
        changed > 10,
        "accelerating walls changed only {changed} wall pressures"
    );
    // In a rotating frame the body acceleration adds the centrifugal one at each wall particle
    // (`physics::rotating_frame`): Ω = (2, 3, 6) rad/s about an axis through the domain's
    // centre, up to |Ω|² |x − x_c| ≈ 42 m/s² (2D: 2D embedding) over the unit domain.
    for model in [WallModel::ExtrapolatedOrSummed, WallModel::Extrapolated] {
        let mut params = s.params;
        params.angular_velocity = [2.0, 3.0, 6.0];
        params.rotating_frame = 1;
        params.rotation_centre = Vector::repeat(0.5);
        let reach = 49.0 * (D as f32).sqrt() * 0.5; // |Ω|² times the farthest corner
        let p_abs = p_abs + 1.0e-5 * 1.1 * params.rho0 * reach * params.h;
        let rho_abs = rho_abs + p_abs / params.c2;
        let mut cpu_fields = s.fields.clone();
        let mut cpu = CpuBackend::<D>::new();
        cpu.sort_by_cell(&mut cpu_fields, params.h)
            .expect("finite positions");
        cpu.wall_pressure(&mut cpu_fields, &params, model, &[]);
        let mut f = s.fields.clone();
        let grid = k.sort_on_shim(&mut f, s.geometry);
        k.wall_pressure(&mut f, &params, &grid, model, &[Vector::<D>::zeros(); 2]);
        let (cpu_p, cpu_rho) = (
            by_id(&cpu_fields, &cpu_fields.pressure),
            by_id(&cpu_fields, &cpu_fields.density),
        );
        let (p, rho) = (by_id(&f, &f.pressure), by_id(&f, &f.density));
        for id in (0..p.len()).filter(|&id| solid(id)) {
            assert!(
                close(p[id], cpu_p[id], 1.0e-5, p_abs),
                "rotating {model:?} p of {id}: cpu {} shim {}",
                cpu_p[id],
                p[id]
            );
            assert!(
                close(rho[id], cpu_rho[id], 1.0e-5, rho_abs),
                "rotating {model:?} density of {id}: cpu {} shim {}",
                cpu_rho[id],
                rho[id]
            );
        }
        if model == WallModel::Extrapolated {
            let changed = (0..p.len())
                .filter(|&id| solid(id) && (p[id] - results[1][id]).abs() > 10.0 * p_abs)
                .count();
            assert!(
                changed > 10,
                "the rotating frame changed only {changed} wall pressures"
            );
        }
    }
    // Not a trivial state: walls under the fluid are pressed, isolated solids are not, and the
    // summed density raises some walls above the extrapolation.
    let (summed, extrapolated) = (&results[0], &results[1]);
    let solids: Vec<usize> = (0..summed.len()).filter(|&id| solid(id)).collect();
    assert!(
        solids.iter().any(|&id| extrapolated[id] > 1000.0),
        "pressed walls"
    );
    assert!(
        solids.iter().any(|&id| extrapolated[id] == 0.0),
        "walls without fluid"
    );
    assert!(
        solids.iter().any(|&id| summed[id] > extrapolated[id] + 100.0),
        "the summed model matters"
    );
    assert!(
        solids
            .iter()
            .any(|&id| summed[id] == extrapolated[id] && summed[id] > 0.0),
        "extrapolation wins"
    );
}

#[test]
fn wall_pressure_on_the_shim_matches_the_cpu_stage_for_both_models() {
    check_wall_pressure(&KERNELS_2, 0x2545f4914f6cdd1d);
    check_wall_pressure(&KERNELS_3, 0x9e3779b97f4a7c15);
}

/// [A12] eqs. (22)-(23): `2 u_w − Σ u_f W / Σ W` in f32 with the same terms on both sides, the
/// sums in another order (see `DENSITY_REL`): each sum within 2 (n − 1) 2⁻²⁴ ≤ 1e-5 of the sum of
/// its terms' magnitudes, so the Shepard average differs by at most 2e-5 max |u_f| (weights and
/// velocities both rounded), here 2e-5 m/s (|u| < 1 m/s per component); `2 u_w` is exact.
const WALL_VELOCITY_ABS: f32 = 2.0e-5;

fn check_wall_velocity<const D: usize>(k: &Kernels<D>, seed: u64) {
    let mut s = setup::<D>(seed);
    // A value per particle that the stage must leave alone on fluid entries.
    let mut rng = Rng(seed ^ 0x5555);
    s.fields.wall_velocity = (0..s.fields.len())
        .map(|_| Vector::from_fn(|_, _| rng.sym(5.0)))
        .collect();
    let mut cpu_fields = s.fields.clone();
    let mut cpu = CpuBackend::<D>::new();
    cpu.sort_by_cell(&mut cpu_fields, s.params.h)
        .expect("finite positions");
    cpu.wall_velocity(&mut cpu_fields, &s.params);
    let mut f = s.fields.clone();
    let grid = k.sort_on_shim(&mut f, s.geometry);
    k.wall_velocity(&mut f, &s.params, &grid);
    let (cpu_v, v) = (
        by_id(&cpu_fields, &cpu_fields.wall_velocity),
        by_id(&f, &f.wall_velocity),
    );
    let kind = by_id(&s.fields, &s.fields.kind);
    let (input, own) = (
        by_id(&s.fields, &s.fields.wall_velocity),
        by_id(&s.fields, &s.fields.velocity),
    );
    let (mut worst, mut mirrored, mut dry) = (0.0f32, 0, 0);
    for id in 0..v.len() {
        if kind[id] == FLUID {
            assert_eq!(v[id], input[id], "fluid {id}'s entry is untouched");
            assert_eq!(cpu_v[id], input[id], "fluid {id}'s entry is untouched (cpu)");
            continue;
        }
        for c in 0..D {
            assert!(
                close(v[id][c], cpu_v[id][c], 0.0, WALL_VELOCITY_ABS),
                "wall velocity of {id} axis {c}: cpu {} shim {}",
                cpu_v[id][c],
                v[id][c]
            );
            worst = worst.max((v[id][c] - cpu_v[id][c]).abs());
        }
        if v[id] == own[id] {
            dry += 1;
        } else if (v[id] - own[id]).norm() > 0.1 {
            mirrored += 1;
        }
    }
    eprintln!("wall_velocity D={D}: max |du| {worst:.2e} m/s, {mirrored} mirrored, {dry} without fluid");
    // Not a trivial state: walls by the fluid take the mirrored velocity, the far cluster keeps
    // its own.
    assert!(mirrored > 10, "walls next to the fluid: {mirrored}");
    assert!(dry >= 12, "solids away from the fluid keep their velocity: {dry}");
}

#[test]
fn wall_velocity_on_the_shim_matches_the_cpu_stage() {
    check_wall_velocity(&KERNELS_2, 0x2545f4914f6cdd1d);
    check_wall_velocity(&KERNELS_3, 0x9e3779b97f4a7c15);
}

fn check_neighbours<const D: usize>(k: &Kernels<D>, seed: u64) {
    let mut s = setup::<D>(seed);
    // Beyond what the CPU grid accepts: huge, infinite and NaN coordinates, two coincident
    // particles far away, a pair straddling the lower corner of the padded grid.
    let h = s.params.h;
    let mut extra: Vec<Vector<D>> = vec![
        Vector::repeat(1.0e20),
        Vector::repeat(1.0e20),
        Vector::repeat(-1.0e20),
        Vector::repeat(f32::INFINITY),
        Vector::repeat(f32::NAN),
        Vector::repeat(-h - 0.1 * h),
        Vector::repeat(-h + 0.3 * h),
    ];
    let mut odd = Vector::<D>::repeat(0.5);
    odd[1] = 3.0e9;
    extra.push(odd);
    odd[0] += 0.5 * h;
    extra.push(odd);
    for x in extra {
        s.fields.push(x, Vector::zeros(), 1.0, 1000.0, FLUID);
    }
    let mut f = s.fields.clone();
    let grid = k.sort_on_shim(&mut f, s.geometry);
    let found = k.neighbour_lists(&f.position, h, &grid);
    let mut pairs = 0;
    for (i, found) in found.iter().enumerate() {
        let naive = neighbours_naive(&f.position, i, h);
        assert_eq!(found, &naive, "neighbours of particle {i} at {:?}", f.position[i]);
        pairs += naive.len();
    }
    let n = f.len();
    assert!(
        pairs > 10 * n,
        "real neighbourhoods ({pairs} pairs for {n} particles)"
    );
}

#[test]
fn candidate_neighbours_on_the_shim_equal_the_brute_force_set() {
    check_neighbours(&KERNELS_2, 0x2545f4914f6cdd1d);
    check_neighbours(&KERNELS_3, 0x9e3779b97f4a7c15);
}

/// `StepParams<D>` (`#[repr(C)]`) and its mirror in `kernels/sph.cuh` have the same size and
/// field offsets, as the host compiler lays the C++ struct out (the kernels read the Rust
/// struct's bytes).
fn rust_step_params_layout<const D: usize>() -> Vec<u64> {
    use std::mem::offset_of;
    let offsets = [
        std::mem::size_of::<StepParams<D>>(),
        offset_of!(StepParams<D>, h),
        offset_of!(StepParams<D>, rho0),
        offset_of!(StepParams<D>, c2),
        offset_of!(StepParams<D>, mu),
        offset_of!(StepParams<D>, alpha),
        offset_of!(StepParams<D>, c),
        offset_of!(StepParams<D>, pressure_gradient_scale),
        offset_of!(StepParams<D>, gravity),
        offset_of!(StepParams<D>, domain_min),
        offset_of!(StepParams<D>, domain_max),
        offset_of!(StepParams<D>, angular_velocity),
        offset_of!(StepParams<D>, rotation_centre),
        offset_of!(StepParams<D>, viscosity_scale),
        offset_of!(StepParams<D>, surface_tension_gamma),
        offset_of!(StepParams<D>, surface_tension_sigma),
        offset_of!(StepParams<D>, spacing),
        offset_of!(StepParams<D>, density_spiky_scale),
        offset_of!(StepParams<D>, density_kernel),
        offset_of!(StepParams<D>, surface_tension_model),
        offset_of!(StepParams<D>, rotating_frame),
        offset_of!(StepParams<D>, phases),
    ];
    offsets.iter().map(|&o| o as u64).collect()
}

#[test]
fn step_params_has_the_same_layout_in_rust_and_in_the_kernels() {
    let mut cpp = vec![0u64; shim::STEP_PARAMS_FIELDS + 1];
    // SAFETY: the launcher writes STEP_PARAMS_FIELDS + 1 values.
    unsafe { shim::sph_shim_step_params_layout_2(cpp.as_mut_ptr()) };
    assert_eq!(cpp, rust_step_params_layout::<2>(), "2D: size, then offsets");
    // SAFETY: as above.
    unsafe { shim::sph_shim_step_params_layout_3(cpp.as_mut_ptr()) };
    assert_eq!(cpp, rust_step_params_layout::<3>(), "3D: size, then offsets");
}
