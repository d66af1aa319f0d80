//! VTK's scalar data types, as named in the `type` attribute of a `DataArray`.

/// A VTK scalar data type, as named in the `type` attribute of a `DataArray`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VtkType {
    /// `Int8`
    Int8,
    /// `UInt8`
    UInt8,
    /// `Int16`
    Int16,
    /// `UInt16`
    UInt16,
    /// `Int32`
    Int32,
    /// `UInt32`
    UInt32,
    /// `Int64`
    Int64,
    /// `UInt64`
    UInt64,
    /// `Float32`
    Float32,
    /// `Float64`
    Float64,
}

impl VtkType {
    /// Size of one value in bytes.
    pub fn size(self) -> usize {
        match self {
            VtkType::Int8 | VtkType::UInt8 => 1,
            VtkType::Int16 | VtkType::UInt16 => 2,
            VtkType::Int32 | VtkType::UInt32 | VtkType::Float32 => 4,
            VtkType::Int64 | VtkType::UInt64 | VtkType::Float64 => 8,
        }
    }

    /// The VTK name of the type (`"Float32"`, ...).
    pub fn name(self) -> &'static str {
        match self {
            VtkType::Int8 => "Int8",
            VtkType::UInt8 => "UInt8",
            VtkType::Int16 => "Int16",
            VtkType::UInt16 => "UInt16",
            VtkType::Int32 => "Int32",
            VtkType::UInt32 => "UInt32",
            VtkType::Int64 => "Int64",
            VtkType::UInt64 => "UInt64",
            VtkType::Float32 => "Float32",
            VtkType::Float64 => "Float64",
        }
    }

    /// Parses a VTK type name (also accepts the legacy lower-case C names).
    pub fn parse(s: &str) -> Option<VtkType> {
        Some(match s {
            "Int8" | "char" => VtkType::Int8,
            "UInt8" | "unsigned_char" => VtkType::UInt8,
            "Int16" | "short" => VtkType::Int16,
            "UInt16" | "unsigned_short" => VtkType::UInt16,
            "Int32" | "int" => VtkType::Int32,
            "UInt32" | "unsigned_int" => VtkType::UInt32,
            "Int64" | "long" | "long_long" => VtkType::Int64,
            "UInt64" | "unsigned_long" | "unsigned_long_long" => VtkType::UInt64,
            "Float32" | "float" => VtkType::Float32,
            "Float64" | "double" => VtkType::Float64,
            _ => return None,
        })
    }

    /// Decodes little-endian values (length must be a multiple of
    /// [`size`](Self::size)) to `f64`. Exact for every type except 64-bit
    /// integers beyond 2^53.
    pub(crate) fn decode_le(self, bytes: &[u8]) -> Vec<f64> {
        fn conv<const N: usize>(bytes: &[u8], f: impl Fn([u8; N]) -> f64) -> Vec<f64> {
            bytes
                .chunks_exact(N)
                .map(|c| {
                    let mut a = [0u8; N];
                    a.copy_from_slice(c);
                    f(a)
                })
                .collect()
        }
        match self {
            VtkType::Int8 => conv(bytes, |a: [u8; 1]| f64::from(i8::from_le_bytes(a))),
            VtkType::UInt8 => conv(bytes, |a: [u8; 1]| f64::from(a[0])),
            VtkType::Int16 => conv(bytes, |a| f64::from(i16::from_le_bytes(a))),
            VtkType::UInt16 => conv(bytes, |a| f64::from(u16::from_le_bytes(a))),
            VtkType::Int32 => conv(bytes, |a| f64::from(i32::from_le_bytes(a))),
            VtkType::UInt32 => conv(bytes, |a| f64::from(u32::from_le_bytes(a))),
            VtkType::Int64 => conv(bytes, |a| i64::from_le_bytes(a) as f64),
            VtkType::UInt64 => conv(bytes, |a| u64::from_le_bytes(a) as f64),
            VtkType::Float32 => conv(bytes, |a| f64::from(f32::from_le_bytes(a))),
            VtkType::Float64 => conv(bytes, f64::from_le_bytes),
        }
    }
}
