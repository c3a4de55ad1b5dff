//! A spawn or despawn queued during a step, applied at its end in the
//! order queued ([`World::apply_queued`](super::World::apply_queued)).

use super::{Entity, Particle, RigidBody};

/// A queued change to the world's entities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Command {
    Spawn(Entity, Particle),
    SpawnRigid(Entity, RigidBody),
    Despawn(Entity),
}
