//! The world's entities: spawning and despawning them, now or queued to
//! the end of a step, and asking which live and in which row.

use super::command::Command;
use super::{Entities, Entity, EntityError, Particle, Removal, RemovalCause, RigidBody, SpawnError, World};

impl World {
    /// Spawns a particle now.
    ///
    /// # Errors
    /// [`SpawnError`] naming the invalid field; nothing is spawned.
    pub fn spawn(&mut self, particle: Particle) -> Result<Entity, SpawnError> {
        particle.validate()?;
        self.check_room(1)?;
        let entity = self.entities.reserve();
        self.bind(entity, &particle);
        Ok(entity)
    }

    /// Spawns a rigid body now.
    ///
    /// # Errors
    /// [`SpawnError`] naming the invalid field; nothing is spawned.
    pub fn spawn_rigid(&mut self, body: RigidBody) -> Result<Entity, SpawnError> {
        body.validate()?;
        self.check_room(1)?;
        let entity = self.entities.reserve();
        self.bind_rigid(entity, &body);
        Ok(entity)
    }

    /// Whether `more` particles fit under [`WorldConfig::max_particles`],
    /// counting the live ones and the queued spawns.
    pub(crate) fn check_room(&self, more: usize) -> Result<(), SpawnError> {
        let limit = self.config.max_particles;
        let held = self.entities.len().saturating_add(self.queued_spawns);
        if held.saturating_add(more) > limit {
            return Err(SpawnError::ParticleLimit { limit });
        }
        Ok(())
    }

    fn bind(&mut self, entity: Entity, particle: &Particle) -> usize {
        let row = self.entities.bind(entity);
        self.revision += 1;
        if let Some(log) = &mut self.row_log {
            log.push(super::world::RowChange::Added);
        }
        self.particles.push(particle);
        self.columns.push_defaults();
        row
    }

    fn bind_rigid(&mut self, entity: Entity, body: &RigidBody) {
        let row = self.bind(entity, &body.particle);
        self.particles.rigid_row[row] = self.rigid.len() as u32;
        self.rigid.push(row, body);
    }

    /// Despawns an entity now: its row is swap-removed from every column and
    /// from the integrator's history.
    ///
    /// # Errors
    /// [`EntityError`] for a handle that names no live entity.
    pub fn despawn(&mut self, entity: Entity) -> Result<(), EntityError> {
        let row = self.entities.row(entity)?;
        self.revision += 1;
        if let Some(log) = &mut self.row_log {
            log.push(super::world::RowChange::Removed(row as u32));
        }
        let body = self.particles.rigid_row[row];
        if body != u32::MAX {
            let body = body as usize;
            self.rigid.swap_remove(body);
            if let Some(&owner) = self.rigid.owner.get(body) {
                self.particles.rigid_row[owner as usize] = body as u32;
            }
        }
        self.entities.swap_remove(entity)?;
        let rows = self.particles.len();
        self.particles.swap_remove(row);
        self.columns.swap_remove(row);
        self.integrator.swap_remove(row, rows);
        if let Some(&moved_body) = self.particles.rigid_row.get(row)
            && moved_body != u32::MAX
        {
            self.rigid.owner[moved_body as usize] = row as u32;
        }
        Ok(())
    }

    /// Queues a spawn for the end of the current (or next) step; the handle is
    /// valid at once but names a live entity only after the step.
    ///
    /// # Errors
    /// [`SpawnError`] naming the invalid field; nothing is queued.
    pub fn queue_spawn(&mut self, particle: Particle) -> Result<Entity, SpawnError> {
        particle.validate()?;
        self.check_room(1)?;
        let entity = self.entities.reserve();
        self.queue.push(Command::Spawn(entity, particle));
        self.queued_spawns += 1;
        Ok(entity)
    }

    /// Queues a rigid-body spawn (see [`queue_spawn`](Self::queue_spawn)).
    ///
    /// # Errors
    /// [`SpawnError`] naming the invalid field; nothing is queued.
    pub fn queue_spawn_rigid(&mut self, body: RigidBody) -> Result<Entity, SpawnError> {
        body.validate()?;
        self.check_room(1)?;
        let entity = self.entities.reserve();
        self.queue.push(Command::SpawnRigid(entity, body));
        self.queued_spawns += 1;
        Ok(entity)
    }

    /// Queues a despawn for the end of the current (or next) step.
    ///
    /// # Errors
    /// [`EntityError`] for a handle that names neither a live nor a queued entity.
    pub fn queue_despawn(&mut self, entity: Entity) -> Result<(), EntityError> {
        match self.entities.row(entity) {
            Ok(_) | Err(EntityError::Pending { .. }) => {
                self.queue.push(Command::Despawn(entity));
                Ok(())
            }
            Err(e) => Err(e),
        }
    }

    /// Applies queued spawns and despawns in the order they were queued.
    /// Returns `(spawned, despawned)`. Despawning an entity that is already
    /// gone by then (despawned twice) is skipped.
    pub fn apply_queued(&mut self) -> (u32, u32) {
        self.queued_spawns = 0;
        if self.queue.is_empty() {
            return (0, 0);
        }
        let (mut spawned, mut despawned) = (0, 0);
        let mut queue = core::mem::take(&mut self.queue);
        for command in queue.drain(..) {
            match command {
                Command::Spawn(entity, particle) => {
                    self.bind(entity, &particle);
                    spawned += 1;
                }
                Command::SpawnRigid(entity, body) => {
                    self.bind_rigid(entity, &body);
                    spawned += 1;
                }
                Command::Despawn(entity) => {
                    if self.despawn(entity).is_ok() {
                        despawned += 1;
                        self.removed.push(Removal {
                            entity,
                            cause: RemovalCause::Despawned,
                        });
                    }
                }
            }
        }
        // Give the (empty) buffer back so its capacity is reused.
        if self.queue.is_empty() {
            self.queue = queue;
        }
        (spawned, despawned)
    }

    /// The entities the last step removed, in the order it removed them:
    /// those whose lifetime ran out, then the queued despawns it applied
    /// (a despawn queued between steps and applied by
    /// [`apply_queued`](Self::apply_queued) is added too). A game drops
    /// the handles it kept for them here, in its next `fixed_update` or
    /// after [`step`](Self::step); the next step replaces the list. A
    /// direct [`despawn`](Self::despawn) is the caller's own and is not
    /// listed.
    #[must_use]
    pub fn removed(&self) -> &[Removal] {
        &self.removed
    }

    /// The entity allocator (handles and rows).
    #[must_use]
    pub fn entities(&self) -> &Entities {
        &self.entities
    }

    /// Number of live entities (particles, including rigid bodies).
    #[must_use]
    pub fn len(&self) -> usize {
        self.entities.len()
    }

    /// Whether no entity lives.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.entities.is_empty()
    }

    /// Whether the handle names a live entity.
    #[must_use]
    pub fn contains(&self, entity: Entity) -> bool {
        self.entities.contains(entity)
    }

    /// The row of a live entity in every column.
    ///
    /// # Errors
    /// [`EntityError`] for a handle that names no live entity.
    pub fn row(&self, entity: Entity) -> Result<usize, EntityError> {
        self.entities.row(entity)
    }
}
