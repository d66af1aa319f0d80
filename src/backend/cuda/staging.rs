//! A rank's particles staged through the host (`distributed::RankBackend`, docs/distributed.md):
//! chosen fields copied out, the step-start copies included, and written back in place after
//! the host changed the ghosts' rows; and the owned mask of a split run's reductions
//! (`backend::partition`) uploaded.

use super::*;
use crate::backend::cuda::launch::Element;

/// A vector field of the host, `n` long, from a device buffer of at least `n·D` floats.
fn vectors_from<const D: usize, K: Memory>(
    dev: &K,
    buf: &K::Buf<f32>,
    n: usize,
    out: &mut Vec<Vector<D>>,
) -> Result<(), DeviceFault> {
    let flat = dev.download(buf)?;
    if flat.len() < n * D {
        return Err(DeviceFault(format!("{} floats for {n} vectors", flat.len())));
    }
    out.clear();
    out.extend(flat[..n * D].chunks_exact(D).map(Vector::<D>::from_column_slice));
    Ok(())
}

/// A scalar field of the host, `n` long, from a device buffer of at least `n` items.
fn scalars_from<T: Element, K: Memory>(
    dev: &K,
    buf: &K::Buf<T>,
    n: usize,
    out: &mut Vec<T>,
) -> Result<(), DeviceFault> {
    let mut all = dev.download(buf)?;
    if all.len() < n {
        return Err(DeviceFault(format!("{} items for {n} particles", all.len())));
    }
    all.truncate(n);
    *out = all;
    Ok(())
}

/// [`vectors_from`] a buffer the device may not hold (the host's field then cleared).
fn optional_vectors_from<const D: usize, K: Memory>(
    dev: &K,
    buf: Option<&K::Buf<f32>>,
    n: usize,
    out: &mut Vec<Vector<D>>,
) -> Result<(), DeviceFault> {
    match buf {
        Some(b) => vectors_from(dev, b, n, out),
        None => {
            out.clear();
            Ok(())
        }
    }
}

/// [`scalars_from`] a buffer the device may not hold (the host's field then cleared).
fn optional_scalars_from<K: Memory>(
    dev: &K,
    buf: Option<&K::Buf<f32>>,
    n: usize,
    out: &mut Vec<f32>,
) -> Result<(), DeviceFault> {
    match buf {
        Some(b) => scalars_from(dev, b, n, out),
        None => {
            out.clear();
            Ok(())
        }
    }
}

/// Writes the host's `n`-long `src` into the start of `dst` (a buffer made at the particle
/// count); a host field of another length is an error, not a partial copy.
fn write_into<T: Element, K: Memory>(
    dev: &K,
    src: &[T],
    items: usize,
    dst: &mut K::Buf<T>,
) -> Result<(), DeviceFault> {
    if src.len() != items {
        return Err(DeviceFault(format!(
            "{} host items for {items} on the device",
            src.len()
        )));
    }
    dev.write(src, dst)
}

impl<const D: usize, K: Launch<D>> CudaBackend<D, K> {
    /// `Backend::download_some`: the fields `which` into `fields`, cut to the particle count;
    /// a field the device does not hold is cleared on the host (kept for the rest densities and
    /// the acting pressure, as `download_fields` does).
    pub(super) fn download_chosen(
        &mut self,
        fields: &mut Fields<D>,
        which: &[Field],
    ) -> Result<(), BackendError> {
        let (n, dev) = (self.n, &self.dev);
        let e = |x: DeviceFault| device_error("copying fields to the host for the ranks", x);
        for field in which {
            match field {
                Field::Position => vectors_from(dev, &self.f.position, n, &mut fields.position),
                Field::Velocity => vectors_from(dev, &self.f.velocity, n, &mut fields.velocity),
                Field::Acceleration => vectors_from(dev, &self.f.acceleration, n, &mut fields.acceleration),
                Field::PositionStart => {
                    vectors_from(dev, &self.f.position_start, n, &mut fields.position_start)
                }
                Field::VelocityStart => {
                    vectors_from(dev, &self.f.velocity_start, n, &mut fields.velocity_start)
                }
                Field::Density => scalars_from(dev, &self.f.density, n, &mut fields.density),
                Field::Pressure => scalars_from(dev, &self.f.pressure, n, &mut fields.pressure),
                Field::Mass => scalars_from(dev, &self.f.mass, n, &mut fields.mass),
                Field::Kind => scalars_from(dev, &self.f.kind, n, &mut fields.kind),
                Field::Id => scalars_from(dev, &self.f.id, n, &mut fields.id),
                Field::WallVelocity => {
                    optional_vectors_from(dev, self.f.wall_velocity.as_ref(), n, &mut fields.wall_velocity)
                }
                Field::Normal => optional_vectors_from(dev, self.normal.as_ref(), n, &mut fields.normal),
                Field::DensityRate => {
                    optional_scalars_from(dev, self.density_rate.as_ref(), n, &mut fields.density_rate)
                }
                Field::DensityStart => {
                    optional_scalars_from(dev, self.density_start.as_ref(), n, &mut fields.density_start)
                }
                Field::RestDensity => match &self.f.rest_density {
                    Some(b) => scalars_from(dev, b, n, &mut fields.rest_density),
                    None => Ok(()),
                },
                Field::ActingPressure => match &self.f.acting_pressure {
                    Some(b) => scalars_from(dev, b, n, &mut fields.acting_pressure),
                    None => Ok(()),
                },
            }
            .map_err(e)?;
        }
        Ok(())
    }

    /// `Backend::upload_some`: the fields `which` of `fields` (as many particles, same order)
    /// written over the device's; a field the device does not hold yet is made from the host's
    /// where the host has one.
    pub(super) fn upload_chosen(&mut self, fields: &Fields<D>, which: &[Field]) -> Result<(), BackendError> {
        if fields.len() != self.n {
            return Err(device_error(
                "writing the ranks' fields to the device",
                DeviceFault(format!(
                    "{} host particles for {} on the device",
                    fields.len(),
                    self.n
                )),
            ));
        }
        let (n, nd) = (self.n, self.n * D);
        let e = |x: DeviceFault| device_error("writing the ranks' fields to the device", x);
        let dev = &self.dev;
        // An optional buffer: written over, or made where only the host has the field.
        let optional =
            |buf: &mut Option<K::Buf<f32>>, host: &[f32], items: usize| -> Result<(), DeviceFault> {
                match buf {
                    Some(b) => write_into(dev, host, items, b),
                    None if !host.is_empty() && host.len() == items => {
                        *buf = Some(dev.upload(host)?);
                        Ok(())
                    }
                    None => Ok(()),
                }
            };
        for field in which {
            match field {
                Field::Position => write_into(dev, floats(&fields.position), nd, &mut self.f.position),
                Field::Velocity => write_into(dev, floats(&fields.velocity), nd, &mut self.f.velocity),
                Field::Acceleration => {
                    write_into(dev, floats(&fields.acceleration), nd, &mut self.f.acceleration)
                }
                Field::PositionStart => write_into(
                    dev,
                    floats(&fields.position_start),
                    nd,
                    &mut self.f.position_start,
                ),
                Field::VelocityStart => write_into(
                    dev,
                    floats(&fields.velocity_start),
                    nd,
                    &mut self.f.velocity_start,
                ),
                Field::Density => write_into(dev, &fields.density, n, &mut self.f.density),
                Field::Pressure => write_into(dev, &fields.pressure, n, &mut self.f.pressure),
                Field::Mass => write_into(dev, &fields.mass, n, &mut self.f.mass),
                Field::Kind => write_into(dev, &fields.kind, n, &mut self.f.kind),
                Field::Id => write_into(dev, &fields.id, n, &mut self.f.id),
                Field::WallVelocity => optional(&mut self.f.wall_velocity, floats(&fields.wall_velocity), nd),
                Field::Normal => optional(&mut self.normal, floats(&fields.normal), nd),
                Field::DensityRate => optional(&mut self.density_rate, &fields.density_rate, n),
                Field::DensityStart => optional(&mut self.density_start, &fields.density_start, n),
                Field::RestDensity => optional(&mut self.f.rest_density, &fields.rest_density, n),
                Field::ActingPressure => optional(&mut self.f.acting_pressure, &fields.acting_pressure, n),
            }
            .map_err(e)?;
        }
        Ok(())
    }

    /// Uploads the partition's mask (`owned`) for the current particle count: 1 where the
    /// partition counts the particle.
    pub(super) fn upload_owned(&mut self) -> Result<(), BackendError> {
        let mask: Vec<u32> = (0..self.n.max(1))
            .map(|i| u32::from(self.partition.counts(i)))
            .collect();
        self.owned = self
            .dev
            .upload(&mask)
            .map_err(|e| device_error("uploading the owned particles", e))?;
        Ok(())
    }
}
