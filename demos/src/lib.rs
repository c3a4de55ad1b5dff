//! The `tickwork` command line and the demo binaries. Thin by design: every
//! piece of logic a game would need lives in the engine or integrators crates.
#![warn(missing_docs)]

pub mod cli;
