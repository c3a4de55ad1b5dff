//! The `tickwork` command line and the demo binaries. Thin by design: every
//! piece of logic a game would need lives in the engine or integrators
//! crates. The integrator lab lives here because no game needs it: it is a
//! tool for comparing methods.
#![warn(missing_docs)]

pub mod breakout;
// The command line and the lab are native tools (files, plots, a
// terminal); the games build for the browser too.
#[cfg(not(target_arch = "wasm32"))]
pub mod cli;
#[cfg(not(target_arch = "wasm32"))]
pub mod lab;
pub mod lander;
pub mod platformer;
pub mod rally;
