//! Which entities a step removed, and why: so a game drops the handles it
//! kept for particles whose lifetime ran out, or that a system despawned,
//! instead of finding out from a `Despawned` error.

use crate::layout::Entity;

/// Why an entity left the world.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RemovalCause {
    /// Its lifetime ran out ([`Particle::lifetime`](crate::Particle)).
    Expired,
    /// A queued despawn was applied
    /// ([`World::queue_despawn`](crate::World::queue_despawn), or a
    /// system's).
    Despawned,
}

/// An entity the last step removed ([`World::removed`](crate::World::removed)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Removal {
    /// The entity; its handle now names nothing.
    pub entity: Entity,
    /// Why it was removed.
    pub cause: RemovalCause,
}
