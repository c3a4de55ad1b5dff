//! The integrators' tests, one module a subject, in one test binary. The
//! allocation test is apart (`tests/no_allocation.rs`): it installs a
//! counting global allocator.

mod angular;
mod blocks;
mod chunking;
mod common;
mod convergence;
mod drag;
mod history_keying;
mod long_runs;
mod newmark_and_trapezoid;
mod partial_restart;
mod particle_churn;
mod solvers_and_errors;
