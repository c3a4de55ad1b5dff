//! What a step refuses before it changes anything: forces and colliders
//! of pairs past `WorldConfig::max_pairs`, characters out of range.

use super::SimulationError;
use crate::world::World;

impl World {
    /// The pairs each force would visit among the world's particles,
    /// against [`WorldConfig::max_pairs`](crate::WorldConfig): checked
    /// before the step changes anything (the world grows between steps,
    /// by spawns and emitters, and forces are added between them).
    pub(super) fn check_pairs(&self, tick: u64) -> Result<(), SimulationError> {
        self.check_force_pairs(tick)?;
        let (particles, limit) = (self.entities.len(), self.config.max_pairs);
        let pairs = self.sensor_pairs();
        if pairs > limit {
            return Err(SimulationError::SensorPairLimit {
                tick,
                sensors: self.sensors.list.len(),
                particles,
                pairs,
                limit,
            });
        }
        Ok(())
    }

    /// The forces' part of [`check_pairs`](Self::check_pairs): also asked
    /// before the energy's potentials visit their pairs.
    pub(crate) fn check_force_pairs(&self, tick: u64) -> Result<(), SimulationError> {
        let particles = self.entities.len();
        let limit = self.config.max_pairs;
        for force in &self.forces {
            let pairs = force.pairs(particles);
            if pairs > limit {
                return Err(SimulationError::PairLimit {
                    tick,
                    force: force.name(),
                    particles,
                    pairs,
                    limit,
                });
            }
        }
        Ok(())
    }

    /// Refuses a step with a character whose numbers are out of range.
    pub(crate) fn check_characters(&self, tick: u64) -> Result<(), SimulationError> {
        for (id, character) in &self.characters.list {
            character
                .validate()
                .map_err(|error| SimulationError::Character { tick, id: *id, error })?;
        }
        Ok(())
    }
}
