//! A world whose particles are stepped elsewhere (the GPU step, `gpu_step`):
//! what such a stepper reads of the world and writes back into it, through
//! these methods rather than the world's fields, so that the world keeps
//! its own invariants (its revision counts every change, its tick and time
//! follow its steps).

use glam::{Vec3, Vec3A};

use super::World;
use super::world::RowChange;
use crate::clock::FixedStep;
use crate::colliders::RowTouch;

impl World {
    /// The changes to the rows logged since the log was last taken (empty
    /// when the world does not log them); the log stays on, empty.
    pub(crate) fn take_row_log(&mut self) -> Vec<RowChange> {
        self.row_log.take().unwrap_or_default()
    }

    /// Hands `log` back to the world (emptied or not), which logs its row
    /// changes into it from now on.
    pub(crate) fn give_row_log(&mut self, log: Vec<RowChange>) {
        self.row_log = Some(log);
    }

    /// Whether a particle's state was changed outside the steps since the
    /// last one (a teleport, a set velocity).
    pub(crate) fn edited_outside_steps(&self) -> bool {
        self.edited
    }

    /// Forgets the last step's contacts (the stepper names its own).
    pub(crate) fn clear_contacts(&mut self) {
        self.contacts.clear();
    }

    /// The step's touches found elsewhere, named as the CPU's step names
    /// its own (sorted by collider and row, whatever order they came in).
    pub(crate) fn set_touches(&mut self, touches: impl IntoIterator<Item = RowTouch>) {
        self.touches.clear();
        self.touches.extend(touches);
        self.name_contacts(false);
    }

    /// Writes each row's position, velocity and previous position stepped
    /// elsewhere (`x`, `v`, `previous`, a row each, in row order), a change
    /// the world's revision counts.
    pub(crate) fn store_rows(&mut self, x: &[Vec3], v: &[Vec3], previous: &[Vec3]) {
        let p = &mut self.particles;
        for (row, ((x, v), previous)) in x.iter().zip(v).zip(previous).enumerate() {
            p.position.set(row, Vec3A::from(*x));
            p.velocity.set(row, Vec3A::from(*v));
            p.previous_position.set(row, Vec3A::from(*previous));
        }
        self.revision += 1;
    }

    /// Books `steps` steps of `last.dt` taken elsewhere, the last of them
    /// `last`: the particles' lived time grows by each step in turn (as
    /// each CPU step adds it), and the tick and time are those after
    /// `last`; the steps' contacts and removals are forgotten.
    pub(crate) fn book_steps(&mut self, steps: u64, last: FixedStep) {
        self.contacts.clear();
        self.removed.clear();
        let lifetimes = &mut self.particles.lifetimes;
        for _ in 0..steps {
            lifetimes.lived += last.dt;
        }
        self.tick = last.tick + 1;
        self.time = last.time + last.dt;
    }
}
