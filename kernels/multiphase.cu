// The `multiphase` effect's variants of the density, equation-of-state and correction stages
// ([HA06] Hu & Adams, J. Comput. Phys. 213 (2006) 844; `physics::multiphase`). Twins of the
// multiphase branches of `CpuBackend::density`, `equation_of_state`, `correction_error`,
// `correction_pressure`, `correct_positions` and `predicted_density` (also the branches of
// `mix_velocity_pressure` and `velocity_from_pressure`), which run when `Fields::rest_density` is allocated; `rest` is that field
// (kg/m^3, per particle). The force, wall-pressure, solid-force and state-extremes variants are
// template flags of their own files (`forces_*_mp`, `wall_pressure_multiphase`,
// `solid_forces_multiphase`, `state_extremes_multiphase`).
#include "sph.cuh"
#include "extremes.cuh"
#include "multiphase.cuh"

/// [HA06] density: rho_i = m_i sum_j W(|x_i - x_j|, h) (`w_density`: the number density times the
/// particle's own mass), fluid only. Twin of `multiphase::number_density_term` and `density`.
SPH_KERNEL(density_multiphase)(u32 n, StepParams p, GridGeometry g,
                               const u32* __restrict__ cell_start,
                               const u32* __restrict__ cell_key, const float* __restrict__ pos,
                               const float* __restrict__ mass, const u32* __restrict__ kind,
                               float* __restrict__ density) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const Smoothing s = smoothing(p.h);
    const vec_t xi = vload(pos, i);
    float sigma = 0.0f;
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        vec_t d = vsub(xi, vload(pos, j));
        float r2 = vdot(d, d);
        if (r2 < s.h2) {
            d = pair_offset(d, &r2, i, j, s.h);
            sigma += w_density(s, p, r2);
        }
    });
    density[i] = mass[i] * sigma;
}

/// [HA06] variant of `predicted_density` (density.cu): `rho*_i = base_i + tau m_i sum_{j != i}
/// (u_i - u_j) . grad W_rho(x_i - x_j)` [kg/m^3] with the particle's own mass and rest density,
/// fluid only (each term `m_i (u_i - u_j) . grad W`, summed, as the CPU). Twin of the multiphase
/// branch of `CpuBackend::predicted_density`.
SPH_KERNEL(predicted_density_multiphase)(u32 n, StepParams p, GridGeometry g,
                                         const u32* __restrict__ cell_start,
                                         const u32* __restrict__ cell_key,
                                         const float* __restrict__ pos,
                                         const float* __restrict__ vel,
                                         const float* __restrict__ mass,
                                         const float* __restrict__ rest,
                                         const u32* __restrict__ kind,
                                         const float* __restrict__ density_start, float tau,
                                         float* __restrict__ density) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const Smoothing s = smoothing(p.h);
    const vec_t xi = vload(pos, i);
    const vec_t ui = vload(vel, i);
    const float m_i = mass[i];
    float rate = 0.0f;  // d rho_i / dt [kg/(m^3 s)]
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        vec_t d = vsub(xi, vload(pos, j));
        float r2 = vdot(d, d);
        if (r2 < s.h2 && j != i) {
            d = pair_offset(d, &r2, i, j, s.h);
            const vec_t grad = grad_w_density(s, p, d, sqrtf(r2));
            rate += m_i * vdot(vsub(ui, vload(vel, j)), grad);
        }
    });
    density[i] = velocity_solve_base(density_start[i], rest[i]) + tau * rate;
}

/// Eq. (19) with each particle's own rest density: p = max(C^2 (rho - rho0_i), 0), fluid only.
SPH_KERNEL(equation_of_state_multiphase)(u32 n, StepParams p, const float* __restrict__ density,
                                         const float* __restrict__ rest,
                                         const u32* __restrict__ kind, float* __restrict__ pressure) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    pressure[i] = fmaxf(p.c2 * (density[i] - rest[i]), 0.0f);
}

/// Eq. (24) with note 6 against each particle's own rest density: as `correction_error`.
SPH_KERNEL(correction_error_multiphase)(u32 n, const float* __restrict__ rest,
                                        const float* __restrict__ density,
                                        const float* __restrict__ pressure,
                                        const u32* __restrict__ kind, int* __restrict__ out) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != SPH_FLUID) return;
    const double e = ((double)density[i] - (double)rest[i]) / (double)rest[i];
    const double compression = e > 0.0 ? e : 0.0;
    const double residual = pressure[i] > 0.0f ? fabs(e) : compression;
    const int bc = max_bits((float)compression), br = max_bits((float)residual);
    if (bc > out[0]) atomicMax(&out[0], bc);
    if (br > out[1]) atomicMax(&out[1], br);
}

/// Eq. (19) inside the correction with each particle's own rest density: as
/// `correction_pressure_fluid`, `rho0` replaced by `rest[i]`.
SPH_KERNEL(correction_pressure_fluid_multiphase)(u32 n, const float* __restrict__ rest, float k,
                                                 float beta, int has_prev,
                                                 const float* __restrict__ density,
                                                 const float* __restrict__ pressure,
                                                 const u32* __restrict__ kind,
                                                 const float* __restrict__ delta_p_prev,
                                                 float* __restrict__ delta_p) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    if (kind[i] != SPH_FLUID) {
        delta_p[i] = 0.0f;
        return;
    }
    const float m = has_prev ? beta * delta_p_prev[i] : 0.0f;
    const float p_m = pressure[i] + m;
    delta_p[i] = (fmaxf(p_m + k * (density[i] - rest[i]), 0.0f) - p_m) + m;
}

/// Eq. (23) with the [HA06] volume-form pressure force of the increments:
/// dx_i = tau^2 sum_j -(dp_i V_i^2 + dp_j V_j^2) grad W / m_i, fluid only; as
/// `correction_displacement` otherwise.
SPH_KERNEL(correction_displacement_multiphase)(u32 n, StepParams p, GridGeometry g,
                                               const u32* __restrict__ cell_start,
                                               const u32* __restrict__ cell_key,
                                               const float* __restrict__ pos,
                                               const float* __restrict__ mass,
                                               const float* __restrict__ density,
                                               const float* __restrict__ delta_p,
                                               const u32* __restrict__ kind, float tau2,
                                               float* __restrict__ displacement,
                                               int* __restrict__ largest) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    if (kind[i] != SPH_FLUID) {
        vstore(displacement, i, vzero());
        return;
    }
    const Smoothing s = smoothing(p.h);
    const vec_t x_i = vload(pos, i);
    const float m_i = mass[i];
    const float q_i = multiphase_pressure_term(delta_p[i], m_i, density[i]);
    vec_t a = vzero();
    SPH_FOR_EACH_CANDIDATE(g, cell_start, cell_key[i], j, {
        if (j == i) continue;
        vec_t d = vsub(x_i, vload(pos, j));
        float r2 = vdot(d, d);
        if (!(r2 < s.h2)) continue;
        d = pair_offset(d, &r2, i, j, s.h);
        const vec_t grad = vscale(grad_w_spiky(s, d, sqrtf(r2)), p.pressure_gradient_scale);
        const float q_j = multiphase_pressure_term(delta_p[j], mass[j], density[j]);
        a = vadd(a, multiphase_pressure_acceleration(q_i, q_j, m_i, grad));
    });
    const vec_t dx = vscale(a, tau2);  // eq. (23)
    vstore(displacement, i, dx);
    const int b = max_bits(sqrtf(vdot(dx, dx)));
    if (b > *largest) atomicMax(largest, b);
}
