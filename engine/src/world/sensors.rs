//! A world's sensors (adding, changing, removing them), the overlaps they
//! found in the last step, and queries of which particles are within a sphere or a box now (the same
//! overlap rule, [`Sensor`]).

use glam::{Vec3, Vec3A};

use super::World;
use crate::layout::Entity;
use crate::sensor::{Overlap, OverlapPhase, Sensor, SensorError, SensorId};

impl World {
    /// Adds a sensor; from the next step on, [`overlaps`](Self::overlaps)
    /// lists the particles overlapping it.
    ///
    /// # Errors
    /// [`SensorError::Invalid`] for a centre that is not finite or a size
    /// that is not finite or below 0.
    pub fn add_sensor(&mut self, sensor: Sensor) -> Result<SensorId, SensorError> {
        sensor.validate()?;
        let s = &mut self.sensors;
        let id = SensorId(s.next);
        s.next += 1;
        s.list.push((id, sensor));
        Ok(id)
    }

    /// The sensor `id`.
    ///
    /// # Errors
    /// [`SensorError::Unknown`] for a removed or foreign handle.
    pub fn sensor(&self, id: SensorId) -> Result<&Sensor, SensorError> {
        let k = self.sensors.index(id)?;
        Ok(&self.sensors.list[k].1)
    }

    /// Replaces the sensor `id` (moves a trigger zone, grows a radius),
    /// from the next step on.
    ///
    /// # Errors
    /// [`SensorError::Unknown`] for a removed or foreign handle;
    /// [`SensorError::Invalid`] as for [`add_sensor`](Self::add_sensor).
    pub fn set_sensor(&mut self, id: SensorId, sensor: Sensor) -> Result<(), SensorError> {
        let k = self.sensors.index(id)?;
        sensor.validate()?;
        self.sensors.list[k].1 = sensor;
        Ok(())
    }

    /// Removes the sensor `id` and returns it; its overlaps end with the
    /// next step.
    ///
    /// # Errors
    /// [`SensorError::Unknown`] for a removed or foreign handle.
    pub fn remove_sensor(&mut self, id: SensorId) -> Result<Sensor, SensorError> {
        let k = self.sensors.index(id)?;
        Ok(self.sensors.list.remove(k).1)
    }

    /// The sensors with their handles, in the order added.
    pub fn sensors(&self) -> impl Iterator<Item = (SensorId, &Sensor)> {
        self.sensors.list.iter().map(|(id, s)| (*id, s))
    }

    /// Every sensor's overlaps after the last step, by sensor (in the order
    /// added) and then by entity, each with its phase: began this step,
    /// stays, or ended (left, or removed). The same on any number of
    /// threads; the next step replaces them.
    #[must_use]
    pub fn overlaps(&self) -> &[Overlap] {
        &self.sensors.overlaps
    }

    /// The live particles within the ball of `radius` around `centre` now
    /// (each particle's own radius counts, as for a [`Sensor`]), in row
    /// order. A NaN or negative radius finds none.
    pub fn within(&self, centre: Vec3, radius: f32) -> impl Iterator<Item = Entity> + '_ {
        self.touching(Sensor::sphere(centre, radius), None)
    }

    /// The live particles overlapping the axis-aligned box from `min` to
    /// `max` now (each particle's own radius counts), in row order. An
    /// inverted or NaN box finds none.
    pub fn in_box(&self, min: Vec3, max: Vec3) -> impl Iterator<Item = Entity> + '_ {
        self.touching(Sensor::cuboid(min, max), None)
    }

    /// The particles overlapping `sensor` centred where it is, but `skip`.
    fn touching(&self, sensor: Sensor, skip: Option<usize>) -> impl Iterator<Item = Entity> + '_ {
        let valid = sensor.validate().is_ok();
        let centre = Vec3A::from(sensor.centre);
        let p = &self.particles;
        self.entities
            .rows()
            .iter()
            .enumerate()
            .filter(move |&(row, _)| {
                valid && Some(row) != skip && sensor.touches(centre, p.position.row(row), p.radius[row])
            })
            .map(|(_, &entity)| entity)
    }

    /// The pairs the sensors will test next step: active sensors times
    /// particles (saturating).
    pub(crate) fn sensor_pairs(&self) -> u64 {
        (self.sensors.list.len() as u64).saturating_mul(self.entities.len() as u64)
    }

    /// After a step: each sensor's overlaps, and their phases against the
    /// step before's. Allocates nothing once the lists have grown.
    pub(crate) fn find_overlaps(&mut self) {
        if self.sensors.list.is_empty() && self.sensors.overlaps.is_empty() {
            return;
        }
        let mut found = core::mem::take(&mut self.sensors.before);
        found.clear();
        for &(id, sensor) in &self.sensors.list {
            let (centre, skip) = match sensor.follow {
                None => (sensor.centre, None),
                Some(entity) => match self.entities.row(entity) {
                    Ok(row) => (Vec3::from(self.particles.position.row(row)) + sensor.centre, Some(row)),
                    // Its entity is gone: it reports nothing.
                    Err(_) => continue,
                },
            };
            let placed = Sensor { centre, ..sensor };
            found.extend(self.touching(placed, skip).map(|entity| Overlap {
                sensor: id,
                entity,
                phase: OverlapPhase::Began,
            }));
        }
        // Keys are unique (one entry per sensor and entity): an unstable
        // sort, which allocates nothing, is deterministic.
        found.sort_unstable_by_key(Overlap::key);
        let before = core::mem::replace(&mut self.sensors.overlaps, found);
        let now = &mut self.sensors.overlaps;
        let was = |o: &&Overlap| o.phase != OverlapPhase::Ended;
        let mut old = before.iter().filter(was).peekable();
        for o in now.iter_mut() {
            while old.next_if(|b| b.key() < o.key()).is_some() {}
            if old.next_if(|b| b.key() == o.key()).is_some() {
                o.phase = OverlapPhase::Stays;
            }
        }
        let current = now.len();
        for b in before.iter().filter(was) {
            if now[..current].binary_search_by_key(&b.key(), Overlap::key).is_err() {
                now.push(Overlap {
                    phase: OverlapPhase::Ended,
                    ..*b
                });
            }
        }
        if now.len() > current {
            now.sort_unstable_by_key(Overlap::key);
        }
        self.sensors.before = before;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_overlap_rule_counts_the_particles_radius() {
        let ball = Sensor::sphere(Vec3::ZERO, 1.0);
        let at = |x: f32| Vec3A::new(x, 0.0, 0.0);
        assert!(ball.touches(Vec3A::ZERO, at(0.99), 0.0));
        assert!(!ball.touches(Vec3A::ZERO, at(1.0), 0.0), "touching is not overlapping");
        assert!(ball.touches(Vec3A::ZERO, at(1.4), 0.5));
        let cube = Sensor::cuboid(Vec3::splat(-1.0), Vec3::splat(1.0));
        assert!(cube.touches(Vec3A::ZERO, at(0.5), 0.0), "inside");
        assert!(!cube.touches(Vec3A::ZERO, at(1.5), 0.4));
        assert!(cube.touches(Vec3A::ZERO, at(1.3), 0.4), "within its radius of a face");
        // A corner is rounded by the particle's radius.
        let corner = Vec3A::splat(1.0 + 0.3);
        assert!(!cube.touches(Vec3A::ZERO, corner, 0.5), "0.52 from the corner");
        assert!(cube.touches(Vec3A::ZERO, corner, 0.6));
        assert!(Sensor::sphere(Vec3::ZERO, 0.0).touches(Vec3A::ZERO, at(0.1), 0.2));
    }
}
