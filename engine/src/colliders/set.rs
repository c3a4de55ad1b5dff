//! A world's colliders with their handles and whether each reports contacts.

use core::fmt;

use super::Collider;
use super::contacts::ColliderId;

/// The colliders of a world, in the order they were added (the order they
/// act in), each with its [`ColliderId`].
#[derive(Debug, Default)]
pub(crate) struct ColliderSet {
    pub colliders: Vec<Box<dyn Collider>>,
    pub ids: Vec<ColliderId>,
    /// Whether each collider reports contacts.
    pub reports: Vec<bool>,
    /// The next id to hand out (ids are never reused).
    next: u64,
}

impl Clone for ColliderSet {
    fn clone(&self) -> Self {
        Self {
            colliders: self.colliders.clone(),
            ids: self.ids.clone(),
            reports: self.reports.clone(),
            next: self.next,
        }
    }

    fn clone_from(&mut self, source: &Self) {
        self.colliders.clone_from(&source.colliders);
        self.ids.clone_from(&source.ids);
        self.reports.clone_from(&source.reports);
        self.next = source.next;
    }
}

impl ColliderSet {
    pub fn push(&mut self, collider: Box<dyn Collider>) -> ColliderId {
        let id = ColliderId(self.next);
        // 64 bits: a game adding a collider every microsecond runs out
        // after half a million years.
        self.next += 1;
        self.colliders.push(collider);
        self.ids.push(id);
        self.reports.push(false);
        id
    }

    /// The index of `id` in the list.
    pub fn index(&self, id: ColliderId) -> Result<usize, ColliderError> {
        // Ids ascend with the list (removal keeps the order): a binary search.
        self.ids.binary_search(&id).map_err(|_| ColliderError::Unknown { id })
    }

    pub fn remove(&mut self, id: ColliderId) -> Result<Box<dyn Collider>, ColliderError> {
        let k = self.index(id)?;
        self.ids.remove(k);
        self.reports.remove(k);
        Ok(self.colliders.remove(k))
    }

    /// Whether any collider reports contacts.
    pub fn any_reports(&self) -> bool {
        self.reports.iter().any(|r| *r)
    }
}

/// A collider handle that names no collider of the world, or of the
/// wanted type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColliderError {
    /// The collider was removed, or the handle is from another world.
    Unknown {
        /// The handle.
        id: ColliderId,
    },
    /// The collider is of another type than the one asked for.
    WrongType {
        /// The handle.
        id: ColliderId,
        /// Its collider's name (`"plane"`).
        actual: &'static str,
        /// The type asked for.
        wanted: &'static str,
    },
}

impl fmt::Display for ColliderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Unknown { id } => write!(f, "{id} is not in this world (removed, or from another world)"),
            Self::WrongType { id, actual, wanted } => {
                write!(f, "{id} is a {actual} collider, not a {wanted}")
            }
        }
    }
}

impl std::error::Error for ColliderError {}
