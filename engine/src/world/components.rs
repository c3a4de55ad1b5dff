//! Game components: the world's calls that reach the typed columns games
//! attach to every entity (`register`, `insert`, `get`, `query_mut`).

use super::{Component, Entity, RowsMut, World, WorldError};

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
