//! The ECS-lite world: generational entities over struct-of-arrays columns.
//!
//! Every entity is a particle (position, velocity, mass, radius, colour, age,
//! lifetime); rigid bodies add an orientation in a second table; games add
//! their own typed [`Component`] columns. Rows are dense and removal is
//! `swap_remove`, so spawn and despawn are O(1) and every column stays dense:
//! the vector columns in blocks of four particles per axis the fused step
//! hands the integrator as they are ([`Vec3Column`]), the scalars as slices.
//! The integrator's per-particle history follows the same swap.

/// `Clone` with a field-wise `clone_from`, so copying into an existing value
/// reuses every `Vec`'s buffer (`#[derive(Clone)]` reallocates them all).
macro_rules! clone_fields {
    ($ty:ty { $($field:ident),* $(,)? }) => {
        impl Clone for $ty {
            fn clone(&self) -> Self {
                Self { $($field: self.$field.clone()),* }
            }
            fn clone_from(&mut self, source: &Self) {
                $(self.$field.clone_from(&source.$field);)*
            }
        }
    };
}

mod checksum;
mod colliders;
pub(crate) mod column;
mod components;
mod config;
mod entity;
pub(crate) mod facts;
mod particles;
mod rigid;
mod snapshot;

use core::fmt;

use glam::{Quat, Vec3, Vec3A};
use rand::SeedableRng;
use rand_pcg::Pcg32;
use tickwork_integrators::angular::{AngularIntegrator, build_angular};
use tickwork_integrators::{Integrator, UnknownMethod, build};

pub use checksum::StableHasher;
pub use column::{RowsMut, Vec3Column};
pub use components::{Component, QueryMut};
pub use config::{WorldConfig, WorldError};
pub use entity::{Entities, Entity, EntityError};
pub use particles::{Colour, Particle, Particles, SpawnError};
pub use rigid::{RigidBodies, RigidBody};
pub use snapshot::Snapshot;

use crate::colliders::set::ColliderSet;
use crate::colliders::{Contact, RowTouch};
use crate::emitter::Emitter;
use crate::forces::Force;
pub(crate) use crate::step::{Lane, Rows};
use components::Columns;

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Command {
    Spawn(Entity, Particle),
    SpawnRigid(Entity, RigidBody),
    Despawn(Entity),
}

/// The particle world. See the [module docs](self).
pub struct World {
    pub(crate) entities: Entities,
    pub(crate) particles: Particles,
    pub(crate) rigid: RigidBodies,
    columns: Columns,
    pub(crate) forces: Vec<Box<dyn Force>>,
    pub(crate) colliders: ColliderSet,
    /// The contacts of the last step, for colliders that report them.
    pub(crate) contacts: Vec<Contact>,
    pub(crate) emitters: Vec<Emitter>,
    pub(crate) integrator: Box<dyn Integrator<Vec3A>>,
    pub(crate) angular: Box<dyn AngularIntegrator<Quat>>,
    pub(crate) queue: Vec<Command>,
    /// Spawn commands in `queue`, for the particle limit.
    pub(crate) queued_spawns: usize,
    pub(crate) rng: Pcg32,
    pub(crate) tick: u64,
    pub(crate) time: f64,
    pub(crate) config: WorldConfig,
    /// Unique per world value (clones get their own), with `revision`
    /// telling renderers whether their copy of the columns is current.
    id: u64,
    /// Counts changes to the particle and rigid-body columns.
    pub(crate) revision: u64,
    /// `particles_mut` was called since the last step began.
    pub(crate) edited: bool,
    // Scratch reused by every step.
    pub(crate) lanes: Vec<Lane>,
    pub(crate) expired_rows: Vec<u32>,
    pub(crate) expired: Vec<Entity>,
    /// The rows the plain (unfused) step integrates, gathered from the blocks.
    pub(crate) gathered: Rows,
    /// Contacts by row, before they are sorted and named.
    pub(crate) touches: Vec<RowTouch>,
}

impl Clone for World {
    fn clone(&self) -> Self {
        Self {
            entities: self.entities.clone(),
            particles: self.particles.clone(),
            rigid: self.rigid.clone(),
            columns: self.columns.clone(),
            forces: self.forces.clone(),
            colliders: self.colliders.clone(),
            contacts: self.contacts.clone(),
            emitters: self.emitters.clone(),
            integrator: self.integrator.clone_boxed(),
            angular: self.angular.clone_boxed(),
            queue: self.queue.clone(),
            queued_spawns: self.queued_spawns,
            rng: self.rng.clone(),
            tick: self.tick,
            time: self.time,
            config: self.config.clone(),
            id: next_world_id(),
            revision: 0,
            edited: false,
            lanes: Vec::new(),
            expired_rows: Vec::new(),
            expired: Vec::new(),
            gathered: Rows::default(),
            touches: Vec::new(),
        }
    }

    /// Copies `source` into `self`, reusing this world's buffers (no
    /// allocation once they are large enough), which is what makes a
    /// snapshot every step affordable.
    fn clone_from(&mut self, source: &Self) {
        self.entities.clone_from(&source.entities);
        self.particles.clone_from(&source.particles);
        self.rigid.clone_from(&source.rigid);
        self.columns.clone_from(&source.columns);
        self.forces.clone_from(&source.forces);
        self.colliders.clone_from(&source.colliders);
        self.contacts.clone_from(&source.contacts);
        self.emitters.clone_from(&source.emitters);
        if !self.integrator.copy_state_from(source.integrator.as_ref()) {
            self.integrator = source.integrator.clone_boxed();
            self.lanes.clear();
        }
        if !self.angular.copy_state_from(source.angular.as_ref()) {
            self.angular = source.angular.clone_boxed();
        }
        self.queue.clone_from(&source.queue);
        self.queued_spawns = source.queued_spawns;
        self.rng.clone_from(&source.rng);
        self.tick = source.tick;
        self.time = source.time;
        self.config.clone_from(&source.config);
        self.revision += 1;
        // A restored state came from outside the step: checked at the next.
        self.edited = true;
    }
}

/// A process-wide unique world id.
fn next_world_id() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

impl fmt::Debug for World {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("World")
            .field("entities", &self.entities.len())
            .field("rigid_bodies", &self.rigid.len())
            .field("integrator", &self.integrator.info().name)
            .field("forces", &self.forces)
            .field("colliders", &self.colliders.colliders)
            .field("tick", &self.tick)
            .finish_non_exhaustive()
    }
}

impl Default for World {
    fn default() -> Self {
        Self::new(WorldConfig::default()).unwrap_or_else(|_| unreachable!("the default methods are registered"))
    }
}

impl World {
    /// An empty world.
    ///
    /// # Errors
    /// [`UnknownMethod`] when an integrator name is not registered (the
    /// message lists the valid names).
    pub fn new(config: WorldConfig) -> Result<Self, UnknownMethod> {
        let integrator = build::<Vec3A>(&config.integrator)?;
        let angular = build_angular::<Quat>(&config.angular_integrator)?;
        Ok(Self {
            entities: Entities::default(),
            particles: Particles::default(),
            rigid: RigidBodies::default(),
            columns: Columns::default(),
            forces: Vec::new(),
            colliders: ColliderSet::default(),
            contacts: Vec::new(),
            emitters: Vec::new(),
            integrator,
            angular,
            queue: Vec::new(),
            queued_spawns: 0,
            rng: Pcg32::seed_from_u64(config.seed),
            tick: 0,
            time: 0.0,
            config,
            id: next_world_id(),
            revision: 0,
            edited: false,
            lanes: Vec::new(),
            expired_rows: Vec::new(),
            expired: Vec::new(),
            gathered: Rows::default(),
            touches: Vec::new(),
        })
    }

    // ---- entities -------------------------------------------------------

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
        let body = self.particles.rigid_row[row];
        if body != u32::MAX {
            let body = body as usize;
            self.rigid.swap_remove(body);
            if let Some(&owner) = self.rigid.owner.get(body) {
                self.particles.rigid_row[owner as usize] = body as u32;
            }
        }
        self.entities.swap_remove(entity)?;
        self.particles.swap_remove(row);
        self.columns.swap_remove(row);
        self.integrator.swap_remove(row);
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

    // ---- particle data ----------------------------------------------------

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
        particles::check_vector("velocity", velocity).map_err(|error| WorldError::Invalid { entity, error })?;
        self.particles.velocity.set(row, velocity.into());
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
        particles::check_vector("position", position).map_err(|error| WorldError::Invalid { entity, error })?;
        self.particles.position.set(row, position.into());
        self.particles.previous_position.set(row, position.into());
        self.particles.teleported_at[row] = self.tick;
        self.revision += 1;
        Ok(())
    }

    // ---- forces, colliders, emitters, methods -----------------------------

    /// Adds a force generator.
    pub fn add_force(&mut self, force: impl Force + 'static) {
        self.forces.push(Box::new(force));
    }

    /// The force generators, to inspect, change or remove.
    pub fn forces_mut(&mut self) -> &mut Vec<Box<dyn Force>> {
        &mut self.forces
    }

    /// The force generators.
    #[must_use]
    pub fn forces(&self) -> &[Box<dyn Force>] {
        &self.forces
    }

    /// The first force of type `T`, to change between steps without
    /// replacing it (a game's thrust, a wind gust).
    pub fn force_mut<T: Force + 'static>(&mut self) -> Option<&mut T> {
        self.forces.iter_mut().find_map(|f| f.as_any_mut().downcast_mut::<T>())
    }

    /// Adds an emitter.
    ///
    /// # Errors
    /// [`SpawnError`] naming the invalid setting; nothing is added.
    pub fn add_emitter(&mut self, emitter: Emitter) -> Result<(), SpawnError> {
        emitter.validate()?;
        self.emitters.push(emitter);
        Ok(())
    }

    /// The emitters, to move or change (particles from an emitter changed to
    /// an invalid setting are refused at the step with an error).
    pub fn emitters_mut(&mut self) -> &mut Vec<Emitter> {
        &mut self.emitters
    }

    /// Switches the integrator by name. History starts afresh: multi-step
    /// methods bootstrap again.
    ///
    /// # Errors
    /// [`UnknownMethod`] listing the valid names; the integrator is unchanged.
    pub fn set_integrator(&mut self, name: &str) -> Result<(), UnknownMethod> {
        self.integrator = build::<Vec3A>(name)?;
        self.lanes.clear();
        self.config.integrator = self.integrator.info().name.to_owned();
        Ok(())
    }

    /// The integrator in use.
    #[must_use]
    pub fn integrator(&self) -> &dyn Integrator<Vec3A> {
        self.integrator.as_ref()
    }

    /// Switches the angular integrator by name.
    ///
    /// # Errors
    /// [`UnknownMethod`] listing the valid names; the method is unchanged.
    pub fn set_angular_integrator(&mut self, name: &str) -> Result<(), UnknownMethod> {
        self.angular = build_angular::<Quat>(name)?;
        self.config.angular_integrator = self.angular.info().name.to_owned();
        Ok(())
    }

    /// The angular integrator in use.
    #[must_use]
    pub fn angular_integrator(&self) -> &dyn AngularIntegrator<Quat> {
        self.angular.as_ref()
    }

    /// The world's seeded random generator; games that draw from it stay
    /// deterministic and snapshots capture it.
    pub fn rng(&mut self) -> &mut Pcg32 {
        &mut self.rng
    }

    /// The next tick to run.
    #[must_use]
    pub fn tick(&self) -> u64 {
        self.tick
    }

    /// Simulated time at the end of the last step, in seconds.
    #[must_use]
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The settings the world was made with (integrator names follow switches).
    #[must_use]
    pub fn config(&self) -> &WorldConfig {
        &self.config
    }

    // ---- snapshots ----------------------------------------------------------

    /// This world's identity: unique in the process, different for a clone.
    #[must_use]
    pub fn id(&self) -> u64 {
        self.id
    }

    /// Counts changes to the particle and rigid-body columns (steps,
    /// spawns, despawns, teleports, restores, mutable access): a renderer
    /// holding a copy made at the same `(id, revision)` is current.
    #[must_use]
    pub fn revision(&self) -> u64 {
        self.revision
    }
}
