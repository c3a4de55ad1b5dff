//! The facade crate's tests, and the repository's documents kept true: one
//! test binary.

mod facade;
mod readme;
