// Stage `wall_pressure`: pressure and density of solid particles, [A12] (Adami et al. 2012)
// eq. (27), extrapolated from the fluid neighbours with the body acceleration `g - a_w` in the
// wall's frame (`motion`: one `rigid.cuh` record per solid; `a_w` the wall's acceleration at the
// wall particle [m/s^2], `rigid_acceleration_at`; zeros for walls at rest, where `g - 0` is `g`
// bit for bit), plus the centrifugal acceleration at the wall in a
// rotating frame (`rotating_frame.cuh`). Twin of
// `CpuBackend::wall_pressure` and `boundary::wall_pressure::WallPressureSums`; fluid entries are
// left as they are. Writing in place is safe: a solid reads only its fluid neighbours' pressure
// and density, which this kernel never writes. `wall_pressure_multiphase` (the `multiphase`
// effect, [HA06]) takes the summed branch's density as the wall's number density times its own
// mass, `m_w sum W`, instead of (18) (`multiphase::wall_density`).
#include "sph.cuh"
#include "rotating_frame.cuh"
#include "rigid.cuh"

/// [A12] eq. (27): p_w = max((sum_f p_f W_wf + (g - a_w) . sum_f rho_f (x_w - x_f) W_wf) / sum_f W_wf, 0)
/// over fluid neighbours f (0 without any); with `extrapolated_or_summed` != 0
/// (`WallModel::ExtrapolatedOrSummed`) the max with eq. (19) of the solid's own summed density
/// (18) over all neighbours; then rho_w = rho0 + p_w / C^2. Pressure [Pa], density [kg/m^3].
template <bool MULTIPHASE>
__device__ __forceinline__ void wall_pressure_body(u32 n, const StepParams& p, const GridGeometry& g,
                                                   const u32* __restrict__ cell_start,
                                                   const u32* __restrict__ cell_key,
                                                   const float* __restrict__ pos,
                                                   const float* __restrict__ mass,
                                                   const u32* __restrict__ kind, const u32* __restrict__ id,
                                                   const float* __restrict__ motion,
                                                   int extrapolated_or_summed, float* pressure,
                                                   float* density) {
    u32 w = blockIdx.x * blockDim.x + threadIdx.x;
    if (w >= n || kind[w] == SPH_FLUID) return;
    const Smoothing s = smoothing(p.h);
    const vec_t xw = vload(pos, w);
    // WallPressureSums: weight, pressure, density_offset.
    float weight = 0.0f, pressure_sum = 0.0f;
    vec_t density_offset = vzero();
    float summed_density = 0.0f;
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[w], j, {
        vec_t d = pair_delta(g, xw, pos, j);
        float r2 = vdot(d, d);
        if (r2 < s.h2) {
            d = pair_offset(d, &r2, id[w], id[j], s.h);
            float wj = w_poly6(s, r2);
            // Eq. (18)'s own kernel for the summed density (poly6, or the corrected solver's spiky).
            const float wd = w_density(s, p, r2);
            if (MULTIPHASE)
                summed_density += wd;  // [HA06] number density
            else
                summed_density += mass[j] * wd;
            if (kind[j] == SPH_FLUID) {
                weight += wj;
                pressure_sum += pressure[j] * wj;
                density_offset = vadd(density_offset, vscale(d, density[j] * wj));
            }
        }
    });
    if (MULTIPHASE) summed_density = mass[w] * summed_density;
    float pw = 0.0f;
    if (!(weight <= 0.0f)) {  // as `WallPressureSums::pressure`: a NaN weight falls through
        const vec_t a_w = rigid_acceleration_at(rigid_record(motion, kind[w] - 1u), xw);
        vec_t body;
        for (int k = 0; k < D; ++k) body.c[k] = p.gravity[k] - a_w.c[k];
        // In a rotating frame: plus the centrifugal acceleration at the wall ([B67] 3.2).
        if (p.rotating_frame) body = vadd(body, rotating_frame_centrifugal(p, xw));
        pw = fmaxf((pressure_sum + vdot(body, density_offset)) / weight, 0.0f);
    }
    if (extrapolated_or_summed) pw = fmaxf(pw, fmaxf(p.c2 * (summed_density - p.rho0), 0.0f));
    pressure[w] = pw;
    density[w] = p.rho0 + pw / p.c2;
}

#define SPH_WALL_PRESSURE_ENTRY(name, MULTIPHASE)                                                  \
    SPH_KERNEL(name)(u32 n, StepParams p, GridGeometry g, const u32* __restrict__ cell_start,      \
                     const u32* __restrict__ cell_key, const float* __restrict__ pos,              \
                     const float* __restrict__ mass, const u32* __restrict__ kind, const u32* __restrict__ id,                 \
                     const float* __restrict__ motion, int extrapolated_or_summed,                 \
                     float* pressure, float* density) {                                            \
        wall_pressure_body<MULTIPHASE>(n, p, g, cell_start, cell_key, pos, mass, kind, id, motion,     \
                                       extrapolated_or_summed, pressure, density);                 \
    }

/// [A12] eq. (27) (above).
SPH_WALL_PRESSURE_ENTRY(wall_pressure, false)
/// The same with the summed branch's number density ([HA06], the `multiphase` effect).
SPH_WALL_PRESSURE_ENTRY(wall_pressure_multiphase, true)
