//! Rigid bodies: a particle (centre of mass) plus an orientation.

use glam::{Quat, Vec3};

use crate::layout::{Particle, SpawnError, check_vector};

/// A rigid body to spawn: its centre of mass moves as a [`Particle`]; its
/// orientation turns under Euler's equations with a diagonal inertia tensor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidBody {
    /// The centre of mass (position, velocity, mass, radius, colour, lifetime).
    pub particle: Particle,
    /// Orientation, body to world (default: identity). Normalised on spawn.
    pub orientation: Quat,
    /// Angular velocity in the world frame, radians per second (default: zero).
    pub angular_velocity: Vec3,
    /// Principal moments of inertia in the body frame, each above zero
    /// (default: `(1, 1, 1)`).
    pub inertia: Vec3,
    /// Half extents of the box drawn for the body, in metres (default: `(0.5, 0.25, 0.1)`).
    pub half_extents: Vec3,
}

impl Default for RigidBody {
    fn default() -> Self {
        Self {
            particle: Particle::default(),
            orientation: Quat::IDENTITY,
            angular_velocity: Vec3::ZERO,
            inertia: Vec3::ONE,
            half_extents: Vec3::new(0.5, 0.25, 0.1),
        }
    }
}

impl RigidBody {
    /// A box of `mass` and half extents `h`, with the inertia of a solid box:
    /// `I_x = m (h_y^2 + h_z^2) / 3`, and so on.
    #[must_use]
    pub fn solid_box(mass: f32, h: Vec3) -> Self {
        let m = mass / 3.0;
        Self {
            particle: Particle {
                mass,
                ..Particle::default()
            },
            inertia: Vec3::new(
                m * (h.y * h.y + h.z * h.z),
                m * (h.x * h.x + h.z * h.z),
                m * (h.x * h.x + h.y * h.y),
            ),
            half_extents: h,
            ..Self::default()
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    /// [`SpawnError`] naming the field (the particle's, a non-finite angular
    /// velocity, an inertia that is not finite and above zero, a zero or
    /// non-finite orientation).
    pub fn validate(&self) -> Result<(), SpawnError> {
        self.particle.validate()?;
        check_vector("angular_velocity", self.angular_velocity)?;
        check_vector("inertia", self.inertia)?;
        for (value, field) in self
            .inertia
            .to_array()
            .into_iter()
            .zip(["inertia.x", "inertia.y", "inertia.z"])
        {
            // A subnormal moment has an infinite inverse.
            if value < f32::MIN_POSITIVE {
                return Err(SpawnError::invalid(
                    field,
                    value,
                    "a moment of inertia above zero whose inverse is finite",
                ));
            }
        }
        let norm = self.orientation.length();
        if !norm.is_finite() || norm < 1e-6 {
            return Err(SpawnError::invalid(
                "orientation",
                norm,
                "a quaternion of non-zero length",
            ));
        }
        Ok(())
    }
}

/// The rigid-body columns. Row `k` belongs to the particle in row `owner[k]`.
#[derive(Debug, Default, PartialEq)]
pub struct RigidBodies {
    /// The particle row of each body.
    pub owner: Vec<u32>,
    /// Orientations now.
    pub orientation: Vec<Quat>,
    /// Orientations at the start of the last step, for interpolation.
    pub previous_orientation: Vec<Quat>,
    /// Angular velocities (world frame).
    pub angular_velocity: Vec<Vec3>,
    /// Principal moments of inertia (body frame).
    pub inertia: Vec<Vec3>,
    /// Half extents for drawing.
    pub half_extents: Vec<Vec3>,
}

impl RigidBodies {
    /// Number of bodies.
    #[must_use]
    pub fn len(&self) -> usize {
        self.owner.len()
    }

    /// Whether there are none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.owner.is_empty()
    }

    pub(crate) fn push(&mut self, owner: usize, body: &RigidBody) {
        let q = body.orientation.normalize();
        self.owner.push(owner as u32);
        self.orientation.push(q);
        self.previous_orientation.push(q);
        self.angular_velocity.push(body.angular_velocity);
        self.inertia.push(body.inertia);
        self.half_extents.push(body.half_extents);
    }

    pub(crate) fn swap_remove(&mut self, row: usize) {
        self.owner.swap_remove(row);
        self.orientation.swap_remove(row);
        self.previous_orientation.swap_remove(row);
        self.angular_velocity.swap_remove(row);
        self.inertia.swap_remove(row);
        self.half_extents.swap_remove(row);
    }
}

clone_fields!(RigidBodies {
    owner,
    orientation,
    previous_orientation,
    angular_velocity,
    inertia,
    half_extents
});
