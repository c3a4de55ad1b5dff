//! The characters a world holds (the data and their step; what a world
//! does with them is in `characters.rs`).

use crate::character::{Character, CharacterError, CharacterId, Solids, step_character};
use crate::colliders::set::ColliderSet;

/// The characters of a world, in the order added, with their handles.
#[derive(Clone, Debug, Default)]
pub(crate) struct Characters {
    pub list: Vec<(CharacterId, Character)>,
    /// The next id to hand out (ids are never reused).
    pub next: u64,
}

impl Characters {
    pub fn index(&self, id: CharacterId) -> Result<usize, CharacterError> {
        // Ids ascend with the list (removal keeps the order).
        self.list
            .binary_search_by_key(&id, |(k, _)| *k)
            .map_err(|_| CharacterError::Unknown { id })
    }

    /// Moves every character one step of `dt` among `colliders`.
    pub fn step(&mut self, colliders: &ColliderSet, dt: f32) {
        let solids = Solids {
            colliders: &colliders.colliders,
            ids: &colliders.ids,
        };
        for (_, character) in &mut self.list {
            step_character(character, &solids, dt);
        }
    }
}
