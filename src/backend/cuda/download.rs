//! `Backend::download` on the device: every field the host keeps, copied into `Fields` and
//! cut to the particle count (device buffers may be longer); the step-start copies stay on the
//! device.

use super::*;

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    /// Copies every field the host keeps into `fields` (module doc).
    pub(super) fn download_fields(&mut self, fields: &mut Fields<D>) -> Result<(), BackendError> {
        let n = self.n;
        let s = &self.dev;
        let e = |x: DeviceFault| device_error("copying the fields to the host", x);
        fields.position.resize(n, Vector::zeros());
        fields.velocity.resize(n, Vector::zeros());
        fields.acceleration.resize(n, Vector::zeros());
        s.download_into(&self.f.position, floats_mut(&mut fields.position))
            .map_err(e)?;
        s.download_into(&self.f.velocity, floats_mut(&mut fields.velocity))
            .map_err(e)?;
        s.download_into(&self.f.acceleration, floats_mut(&mut fields.acceleration))
            .map_err(e)?;
        fields.density = s.download(&self.f.density).map_err(e)?;
        fields.pressure = s.download(&self.f.pressure).map_err(e)?;
        fields.mass = s.download(&self.f.mass).map_err(e)?;
        fields.kind = s.download(&self.f.kind).map_err(e)?;
        fields.id = s.download(&self.f.id).map_err(e)?;
        for v in [&mut fields.density, &mut fields.pressure, &mut fields.mass] {
            v.truncate(n);
        }
        fields.kind.truncate(n);
        fields.id.truncate(n);
        match &self.f.wall_velocity {
            Some(b) => {
                fields.wall_velocity.resize(n, Vector::zeros());
                s.download_into(b, floats_mut(&mut fields.wall_velocity))
                    .map_err(e)?;
            }
            None => fields.wall_velocity.clear(),
        }
        if let Some(rest) = &self.f.rest_density {
            fields.rest_density = s.download(rest).map_err(e)?;
            fields.rest_density.truncate(n);
        }
        if let Some(acting) = &self.f.acting_pressure {
            fields.acting_pressure = s.download(acting).map_err(e)?;
            fields.acting_pressure.truncate(n);
        }
        // The step-start copies are the backend's scratch of SSP-RK3; the host keeps none.
        fields.position_start.clear();
        fields.velocity_start.clear();
        fields.density_start.clear();
        match &self.density_rate {
            Some(rate) => {
                fields.density_rate = s.download(rate).map_err(e)?;
                fields.density_rate.truncate(n);
            }
            None => fields.density_rate.clear(),
        }
        match &self.normal {
            Some(normal) => {
                fields.normal.resize(n, Vector::zeros());
                s.download_into(normal, floats_mut(&mut fields.normal))
                    .map_err(e)?;
            }
            None => fields.normal.clear(),
        }
        Ok(())
    }
}
