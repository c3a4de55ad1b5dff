//! The scene file format: serde types that mirror the RON text.
//!
//! Values are checked while they are read (finite vectors, positive masses,
//! known integrator names, spring ends that exist), so an error carries the
//! line and column where the bad value is, and the field path.
//!
//! One file per part of the format: the file's root ([`SceneFile`], in
//! `scene_file.rs`), then what it lists: `camera.rs`, `force.rs`,
//! `collider.rs`, `particle.rs`, `lattice.rs`, `emitter.rs`,
//! `rigid_body.rs`; the values they share: `rate.rs`, `method_name.rs`,
//! `colour.rs`, the checked `numbers.rs` and `vectors.rs`, and
//! `particle_index.rs`; and the checks across an item's fields,
//! `check_item.rs`.

mod camera;
mod check_item;
mod collider;
mod colour;
mod emitter;
mod force;
mod lattice;
mod method_name;
mod numbers;
mod particle;
mod particle_index;
mod rate;
mod rigid_body;
mod scene_file;
mod vectors;

pub use camera::{CameraHint, Projection};
pub use collider::{ColliderSpec, ContactSpec, MaterialSpec};
pub use colour::ColourSpec;
pub use emitter::EmitterSpec;
pub use force::{EndSpec, ForceSpec};
pub use lattice::{LatticeCount, LatticeSpec, MAX_LATTICE_PARTICLES};
pub use method_name::MethodName;
pub use numbers::{Finite, NonNegative, Positive, Unit};
pub use particle::ParticleSpec;
pub(crate) use particle_index::PARTICLE_COUNT;
pub use particle_index::ParticleIndex;
pub use rate::RateSpec;
pub use rigid_body::{Orientation, RigidBodySpec};
pub use scene_file::SceneFile;
pub use vectors::{Direction, Vector};
