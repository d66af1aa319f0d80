// Stage `gradient_moment`: the first moment of the spiky gradient (21) over the owned fluid
// particles with full kernel support, the factor the pressure force (16) divides by
// (`physics::gradient_moment`, [BL99] eq. 43's scalar part). Twin of
// `CpuBackend::gradient_moment`: each fluid particle i sums in f32, over its neighbours j (itself
// included), the Shepard sum V_j W_poly6(r_ij) and the moment -V_j x_ij . grad W_spiky(x_ij) / D
// with V_j = m_j / rho_j; where the Shepard sum is at least SPH_FULL_SUPPORT, out[0] += moment
// and out[1] += 1, in f64 (per thread, see below). The host zeroes `out` (2 doubles).
#include "sph.cuh"
#include "extremes.cuh"

/// `physics::gradient_moment::FULL_SUPPORT`.
#define SPH_FULL_SUPPORT 0.95

SPH_KERNEL(gradient_moment)(u32 n, StepParams p, GridGeometry g, const u32* __restrict__ cell_start,
                            const u32* __restrict__ cell_key, const float* __restrict__ pos,
                            const float* __restrict__ mass, const float* __restrict__ density,
                            const u32* __restrict__ kind, const u32* __restrict__ id,
                            const u32* __restrict__ owned, double* __restrict__ out) {
    // Grid-stride loop: the backend launches about n/8 threads, each adding its sums once (two
    // addresses every thread would otherwise hit). The shim launches one thread per particle.
    const u32 stride = gridDim.x * blockDim.x;
    const Smoothing s = smoothing(p.h);
    double moment = 0.0, count = 0.0;
    for (u32 i = blockIdx.x * blockDim.x + threadIdx.x; i < n; i += stride) {
        // A ghost of a split run: its owner adds it (`backend::partition`).
        if (kind[i] != SPH_FLUID || !owned[i]) continue;
        const vec_t xi = vload(pos, i);
        float shepard = 0.0f, m_i = 0.0f;
        SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
            vec_t d = pair_delta(g, xi, pos, j);
            float r2 = vdot(d, d);
            if (r2 < s.h2) {
                d = pair_offset(d, &r2, id[i], id[j], s.h);
                const float volume = mass[j] / density[j];
                shepard += volume * w_poly6(s, r2);
                m_i += -volume * vdot(d, grad_w_spiky(s, d, sqrtf(r2))) / (float)D;
            }
        });
        // `MomentSums::of_particle`: full support, and a finite moment.
        if ((double)shepard >= SPH_FULL_SUPPORT && finite_float(m_i)) {
            moment += (double)m_i;
            count += 1.0;
        }
    }
    if (count > 0.0) {
        atomicAdd(&out[0], moment);
        atomicAdd(&out[1], count);
    }
}
