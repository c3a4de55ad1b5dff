//! Game components: typed columns that games attach to every entity, and
//! the world's calls that reach them (`insert`, `get`, `query_mut`).

use core::any::{Any, TypeId, type_name};
use std::collections::BTreeMap;

use super::{Entity, RowsMut, World, WorldError};

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

/// Mutable access to the position and velocity columns and one game column,
/// row by row (all slices have the same length; `entities[i]` owns row `i`).
#[derive(Debug)]
pub struct QueryMut<'a, T> {
    /// The entity of each row.
    pub entities: &'a [Entity],
    /// Positions.
    pub position: RowsMut<'a>,
    /// Velocities.
    pub velocity: RowsMut<'a>,
    /// The game's column.
    pub component: &'a mut [T],
}

impl World {
    /// Adds a column of `T` to every entity (default values). Registering twice is a no-op.
    pub fn register<T: Component>(&mut self) {
        self.columns.register::<T>(self.entities.len());
    }

    /// Sets an entity's `T`.
    ///
    /// # Errors
    /// [`WorldError`] for a dead handle or an unregistered `T`.
    pub fn insert<T: Component>(&mut self, entity: Entity, value: T) -> Result<(), WorldError> {
        *self.get_mut::<T>(entity)? = value;
        Ok(())
    }

    /// An entity's `T`.
    ///
    /// # Errors
    /// [`WorldError`] for a dead handle or an unregistered `T`.
    pub fn get<T: Component>(&self, entity: Entity) -> Result<&T, WorldError> {
        let row = self.row(entity)?;
        let column = self.columns.get::<T>().ok_or_else(unregistered::<T>)?;
        Ok(&column[row])
    }

    /// An entity's `T`, mutable.
    ///
    /// # Errors
    /// [`WorldError`] for a dead handle or an unregistered `T`.
    pub fn get_mut<T: Component>(&mut self, entity: Entity) -> Result<&mut T, WorldError> {
        let row = self.row(entity)?;
        let column = self.columns.get_mut::<T>().ok_or_else(unregistered::<T>)?;
        Ok(&mut column[row])
    }

    /// The whole column of `T`, row-aligned with the particle columns.
    ///
    /// # Errors
    /// [`WorldError::UnregisteredComponent`] for an unregistered `T`.
    pub fn column<T: Component>(&self) -> Result<&[T], WorldError> {
        self.columns.get::<T>().map(Vec::as_slice).ok_or_else(unregistered::<T>)
    }

    /// Positions, velocities and the column of `T`, mutable, row by row.
    ///
    /// # Errors
    /// [`WorldError::UnregisteredComponent`] for an unregistered `T`.
    pub fn query_mut<T: Component>(&mut self) -> Result<QueryMut<'_, T>, WorldError> {
        let component = self.columns.get_mut::<T>().ok_or_else(unregistered::<T>)?;
        Ok(QueryMut {
            entities: self.entities.rows(),
            position: RowsMut::new(&mut self.particles.position),
            velocity: RowsMut::new(&mut self.particles.velocity),
            component,
        })
    }
}

fn unregistered<T>() -> WorldError {
    WorldError::UnregisteredComponent {
        type_name: core::any::type_name::<T>(),
    }
}
