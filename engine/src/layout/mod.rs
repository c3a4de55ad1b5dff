//! How particles are named and laid out, below everything that acts on
//! them: entity handles and the rows they map to ([`Entity`],
//! [`Entities`]), what a spawn describes ([`Particle`]), the per-axis
//! block columns ([`Vec3Column`]), scratch rows ([`Rows`]) and the chunk
//! the fused step works in ([`CHUNK`]).
//!
//! Forces, colliders and emitters use these; the world stores them with
//! the forces, colliders and emitters; the step drives the world. So
//! imports point one way, as the data flows (`engine/tests/modules.rs`
//! checks it): step -> world -> forces, colliders, emitter -> layout.

mod column;
mod entity;
mod particle;
mod rows;

pub(crate) use column::{LANES, gather, scatter};
pub use column::{RowsMut, Vec3Column};
pub use entity::{Entities, Entity, EntityError};
pub(crate) use particle::check_vector;
pub use particle::{Colour, Particle, SpawnError};
pub(crate) use rows::Rows;

/// Particles integrated together in the fused step: the integrators'
/// chunk, defined once (see [`tickwork_integrators::CHUNK`]).
pub use tickwork_integrators::CHUNK;
