// Shared by every kernel in this folder: the dimension, the step parameters, the neighbour grid
// and the smoothing kernels. Mirrors `model::params`, `smoothing.rs` and the CUDA backend's
// dense cell grid (`backend::cuda::grid`). Single precision, as in the paper (section 3).
//
// Rules for kernels here (so the C++ host shim in `shim/` runs them exactly):
// - one thread per item, `unsigned i = blockIdx.x * blockDim.x + threadIdx.x; if (i >= n) return;`;
// - no shared memory, no __syncthreads, no warp intrinsics: a thread never waits for another;
// - cross-thread results only through the atomics of `shim/cuda_shim.h` (atomicAdd on unsigned,
//   float and double, atomicMax/atomicMin on int and unsigned).
// - every entry point is declared with SPH_KERNEL(name)(args), which is `extern "C" __global__`
//   on the GPU and a plain function in the shim.
#pragma once

#if !defined(SPH_DIM) || (SPH_DIM != 2 && SPH_DIM != 3)
#error "compile with -DSPH_DIM=2 or -DSPH_DIM=3"
#endif
#define D SPH_DIM

#ifndef SPH_KERNEL
#define SPH_KERNEL(name) extern "C" __global__ void name
#endif

#define SPH_FLUID 0u

typedef unsigned int u32;

/// A D-vector of floats, laid out as the Rust `Vector<D>` (`[f32; D]`).
struct vec_t {
    float c[D];
};

__device__ __forceinline__ vec_t vzero() {
    vec_t r;
    for (int k = 0; k < D; ++k) r.c[k] = 0.0f;
    return r;
}
__device__ __forceinline__ vec_t vload(const float* a, u32 i) {
    vec_t r;
    for (int k = 0; k < D; ++k) r.c[k] = a[(size_t)i * D + k];
    return r;
}
__device__ __forceinline__ void vstore(float* a, u32 i, vec_t v) {
    for (int k = 0; k < D; ++k) a[(size_t)i * D + k] = v.c[k];
}
__device__ __forceinline__ vec_t vsub(vec_t a, vec_t b) {
    for (int k = 0; k < D; ++k) a.c[k] -= b.c[k];
    return a;
}
__device__ __forceinline__ vec_t vadd(vec_t a, vec_t b) {
    for (int k = 0; k < D; ++k) a.c[k] += b.c[k];
    return a;
}
__device__ __forceinline__ vec_t vscale(vec_t a, float s) {
    for (int k = 0; k < D; ++k) a.c[k] *= s;
    return a;
}
__device__ __forceinline__ float vdot(vec_t a, vec_t b) {
    float s = 0.0f;
    for (int k = 0; k < D; ++k) s += a.c[k] * b.c[k];
    return s;
}

#include "pair_coefficients.cuh"

/// Mirror of `model::params::StepParams<D>` (`#[repr(C)]`), SI units.
struct StepParams {
    float h;                        // kernel support [m]
    float rho0;                     // rest density [kg/m^3]
    float c2;                       // C^2 of eq. (19) [m^2/s^2]
    PairCoefficients pair;          // the pair terms' coefficients (kernels/pair_terms.table)
    float c;                        // sound speed [m/s]
    float pressure_gradient_scale;  // 1/kappa of the spiky gradient in eq. (16)
    float gravity[D];               // [m/s^2]
    float domain_min[D];            // [m]
    float domain_max[D];            // [m]
    float angular_velocity[3];      // Omega of the rotating frame [rad/s] (0 without one)
    float rotation_centre[D];       // a point on the rotation axis [m]
    float viscosity_scale;          // 1/lambda of the viscosity Laplacian in eq. (17)
    float surface_tension_gamma;    // [AAT13] gamma of the surface tension (0 without it)
    float surface_tension_sigma;    // sigma' of the surface stress (0 unless that model)
    float spacing;                  // initial particle spacing dx [m]
    float density_spiky_scale;      // c of the scaled spiky density c W_spiky (unused with poly6)
    u32 density_kernel;             // kernel of eq. (18): SPH_DENSITY_POLY6 or _SCALED_SPIKY
    u32 surface_tension_model;      // SPH_SURFACE_STRESS or SPH_SURFACE_AKINCI
    u32 rotating_frame;             // 1 with the rotating_frame effect, else 0
    u32 phases;                     // SPH_PHASES_SINGLE or SPH_PHASES_MULTI ([HA06])
    float density_diffusion;        // delta of [F19] density diffusion (0 without the effect)
    float artificial_viscosity_wall_factor;  // factor on alpha between fluid and solid particles
    u32 periodic;                   // bit k: axis k is periodic, period the domain (crate::periodic)
};

/// `physics::density::DensityKernel`.
#define SPH_DENSITY_POLY6 0u
#define SPH_DENSITY_SCALED_SPIKY 1u
/// `model::SurfaceTensionModel`.
#define SPH_SURFACE_STRESS 0u
#define SPH_SURFACE_AKINCI 1u
/// `physics::multiphase::Phases`: the host picks each stage's entry (`name` or
/// `name_multiphase`) by it; the surface-tension kernels read it.
#define SPH_PHASES_SINGLE 0u
#define SPH_PHASES_MULTI 1u

/// Mirror of `backend::cuda::grid::GridGeometry<D>` (`#[repr(C)]`): a dense grid of cells of
/// size h over the domain, padded by one cell on each side.
struct GridGeometry {
    float origin[D];           // lower corner of cell (0, 0[, 0]) [m]
    float inv_cell;            // 1 / cell size [1/m]
    u32 dims[D];               // cells per axis, x fastest in the key
    u32 periodic;              // bit k: axis k wraps (`crate::periodic`); 0: no periodic axis
    float period_min[D];       // lower face of the period along a periodic axis [m]
    float period[D];           // period L along a periodic axis [m]
    float period_inv_cell[D];  // n / L: inverse cell size along a periodic axis [1/m]
};

/// Twin of `Periodic::minimum_image`: the offset d = x_i - x_j [m] moved by one period along each
/// periodic axis where |d_k| > L_k / 2 (the same f32 operations). Every pair loop takes its
/// offset through this (SPH_PAIR_OFFSET), so no kernel uses a raw difference across the seam.
__device__ __forceinline__ vec_t periodic_minimum_image(const GridGeometry& g, vec_t d) {
    if (g.periodic == 0u) return d;
    for (int k = 0; k < D; ++k) {
        if (g.periodic & (1u << k)) {
            const float l = g.period[k];
            if (d.c[k] > 0.5f * l)
                d.c[k] -= l;
            else if (d.c[k] < -0.5f * l)
                d.c[k] += l;
        }
    }
    return d;
}

/// The pair offset x_i - x_j [m] of particle j at `pos` from x_i: the minimum image.
__device__ __forceinline__ vec_t pair_delta(const GridGeometry& g, vec_t xi, const float* pos, u32 j) {
    return periodic_minimum_image(g, vsub(xi, vload(pos, j)));
}

/// Cell coordinates of a position, clamped to [1, dims - 2] so that the neighbour cells exist.
/// Clamping is monotone and moves a coordinate by at most the distance to the grid, so every pair
/// closer than one cell still lands in the same or adjacent cells.
__device__ __forceinline__ void cell_of(const GridGeometry& g, vec_t x, int cell[D]) {
    for (int k = 0; k < D; ++k) {
        float f = floorf((x.c[k] - g.origin[k]) * g.inv_cell);
        int hi = (int)g.dims[k] - 2;
        // Compare as float first: a huge or NaN coordinate must not overflow the int conversion.
        int ck = !(f >= 1.0f) ? 1 : (f > (float)hi ? hi : (int)f);
        if (g.periodic & (1u << k)) {
            // The period's n = dims - 2 cells, at 1..n: the coordinate modulo n (positions a
            // little outside the period between two wraps land in the cell they are images of).
            const int n = (int)g.dims[k] - 2;
            float q = floorf((x.c[k] - g.period_min[k]) * g.period_inv_cell[k]);
            q = !(q >= (float)-n) ? (float)-n : (q > (float)(2 * n - 1) ? (float)(2 * n - 1) : q);
            ck = ((int)q % n + n) % n + 1;
        }
        cell[k] = ck;
    }
}

__device__ __forceinline__ u32 cell_key(const GridGeometry& g, const int cell[D]) {
    u32 key = (u32)cell[D - 1];
    for (int k = D - 2; k >= 0; --k) key = key * g.dims[k] + (u32)cell[k];
    return key;
}

/// Visits the 3^(D-1) rows of cells around `key` (the key of particle i's cell at the last sort):
/// each row `(x-1, x, x+1)` is one contiguous particle range `[cell_start[row-1], cell_start[row+2])`.
/// BODY sees `j` (u32). Mirrors `Grid::for_each_neighbour`'s ranges (the caller tests r < h).
#define SPH_FOR_EACH_CANDIDATE(g, cell_start, key, j, BODY)                                  \
    do {                                                                                      \
        if ((g).periodic != 0u) {                                                             \
            SPH_FOR_EACH_CANDIDATE_PERIODIC(g, cell_start, key, j, BODY);                     \
            break;                                                                            \
        }                                                                                     \
        const u32 _stride1 = (g).dims[0];                                                     \
        const u32 _rows = (D == 3) ? 9u : 3u;                                                 \
        for (u32 _r = 0; _r < _rows; ++_r) {                                                  \
            long long _row = (long long)(key) + ((long long)(_r % 3u) - 1) * _stride1;        \
            if (D == 3) _row += ((long long)(_r / 3u) - 1) * _stride1 * (long long)(g).dims[1 % D]; \
            const u32 _a = (cell_start)[_row - 1];                                            \
            const u32 _b = (cell_start)[_row + 2];                                            \
            for (u32 j = _a; j < _b; ++j) {                                                   \
                BODY                                                                          \
            }                                                                                 \
        }                                                                                     \
    } while (0)

/// The candidates of a grid with periodic axes (`crate::periodic`): the 3^D cells around `key`
/// one by one, axis 0 fastest, each coordinate wrapped into the period's cells 1..n along a
/// periodic axis (a row of three cells is not contiguous across the seam). Mirrors
/// `Grid::link_periodic`.
#define SPH_FOR_EACH_CANDIDATE_PERIODIC(g, cell_start, key, j, BODY)                          \
    do {                                                                                      \
        int _c[D];                                                                            \
        u32 _rest = (key);                                                                    \
        for (int _k = 0; _k < D; ++_k) {                                                      \
            _c[_k] = (int)(_rest % (g).dims[_k]);                                             \
            _rest /= (g).dims[_k];                                                            \
        }                                                                                     \
        const u32 _cells = (D == 3) ? 27u : 9u;                                               \
        for (u32 _t = 0; _t < _cells; ++_t) {                                                 \
            u32 _o = _t;                                                                      \
            u32 _cell = 0u, _stride = 1u;                                                     \
            for (int _k = 0; _k < D; ++_k) {                                                  \
                int _ck = _c[_k] + (int)(_o % 3u) - 1;                                        \
                _o /= 3u;                                                                     \
                if ((g).periodic & (1u << _k)) {                                              \
                    const int _n = (int)(g).dims[_k] - 2;                                     \
                    _ck = _ck < 1 ? _ck + _n : (_ck > _n ? _ck - _n : _ck);                   \
                }                                                                             \
                _cell += (u32)_ck * _stride;                                                  \
                _stride *= (g).dims[_k];                                                      \
            }                                                                                 \
            const u32 _a = (cell_start)[_cell];                                               \
            const u32 _b = (cell_start)[_cell + 1u];                                          \
            for (u32 j = _a; j < _b; ++j) {                                                   \
                BODY                                                                          \
            }                                                                                 \
        }                                                                                     \
    } while (0)

/// Twin of `Periodic::wrap` for the domain of `p` (stage `wrap_positions`): a coordinate
/// outside [min_k, max_k) along a periodic axis moves by one period L_k = max_k - min_k; a
/// result on the excluded face max_k goes to min_k.
__device__ __forceinline__ vec_t periodic_wrap(const StepParams& p, vec_t x) {
    for (int k = 0; k < D; ++k) {
        if (p.periodic & (1u << k)) {
            const float lo = p.domain_min[k], hi = p.domain_max[k], l = hi - lo;
            if (x.c[k] >= hi) {
                x.c[k] -= l;
                if (x.c[k] < lo) x.c[k] = lo;
            } else if (x.c[k] < lo) {
                x.c[k] += l;
                if (x.c[k] >= hi) x.c[k] = lo;
            }
        }
    }
    return x;
}

/// Mirror of `smoothing::Smoothing<D>` (Müller et al. 2003 kernels), support h.
struct Smoothing {
    float h, h2, poly6, spiky, visc, visc_laplacian;
};

#define SPH_PI 3.14159265358979323846

__device__ __forceinline__ Smoothing smoothing(float h) {
    Smoothing s;
    double hd = (double)h;
    s.h = h;
    s.h2 = h * h;
    if (D == 2) {
        s.poly6 = (float)(4.0 / (SPH_PI * pow(hd, 8)));
        s.spiky = (float)(10.0 / (SPH_PI * pow(hd, 5)));
        s.visc = (float)(10.0 / (3.0 * SPH_PI * hd * hd));
        s.visc_laplacian = (float)(40.0 / (SPH_PI * pow(hd, 5)));
    } else {
        s.poly6 = (float)(315.0 / (64.0 * SPH_PI * pow(hd, 9)));
        s.spiky = (float)(15.0 / (SPH_PI * pow(hd, 6)));
        s.visc = (float)(15.0 / (2.0 * SPH_PI * hd * hd * hd));
        s.visc_laplacian = (float)(45.0 / (SPH_PI * pow(hd, 6)));
    }
    return s;
}

/// `smoothing::R_MIN_FRACTION`: below this fraction of h the spiky gradient keeps the magnitude
/// it has there.
#define SPH_R_MIN_FRACTION 1.0e-3f

/// `smoothing::COINCIDENT_FRACTION`: pairs closer than this fraction of h are coincident.
#define SPH_COINCIDENT_FRACTION 1.0e-6f

/// Twin of `smoothing::pair_offset`: the offset x_i - x_j [m] a pair loop uses for particles of
/// ids id_i, id_j (`Fields::id`, so the same in any order and on any rank) at `d`, with `*r2` =
/// |d|^2 updated. A pair id_i != id_j closer than SPH_COINCIDENT_FRACTION h gets the offset of
/// that length along axis (id_i + id_j) mod D with the sign of id_i - id_j: antisymmetric, so
/// coincident particles push each other apart (note 4).
__device__ __forceinline__ vec_t pair_offset(vec_t d, float* r2, u32 id_i, u32 id_j, float h) {
    const float e = SPH_COINCIDENT_FRACTION * h;
    if (id_i == id_j || *r2 >= e * e) return d;
    vec_t o = vzero();
    o.c[(unsigned)(((unsigned long long)id_i + (unsigned long long)id_j) % D)] = id_i > id_j ? e : -e;
    *r2 = e * e;
    return o;
}

/// Poly6 kernel W(r^2) [1/m^D].
__device__ __forceinline__ float w_poly6(const Smoothing& s, float r2) {
    if (r2 >= s.h2) return 0.0f;
    float q = s.h2 - r2;
    return s.poly6 * q * q * q;
}

/// Spiky kernel (21) W(r) [1/m^D]. Twin of `Smoothing::w_spiky`.
__device__ __forceinline__ float w_spiky(const Smoothing& s, float r) {
    if (r >= s.h) return 0.0f;
    float q = s.h - r;
    return s.spiky * q * q * q;
}

/// The kernel of eq. (18) at squared distance r2 [1/m^D]: poly6, or `p.density_spiky_scale *
/// W_spiky(r)` (the corrected solver), as `p.density_kernel` says. Twin of
/// `physics::density::density_kernel`.
__device__ __forceinline__ float w_density(const Smoothing& s, const StepParams& p, float r2) {
    return p.density_kernel == SPH_DENSITY_SCALED_SPIKY
               ? p.density_spiky_scale * w_spiky(s, sqrtf(r2))
               : w_poly6(s, r2);
}

/// Gradient of the spiky kernel at offset x, |x| = r [1/m^(D+1)]; the magnitude is taken at r no
/// smaller than SPH_R_MIN_FRACTION h, zero at r = 0. Twin of `Smoothing::grad_w_spiky`.
__device__ __forceinline__ vec_t grad_w_spiky(const Smoothing& s, vec_t x, float r) {
    if (r >= s.h || r <= 0.0f) return vzero();
    float q = s.h - fmaxf(r, SPH_R_MIN_FRACTION * s.h);
    return vscale(x, -3.0f * s.spiky * q * q / r);
}

/// Gradient of eq. (20) at offset x, `-6 K (h^2 - r^2)^2 x` [1/m^(D+1)] (r^2 recomputed from x).
/// Twin of `Smoothing::grad_w`.
__device__ __forceinline__ vec_t grad_w_poly6(const Smoothing& s, vec_t x) {
    const float r2 = vdot(x, x);
    if (r2 >= s.h2) return vzero();
    const float q = s.h2 - r2;
    return vscale(x, -6.0f * s.poly6 * q * q);
}

/// Gradient of the kernel of eq. (18) (`w_density`) at offset x = x_i - x_j, |x| = r
/// [1/m^(D+1)]: the poly6 gradient, or `p.density_spiky_scale` times the spiky gradient, as
/// `p.density_kernel` says. Twin of `physics::density::density_kernel_gradient`.
__device__ __forceinline__ vec_t grad_w_density(const Smoothing& s, const StepParams& p, vec_t x,
                                                float r) {
    return p.density_kernel == SPH_DENSITY_SCALED_SPIKY
               ? vscale(grad_w_spiky(s, x, r), p.density_spiky_scale)
               : grad_w_poly6(s, x);
}

/// Twin of `physics::density::SURFACE_DENSITY_RATIO`: below this rho/rho0 the velocity solve
/// takes a particle for one at the free surface.
#define SPH_SURFACE_DENSITY_RATIO 0.98f

/// The velocity solve's base density [kg/m^3] from the particle's density (18) `rho` at the
/// solve's start and its rest density `rho0`: rho0 inside the fluid, `rho` at the free surface.
/// Twin of `physics::density::velocity_solve_base`.
__device__ __forceinline__ float velocity_solve_base(float rho, float rho0) {
    return rho >= SPH_SURFACE_DENSITY_RATIO * rho0 ? rho0 : rho;
}

/// Laplacian of the viscosity kernel [1/m^(D+2)].
__device__ __forceinline__ float laplacian_w_viscosity(const Smoothing& s, float r) {
    if (r >= s.h) return 0.0f;
    return s.visc_laplacian * (s.h - r);
}
