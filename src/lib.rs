//! Tickwork: a fixed-timestep game loop with pluggable, verified numerical
//! integrators. This facade re-exports the workspace's crates:
//!
//! - [`integrators`]: every time-integration method, by name, verified to its order;
//! - [`engine`]: the clock, world, forces, scenes and renderer.
#![warn(missing_docs)]

pub use tickwork_engine as engine;
pub use tickwork_integrators as integrators;

/// The README's examples, compiled and run as doctests so they never rot.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
