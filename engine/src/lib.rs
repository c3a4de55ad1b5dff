//! The Tickwork engine: the fixed-step clock, the particle world, forces,
//! scenes and rendering. It starts as the home of the integrators' engine-side
//! re-exports; the engine issue fills it.
#![warn(missing_docs)]

pub use tickwork_integrators as integrators;
