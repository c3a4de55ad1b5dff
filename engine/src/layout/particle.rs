//! What a spawn describes: a [`Particle`] (position, velocity, mass,
//! radius, colour, lifetime), checked field by field, and why a spawn is
//! refused ([`SpawnError`]). Emitters make them, the world stores them.

use core::fmt;

use glam::Vec3;

/// An sRGB colour with alpha, 8 bits per channel (what the GPU reads).
pub type Colour = [u8; 4];

/// A particle to spawn. Fields state their defaults; use struct update syntax:
///
/// ```
/// # use tickwork_engine::world::Particle;
/// # use glam::Vec3;
/// let ball = Particle { position: Vec3::new(0.0, 2.0, 0.0), radius: 0.2, ..Particle::default() };
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Particle {
    /// Position in metres (default: origin).
    pub position: Vec3,
    /// Velocity in metres per second (default: zero).
    pub velocity: Vec3,
    /// Mass in kilograms, above zero (default: `1.0`). Ignored when `immovable`.
    pub mass: f32,
    /// Infinite mass: no force accelerates it and collisions do not move it;
    /// it keeps its velocity (a moving platform) (default: `false`).
    pub immovable: bool,
    /// Radius in metres for drawing and collisions, not negative (default: `0.05`).
    pub radius: f32,
    /// Colour (default: white, opaque).
    pub colour: Colour,
    /// Seconds until the particle expires, above zero; `None` lives forever (default: `None`).
    pub lifetime: Option<f32>,
}

impl Default for Particle {
    fn default() -> Self {
        Self {
            position: Vec3::ZERO,
            velocity: Vec3::ZERO,
            mass: 1.0,
            immovable: false,
            radius: 0.05,
            colour: [255, 255, 255, 255],
            lifetime: None,
        }
    }
}

/// A spawn refused: a field is invalid, or the world is full.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpawnError {
    /// A field is invalid.
    Invalid {
        /// The field at fault (`"mass"`, `"position.y"`, ...).
        field: &'static str,
        /// The value given.
        value: f32,
        /// What is required.
        expected: &'static str,
    },
    /// The world already holds (or has queued) as many particles as
    /// [`WorldConfig::max_particles`](crate::world::WorldConfig) allows.
    ParticleLimit {
        /// The limit in force.
        limit: usize,
    },
}

impl SpawnError {
    /// An invalid field.
    #[must_use]
    pub const fn invalid(field: &'static str, value: f32, expected: &'static str) -> Self {
        Self::Invalid { field, value, expected }
    }

    /// The field at fault, for [`Invalid`](Self::Invalid) (`None` for a limit).
    #[must_use]
    pub const fn field(&self) -> Option<&'static str> {
        match self {
            Self::Invalid { field, .. } => Some(field),
            Self::ParticleLimit { .. } => None,
        }
    }
}

impl fmt::Display for SpawnError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Invalid { field, value, expected } => {
                let value = crate::clock::Number::from(*value);
                write!(f, "invalid particle {field}: {value} (expected {expected})")
            }
            Self::ParticleLimit { limit } => write!(
                f,
                "the world already holds its limit of {limit} particles (WorldConfig::max_particles); \
                 despawn some or raise the limit"
            ),
        }
    }
}

impl std::error::Error for SpawnError {}

impl Particle {
    /// Checks every field; the first invalid one is the error.
    ///
    /// # Errors
    /// [`SpawnError`] naming the field: NaN or infinite coordinates, a mass
    /// that is not finite and above zero (unless `immovable`), a negative or
    /// non-finite radius, a lifetime that is not finite and above zero.
    pub fn validate(&self) -> Result<(), SpawnError> {
        check_vector("position", self.position)?;
        check_vector("velocity", self.velocity)?;
        let valid_mass = self.mass.is_finite() && self.mass > 0.0;
        if !(self.immovable || valid_mass) {
            return Err(SpawnError::invalid(
                "mass",
                self.mass,
                "a finite mass above zero, or immovable: true",
            ));
        }
        if !(self.radius.is_finite() && self.radius >= 0.0) {
            return Err(SpawnError::invalid(
                "radius",
                self.radius,
                "a finite radius, not negative",
            ));
        }
        if let Some(lifetime) = self.lifetime
            && !(lifetime.is_finite() && lifetime > 0.0)
        {
            return Err(SpawnError::invalid("lifetime", lifetime, "finite seconds above zero"));
        }
        Ok(())
    }

    /// `1 / mass`, or 0 for an immovable particle.
    #[must_use]
    pub fn inverse_mass(&self) -> f32 {
        if self.immovable { 0.0 } else { 1.0 / self.mass }
    }
}

/// Every coordinate of `v` finite; the first that is not is the error,
/// named `field.x` (`.y`, `.z`).
pub(crate) fn check_vector(field: &'static str, v: Vec3) -> Result<(), SpawnError> {
    const NAMES: [[&str; 3]; 4] = [
        ["position.x", "position.y", "position.z"],
        ["velocity.x", "velocity.y", "velocity.z"],
        ["angular_velocity.x", "angular_velocity.y", "angular_velocity.z"],
        ["inertia.x", "inertia.y", "inertia.z"],
    ];
    let names = match field {
        "position" => NAMES[0],
        "velocity" => NAMES[1],
        "angular_velocity" => NAMES[2],
        _ => NAMES[3],
    };
    for (value, name) in v.to_array().into_iter().zip(names) {
        if !value.is_finite() {
            return Err(SpawnError::invalid(name, value, "a finite number"));
        }
    }
    Ok(())
}
