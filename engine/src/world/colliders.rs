//! The world's colliders through their handles, and the contacts of the
//! last step.

use super::World;
use crate::colliders::{Collider, ColliderError, ColliderId, Contact};

impl World {
    /// Adds a collider and returns its handle, to change it
    /// ([`collider_mut`](Self::collider_mut)), remove it, or have it report
    /// contacts ([`report_contacts`](Self::report_contacts)). Colliders act
    /// in the order they were added.
    pub fn add_collider(&mut self, collider: impl Collider + 'static) -> ColliderId {
        self.colliders.push(Box::new(collider))
    }

    /// The collider `id`, as its type `T` (a [`Plane`](crate::Plane), a
    /// [`BoxCollider`](crate::BoxCollider), a game's own).
    ///
    /// # Errors
    /// [`ColliderError`] for a removed or foreign handle, or another type.
    pub fn collider<T: Collider + 'static>(&self, id: ColliderId) -> Result<&T, ColliderError> {
        let collider = &self.colliders.colliders[self.colliders.index(id)?];
        collider.as_any().downcast_ref::<T>().ok_or(ColliderError::WrongType {
            id,
            actual: collider.name(),
            wanted: short_type_name::<T>(),
        })
    }

    /// The collider `id`, as its type `T`, to change between steps (a
    /// paddle's velocity, a door's position).
    ///
    /// # Errors
    /// [`ColliderError`] for a removed or foreign handle, or another type.
    pub fn collider_mut<T: Collider + 'static>(&mut self, id: ColliderId) -> Result<&mut T, ColliderError> {
        let k = self.colliders.index(id)?;
        let collider = &mut self.colliders.colliders[k];
        let actual = collider.name();
        collider
            .as_any_mut()
            .downcast_mut::<T>()
            .ok_or(ColliderError::WrongType {
                id,
                actual,
                wanted: short_type_name::<T>(),
            })
    }

    /// Removes the collider `id` (a broken brick) and returns it; the
    /// others keep their handles and their order.
    ///
    /// # Errors
    /// [`ColliderError::Unknown`] for a removed or foreign handle.
    pub fn remove_collider(&mut self, id: ColliderId) -> Result<Box<dyn Collider>, ColliderError> {
        self.colliders.remove(id)
    }

    /// Whether the collider `id` is in this world.
    #[must_use]
    pub fn has_collider(&self, id: ColliderId) -> bool {
        self.colliders.index(id).is_ok()
    }

    /// The colliders with their handles, in the order they act.
    pub fn colliders(&self) -> impl Iterator<Item = (ColliderId, &dyn Collider)> {
        self.colliders
            .ids
            .iter()
            .zip(&self.colliders.colliders)
            .map(|(id, c)| (*id, c.as_ref()))
    }

    /// Has the collider `id` report its contacts from the next step on
    /// ([`contacts`](Self::contacts)). A reporting collider is resolved on
    /// rows rather than blocks of four (for a floor under a million
    /// particles, several times slower); its physics is the same bits.
    ///
    /// # Errors
    /// [`ColliderError::Unknown`] for a removed or foreign handle.
    pub fn report_contacts(&mut self, id: ColliderId) -> Result<(), ColliderError> {
        let k = self.colliders.index(id)?;
        self.colliders.reports[k] = true;
        Ok(())
    }

    /// The contacts the last step found, for the colliders that report
    /// them: one per entity and collider it touched, one per touching pair
    /// of spheres; ordered by collider (in the order they were added), then
    /// by the entity's row, the same on any number of threads. Read them
    /// in a game's next `fixed_update`, or after [`step`](Self::step); the
    /// next step replaces them.
    ///
    /// A contact is a collider acting on an entity in the step: a particle
    /// resting on a floor under gravity reports one every step (the floor
    /// stops it each step), and one the collider leaves alone (nothing
    /// pulls it in, it does not move) reports none, as one that does not
    /// touch. "Grounded" is a contact with the ground this step.
    #[must_use]
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }
}

/// `BoxCollider` for `tickwork_engine::colliders::aabb::BoxCollider`.
fn short_type_name<T>() -> &'static str {
    let name = core::any::type_name::<T>();
    name.rsplit("::").next().unwrap_or(name)
}
