//! The shape keys of `[[solid]]` and `[[fluid_box]]` as read: the shape's name, and the
//! `rotation`/`scale` and cylinder `axis` values that take a number, an array or a name.

use serde::Deserialize;

/// Shape of a `[[solid]]` body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolidShape {
    /// A box `[min, max]` filled with solid particles.
    Box,
    /// Walls of `L` particle layers around the inside box `[min, max]`;
    /// open at the top (last axis) unless `open_top = false`.
    Container,
    /// A filled cylinder: 2D a disc (`centre`, `radius`), 3D also `length` and `axis`.
    Cylinder,
    /// A filled ball (2D: a disc) of `radius` about `centre`.
    Sphere,
    /// The inside of a closed triangle mesh read from `file` (STL or OBJ; 3D only), placed by
    /// `scale`, `rotation` and `translation`.
    Mesh,
}

impl SolidShape {
    /// The name used in scene files (`"box"`).
    pub fn name(self) -> &'static str {
        match self {
            SolidShape::Box => "box",
            SolidShape::Container => "container",
            SolidShape::Cylinder => "cylinder",
            SolidShape::Sphere => "sphere",
            SolidShape::Mesh => "mesh",
        }
    }
}

/// A number or an array of numbers (`rotation`, `scale`).
#[derive(Debug, Clone, PartialEq)]
pub enum NumberOrVector {
    /// One number.
    Number(f64),
    /// An array of numbers.
    Vector(Vec<f64>),
}

impl<'de> Deserialize<'de> for NumberOrVector {
    /// A number or an array of numbers; anything else is an error saying so.
    fn deserialize<De: serde::Deserializer<'de>>(deserializer: De) -> Result<Self, De::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = NumberOrVector;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number or an array of numbers")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Self::Value, E> {
                Ok(NumberOrVector::Number(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Self::Value, E> {
                Ok(NumberOrVector::Number(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Self::Value, E> {
                Ok(NumberOrVector::Number(v as f64))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> Result<Self::Value, A::Error> {
                Vec::<f64>::deserialize(serde::de::value::SeqAccessDeserializer::new(seq))
                    .map(NumberOrVector::Vector)
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// A cylinder's `axis`: a named axis or a direction vector.
#[derive(Debug, Clone, PartialEq)]
pub enum AxisFile {
    /// `"x"`, `"y"` or `"z"` (unchecked here).
    Named(String),
    /// A direction, 3 entries (unchecked here).
    Vector(Vec<f64>),
}

impl<'de> Deserialize<'de> for AxisFile {
    /// A string or an array of numbers; anything else is an error saying so.
    fn deserialize<De: serde::Deserializer<'de>>(deserializer: De) -> Result<Self, De::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = AxisFile;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("\"x\", \"y\", \"z\" or an array of 3 numbers")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Self::Value, E> {
                Ok(AxisFile::Named(v.to_string()))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> Result<Self::Value, A::Error> {
                Vec::<f64>::deserialize(serde::de::value::SeqAccessDeserializer::new(seq))
                    .map(AxisFile::Vector)
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}
