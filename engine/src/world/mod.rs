//! The ECS-lite world: generational entities over struct-of-arrays columns.
//!
//! Every entity is a particle (position, velocity, mass, radius, colour, age,
//! lifetime); rigid bodies add an orientation in a second table; games add
//! their own typed [`Component`] columns. Rows are dense and removal is
//! `swap_remove`, so spawn and despawn are O(1) and every column stays dense:
//! the vector columns in blocks of four particles per axis the fused step
//! hands the integrator as they are ([`Vec3Column`]), the scalars as slices.
//! The integrator's per-particle history follows the same swap.

/// `Clone` with a field-wise `clone_from`, so copying into an existing value
/// reuses every `Vec`'s buffer (`#[derive(Clone)]` reallocates them all).
macro_rules! clone_fields {
    ($ty:ty { $($field:ident),* $(,)? }) => {
        impl Clone for $ty {
            fn clone(&self) -> Self {
                Self { $($field: self.$field.clone()),* }
            }
            fn clone_from(&mut self, source: &Self) {
                $(self.$field.clone_from(&source.$field);)*
            }
        }
    };
}

mod checksum;
mod colliders;
pub(crate) mod column;
mod components;
mod config;
mod dynamics;
mod entities;
mod entity;
pub(crate) mod facts;
mod particle_data;
mod particles;
mod rigid;
mod snapshot;
#[allow(clippy::module_inception)] // named after the type it defines, which a newcomer looks for
mod world;

pub use checksum::StableHasher;
pub use column::{RowsMut, Vec3Column};
pub use components::{Component, QueryMut};
pub use config::{WorldConfig, WorldError};
pub use entity::{Entities, Entity, EntityError};
pub use particles::{Colour, Particle, Particles, SpawnError};
pub use rigid::{RigidBodies, RigidBody};
pub use snapshot::Snapshot;
pub use world::World;

pub(crate) use crate::step::{Lane, Rows};
pub(crate) use entities::Command;
