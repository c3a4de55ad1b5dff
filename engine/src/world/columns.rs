//! Where game components live: one dense column per registered type,
//! with its type erased ([`Columns`]), so the world can grow, shrink and
//! copy every column alongside the particle rows.

use core::any::{Any, TypeId, type_name};
use std::collections::BTreeMap;

/// A type a game stores per entity, in its own dense column.
///
/// Every live entity has a value (`Default` for entities spawned before the
/// game set one), so columns stay aligned with the particle rows.
pub trait Component: Clone + Default + Send + Sync + 'static {}

impl<T: Clone + Default + Send + Sync + 'static> Component for T {}

/// A column with its type erased, so the world can grow, shrink and copy it.
trait AnyColumn: Send + Sync {
    fn push_default(&mut self);
    fn swap_remove(&mut self, row: usize);
    fn clone_boxed(&self) -> Box<dyn AnyColumn>;
    fn copy_from(&mut self, other: &dyn AnyColumn);
    fn as_any(&self) -> &dyn Any;
    fn as_any_mut(&mut self) -> &mut dyn Any;
}

impl<T: Component> AnyColumn for Vec<T> {
    fn push_default(&mut self) {
        self.push(T::default());
    }
    fn swap_remove(&mut self, row: usize) {
        Vec::swap_remove(self, row);
    }
    fn clone_boxed(&self) -> Box<dyn AnyColumn> {
        Box::new(self.clone())
    }
    fn copy_from(&mut self, other: &dyn AnyColumn) {
        if let Some(other) = other.as_any().downcast_ref::<Vec<T>>() {
            self.clone_from(other);
        }
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
}

/// The game's columns, keyed by type.
#[derive(Default)]
pub struct Columns {
    // BTreeMap keeps iteration order fixed (deterministic snapshots).
    columns: BTreeMap<TypeId, (&'static str, Box<dyn AnyColumn>)>,
}

impl Clone for Columns {
    fn clone(&self) -> Self {
        Self {
            columns: self
                .columns
                .iter()
                .map(|(id, (name, c))| (*id, (*name, c.clone_boxed())))
                .collect(),
        }
    }

    fn clone_from(&mut self, source: &Self) {
        self.columns.retain(|id, _| source.columns.contains_key(id));
        for (id, (name, column)) in &source.columns {
            match self.columns.get_mut(id) {
                Some((_, mine)) => mine.copy_from(column.as_ref()),
                None => {
                    self.columns.insert(*id, (name, column.clone_boxed()));
                }
            }
        }
    }
}

impl core::fmt::Debug for Columns {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_list()
            .entries(self.columns.values().map(|(name, _)| name))
            .finish()
    }
}

impl Columns {
    /// Adds a column of `T` filled with defaults for `len` rows (no-op if present).
    pub(crate) fn register<T: Component>(&mut self, len: usize) {
        self.columns
            .entry(TypeId::of::<T>())
            .or_insert_with(|| (type_name::<T>(), Box::new(vec![T::default(); len])));
    }

    pub(crate) fn get<T: Component>(&self) -> Option<&Vec<T>> {
        self.columns
            .get(&TypeId::of::<T>())
            .and_then(|(_, c)| c.as_any().downcast_ref())
    }

    pub(crate) fn get_mut<T: Component>(&mut self) -> Option<&mut Vec<T>> {
        self.columns
            .get_mut(&TypeId::of::<T>())
            .and_then(|(_, c)| c.as_any_mut().downcast_mut())
    }

    pub(crate) fn push_defaults(&mut self) {
        for (_, column) in self.columns.values_mut() {
            column.push_default();
        }
    }

    pub(crate) fn swap_remove(&mut self, row: usize) {
        for (_, column) in self.columns.values_mut() {
            column.swap_remove(row);
        }
    }
}
