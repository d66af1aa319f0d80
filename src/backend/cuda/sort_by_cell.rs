//! Stage `sort_by_cell` on the device (`kernels/sort_by_cell.cu`): the cell hash, a counting sort by
//! cell key (atomic counts, a multi-level exclusive scan, scatter, each cell ordered by particle
//! id) and the gathers that reorder every field by the permutation.

use super::*;
use crate::periodic::PeriodicAxes;

/// Items per thread at each level of the cell-count scan: a level of `m` items leaves `m/64`
/// chunk sums, scanned the same way, until at most `SCAN_TOP` remain for one thread.
const SCAN_CHUNK: u32 = 64;

/// Largest level the scan leaves to a single thread.
const SCAN_TOP: u32 = 1024;

/// Sizes of the scan's levels above the cell counts: `m/64`, `m/64²`, ... down to `SCAN_TOP`.
fn scan_levels(m: u32) -> Vec<u32> {
    let mut sizes = vec![m.div_ceil(SCAN_CHUNK)];
    while *sizes.last().expect("one level") > SCAN_TOP {
        let next = sizes.last().expect("one level").div_ceil(SCAN_CHUNK);
        sizes.push(next);
    }
    sizes
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum VecField {
    Position,
    Velocity,
    Acceleration,
    PositionStart,
    VelocityStart,
    WallVelocity,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum ScalarField {
    Density,
    Pressure,
    Mass,
    RestDensity,
    DensityRate,
    DensityStart,
    ActingPressure,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum IndexField {
    Kind,
    Id,
    CellKey,
}

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    /// Builds (or keeps) the dense grid for cells of size `h`.
    fn ensure_grid(&mut self, h: Real, axes: PeriodicAxes) -> Result<(), BackendError> {
        if self
            .grid
            .as_ref()
            .is_some_and(|g| g.cell_size == h && g.geometry.periodic == axes.bits())
        {
            return Ok(());
        }
        let geometry = GridGeometry::new_periodic(&self.domain.0, &self.domain.1, h, axes).map_err(|e| {
            BackendError::Unavailable {
                backend: "cuda",
                reason: e.to_string(),
            }
        })?;
        let cells = geometry.cell_count();
        let dev = &self.dev;
        let a = |len: usize| {
            dev.alloc_zeros::<u32>(len.max(1))
                .map_err(|e| device_error("allocating the grid", e))
        };
        self.grid = Some(DeviceGrid {
            geometry,
            cell_size: h,
            key: a(self.n)?,
            cell_key: a(self.n)?,
            cell_count: a(cells + 1)?,
            cell_start: a(cells + 1)?,
            cell_fill: a(cells)?,
            chunk_sums: scan_levels(cells as u32 + 1)
                .into_iter()
                .map(|m| Ok((a(m as usize)?, a(m as usize)?)))
                .collect::<Result<_, BackendError>>()?,
            perm: a(self.n)?,
        });
        Ok(())
    }

    /// Gathers one vector field by the sort's permutation.
    fn gather_vec(&mut self, which: VecField) {
        let n = self.n as u32;
        let grid = self.grid.as_ref().expect("sorted");
        let src = match which {
            VecField::Position => &mut self.f.position,
            VecField::Velocity => &mut self.f.velocity,
            VecField::Acceleration => &mut self.f.acceleration,
            VecField::PositionStart => &mut self.f.position_start,
            VecField::VelocityStart => &mut self.f.velocity_start,
            VecField::WallVelocity => match self.f.wall_velocity.as_mut() {
                Some(b) => b,
                None => return,
            },
        };
        // SAFETY: perm, src and scratch hold n entries (times D for vectors).
        let r = unsafe { self.dev.gather_vec(n, &grid.perm, src, &mut self.scratch_vec) };
        std::mem::swap(src, &mut self.scratch_vec);
        record(&mut self.error, "gathering a vector field", r);
    }

    fn gather_scalar(&mut self, which: ScalarField) {
        let n = self.n as u32;
        let grid = self.grid.as_ref().expect("sorted");
        let src = match which {
            ScalarField::Density => &mut self.f.density,
            ScalarField::Pressure => &mut self.f.pressure,
            ScalarField::Mass => &mut self.f.mass,
            ScalarField::RestDensity => match self.f.rest_density.as_mut() {
                Some(b) => b,
                None => return,
            },
            ScalarField::DensityRate => match self.density_rate.as_mut() {
                Some(b) => b,
                None => return,
            },
            ScalarField::DensityStart => match self.density_start.as_mut() {
                Some(b) => b,
                None => return,
            },
            ScalarField::ActingPressure => match self.f.acting_pressure.as_mut() {
                Some(b) => b,
                None => return,
            },
        };
        // SAFETY: perm and src hold n entries; the scratch holds at least n floats.
        let r = unsafe {
            self.dev
                .gather_f32(n, &grid.perm, src, &mut self.delta_p_previous)
        };
        // delta_p_previous is dead after a sort (the momentum restarts), so it is the scratch.
        std::mem::swap(src, &mut self.delta_p_previous);
        record(&mut self.error, "gathering a scalar field", r);
    }

    fn gather_index(&mut self, which: IndexField) {
        let n = self.n as u32;
        let grid = self.grid.as_mut().expect("sorted");
        let r = match which {
            IndexField::Kind | IndexField::Id => {
                let src = if which == IndexField::Kind {
                    &mut self.f.kind
                } else {
                    &mut self.f.id
                };
                // SAFETY: perm, src and scratch hold n entries.
                let r = unsafe { self.dev.gather_u32(n, &grid.perm, src, &mut self.scratch_u32) };
                std::mem::swap(src, &mut self.scratch_u32);
                r
            }
            // SAFETY: perm, key and cell_key hold n entries.
            IndexField::CellKey => unsafe {
                self.dev.gather_u32(n, &grid.perm, &grid.key, &mut grid.cell_key)
            },
        };
        record(&mut self.error, "gathering an index field", r);
    }

    pub(super) fn launch_sort_by_cell(&mut self, h: f32, axes: PeriodicAxes) -> Result<(), GridError> {
        if self.error.is_some() {
            return Ok(());
        }
        if let Err(e) = self.ensure_grid(h, axes) {
            self.error = Some(e);
            return Ok(());
        }
        let n = self.n;
        let n32 = n as u32;
        {
            let grid = self.grid.as_mut().expect("built above");
            let r = self.dev.zero(&mut grid.cell_count);
            let r2 = self.dev.zero(&mut grid.cell_fill);
            let r = r.and(r2);
            if let Err(e) = r {
                self.error = Some(device_error("clearing the cell counts", e));
                return Ok(());
            }
        }
        let grid = self.grid.as_mut().expect("built above");
        let geometry = grid.geometry;
        let cells = geometry.cell_count();
        let m = (cells + 1) as u32;
        let chunk = SCAN_CHUNK;
        let ncell = cells as u32;
        let dev = &self.dev;
        let mut results = Vec::with_capacity(6);
        // SAFETY (all launches below): buffers sized n, ncell + 1 and chunks as the kernels of
        // kernels/sort_by_cell.cu expect.
        unsafe {
            results.push(dev.cell_hash(
                n32,
                &geometry,
                &self.f.position,
                &mut grid.key,
                &mut grid.cell_count,
            ));
            // The exclusive scan of the counts, level by level (see `scan_levels`).
            let levels = &mut grid.chunk_sums;
            let sizes = scan_levels(m);
            results.push(dev.scan_chunks(m, chunk, &grid.cell_count, &mut grid.cell_start, &mut levels[0].0));
            for l in 1..sizes.len() {
                let (below, above) = levels.split_at_mut(l);
                let (sums, scanned) = (&below[l - 1].0, &mut below[l - 1].1);
                results.push(dev.scan_chunks(sizes[l - 1], chunk, sums, scanned, &mut above[0].0));
            }
            let top = sizes.len() - 1;
            results.push(dev.scan_chunk_sums(sizes[top], &mut levels[top].0));
            for l in (1..sizes.len()).rev() {
                // Level l's scanned sums complete the scan of level l - 1's sums.
                let (below, above) = levels.split_at_mut(l);
                let add = if l == top { &above[0].0 } else { &above[0].1 };
                results.push(dev.scan_add(sizes[l - 1], chunk, &mut below[l - 1].1, add));
            }
            let add = if top == 0 { &levels[0].0 } else { &levels[0].1 };
            results.push(dev.scan_add(m, chunk, &mut grid.cell_start, add));
            results.push(dev.scatter(
                n32,
                &grid.key,
                &grid.cell_start,
                &mut grid.cell_fill,
                &mut grid.perm,
            ));
            results.push(dev.order_cells(ncell, &grid.cell_start, &self.f.id, &mut grid.perm));
        }
        for r in results {
            record(&mut self.error, "sorting by cell", r);
        }
        for v in [
            VecField::Position,
            VecField::Velocity,
            VecField::Acceleration,
            VecField::PositionStart,
            VecField::VelocityStart,
            VecField::WallVelocity,
        ] {
            self.gather_vec(v);
        }
        for sf in [
            ScalarField::Density,
            ScalarField::Pressure,
            ScalarField::Mass,
            ScalarField::RestDensity,
            ScalarField::DensityRate,
            ScalarField::DensityStart,
            ScalarField::ActingPressure,
        ] {
            self.gather_scalar(sf);
        }
        for i in [IndexField::Kind, IndexField::Id, IndexField::CellKey] {
            self.gather_index(i);
        }
        self.has_previous = false;
        Ok(())
    }
}
