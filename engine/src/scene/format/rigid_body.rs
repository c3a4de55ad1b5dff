//! A rigid body of the scene: a particle with an orientation, a spin and
//! the half extents of a solid box, whose inertia is checked once read.

use serde::de::{self, Deserializer};
use serde::{Deserialize, Serialize};

use super::check_item::CheckItem;
use super::particle::ParticleSpec;
use super::vectors::{Vector, origin};
use crate::clock::Number;

/// A rigid body.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidBodySpec {
    /// Centre of mass.
    pub particle: ParticleSpec,
    /// Quaternion `(x, y, z, w)`, of non-zero, finite length; normalised on
    /// load (default: identity).
    #[serde(default = "identity")]
    pub orientation: Orientation,
    /// rad/s, world frame (default: zero).
    #[serde(default = "origin")]
    pub angular_velocity: Vector,
    /// Half extents of a solid box, m, none negative and at most one zero; the
    /// inertia follows from them and the mass (checked: above zero, finite
    /// and of finite inverse on every axis).
    pub half_extents: Vector,
}

fn identity() -> Orientation {
    Orientation([0.0, 0.0, 0.0, 1.0])
}

/// A rotation quaternion `(x, y, z, w)`: finite, of a length that can be
/// normalised (`(0, 0, 0, 0)` is no rotation at all).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Orientation(pub [f32; 4]);

impl<'de> Deserialize<'de> for Orientation {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let (x, y, z, w) = <(f32, f32, f32, f32)>::deserialize(d)?;
        let q = glam::Vec4::new(x, y, z, w);
        let length = q.length();
        if !q.is_finite() || !length.is_finite() || length < 1e-6 {
            return Err(de::Error::custom(format_args!(
                "expected a quaternion (x, y, z, w) of finite coordinates and non-zero, finite length, \
                 got ({x}, {y}, {z}, {w})"
            )));
        }
        Ok(Self([x, y, z, w]))
    }
}

impl CheckItem for RigidBodySpec {
    fn check(&self) -> Result<(), String> {
        let h = self.half_extents.0;
        let [x, y, z] = h.map(Number::from);
        if let Some(axis) = h.iter().position(|&c| c < 0.0) {
            return Err(format!(
                "half_extents.{} = {}: expected half extents that are not negative",
                ["x", "y", "z"][axis],
                Number::from(h[axis])
            ));
        }
        // The same check as `World::spawn_rigid`, here so that it has a position.
        let mass = self.particle.mass.0;
        let body = crate::world::RigidBody::solid_box(mass, glam::Vec3::from_array(h));
        body.validate().map_err(|e| match e {
            crate::world::SpawnError::Invalid { field, value, .. } if field.starts_with("inertia") => format!(
                "half_extents ({x}, {y}, {z}) and mass {} give the moment of inertia {field} = {}: expected \
                 one above zero and finite, whose inverse is finite (at most one half extent may be zero)",
                Number::from(mass),
                Number::from(value)
            ),
            _ => e.to_string(),
        })
    }
}
