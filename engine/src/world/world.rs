//! The [`World`] itself: what it holds (the particle and rigid-body rows,
//! a game's columns, forces, colliders, emitters, the integrators, queued
//! commands, the step's scratch), making one, copying one into another's
//! buffers, and its tick, time, settings and identity.

use core::fmt;

use glam::{Quat, Vec3A};
use rand::SeedableRng;
use rand_pcg::Pcg32;
use tickwork_integrators::angular::{AngularIntegrator, build_angular};
use tickwork_integrators::{Integrator, UnknownMethod, build};

use super::character_set::Characters;
use super::columns::Columns;
use super::command::Command;
use super::{Entities, Entity, Lane, Particles, Removal, RigidBodies, Sensors, SweepScratch, WorldConfig};
use crate::colliders::set::ColliderSet;
use crate::colliders::{Contact, RowTouch};
use crate::emitter::Emitter;
use crate::forces::Force;
use crate::layout::Rows;

/// The particle world. See the [module docs](super).
pub struct World {
    pub(crate) entities: Entities,
    pub(crate) particles: Particles,
    pub(crate) rigid: RigidBodies,
    pub(super) columns: Columns,
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
    /// The entities the last step removed, in the order it removed them.
    pub(crate) removed: Vec<Removal>,
    /// Sensors and their overlaps.
    pub(crate) sensors: Sensors,
    /// Kinematic characters.
    pub(crate) characters: Characters,
    /// The rows the plain (unfused) step integrates, gathered from the blocks.
    pub(crate) gathered: Rows,
    /// The plain step's scratch for contacts inside the step.
    pub(crate) sweep: SweepScratch,
    /// Contacts by row, before they are sorted and named.
    pub(crate) touches: Vec<RowTouch>,
    /// Where a GPU world (`gpu_step::GpuWorld`) steps the particles:
    /// each row removed and added, in order, since it was set (`None`: not
    /// logged), so the GPU's rows follow the CPU's.
    pub(crate) row_log: Option<Vec<RowChange>>,
}

/// A change to the rows, as [`World::row_log`] keeps them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RowChange {
    /// The row was swap-removed: the last row moved into it.
    Removed(u32),
    /// A row was added at the end.
    Added,
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
            removed: self.removed.clone(),
            sensors: self.sensors.clone(),
            characters: self.characters.clone(),
            gathered: Rows::default(),
            sweep: SweepScratch::default(),
            touches: Vec::new(),
            row_log: None,
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
        self.removed.clone_from(&source.removed);
        self.sensors.clone_from(&source.sensors);
        self.characters.clone_from(&source.characters);
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
            removed: Vec::new(),
            sensors: Sensors::default(),
            characters: Characters::default(),
            gathered: Rows::default(),
            sweep: SweepScratch::default(),
            touches: Vec::new(),
            row_log: None,
        })
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

    /// Sets where a runner steps the particles (see
    /// [`WorldConfig::backend`]): from the next step on (a world moved
    /// back to the CPU takes the GPU's state back first).
    pub fn set_backend(&mut self, backend: super::Backend) {
        self.config.backend = backend;
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
