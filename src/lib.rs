//! Tickwork: a fixed-timestep game loop with pluggable, verified numerical
//! integrators. This facade re-exports the workspace's crates.
#![warn(missing_docs)]

pub use tickwork_engine as engine;
pub use tickwork_integrators as integrators;
