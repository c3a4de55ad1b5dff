//! The ECS-lite world: generational entities over struct-of-arrays columns.
//!
//! Every entity is a particle (position, velocity, mass, radius, colour, age,
//! lifetime); rigid bodies add an orientation in a second table; games add
//! their own typed [`Component`] columns. Rows are dense and removal is
//! `swap_remove`, so spawn and despawn are O(1) and every column stays dense:
//! the vector columns in blocks of four particles per axis the fused step
//! hands the integrator as they are ([`Vec3Column`]), the scalars as slices.
//! The integrator's per-particle history follows the same swap.

mod character_set;
mod characters;
mod checksum;
mod colliders;
mod columns;
mod command;
mod components;
mod config;
mod dynamics;
#[cfg(feature = "render")]
mod elsewhere;
mod entities;
pub(crate) mod facts;
mod heading;
mod lane;
mod particle_data;
mod particles;
mod removal;
mod rigid;
mod sensor_set;
mod sensors;
mod snapshot;
#[allow(clippy::module_inception)] // named after the type it defines, which a newcomer looks for
mod world;

pub use checksum::StableHasher;
pub use columns::Component;
pub use components::QueryMut;
pub use config::{Backend, ContactOverflow, WorldConfig, WorldError};
pub use heading::Heading;
pub use particles::Particles;
pub use removal::{Removal, RemovalCause};
pub use rigid::{RigidBodies, RigidBody};
pub use snapshot::Snapshot;
#[cfg(feature = "render")]
pub(crate) use world::RowChange;
pub use world::World;

pub use crate::layout::{Colour, Entities, Entity, EntityError, Particle, RowsMut, SpawnError, Vec3Column};
pub(crate) use command::Command;
pub(crate) use lane::{Lane, SweepScratch};
pub(crate) use sensor_set::Sensors;
