//! The Tickwork engine: the fixed-step clock, the particle world, forces,
//! colliders, scenes and the headless simulator.
//!
//! Data flows one way: time source -> [`FixedClock`] -> fixed steps (forces ->
//! integrator -> colliders) -> interpolation -> renderer. The clock knows
//! nothing of the world; integrators know nothing of entities.
//!
//! Determinism: the same scene, seed and per-tick inputs give bit-identical
//! states, whatever the frame timing and the number of threads.
#![warn(missing_docs)]
#![allow(clippy::needless_range_loop)]

pub mod clock;
pub mod colliders;
pub mod emitter;
pub mod energy;
pub mod forces;
pub mod headless;
pub mod input;
pub mod scene;
mod step;
pub mod world;

pub use clock::{ClockConfig, ClockError, FixedClock, FixedStep, Frame, HitchPolicy, Rate, TimeSource};
pub use colliders::{BoxCollider, Collider, Material, Plane, SphereCollisions};
pub use emitter::Emitter;
pub use energy::Energy;
pub use forces::{Attractor, Force, Gravity, LinearDrag, NBody, QuadraticDrag, Spring, SpringEnd, Springs, Wind};
pub use headless::{HeadlessError, RunSummary, TraceWriter, run_headless};
pub use input::{InputLog, InputQueue};
pub use scene::{Scene, SceneError};
pub use step::{CHUNK, SimulationError, StepReport};
pub use tickwork_integrators as integrators;
pub use world::{Entity, EntityError, Particle, RigidBody, Snapshot, SpawnError, World, WorldConfig, WorldError};
