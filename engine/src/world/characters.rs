//! A world's characters: adding, reading, driving and removing them, the
//! step that moves them ([`crate::character`]), and the sensors they touch.

use glam::Vec3;

use super::World;
use crate::character::{Character, CharacterError, CharacterId, MAX_CHARACTERS};
use crate::sensor::{Sensor, SensorId, SensorShape};

impl World {
    /// Adds a character (see [`crate::character`]); each step from the next
    /// moves it, after the kinematic colliders.
    ///
    /// # Errors
    /// [`CharacterError::Invalid`] for a number out of range;
    /// [`CharacterError::TooMany`] past [`MAX_CHARACTERS`].
    pub fn add_character(&mut self, character: Character) -> Result<CharacterId, CharacterError> {
        character.validate()?;
        let list = &mut self.characters;
        if list.list.len() >= MAX_CHARACTERS {
            return Err(CharacterError::TooMany { limit: MAX_CHARACTERS });
        }
        let id = CharacterId(list.next);
        list.next += 1;
        list.list.push((id, character));
        Ok(id)
    }

    /// The character `id`.
    ///
    /// # Errors
    /// [`CharacterError::Unknown`] for a removed or foreign handle.
    pub fn character(&self, id: CharacterId) -> Result<&Character, CharacterError> {
        let k = self.characters.index(id)?;
        Ok(&self.characters.list[k].1)
    }

    /// The character `id`, to drive ([`Character::run`],
    /// [`Character::jump`]) or place; the next step checks its numbers.
    ///
    /// # Errors
    /// [`CharacterError::Unknown`] for a removed or foreign handle.
    pub fn character_mut(&mut self, id: CharacterId) -> Result<&mut Character, CharacterError> {
        let k = self.characters.index(id)?;
        Ok(&mut self.characters.list[k].1)
    }

    /// Removes the character `id` and returns it.
    ///
    /// # Errors
    /// [`CharacterError::Unknown`] for a removed or foreign handle.
    pub fn remove_character(&mut self, id: CharacterId) -> Result<Character, CharacterError> {
        let k = self.characters.index(id)?;
        Ok(self.characters.list.remove(k).1)
    }

    /// The characters with their handles, in the order added.
    pub fn characters(&self) -> impl Iterator<Item = (CharacterId, &Character)> {
        self.characters.list.iter().map(|(id, c)| (*id, c))
    }

    /// The sensors the character `id`'s box overlaps now, in the order
    /// added (a coin picked up, spikes touched).
    ///
    /// # Errors
    /// [`CharacterError::Unknown`] for a removed or foreign handle.
    pub fn sensors_touching(&self, id: CharacterId) -> Result<impl Iterator<Item = SensorId> + '_, CharacterError> {
        let character = self.character(id)?;
        let body = (
            character.position.extend(0.0),
            character.config.half_extents.extend(0.0),
        );
        Ok(self.sensors.list.iter().filter_map(move |(sid, sensor)| {
            let centre = match sensor.follow {
                Some(entity) => self.position(entity).ok()? + sensor.centre,
                None => sensor.centre,
            };
            overlaps(body, sensor, centre).then_some(*sid)
        }))
    }

    /// Moves every character one step of `dt` (after the colliders moved).
    pub(crate) fn move_characters(&mut self, dt: f32) {
        self.characters.step(&self.colliders, dt);
    }
}

/// Whether a character's box `(centre, half extents)` (flat: no depth on
/// z) and `sensor` centred at `centre` overlap.
fn overlaps((at, h): (Vec3, Vec3), sensor: &Sensor, centre: Vec3) -> bool {
    match sensor.shape {
        SensorShape::Box { half_extents } => {
            let apart = (at - centre).abs() - (h + half_extents);
            apart.x < 0.0 && apart.y < 0.0 && apart.z <= 0.0
        }
        SensorShape::Sphere { radius } => {
            let nearest = centre.clamp(at - h, at + h);
            (nearest - centre).length_squared() < radius * radius
        }
    }
}
