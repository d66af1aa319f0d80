//! The kernels of `kernels/` compiled as C++ for the CPU (`kernels/shim`, built by `build.rs`
//! with `--features cuda`), and [`Shim`], the device the CUDA backend runs on there: memory is
//! host vectors, and each launch runs the kernel's threads one after another with the launch
//! shape of `kernels/launch.table`. So CI runs the CUDA backend's own sequencing
//! (`CudaBackend<D, Shim>`) without a GPU, and tests can call each kernel's launcher
//! `sph_shim_<kernel>_<D>` directly.
//!
//! All pointers given to a launcher must be valid for the lengths the kernel reads and writes
//! (`n` items, times `D` for vectors); the functions are `unsafe` for that reason alone.
#![allow(missing_docs)]

use super::CudaBackend;
use super::extremes::DeviceExtremes;
use super::grid::GridGeometry;
use super::launch::{DeviceFault, Element, Memory};
use crate::backend::{Backend, BackendError};
use crate::fields::Fields;
use crate::model::params::StepParams;
use std::ops::Range;

include!(concat!(env!("OUT_DIR"), "/shim_externs.rs"));

/// The fields of `StepParams` in declaration order, as `sph_shim_step_params_layout_D` reports
/// their offsets.
pub const STEP_PARAMS_FIELDS: usize = 23;

#[link(name = "sph_kernel_shim_2", kind = "static")]
unsafe extern "C" {
    /// `StepParams`'s size and its fields' offsets in declaration order, as the kernels lay it
    /// out ([`STEP_PARAMS_FIELDS`] + 1 values).
    pub fn sph_shim_step_params_layout_2(out: *mut u64);
    /// `sizeof(Extremes)`, then each field's offset (11 values).
    pub fn sph_shim_extremes_layout_2(out: *mut u32);
    /// `GridGeometry`'s size and its fields' offsets in declaration order (8 values).
    pub fn sph_shim_grid_geometry_layout_2(out: *mut u64);
    /// Test only: the neighbours `SPH_FOR_EACH_CANDIDATE` yields with `r < h`; `count[i]` of
    /// them, the first `max` in `list[i * max ..]`.
    pub fn sph_shim_neighbour_list_2(
        n: u32,
        h: f32,
        g: *const GridGeometry<2>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        max: u32,
        count: *mut u32,
        list: *mut u32,
    );
}

#[link(name = "sph_kernel_shim_3", kind = "static")]
unsafe extern "C" {
    /// As [`sph_shim_step_params_layout_2`].
    pub fn sph_shim_step_params_layout_3(out: *mut u64);
    /// As [`sph_shim_extremes_layout_2`].
    pub fn sph_shim_extremes_layout_3(out: *mut u32);
    /// As [`sph_shim_grid_geometry_layout_2`].
    pub fn sph_shim_grid_geometry_layout_3(out: *mut u64);
    /// As [`sph_shim_neighbour_list_2`].
    pub fn sph_shim_neighbour_list_3(
        n: u32,
        h: f32,
        g: *const GridGeometry<3>,
        cell_start: *const u32,
        cell_key: *const u32,
        pos: *const f32,
        max: u32,
        count: *mut u32,
        list: *mut u32,
    );
}

/// The host shim as a device: buffers are vectors, launches run on the calling thread, and
/// nothing can fail but a length mismatch in a copy.
#[derive(Clone, Copy, Debug, Default)]
pub struct Shim;

impl Shim {
    /// The CUDA backend on the host shim, holding a copy of `fields` (for
    /// `Simulation::use_backend_from`).
    ///
    /// # Errors
    /// Never in practice: the shim's memory is the host's.
    pub fn backend<const D: usize>(
        fields: &Fields<D>,
        params: &StepParams<D>,
    ) -> Result<Box<dyn Backend<D> + Send>, BackendError> {
        Ok(Box::new(CudaBackend::on_device(Shim, fields, params)?))
    }
}

fn same_length(what: &str, src: usize, dst: usize) -> Result<(), DeviceFault> {
    if src == dst {
        Ok(())
    } else {
        Err(DeviceFault(format!("{what}: {src} items into a buffer of {dst}")))
    }
}

impl Memory for Shim {
    type Buf<T: Element> = Vec<T>;

    fn alloc_zeros<T: Element>(&self, len: usize) -> Result<Vec<T>, DeviceFault> {
        Ok(vec![T::default(); len])
    }

    fn upload<T: Element>(&self, src: &[T]) -> Result<Vec<T>, DeviceFault> {
        Ok(src.to_vec())
    }

    fn write<T: Element>(&self, src: &[T], dst: &mut Vec<T>) -> Result<(), DeviceFault> {
        // As cudarc's memcpy_htod: into the start of a buffer at least as long.
        if src.len() > dst.len() {
            return same_length("uploading", src.len(), dst.len());
        }
        dst[..src.len()].copy_from_slice(src);
        Ok(())
    }

    fn copy<T: Element>(&self, src: &Vec<T>, dst: &mut Vec<T>) -> Result<(), DeviceFault> {
        let k = src.len().min(dst.len());
        dst[..k].copy_from_slice(&src[..k]);
        Ok(())
    }

    fn download<T: Element>(&self, src: &Vec<T>) -> Result<Vec<T>, DeviceFault> {
        Ok(src.clone())
    }

    fn download_into<T: Element>(&self, src: &Vec<T>, dst: &mut [T]) -> Result<(), DeviceFault> {
        // As cudarc's memcpy_dtoh: the whole buffer, into the start of `dst`.
        if src.len() > dst.len() {
            return same_length("downloading", src.len(), dst.len());
        }
        dst[..src.len()].copy_from_slice(src);
        Ok(())
    }

    fn download_range<T: Element>(&self, src: &Vec<T>, range: Range<usize>) -> Result<Vec<T>, DeviceFault> {
        src.get(range)
            .map(<[T]>::to_vec)
            .ok_or_else(|| DeviceFault("downloading past the end of a buffer".into()))
    }

    fn zero<T: Element>(&self, buf: &mut Vec<T>) -> Result<(), DeviceFault> {
        buf.fill(T::default());
        Ok(())
    }

    fn synchronize(&self) -> Result<(), DeviceFault> {
        Ok(())
    }

    fn name(&self) -> String {
        "host shim (the CUDA kernels on the CPU)".into()
    }
}
