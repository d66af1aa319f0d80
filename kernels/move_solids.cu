// Stage `move_solids`: the prescribed motion of solids (`boundary::motion`). Twin of
// `CpuBackend::move_solids`: every solid particle i of kind 1 + s and id first_id + k moves to
// `reference[k] + displacement_s` [m] and takes the velocity `velocity_s` [m/s], with the same
// f32 addition, so both backends place the walls bitwise alike. `motion` holds 2 D floats per
// solid, `[d_s, d'_s]`, computed once on the host (in f64, rounded to f32); a fixed solid in a
// scene with moving ones has zeros there. `reference` holds D floats per solid particle, by id.
// The host launches this only when some solid moves.
#include "sph.cuh"

SPH_KERNEL(move_solids)(u32 n, const u32* __restrict__ kind, const u32* __restrict__ id,
                        u32 first_id, const float* __restrict__ reference,
                        const float* __restrict__ motion, float* __restrict__ pos,
                        float* __restrict__ vel) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] == SPH_FLUID) return;
    const u32 s = kind[i] - 1u;
    const vec_t displacement = vload(motion, 2u * s);
    const vec_t velocity = vload(motion, 2u * s + 1u);
    vstore(pos, i, vadd(vload(reference, id[i] - first_id), displacement));
    vstore(vel, i, velocity);
}
