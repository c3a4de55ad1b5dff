//! The world's particle data: the particle and rigid-body columns, read or
//! changed in place, and one entity's position, velocity, orientation and
//! age; setting a velocity, teleporting.

use glam::{Quat, Vec3};

use super::{Entity, EntityError, Particles, RigidBodies, World, WorldError};
use crate::layout::check_vector;

impl World {
    /// The particle columns.
    #[must_use]
    pub fn particles(&self) -> &Particles {
        &self.particles
    }

    /// Seconds since `entity` spawned (the sum of the steps' `dt` since).
    ///
    /// # Errors
    /// [`EntityError`] for a handle that names no live entity.
    pub fn age(&self, entity: Entity) -> Result<f32, EntityError> {
        Ok(self.particles.age_of(self.entities.row(entity)?))
    }

    /// The particle columns, to change in place (a game's own fixed systems).
    /// Changing positions this way is seen as a teleport by history methods
    /// but not by interpolation; prefer [`teleport`](Self::teleport).
    pub fn particles_mut(&mut self) -> &mut Particles {
        self.revision += 1;
        // The next step checks the state it starts from, so a NaN written
        // here is named as such, not blamed on the step.
        self.edited = true;
        // Lifetimes, masses and radii may change: derived facts are redone.
        self.particles.forget_derived();
        &mut self.particles
    }

    /// The rigid-body columns.
    #[must_use]
    pub fn rigid_bodies(&self) -> &RigidBodies {
        &self.rigid
    }

    /// The rigid-body columns, to change in place.
    pub fn rigid_bodies_mut(&mut self) -> &mut RigidBodies {
        self.revision += 1;
        &mut self.rigid
    }

    /// An entity's position.
    ///
    /// # Errors
    /// [`EntityError`] for a handle that names no live entity.
    pub fn position(&self, entity: Entity) -> Result<Vec3, EntityError> {
        Ok(self.particles.position.row(self.row(entity)?).into())
    }

    /// Where an entity is drawn a frame `alpha` of the way from the last
    /// step's start to its end (its previous position lerped to its
    /// current one, as the renderer draws its particle): where a game puts
    /// a sprite or a label that moves with it.
    ///
    /// # Errors
    /// [`EntityError`] for a handle that names no live entity.
    pub fn drawn_position(&self, entity: Entity, alpha: f32) -> Result<Vec3, EntityError> {
        let row = self.row(entity)?;
        let (from, to) = (
            self.particles.previous_position.row(row),
            self.particles.position.row(row),
        );
        Ok((from + (to - from) * alpha).into())
    }

    /// An entity's velocity.
    ///
    /// # Errors
    /// [`EntityError`] for a handle that names no live entity.
    pub fn velocity(&self, entity: Entity) -> Result<Vec3, EntityError> {
        Ok(self.particles.velocity.row(self.row(entity)?).into())
    }

    /// A rigid body's orientation (identity for a plain particle).
    ///
    /// # Errors
    /// [`EntityError`] for a handle that names no live entity.
    pub fn orientation(&self, entity: Entity) -> Result<Quat, EntityError> {
        let body = self.particles.rigid_row[self.row(entity)?];
        Ok(self
            .rigid
            .orientation
            .get(body as usize)
            .copied()
            .unwrap_or(Quat::IDENTITY))
    }

    /// Sets an entity's velocity (an impulse, a thrust).
    ///
    /// # Errors
    /// [`WorldError`] for a dead handle or a non-finite velocity.
    pub fn set_velocity(&mut self, entity: Entity, velocity: Vec3) -> Result<(), WorldError> {
        let row = self.row(entity)?;
        check_vector("velocity", velocity).map_err(|error| WorldError::Invalid { entity, error })?;
        self.particles.velocity.set(row, velocity.into());
        self.revision += 1;
        Ok(())
    }

    /// Moves an entity to `position` outside the step. Its previous position
    /// moves too, so interpolation does not streak across the jump, and
    /// `teleported_at` records the tick for trails.
    ///
    /// # Errors
    /// [`WorldError`] for a dead handle or a non-finite position.
    pub fn teleport(&mut self, entity: Entity, position: Vec3) -> Result<(), WorldError> {
        let row = self.row(entity)?;
        check_vector("position", position).map_err(|error| WorldError::Invalid { entity, error })?;
        self.particles.position.set(row, position.into());
        self.particles.previous_position.set(row, position.into());
        self.particles.teleported_at[row] = self.tick;
        self.revision += 1;
        Ok(())
    }
}
