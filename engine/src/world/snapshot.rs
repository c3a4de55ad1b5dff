//! Whole-world copies: a [`Snapshot`] to go back to (a frozen world, a
//! rollback). The state hash that compares runs is in `checksum.rs`.

use super::World;

/// A copy of a whole world (entities, columns, forces, integrator history,
/// random generator), taken by [`World::snapshot`] and put back by
/// [`World::restore`].
#[derive(Clone, Debug)]
pub struct Snapshot {
    world: World,
}

impl Snapshot {
    /// The tick the snapshot was taken at.
    #[must_use]
    pub fn tick(&self) -> u64 {
        self.world.tick
    }
}

impl World {
    /// A copy of the whole state.
    #[must_use]
    pub fn snapshot(&self) -> Snapshot {
        Snapshot { world: self.clone() }
    }

    /// Overwrites `snapshot` with the current state, reusing its buffers.
    pub fn snapshot_into(&self, snapshot: &mut Snapshot) {
        snapshot.world.clone_from(self);
    }

    /// Puts back a snapshot's state (buffers reused). Forces, colliders and
    /// emitters come back as they were too.
    pub fn restore(&mut self, snapshot: &Snapshot) {
        self.clone_from(&snapshot.world);
    }
}
