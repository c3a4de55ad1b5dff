//! Lifetimes and emitters: the particles whose time ran out, and the ones
//! the emitters are due.

use super::{SimulationError, StepReport};
use crate::world::{Removal, RemovalCause, World};

impl World {
    pub(super) fn expire(&mut self, report: &mut StepReport) {
        if self.expired_rows.is_empty() {
            return;
        }
        // Rows ascend (one scan in row order); turn them into handles
        // first, since each despawn moves the last row.
        self.expired.clear();
        let rows = self.entities.rows();
        self.expired
            .extend(self.expired_rows.iter().map(|&row| rows[row as usize]));
        for k in 0..self.expired.len() {
            let entity = self.expired[k];
            if self.despawn(entity).is_ok() {
                report.expired += 1;
                self.removed.push(Removal {
                    entity,
                    cause: RemovalCause::Expired,
                });
            }
        }
    }

    /// Emitter settings and the spawns they are due this step, checked
    /// before the step changes anything (`emitters_mut` lets a game change
    /// settings between steps); `due` is computed as [`Emitter::due`] will.
    pub(super) fn check_emitters(&self, dt: f32, tick: u64) -> Result<(), SimulationError> {
        for (k, emitter) in self.emitters.iter().enumerate() {
            emitter
                .validate()
                .map_err(|error| SimulationError::Emitter { tick, index: k, error })?;
            let due = emitter.peek_due(dt);
            let limit = self.config.max_spawns_per_step;
            if due.is_nan() || due > limit as f32 {
                return Err(SimulationError::SpawnLimit {
                    tick,
                    emitter: k,
                    due: f64::from(due),
                    limit,
                });
            }
        }
        Ok(())
    }

    pub(super) fn emit(&mut self, dt: f32, tick: u64) -> Result<(), SimulationError> {
        for k in 0..self.emitters.len() {
            let due = self.emitters[k].due(dt);
            // Known only now, after expiry has made room: past the limit,
            // the world is left as the step made it (as for `NonFinite`).
            if self.check_room(due as usize).is_err() {
                return Err(SimulationError::ParticleLimit {
                    tick,
                    emitter: k,
                    limit: self.config.max_particles,
                });
            }
            for _ in 0..due as u32 {
                let particle = self.emitters[k].particle(&mut self.rng);
                let entity = self.entities.reserve();
                self.queue.push(crate::world::Command::Spawn(entity, particle));
            }
            self.queued_spawns += due as usize;
        }
        Ok(())
    }
}
