//! The velocity solve's warm start on the device (`kernels/anderson.cu`'s
//! `velocity_solve_warm_start` and `velocity_solve_record`), twin of `backend::cpu::warm_start`:
//! each integrator stage's solve starts from the increments its solve of the previous step ended
//! with. A child module of `device` (it reads the backend's private buffers).

use super::{CudaBackend, device_error, record};
use crate::backend::cuda::launch::{Buffer, DeviceFault, Launch, Memory};
use crate::backend::{BackendError, SolveRecord, VELOCITY_SOLVE_SLOTS};

/// Every slot's records by particle id (`id * VELOCITY_SOLVE_SLOTS + slot`, so that a larger id
/// only lengthens them): the number of the slot's solve that recorded each and the increment
/// `P − P_start` [Pa]; a record counts when its number is the slot's count of solves (the CPU
/// twin's rule). The buffers are allocated at the first kept solve and grown, their records
/// kept, when ids outgrow them. They survive `Backend::reload`: ids do not change.
pub(super) struct VelocitySolveRecords<K: Memory> {
    solves: [u32; VELOCITY_SOLVE_SLOTS],
    buffers: Option<RecordBuffers<K>>,
}

/// The numbers of the solves that recorded (`u32`) and the increments [Pa] (`f32`).
type RecordBuffers<K> = (<K as Memory>::Buf<u32>, <K as Memory>::Buf<f32>);

impl<K: Memory> Default for VelocitySolveRecords<K> {
    fn default() -> Self {
        Self {
            solves: [0; VELOCITY_SOLVE_SLOTS],
            buffers: None,
        }
    }
}

impl<K: Memory> VelocitySolveRecords<K> {
    /// Device bytes held (for `Backend::heap_bytes`).
    pub(super) fn num_bytes(&self) -> usize {
        self.buffers
            .as_ref()
            .map_or(0, |(by, inc)| by.num_bytes() + inc.num_bytes())
    }
}

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    pub(super) fn launch_warm_start_velocity_solve(&mut self, slot: usize) {
        let solves = self.solve_records.solves[slot];
        if solves == 0 || self.error.is_some() {
            return;
        }
        let Some((recorded_by, increment)) = self.solve_records.buffers.as_ref() else {
            return;
        };
        let (n, slots) = (self.n as u32, VELOCITY_SOLVE_SLOTS as u32);
        let r = unsafe {
            // SAFETY: the records hold `id_bound` ids (`ensure_records`), every id is below it.
            self.dev.velocity_solve_warm_start(
                n,
                slots,
                slot as u32,
                solves,
                &self.f.kind,
                &self.f.id,
                recorded_by,
                increment,
                &mut self.f.pressure,
            )
        };
        record(&mut self.error, "warm-starting the velocity solve", r);
    }

    pub(super) fn launch_record_velocity_solve(&mut self, slot: usize, keep: bool) {
        let next = self.solve_records.solves[slot].wrapping_add(1);
        self.solve_records.solves[slot] = next;
        if !keep || !self.ensure_records() {
            return;
        }
        let Some((recorded_by, increment)) = self.solve_records.buffers.as_mut() else {
            return;
        };
        let (n, slots) = (self.n as u32, VELOCITY_SOLVE_SLOTS as u32);
        let r = unsafe {
            // SAFETY: as in `launch_warm_start_velocity_solve`.
            self.dev.velocity_solve_record(
                n,
                slots,
                slot as u32,
                next,
                &self.f.kind,
                &self.f.id,
                &self.f.pressure,
                &self.pressure_solve_start,
                recorded_by,
                increment,
            )
        };
        record(&mut self.error, "recording the velocity solve", r);
    }

    pub(super) fn velocity_solve_records(&mut self, ids: &[u32]) -> Result<Vec<SolveRecord>, BackendError> {
        let (solves, dev) = (self.solve_records.solves, &self.dev);
        let (by, inc) = match &self.solve_records.buffers {
            Some((by, inc)) => (
                dev.download(by)
                    .map_err(|e| device_error("copying the velocity solve's records", e))?,
                dev.download(inc)
                    .map_err(|e| device_error("copying the velocity solve's records", e))?,
            ),
            None => (Vec::new(), Vec::new()),
        };
        Ok(ids
            .iter()
            .map(|&id| {
                std::array::from_fn(|slot| {
                    let k = id as usize * VELOCITY_SOLVE_SLOTS + slot;
                    (solves[slot] != 0 && by.get(k) == Some(&solves[slot])).then(|| inc[k])
                })
            })
            .collect())
    }

    pub(super) fn restore_velocity_solve_records(
        &mut self,
        ids: &[u32],
        records: &[SolveRecord],
    ) -> Result<(), BackendError> {
        self.solve_records = VelocitySolveRecords::default();
        if records.iter().all(|r| r.iter().all(Option::is_none)) {
            return Ok(());
        }
        let bound = ids
            .iter()
            .map(|&k| k as usize + 1)
            .max()
            .unwrap_or(0)
            .max(self.id_bound);
        let len = (bound * VELOCITY_SOLVE_SLOTS).max(1);
        let (mut by, mut inc) = (vec![0u32; len], vec![0.0f32; len]);
        for (&id, record) in ids.iter().zip(records) {
            for (slot, value) in record.iter().enumerate() {
                if let Some(v) = value {
                    let k = id as usize * VELOCITY_SOLVE_SLOTS + slot;
                    by[k] = 1;
                    inc[k] = *v;
                }
            }
        }
        let up = |e| device_error("uploading the velocity solve's records", e);
        let buffers = (
            self.dev.upload(&by).map_err(up)?,
            self.dev.upload(&inc).map_err(up)?,
        );
        self.solve_records = VelocitySolveRecords {
            solves: [1; VELOCITY_SOLVE_SLOTS],
            buffers: Some(buffers),
        };
        Ok(())
    }

    /// Makes the records hold `id_bound` ids, keeping those held; `false` after a failure.
    fn ensure_records(&mut self) -> bool {
        let len = (self.id_bound * VELOCITY_SOLVE_SLOTS).max(1);
        if self.error.is_some() {
            return false;
        }
        if self
            .solve_records
            .buffers
            .as_ref()
            .is_some_and(|(by, _)| by.len() >= len)
        {
            return true;
        }
        let dev = &self.dev;
        let old = self.solve_records.buffers.take();
        let r = (|| -> Result<RecordBuffers<K>, DeviceFault> {
            let (mut by, mut inc) = (dev.alloc_zeros::<u32>(len)?, dev.alloc_zeros::<f32>(len)?);
            if let Some((old_by, old_inc)) = &old {
                dev.copy(old_by, &mut by)?;
                dev.copy(old_inc, &mut inc)?;
            }
            Ok((by, inc))
        })();
        self.solve_records.buffers = record(&mut self.error, "allocating the velocity solve's records", r);
        self.solve_records.buffers.is_some()
    }
}
