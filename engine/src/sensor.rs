//! Sensors: volumes that report which particles overlap them each step and
//! push nothing (trigger volumes, a pickup radius, a bullet's hit test,
//! the zone a player must reach).
//!
//! ```text
//! a particle at x of radius r overlaps
//!   a sphere (centre c, radius R)     when |x - c| < R + r
//!   a box (centre c, half extents h)  when the distance from x to the box < r
//! ```
//!
//! After each step a world lists every overlap of every sensor
//! ([`World::overlaps`](crate::World::overlaps)), ordered by sensor (in the
//! order added) and then by entity, each with its [`OverlapPhase`]: began
//! this step, still overlapping, or ended (the particle left, was removed,
//! or the sensor's entity was). A sensor may follow an entity (a ship's
//! pickup radius): its centre is then an offset from that entity's
//! position, and the entity itself is not reported.

use core::fmt;

use glam::{Vec3, Vec3A};

use crate::layout::Entity;

/// A sensor's handle, from [`World::add_sensor`](crate::World::add_sensor):
/// stable while the sensor is in its world, never reused within it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SensorId(pub(crate) u64);

impl SensorId {
    /// A handle to no sensor, for a game's fields before set-up (every
    /// lookup with it is an error naming it): also [`SensorId::default`],
    /// as [`ColliderId::PLACEHOLDER`](crate::ColliderId::PLACEHOLDER) is a
    /// collider's.
    pub const PLACEHOLDER: Self = Self(u64::MAX);
}

impl Default for SensorId {
    fn default() -> Self {
        Self::PLACEHOLDER
    }
}

impl fmt::Display for SensorId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if *self == Self::PLACEHOLDER {
            return f.write_str("SensorId::PLACEHOLDER (a handle set before any sensor was added)");
        }
        write!(f, "sensor #{}", self.0)
    }
}

/// A sensor's volume.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SensorShape {
    /// A ball of this radius, metres.
    Sphere {
        /// Radius in metres (at least 0).
        radius: f32,
    },
    /// An axis-aligned box of these half extents, metres.
    Box {
        /// Half the box's size along each axis (each at least 0).
        half_extents: Vec3,
    },
}

/// A volume that reports the particles overlapping it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sensor {
    /// Its volume.
    pub shape: SensorShape,
    /// Its centre, world space; or, when it follows an entity, the offset
    /// of its centre from that entity's position (default: the origin).
    pub centre: Vec3,
    /// The entity it moves with (default none: it stays where it is put).
    /// While that entity is despawned the sensor reports nothing.
    pub follow: Option<Entity>,
}

impl Sensor {
    /// A ball of `radius` metres centred at `centre`.
    #[must_use]
    pub fn sphere(centre: Vec3, radius: f32) -> Self {
        Self {
            shape: SensorShape::Sphere { radius },
            centre,
            follow: None,
        }
    }

    /// The axis-aligned box from `min` to `max`.
    #[must_use]
    pub fn cuboid(min: Vec3, max: Vec3) -> Self {
        Self {
            shape: SensorShape::Box {
                half_extents: (max - min) * 0.5,
            },
            centre: (min + max) * 0.5,
            follow: None,
        }
    }

    /// A ball of `radius` metres around `entity`, moving with it (the
    /// entity itself is not reported).
    #[must_use]
    pub fn around(entity: Entity, radius: f32) -> Self {
        Self {
            shape: SensorShape::Sphere { radius },
            centre: Vec3::ZERO,
            follow: Some(entity),
        }
    }

    /// Checks that every number is usable: finite, sizes at least 0.
    ///
    /// # Errors
    /// [`SensorError::Invalid`] naming the field and its value.
    pub fn validate(&self) -> Result<(), SensorError> {
        let invalid = |field: &'static str, value: f32| SensorError::Invalid { field, value };
        if let Some(bad) = self.centre.to_array().into_iter().find(|c| !c.is_finite()) {
            return Err(invalid("centre", bad));
        }
        match self.shape {
            SensorShape::Sphere { radius } if !(radius.is_finite() && radius >= 0.0) => Err(invalid("radius", radius)),
            SensorShape::Box { half_extents } => match half_extents
                .to_array()
                .into_iter()
                .find(|h| !(h.is_finite() && *h >= 0.0))
            {
                Some(bad) => Err(invalid("half_extents", bad)),
                None => Ok(()),
            },
            SensorShape::Sphere { .. } => Ok(()),
        }
    }

    /// Whether a particle at `x` of radius `r` overlaps this sensor
    /// centred at `centre`.
    #[inline]
    #[must_use]
    pub(crate) fn touches(&self, centre: Vec3A, x: Vec3A, r: f32) -> bool {
        match self.shape {
            SensorShape::Sphere { radius } => {
                let reach = radius + r;
                (x - centre).length_squared() < reach * reach
            }
            SensorShape::Box { half_extents } => {
                let outside = ((x - centre).abs() - Vec3A::from(half_extents)).max(Vec3A::ZERO);
                // Inside (r = 0 included), or nearer than the radius.
                outside == Vec3A::ZERO || outside.length_squared() < r * r
            }
        }
    }
}

/// When an overlap happened, relative to the step before.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OverlapPhase {
    /// It overlaps now and did not after the step before (it entered).
    Began,
    /// It overlapped after the step before and still does.
    Stays,
    /// It overlapped after the step before and no longer does (it left, or
    /// it or the sensor's entity was removed: its handle may be stale).
    Ended,
}

/// One sensor's overlap with one entity in the last step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Overlap {
    /// The sensor.
    pub sensor: SensorId,
    /// The entity overlapping it.
    pub entity: Entity,
    /// Whether it began, stays or ended.
    pub phase: OverlapPhase,
}

impl Overlap {
    /// The order overlaps are listed in: by sensor, then by entity.
    pub(crate) fn key(&self) -> (u64, u64) {
        (self.sensor.0, self.entity.to_bits())
    }
}

/// A sensor that cannot be added or set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SensorError {
    /// A number that is not finite, or a size below 0.
    Invalid {
        /// The field (`"centre"`, `"radius"`, `"half_extents"`).
        field: &'static str,
        /// Its value.
        value: f32,
    },
    /// A handle that names no sensor of this world.
    Unknown {
        /// The handle.
        id: SensorId,
    },
}

impl fmt::Display for SensorError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Invalid { field, value } => write!(
                f,
                "sensor {field} is {value}: a sensor's centre must be finite and its sizes finite and at least 0"
            ),
            Self::Unknown { id } => write!(f, "{id} is not in this world (removed, or another world's)"),
        }
    }
}

impl std::error::Error for SensorError {}
