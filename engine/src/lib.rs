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

pub mod clock;

pub use clock::{ClockConfig, ClockError, FixedClock, FixedStep, Frame, HitchPolicy, Rate, TimeSource};
pub use tickwork_integrators as integrators;
