//! The device memory the backend holds, for `Backend::heap_bytes`.

use super::*;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    /// Every device buffer's size \[B\], counted from its length (the driver's own context is
    /// not): `Backend::heap_bytes`.
    pub(super) fn buffer_bytes(&self) -> usize {
        let f = &self.f;
        let mut bytes = [
            &f.position,
            &f.velocity,
            &f.acceleration,
            &f.position_start,
            &f.velocity_start,
            &f.density,
            &f.pressure,
            &f.mass,
            &self.scratch_vec,
            &self.delta_p,
            &self.delta_p_previous,
            &self.displacement,
            &self.velocity_solve_start,
            &self.pressure_solve_start,
            &self.density_solve_start,
            &self.solid_motion,
            &self.wall_motion,
        ]
        .iter()
        .map(|b| b.num_bytes())
        .sum::<usize>()
            + f.kind.num_bytes()
            + f.id.num_bytes()
            + self.scratch_u32.num_bytes()
            + self.reduce_i32.num_bytes()
            + self.extremes.num_bytes()
            + self.solid_out.num_bytes()
            + self.keep_out_boxes.num_bytes()
            + self.keep_out_out.num_bytes()
            + self.solid_reference.as_ref().map_or(0, |b| b.num_bytes())
            + self.f.wall_velocity.as_ref().map_or(0, |b| b.num_bytes())
            + self.normal.as_ref().map_or(0, |b| b.num_bytes())
            + self.density_rate.as_ref().map_or(0, |b| b.num_bytes())
            + self.density_start.as_ref().map_or(0, |b| b.num_bytes())
            + self.f.rest_density.as_ref().map_or(0, |b| b.num_bytes())
            + self.f.acting_pressure.as_ref().map_or(0, |b| b.num_bytes())
            + self.anderson_buffers.as_ref().map_or(0, |b| b.num_bytes())
            + self.solve_records.num_bytes();
        if let Some(g) = &self.grid {
            bytes += [
                &g.key,
                &g.cell_key,
                &g.cell_count,
                &g.cell_start,
                &g.cell_fill,
                &g.perm,
            ]
            .iter()
            .map(|b| b.num_bytes())
            .sum::<usize>();
            bytes += g
                .chunk_sums
                .iter()
                .map(|(a, b)| a.num_bytes() + b.num_bytes())
                .sum::<usize>();
        }
        bytes
    }
}
