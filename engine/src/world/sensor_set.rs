//! The sensors a world holds and the overlaps they found (the data; what
//! a world does with them is in `sensors.rs`).

use crate::sensor::{Overlap, Sensor, SensorError, SensorId};

/// The sensors of a world, in the order added, and their overlaps.
#[derive(Debug, Default)]
pub(crate) struct Sensors {
    pub list: Vec<(SensorId, Sensor)>,
    /// The next id to hand out (ids are never reused).
    pub next: u64,
    /// The last step's overlaps, by sensor then entity.
    pub overlaps: Vec<Overlap>,
    /// The overlaps of the step before, while a step finds the new ones.
    pub before: Vec<Overlap>,
}

impl Clone for Sensors {
    fn clone(&self) -> Self {
        Self {
            list: self.list.clone(),
            next: self.next,
            overlaps: self.overlaps.clone(),
            before: Vec::new(),
        }
    }

    fn clone_from(&mut self, source: &Self) {
        self.list.clone_from(&source.list);
        self.next = source.next;
        self.overlaps.clone_from(&source.overlaps);
    }
}

impl Sensors {
    pub fn index(&self, id: SensorId) -> Result<usize, SensorError> {
        // Ids ascend with the list (removal keeps the order).
        self.list
            .binary_search_by_key(&id, |(k, _)| *k)
            .map_err(|_| SensorError::Unknown { id })
    }
}
