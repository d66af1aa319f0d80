//! Particles in transit between ranks: every allocated field of a subset of [`Fields`], bit for
//! bit, in one byte buffer (what MPI moves), and appended back on the receiving side.
//!
//! Layout (little-endian): the count (u64), the mask of allocated fields (u32, bit `k` for
//! `Field::ALL[k]`), then each allocated field's values for all the particles, in
//! `Field::ALL`'s order. A receiver whose own fields differ in the mask refuses the packet: both
//! sides run one plan, so a mismatch is a defect, not input.

use super::error::DistributedError;
use crate::fields::{Field, Fields};
use crate::math::{Real, Vector};

/// The mask of the fields `fields` holds (bit `k`: `Field::ALL[k]`). With no particles every
/// optional field reads as absent, so an empty rank sends the mandatory ones only and
/// [`append`] takes its mask from the packet.
pub fn field_mask<const D: usize>(fields: &Fields<D>) -> u32 {
    Field::ALL
        .iter()
        .enumerate()
        .filter(|(_, f)| fields.is_allocated(**f))
        .fold(0, |mask, (k, _)| mask | (1 << k))
}

/// The particles `indices` of `fields`, packed.
pub fn pack<const D: usize>(fields: &Fields<D>, indices: &[u32]) -> Vec<u8> {
    pack_fields(fields, indices, field_mask(fields))
}

/// The fields in `mask` (allocated ones, bit `k`: `Field::ALL[k]`) of the particles `indices`
/// of `fields`, packed: what a ghost refresh sends.
pub fn pack_fields<const D: usize>(fields: &Fields<D>, indices: &[u32], mask: u32) -> Vec<u8> {
    let mask = mask & field_mask(fields);
    let mut out = Vec::with_capacity(12 + indices.len() * 4 * (6 * D + 10));
    out.extend_from_slice(&(indices.len() as u64).to_le_bytes());
    out.extend_from_slice(&mask.to_le_bytes());
    for (k, field) in Field::ALL.iter().enumerate() {
        if mask & (1 << k) == 0 {
            continue;
        }
        match column(fields, *field) {
            Column::Vector(v) => indices.iter().for_each(|&i| {
                v[i as usize]
                    .iter()
                    .for_each(|c| out.extend_from_slice(&c.to_le_bytes()))
            }),
            Column::Real(v) => indices
                .iter()
                .for_each(|&i| out.extend_from_slice(&v[i as usize].to_le_bytes())),
            Column::Index(v) => indices
                .iter()
                .for_each(|&i| out.extend_from_slice(&v[i as usize].to_le_bytes())),
        }
    }
    out
}

/// Appends the particles of `packet` to `fields`; returns how many. An empty `fields` takes the
/// packet's optional fields; otherwise the masks must agree (an empty packet agrees with any).
pub fn append<const D: usize>(fields: &mut Fields<D>, packet: &[u8]) -> Result<usize, DistributedError> {
    let mut reader = Reader { bytes: packet, at: 0 };
    let count = reader.u64()? as usize;
    let mask = reader.u32()?;
    if count == 0 {
        return Ok(0);
    }
    let n = fields.len();
    if n > 0 && field_mask(fields) != mask {
        return Err(DistributedError::FieldMismatch {
            ours: field_mask(fields),
            theirs: mask,
        });
    }
    // Checked before anything is appended, so that a bad packet leaves `fields` as it was.
    match packet.len().cmp(&(12 + 4 * words(fields, mask) * count)) {
        std::cmp::Ordering::Less => {
            return Err(DistributedError::Malformed {
                reason: "the packet ends inside a field",
            });
        }
        std::cmp::Ordering::Greater => {
            return Err(DistributedError::Malformed {
                reason: "bytes after the last field",
            });
        }
        std::cmp::Ordering::Equal => {}
    }
    for (k, field) in Field::ALL.iter().enumerate() {
        if mask & (1 << k) == 0 {
            continue;
        }
        match column_mut(fields, *field) {
            ColumnMut::Vector(v) => {
                for _ in 0..count {
                    let mut x = Vector::<D>::zeros();
                    for c in 0..D {
                        x[c] = Real::from_bits(reader.u32()?);
                    }
                    v.push(x);
                }
            }
            ColumnMut::Real(v) => {
                for _ in 0..count {
                    v.push(Real::from_bits(reader.u32()?));
                }
            }
            ColumnMut::Index(v) => {
                for _ in 0..count {
                    v.push(reader.u32()?);
                }
            }
        }
    }
    debug_assert_eq!(reader.at, packet.len());
    Ok(count)
}

/// Overwrites the particles `indices` of `fields` with the packet's particles, in order (a
/// ghost refresh: the owner's current values of particles this rank already holds). The packet
/// must hold exactly `indices.len()` particles, and fields this rank holds; it is checked whole
/// before anything is written.
pub fn scatter<const D: usize>(
    fields: &mut Fields<D>,
    packet: &[u8],
    indices: &[u32],
) -> Result<(), DistributedError> {
    let mut reader = Reader { bytes: packet, at: 0 };
    let count = reader.u64()? as usize;
    let mask = reader.u32()?;
    if count != indices.len() {
        return Err(DistributedError::Malformed {
            reason: "a refresh holds another number of particles than the ghosts it is for",
        });
    }
    if count == 0 {
        return Ok(());
    }
    if mask & !field_mask(fields) != 0 {
        return Err(DistributedError::FieldMismatch {
            ours: field_mask(fields),
            theirs: mask,
        });
    }
    if packet.len() != 12 + 4 * words(fields, mask) * count {
        return Err(DistributedError::Malformed {
            reason: "a refresh's length does not match its fields",
        });
    }
    for (k, field) in Field::ALL.iter().enumerate() {
        if mask & (1 << k) == 0 {
            continue;
        }
        match column_mut(fields, *field) {
            ColumnMut::Vector(v) => {
                for &i in indices {
                    for c in 0..D {
                        v[i as usize][c] = Real::from_bits(reader.u32()?);
                    }
                }
            }
            ColumnMut::Real(v) => {
                for &i in indices {
                    v[i as usize] = Real::from_bits(reader.u32()?);
                }
            }
            ColumnMut::Index(v) => {
                for &i in indices {
                    v[i as usize] = reader.u32()?;
                }
            }
        }
    }
    Ok(())
}

/// 32-bit words per particle of the fields in `mask`.
fn words<const D: usize>(fields: &Fields<D>, mask: u32) -> usize {
    Field::ALL
        .iter()
        .enumerate()
        .filter(|(k, _)| mask & (1 << k) != 0)
        .map(|(_, f)| {
            if matches!(column(fields, *f), Column::Vector(_)) {
                D
            } else {
                1
            }
        })
        .sum()
}

/// One field's storage, by the type of its values.
enum Column<'a, const D: usize> {
    Vector(&'a [Vector<D>]),
    Real(&'a [Real]),
    Index(&'a [u32]),
}

enum ColumnMut<'a, const D: usize> {
    Vector(&'a mut Vec<Vector<D>>),
    Real(&'a mut Vec<Real>),
    Index(&'a mut Vec<u32>),
}

fn column<const D: usize>(f: &Fields<D>, field: Field) -> Column<'_, D> {
    match field {
        Field::Position => Column::Vector(&f.position),
        Field::Velocity => Column::Vector(&f.velocity),
        Field::Acceleration => Column::Vector(&f.acceleration),
        Field::Density => Column::Real(&f.density),
        Field::Pressure => Column::Real(&f.pressure),
        Field::Mass => Column::Real(&f.mass),
        Field::Kind => Column::Index(&f.kind),
        Field::Id => Column::Index(&f.id),
        Field::PositionStart => Column::Vector(&f.position_start),
        Field::VelocityStart => Column::Vector(&f.velocity_start),
        Field::WallVelocity => Column::Vector(&f.wall_velocity),
        Field::Normal => Column::Vector(&f.normal),
        Field::RestDensity => Column::Real(&f.rest_density),
        Field::DensityRate => Column::Real(&f.density_rate),
        Field::DensityStart => Column::Real(&f.density_start),
        Field::ActingPressure => Column::Real(&f.acting_pressure),
    }
}

fn column_mut<const D: usize>(f: &mut Fields<D>, field: Field) -> ColumnMut<'_, D> {
    match field {
        Field::Position => ColumnMut::Vector(&mut f.position),
        Field::Velocity => ColumnMut::Vector(&mut f.velocity),
        Field::Acceleration => ColumnMut::Vector(&mut f.acceleration),
        Field::Density => ColumnMut::Real(&mut f.density),
        Field::Pressure => ColumnMut::Real(&mut f.pressure),
        Field::Mass => ColumnMut::Real(&mut f.mass),
        Field::Kind => ColumnMut::Index(&mut f.kind),
        Field::Id => ColumnMut::Index(&mut f.id),
        Field::PositionStart => ColumnMut::Vector(&mut f.position_start),
        Field::VelocityStart => ColumnMut::Vector(&mut f.velocity_start),
        Field::WallVelocity => ColumnMut::Vector(&mut f.wall_velocity),
        Field::Normal => ColumnMut::Vector(&mut f.normal),
        Field::RestDensity => ColumnMut::Real(&mut f.rest_density),
        Field::DensityRate => ColumnMut::Real(&mut f.density_rate),
        Field::DensityStart => ColumnMut::Real(&mut f.density_start),
        Field::ActingPressure => ColumnMut::Real(&mut f.acting_pressure),
    }
}

/// Reads little-endian words off a packet, with an error at its end.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], DistributedError> {
        let end = self.at + N;
        let word = self.bytes.get(self.at..end).ok_or(DistributedError::Malformed {
            reason: "the packet ends inside a field",
        })?;
        self.at = end;
        Ok(word.try_into().expect("N bytes"))
    }

    fn u32(&mut self) -> Result<u32, DistributedError> {
        self.take::<4>().map(u32::from_le_bytes)
    }

    fn u64(&mut self) -> Result<u64, DistributedError> {
        self.take::<8>().map(u64::from_le_bytes)
    }
}
