//! The parts of the CUDA kernels below a stage, on the CPU through the host shim
//! (`backend::cuda::shim`): the device scan of the sort, the candidate loop every neighbour
//! kernel runs (`SPH_FOR_EACH_CANDIDATE` of `kernels/sph.cuh`), and the layouts of the structs
//! Rust and the kernels share. Each stage as a whole is checked on every backend by
//! `tests/stages/`. These run everywhere, GPU or not.
#![cfg(feature = "cuda")]

use sph::backend::cuda::extremes::DeviceExtremes;
use sph::backend::cuda::grid::GridGeometry;
use sph::backend::cuda::launch::Launch;
use sph::backend::cuda::shim::{self, Shim};
use sph::grid::{neighbours_naive, neighbours_naive_periodic};
use sph::math::Vector;
use sph::model::params::StepParams;
use sph::periodic::{Periodic, PeriodicAxes};

/// A small deterministic generator (xorshift), so failures reproduce.
struct Rng(u64);

impl Rng {
    /// Uniform in `[0, 1)`.
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform index in `0..n`.
    fn below(&mut self, n: usize) -> usize {
        ((f64::from(self.next()) * n as f64) as usize).min(n - 1)
    }
}

/// The exclusive scan of `counts` by the three scan kernels, launched as the sort launches them.
fn device_scan(counts: &[u32], chunk: u32) -> Vec<u32> {
    let m = counts.len() as u32;
    let chunks = m.div_ceil(chunk);
    let mut out = vec![u32::MAX; counts.len()];
    let mut chunk_sums = vec![u32::MAX; chunks as usize];
    let shim = Shim;
    // SAFETY: `counts` and `out` hold m entries, `chunk_sums` ceil(m / chunk).
    unsafe {
        Launch::<2>::scan_chunks(&shim, m, chunk, &counts.to_vec(), &mut out, &mut chunk_sums)
            .expect("shim launch");
        Launch::<2>::scan_chunk_sums(&shim, chunks, &mut chunk_sums).expect("shim launch");
        Launch::<2>::scan_add(&shim, m, chunk, &mut out, &chunk_sums).expect("shim launch");
    }
    out
}

#[test]
fn scan_on_the_shim_is_an_exclusive_prefix_sum_for_any_chunk() {
    let mut rng = Rng(0xd1b5_4a32_d192_ed03);
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
            assert_eq!(device_scan(&counts, chunk), expected, "m = {m}, chunk = {chunk}");
        }
    }
}

/// A jittered fluid block of spacing `h / 2` in the unit box, then positions beyond what the
/// CPU grid accepts: huge, infinite and NaN coordinates, two coincident particles far away, a
/// pair straddling the lower corner of the padded grid, a pair far out on one axis.
fn positions<const D: usize>(h: f32, seed: u64) -> Vec<Vector<D>> {
    let mut rng = Rng(seed);
    let dx = 0.5 * h;
    let per_axis: usize = if D == 2 { 30 } else { 12 };
    let mut out: Vec<Vector<D>> = (0..per_axis.pow(D as u32))
        .map(|c: usize| {
            Vector::from_fn(|k, _| {
                let i = (c / per_axis.pow(k as u32)) % per_axis;
                (i as f32 + 0.5 + 0.5 * (rng.next() - 0.5)) * dx
            })
        })
        .collect();
    out.extend([
        Vector::repeat(1.0e20),
        Vector::repeat(1.0e20),
        Vector::repeat(-1.0e20),
        Vector::repeat(f32::INFINITY),
        Vector::repeat(f32::NAN),
        Vector::repeat(-h - 0.1 * h),
        Vector::repeat(-h + 0.3 * h),
    ]);
    let mut odd = Vector::<D>::repeat(0.5);
    odd[1] = 3.0e9;
    out.push(odd);
    odd[0] += 0.5 * h;
    out.push(odd);
    out
}

/// Each particle's neighbours (`r < h`, itself included) as the kernels' candidate loop finds
/// them on the dense grid, ascending, with `position` in the grid's order.
fn candidate_neighbours<const D: usize>(
    g: &GridGeometry<D>,
    position: &[Vector<D>],
    h: f32,
) -> Vec<Vec<usize>> {
    const MAX: usize = 512;
    let n = position.len();
    let flat = |v: &[Vector<D>]| -> Vec<f32> { v.iter().flat_map(|x| x.iter().copied()).collect() };
    // The kernel's own cell keys (`cell_hash`); cell_start by counting.
    let mut key = vec![0u32; n];
    let mut cell_count = vec![0u32; g.cell_count() + 1];
    // SAFETY: `pos` holds n vectors, `key` n entries, `cell_count` one per cell and more.
    unsafe { Launch::<D>::cell_hash(&Shim, n as u32, g, &flat(position), &mut key, &mut cell_count) }
        .expect("shim launch");
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| key[i]);
    let sorted: Vec<Vector<D>> = order.iter().map(|&i| position[i]).collect();
    let cell_key: Vec<u32> = order.iter().map(|&i| key[i]).collect();
    let mut cell_start = vec![0u32; g.cell_count() + 1];
    for &k in &cell_key {
        cell_start[k as usize + 1] += 1;
    }
    for c in 0..g.cell_count() {
        cell_start[c + 1] += cell_start[c];
    }
    let mut count = vec![0u32; n];
    let mut list = vec![u32::MAX; n * MAX];
    let pos = flat(&sorted);
    // SAFETY: positions, keys and count hold n items, list n * MAX, cell_start ncell + 1; the
    // grid is this dimension's.
    unsafe {
        match D {
            2 => shim::sph_shim_neighbour_list_2(
                n as u32,
                h,
                std::ptr::from_ref(g).cast(),
                cell_start.as_ptr(),
                cell_key.as_ptr(),
                pos.as_ptr(),
                MAX as u32,
                count.as_mut_ptr(),
                list.as_mut_ptr(),
            ),
            3 => shim::sph_shim_neighbour_list_3(
                n as u32,
                h,
                std::ptr::from_ref(g).cast(),
                cell_start.as_ptr(),
                cell_key.as_ptr(),
                pos.as_ptr(),
                MAX as u32,
                count.as_mut_ptr(),
                list.as_mut_ptr(),
            ),
            d => unreachable!("dimension {d}"),
        }
    }
    // Back to the caller's numbering.
    let mut found = vec![Vec::new(); n];
    for s in 0..n {
        let c = count[s] as usize;
        assert!(
            c <= MAX,
            "particle {s} has {c} neighbours, more than the test's list holds"
        );
        let mut l: Vec<usize> = list[s * MAX..s * MAX + c]
            .iter()
            .map(|&j| order[j as usize])
            .collect();
        l.sort_unstable();
        found[order[s]] = l;
    }
    found
}

fn check_neighbours<const D: usize>(seed: u64) {
    let h = 0.04;
    let position = positions::<D>(h, seed);
    let g = GridGeometry::new(&Vector::repeat(0.0), &Vector::repeat(0.5), h).expect("a small valid domain");
    let found = candidate_neighbours(&g, &position, h);
    let mut pairs = 0;
    for (i, found) in found.iter().enumerate() {
        let naive = neighbours_naive(&position, i, h);
        assert_eq!(
            found, &naive,
            "{D}D: neighbours of particle {i} at {:?}",
            position[i]
        );
        pairs += naive.len();
    }
    let n = position.len();
    assert!(
        pairs > 10 * n,
        "real neighbourhoods ({pairs} pairs for {n} particles)"
    );
}

/// The same with periodic axes (`sph::periodic`): a jittered block of spacing `dx` filling the
/// period `[0, L)` (30 or 12 spacings per axis, `L/h` not a whole number, so the kernels'
/// stretched cells are exercised), a few particles up to `0.2 h` outside it (as between two
/// wraps): the kernels' candidates within `h` of the minimum image are the brute-force set.
fn check_periodic_neighbours<const D: usize>(seed: u64, axes: PeriodicAxes) {
    let (dx, h) = (0.02f32, 0.041f32);
    let mut rng = Rng(seed);
    let per_axis: usize = if D == 2 { 30 } else { 12 };
    let l = per_axis as f32 * dx;
    let mut position: Vec<Vector<D>> = (0..per_axis.pow(D as u32))
        .map(|c: usize| {
            Vector::from_fn(|k, _| {
                let i = (c / per_axis.pow(k as u32)) % per_axis;
                (i as f32 + 0.5 + 0.5 * (rng.next() - 0.5)) * dx
            })
        })
        .collect();
    for t in [-0.2f32, -0.05, 1.0, 1.1] {
        let mut x = Vector::<D>::repeat(0.5 * l);
        x[0] = if t < 0.0 { t * h } else { l + (t - 1.0) * h };
        position.push(x);
    }
    let (min, max) = (Vector::<D>::zeros(), Vector::<D>::repeat(l));
    let periodic = Periodic::new(axes, min, max);
    let g = GridGeometry::new_periodic(&min, &max, h, axes).expect("a period of 14 cells");
    let found = candidate_neighbours(&g, &position, h);
    let mut across = 0;
    for (i, found) in found.iter().enumerate() {
        let naive = neighbours_naive_periodic(&position, i, h, &periodic);
        assert_eq!(
            found, &naive,
            "{D}D: neighbours of particle {i} at {:?}",
            position[i]
        );
        across += naive
            .iter()
            .filter(|&&j| periodic.minimum_image(position[i] - position[j]) != position[i] - position[j])
            .count();
    }
    assert!(across > 10 * per_axis, "{D}D: {across} pairs across the seam");
}

#[test]
fn periodic_candidate_neighbours_on_the_shim_equal_the_minimum_image_set() {
    check_periodic_neighbours::<2>(0x2545_f491_4f6c_dd1e, PeriodicAxes::NONE.with(0).with(1));
    check_periodic_neighbours::<3>(0x9e37_79b9_7f4a_7c16, PeriodicAxes::NONE.with(0));
    check_periodic_neighbours::<3>(0x9e37_79b9_7f4a_7c17, PeriodicAxes::NONE.with(0).with(2));
}

#[test]
fn candidate_neighbours_on_the_shim_equal_the_brute_force_set() {
    check_neighbours::<2>(0x2545_f491_4f6c_dd1d);
    check_neighbours::<3>(0x9e37_79b9_7f4a_7c15);
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
        offset_of!(StepParams<D>, pair),
        std::mem::size_of::<sph::model::pair_terms::PairCoefficients>(),
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
        offset_of!(StepParams<D>, density_diffusion),
        offset_of!(StepParams<D>, periodic),
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

/// `GridGeometry<D>` (`#[repr(C)]`, passed to every neighbour kernel by value) and its mirror in
/// `kernels/sph.cuh`: the same size and field offsets, periodic fields included.
fn rust_grid_geometry_layout<const D: usize>() -> Vec<u64> {
    use std::mem::{offset_of, size_of};
    [
        size_of::<GridGeometry<D>>(),
        offset_of!(GridGeometry<D>, origin),
        offset_of!(GridGeometry<D>, inv_cell),
        offset_of!(GridGeometry<D>, dims),
        offset_of!(GridGeometry<D>, periodic),
        offset_of!(GridGeometry<D>, period_min),
        offset_of!(GridGeometry<D>, period),
        offset_of!(GridGeometry<D>, period_inv_cell),
    ]
    .iter()
    .map(|&o| o as u64)
    .collect()
}

#[test]
fn grid_geometry_has_the_same_layout_in_rust_and_in_the_kernels() {
    let mut cpp = vec![0u64; 8];
    // SAFETY: the launcher writes 8 values.
    unsafe { shim::sph_shim_grid_geometry_layout_2(cpp.as_mut_ptr()) };
    assert_eq!(cpp, rust_grid_geometry_layout::<2>(), "2D: size, then offsets");
    // SAFETY: as above.
    unsafe { shim::sph_shim_grid_geometry_layout_3(cpp.as_mut_ptr()) };
    assert_eq!(cpp, rust_grid_geometry_layout::<3>(), "3D: size, then offsets");
}

#[test]
fn device_extremes_mirror_the_kernel_struct_layout() {
    use std::mem::{offset_of, size_of};
    let rust = [
        size_of::<DeviceExtremes>(),
        offset_of!(DeviceExtremes, max_speed),
        offset_of!(DeviceExtremes, max_acceleration),
        offset_of!(DeviceExtremes, max_density),
        offset_of!(DeviceExtremes, min_density),
        offset_of!(DeviceExtremes, density_nan),
        offset_of!(DeviceExtremes, fluid_count),
        offset_of!(DeviceExtremes, non_finite),
        offset_of!(DeviceExtremes, escaped),
        offset_of!(DeviceExtremes, abs_error_sum),
        offset_of!(DeviceExtremes, compression_sum),
    ];
    let mut c = [0u32; 11];
    // SAFETY: the launcher writes 11 values.
    unsafe { shim::sph_shim_extremes_layout_2(c.as_mut_ptr()) };
    assert_eq!(c.map(|x| x as usize), rust, "2D");
    // SAFETY: as above.
    unsafe { shim::sph_shim_extremes_layout_3(c.as_mut_ptr()) };
    assert_eq!(c.map(|x| x as usize), rust, "3D");
}
