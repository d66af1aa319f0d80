// Stage `move_solids`: the prescribed motion of solids (`boundary::motion`, `boundary::rigid`).
// Twin of `CpuBackend::move_solids`: every solid particle i of kind 1 + s and id first_id + k
// moves to `SolidKinematics::position(reference[k])` [m] (x0 + d, turned about the pivot when
// the solid rotates) and takes the velocity `velocity_at` there [m/s] (`rigid.cuh`), with the
// same f32 operations, so both backends place the walls bitwise alike. `motion` holds one record
// of SPH_MOTION_FLOATS floats per solid, computed once on the host (in f64, rounded to f32); a
// fixed solid in a scene with moving ones has zeros there. `reference` holds D floats per solid
// particle, by id. The host launches this only when some solid moves.
#include "sph.cuh"
#include "rigid.cuh"

SPH_KERNEL(move_solids)(u32 n, const u32* __restrict__ kind, const u32* __restrict__ id,
                        u32 first_id, const float* __restrict__ reference,
                        const float* __restrict__ motion, float* __restrict__ pos,
                        float* __restrict__ vel) {
    u32 i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] == SPH_FLUID) return;
    const float* m = rigid_record(motion, kind[i] - 1u);
    const vec_t x = rigid_position(m, vload(reference, id[i] - first_id));
    vstore(pos, i, x);
    vstore(vel, i, rigid_velocity_at(m, x));
}
