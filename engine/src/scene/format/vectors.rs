//! Checked vectors: a point or velocity `(x, y, z)` of finite coordinates,
//! and a direction that can be normalised, refused while read otherwise.

use serde::de::{self, Deserializer};
use serde::{Deserialize, Serialize};

/// A vector `(x, y, z)` of finite numbers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Vector(pub [f32; 3]);

impl<'de> Deserialize<'de> for Vector {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = <[f32; 3]>::deserialize(d)?;
        if let Some(bad) = v.iter().position(|c| !c.is_finite()) {
            return Err(de::Error::custom(format_args!(
                "expected finite coordinates, got {} for {}",
                v[bad],
                ["x", "y", "z"][bad]
            )));
        }
        Ok(Self(v))
    }
}

impl From<Vector> for glam::Vec3 {
    fn from(v: Vector) -> Self {
        glam::Vec3::from_array(v.0)
    }
}

/// A direction: a vector of finite coordinates whose length is neither zero
/// nor overflows (`(3e38, 3e38, 0)` has an infinite length), so it can be
/// normalised.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Direction(pub [f32; 3]);

impl<'de> Deserialize<'de> for Direction {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let Vector(v) = Vector::deserialize(d)?;
        if glam::Vec3::from_array(v).try_normalize().is_none() {
            return Err(de::Error::custom(format_args!(
                "expected a direction of non-zero, finite length, got {v:?}"
            )));
        }
        Ok(Self(v))
    }
}

impl From<Direction> for glam::Vec3 {
    fn from(v: Direction) -> Self {
        glam::Vec3::from_array(v.0)
    }
}

pub(super) fn origin() -> Vector {
    Vector([0.0; 3])
}
