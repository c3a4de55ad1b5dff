//! Generational entity handles and the map from handles to dense rows.

use core::fmt;

/// A handle to an entity: a slot index and the generation of that slot.
///
/// When an entity is despawned its slot's generation is bumped, so an old
/// handle never reaches a later entity that reuses the slot: using it is an
/// [`EntityError`].
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Entity {
    index: u32,
    generation: u32,
}

impl Entity {
    /// A handle that names no entity in any world (every call with it is an
    /// [`EntityError::Unknown`]), for a game's fields before its set-up
    /// spawns what they name; also `Entity::default()`.
    pub const PLACEHOLDER: Self = Self {
        index: u32::MAX,
        generation: 0,
    };

    /// The slot index (stable while the entity lives; not its row).
    #[must_use]
    pub fn index(self) -> u32 {
        self.index
    }

    /// The slot's generation when this handle was made.
    #[must_use]
    pub fn generation(self) -> u32 {
        self.generation
    }

    /// The handle as one number (index in the low bits), for traces and files.
    #[must_use]
    pub fn to_bits(self) -> u64 {
        u64::from(self.generation) << 32 | u64::from(self.index)
    }
}

impl fmt::Debug for Entity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}v{}", self.index, self.generation)
    }
}

impl Default for Entity {
    fn default() -> Self {
        Self::PLACEHOLDER
    }
}

/// `3v1` (index 3, generation 1), as Bevy and hecs show a handle; messages
/// say "entity 3v1".
impl fmt::Display for Entity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if *self == Self::PLACEHOLDER {
            return f.write_str("Entity::PLACEHOLDER (a handle set before anything was spawned)");
        }
        write!(f, "{}v{}", self.index, self.generation)
    }
}

/// Using a handle that does not name a live entity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EntityError {
    /// The entity was despawned (its slot has moved on to a later generation).
    Despawned {
        /// The stale handle.
        entity: Entity,
    },
    /// The entity's spawn is queued and applies at the end of the step.
    Pending {
        /// The handle.
        entity: Entity,
    },
    /// The handle was never issued by this world.
    Unknown {
        /// The handle.
        entity: Entity,
    },
}

impl fmt::Display for EntityError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Despawned { entity } => write!(f, "entity {entity} was despawned"),
            Self::Pending { entity } => write!(f, "entity {entity} is queued for spawning at the end of the step"),
            Self::Unknown { entity } => write!(f, "entity {entity} was never spawned in this world"),
        }
    }
}

impl std::error::Error for EntityError {}

const FREE: u32 = u32::MAX;
const PENDING: u32 = u32::MAX - 1;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Slot {
    generation: u32,
    /// Row in the dense columns, or `FREE` / `PENDING`.
    row: u32,
}

/// The allocator of handles and the two-way map between handles and rows.
///
/// Rows are dense (0..len) and follow `swap_remove`: removing row `r` moves
/// the last row into `r`, and the moved entity's slot is updated, so every
/// operation is O(1).
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Entities {
    slots: Vec<Slot>,
    free: Vec<u32>,
    rows: Vec<Entity>,
}

impl Entities {
    /// Allocates a handle not yet bound to a row (a queued spawn).
    pub(crate) fn reserve(&mut self) -> Entity {
        if let Some(index) = self.free.pop() {
            let slot = &mut self.slots[index as usize];
            slot.row = PENDING;
            Entity {
                index,
                generation: slot.generation,
            }
        } else {
            let index = u32::try_from(self.slots.len())
                .unwrap_or(u32::MAX - 2)
                .min(u32::MAX - 2);
            self.slots.push(Slot {
                generation: 1,
                row: PENDING,
            });
            Entity { index, generation: 1 }
        }
    }

    /// Binds a reserved handle to the next row (`len`).
    pub(crate) fn bind(&mut self, entity: Entity) -> usize {
        let row = self.rows.len();
        self.slots[entity.index as usize].row = row as u32;
        self.rows.push(entity);
        row
    }

    fn release(&mut self, index: u32) {
        let slot = &mut self.slots[index as usize];
        slot.row = FREE;
        slot.generation = slot.generation.wrapping_add(1);
        // A slot whose generation would wrap is retired, never reused.
        if slot.generation != 0 {
            self.free.push(index);
        }
    }

    /// The row of a live entity.
    ///
    /// # Errors
    /// [`EntityError`] saying why the handle names no live entity.
    pub fn row(&self, entity: Entity) -> Result<usize, EntityError> {
        match self.slots.get(entity.index as usize) {
            Some(slot) if slot.generation == entity.generation => match slot.row {
                FREE => Err(EntityError::Despawned { entity }),
                PENDING => Err(EntityError::Pending { entity }),
                row => Ok(row as usize),
            },
            Some(slot) if entity.generation < slot.generation && entity.generation > 0 => {
                Err(EntityError::Despawned { entity })
            }
            _ => Err(EntityError::Unknown { entity }),
        }
    }

    /// Unbinds `entity` from its row with swap-remove semantics. Returns the
    /// removed row; the entity that was last now lives there.
    pub(crate) fn swap_remove(&mut self, entity: Entity) -> Result<usize, EntityError> {
        let row = self.row(entity)?;
        self.rows.swap_remove(row);
        if let Some(moved) = self.rows.get(row) {
            self.slots[moved.index as usize].row = row as u32;
        }
        self.release(entity.index);
        Ok(row)
    }

    /// The entity in each row.
    #[must_use]
    pub fn rows(&self) -> &[Entity] {
        &self.rows
    }

    /// Number of live entities.
    #[must_use]
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether no entity lives.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// Whether the handle names a live entity.
    #[must_use]
    pub fn contains(&self, entity: Entity) -> bool {
        self.row(entity).is_ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stale_handles_never_reach_later_entities() {
        let mut e = Entities::default();
        let a = e.reserve();
        e.bind(a);
        let b = e.reserve();
        e.bind(b);
        assert_eq!(e.swap_remove(a), Ok(0));
        assert_eq!(e.row(b), Ok(0), "the last row moved into the hole");
        let c = e.reserve();
        e.bind(c);
        assert_eq!(c.index(), a.index(), "the slot is reused");
        assert_ne!(c, a);
        assert_eq!(e.row(a), Err(EntityError::Despawned { entity: a }));
        assert_eq!(e.row(c), Ok(1));
        assert_eq!(e.swap_remove(a), Err(EntityError::Despawned { entity: a }));
        let pending = e.reserve();
        assert_eq!(e.row(pending), Err(EntityError::Pending { entity: pending }));
        let forged = Entity {
            index: 99,
            generation: 1,
        };
        assert_eq!(e.row(forged), Err(EntityError::Unknown { entity: forged }));
        assert_eq!(
            EntityError::Despawned { entity: a }.to_string(),
            "entity 0v1 was despawned"
        );
        // The handle alone, as Bevy and hecs show it: "entity {e}" in a
        // game's message reads once.
        assert_eq!(format!("entity {forged}"), "entity 99v1");
    }
}

clone_fields!(Entities { slots, free, rows });
