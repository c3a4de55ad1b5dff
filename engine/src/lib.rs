//! The Tickwork engine: the fixed-step clock, the particle world, forces,
//! colliders, scenes and the headless simulator.
//!
//! Data flows one way: time source -> [`FixedClock`] -> fixed steps (forces ->
//! integrator -> colliders) -> interpolation -> renderer. The clock knows
//! nothing of the world; integrators know nothing of entities.
//!
//! Priorities, in order: results you can trust (every method at its order,
//! errors instead of silent clamps), determinism (the same scene, seed and
//! per-tick inputs give bit-identical states, whatever the frame timing and
//! the number of threads), then speed (no allocation in steady steps,
//! cache-sized chunks spread over threads).
//!
//! ```
//! use glam::Vec3;
//! use tickwork_engine::{FixedClock, Gravity, Particle, World};
//!
//! let mut world = World::default(); // semi-implicit Euler
//! world.add_force(Gravity::EARTH);
//! let ball = world.spawn(Particle { velocity: Vec3::new(2.0, 5.0, 0.0), ..Particle::default() })?;
//! let mut clock = FixedClock::default(); // 60 Hz
//! for step in clock.step(60).fixed_steps() {
//!     world.step(step)?;
//! }
//! assert_eq!(world.tick(), 60);
//! assert!((world.position(ball)?.x - 2.0).abs() < 1e-4); // x = vx t
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]
#![allow(clippy::needless_range_loop)]

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

#[cfg(feature = "render")]
pub mod app;
pub mod character;
pub mod clock;
pub mod colliders;
#[cfg(feature = "render")]
mod device;
pub mod emitter;
pub mod energy;
pub mod forces;
#[cfg(feature = "render")]
pub mod gpu_step;
pub mod headless;
pub mod input;
pub mod interpolation;
mod layout;
pub mod platform;
#[cfg(feature = "render")]
pub mod render;
pub mod scene;
pub mod sensor;
mod step;
mod text_file;
pub mod threads;
#[cfg(feature = "tiled")]
pub mod tilemap;
pub mod world;

pub use character::{Character, CharacterConfig, CharacterError, CharacterId, Ground, Touch};
pub use clock::{ClockConfig, ClockError, FixedClock, FixedStep, Frame, HitchPolicy, Rate, TimeSource, Timeline};
pub use colliders::{
    AxisPlane, BlockColumns, BoxCollider, Collider, ColliderError, ColliderId, Contact, ContactRule, GpuCollider,
    Material, Plane, SphereCollisions, Touched,
};
pub use emitter::Emitter;
pub use energy::Energy;
pub use forces::{
    Attractor, Force, GpuForce, Gravity, LinearDrag, NBody, QuadraticDrag, Spring, SpringEnd, Springs, WgslF32, Wind,
};
/// The math crate of every public type (`Vec3`, `Quat`), re-exported so
/// games use the same version.
pub use glam;
pub use headless::{HeadlessError, HeadlessSummary, TraceWriter, run_headless};
pub use input::{InputEvent, InputQueue, Key, KeySet, Recording, TickInput};
pub use layout::CHUNK;
pub use scene::{Scene, SceneError};
pub use sensor::{Overlap, OverlapPhase, Sensor, SensorError, SensorId, SensorShape};
pub use step::{NonFiniteCause, SUBNORMAL_FLUSH_EVERY, SimulationError, StepReport};
pub use tickwork_integrators as integrators;
/// Transcendental functions with the same bits on every platform (libm):
/// what a step calls instead of `f32::sin` and friends.
pub use tickwork_integrators::math;
pub use world::{
    ContactOverflow, Entity, EntityError, Heading, Particle, Removal, RemovalCause, RigidBody, Snapshot, SpawnError,
    StableHasher, World, WorldConfig, WorldError,
};
