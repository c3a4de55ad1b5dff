//! The scene's colliders (planes, boxes, particle-particle collisions),
//! their material and when planes and boxes find their contacts; a box's
//! corners are checked against each other once the collider is read.

use serde::{Deserialize, Serialize};

use super::check_item::CheckItem;
use super::numbers::{Finite, NonNegative, Unit, zero};
use super::vectors::{Direction, Vector};
use crate::clock::Number;
use crate::colliders::ContactRule;

/// Bounce and friction (defaults: restitution 0.5, friction 0).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// In `[0, 1]` (default: `0.5`).
    #[serde(default = "half")]
    pub restitution: Unit,
    /// Coulomb coefficient (default: `0.0`).
    #[serde(default = "zero")]
    pub friction: NonNegative,
}

impl Default for MaterialSpec {
    fn default() -> Self {
        Self {
            restitution: half(),
            friction: zero(),
        }
    }
}

fn half() -> Unit {
    Unit(0.5)
}

/// When a plane or a box finds its contacts (default: `InStep`): the
/// scene's [`ContactRule`]. Any other word is an error naming the two.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ContactSpec {
    /// At the end of the step: a particle found inside is moved back to
    /// the surface ([`ContactRule::EndOfStep`]). An elastic bounce gains
    /// the depth it was found at; a fast particle can pass a thin wall.
    EndOfStep,
    /// Inside the step (default), where the step's path meets the surface
    /// ([`ContactRule::InStep`]): no tunnelling, and an elastic bounce
    /// keeps its height.
    #[default]
    InStep,
}

impl From<ContactSpec> for ContactRule {
    fn from(spec: ContactSpec) -> Self {
        match spec {
            ContactSpec::EndOfStep => Self::EndOfStep,
            ContactSpec::InStep => Self::InStep,
        }
    }
}

/// A collider. A misspelt field in any variant is an error.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ColliderSpec {
    /// An infinite plane `normal . x >= offset`.
    Plane {
        /// Normal into the free side (normalised on load).
        normal: Direction,
        /// Offset along the normal, finite (default: 0).
        #[serde(default = "zero_offset")]
        offset: Finite,
        /// Material (default: restitution 0.5, no friction).
        #[serde(default)]
        material: MaterialSpec,
        /// When contacts are found, `InStep` or `EndOfStep` (default: `InStep`).
        #[serde(default)]
        contact: ContactSpec,
    },
    /// An axis-aligned box.
    Box {
        /// Lower corner.
        min: Vector,
        /// Upper corner.
        max: Vector,
        /// Keep particles inside (true) or outside (default: true).
        #[serde(default = "yes")]
        inside: bool,
        /// Material.
        #[serde(default)]
        material: MaterialSpec,
        /// When contacts are found, `InStep` or `EndOfStep` (default: `InStep`).
        #[serde(default)]
        contact: ContactSpec,
    },
    /// Particle-particle collisions.
    Spheres {
        /// Material.
        #[serde(default)]
        material: MaterialSpec,
        /// Swept tests for fast spheres (default `false`; see
        /// [`SphereCollisions::swept`](crate::SphereCollisions::swept)).
        #[serde(default)]
        swept: bool,
    },
}

fn yes() -> bool {
    true
}

fn zero_offset() -> Finite {
    Finite(0.0)
}

impl CheckItem for ColliderSpec {
    fn check(&self) -> Result<(), String> {
        let Self::Box { min, max, .. } = self else {
            return Ok(());
        };
        for (axis, name) in ["x", "y", "z"].into_iter().enumerate() {
            let (lo, hi) = (Number::from(min.0[axis]), Number::from(max.0[axis]));
            if min.0[axis] >= max.0[axis] {
                return Err(format!(
                    "Box.max.{name} = {hi} is not above Box.min.{name} = {lo}: a box's max corner must be \
                     above its min corner on every axis (swap them if they are inverted)"
                ));
            }
            if !(max.0[axis] - min.0[axis]).is_finite() {
                return Err(format!(
                    "Box from min.{name} = {lo} to max.{name} = {hi}: expected a width that is a finite number"
                ));
            }
        }
        Ok(())
    }
}
