//! The fixed step on the GPU: a particle world's state in storage buffers,
//! stepped by compute dispatches, each method's formula a WGSL file of its
//! own (`engine/shaders/gpu_step/`), checked against the CPU's f32 step.
//!
//! A [`GpuWorld`] is made from a [`World`](crate::World): its particles are
//! uploaded once, then [`GpuWorld::step`] records any number of fixed steps
//! into one command buffer, one dispatch each, or [`GpuWorld::advance`]
//! runs one fixed step of the world with the world's own lifetimes,
//! emitters and spawns on the CPU and the GPU's rows following the
//! world's (`rows.rs`); nothing comes back unless asked for
//! ([`GpuWorld::read_back`], which says what it costs). The runners step
//! a world here when its `WorldConfig::backend` says so (`app/backend.rs`).
//! What the GPU step does not do (yet) is refused when the world is made,
//! with an error naming it ([`GpuStepError`]): the methods are explicit
//! and semi-implicit Euler, midpoint, Heun, RK4, Forest-Ruth, velocity
//! Verlet, leapfrog, position Verlet, Beeman and Adams-Bashforth 2-4 (the
//! history ones with their history in a buffer, restarted as the CPU's);
//! the forces gravity, wind, linear and quadratic drag and attractors
//! (their values written into the world's shader as exact bits) and n-body
//! (a tiled all-pairs kernel, a round for each evaluation of the method:
//! every particle's trial positions there, then the sums);
//! the colliders planes whose normal is an axis and boxes (containers and
//! solid), at rest or kinematic, with restitution and friction, their
//! contacts found inside the step (`ContactRule::InStep`, the default:
//! `in_step.wgsl`, the CPU's rule in f32, each contact at its instant) or
//! resolved at the end of the step in their order, and read back where
//! they report them. Subnormal velocities are flushed to 0 after the same
//! ticks as on the CPU (every 64th).
//!
//! Bits: for every method the GPU performs the CPU's operations in the
//! CPU's order (coefficients the CPU computes in f64, Forest-Ruth's, come
//! computed; dot products summed as glam sums them), so where the driver
//! fuses no multiply-add, rounds `sqrt` and division correctly and keeps
//! subnormal numbers (WGSL requires none of these) the states are the
//! CPU's bit for bit, as on lavapipe (tested). What the CPU's step checks
//! every step, the GPU's does not: a position or velocity that becomes
//! infinite or NaN is not reported (read the state back to look). The GPU's states are the same on the
//! same adapter and driver, run to run: no result depends on the order of
//! atomic operations (the flags' ORs, the n-body rounds' maximum and the
//! contacts' slots give the same words in any order, and the contacts are
//! sorted on the CPU).

mod dispatch;
mod error;
mod kernel;
mod rows;
mod world;

pub use dispatch::WORKGROUP;
pub use error::GpuStepError;
pub use kernel::methods;
pub(crate) use kernel::takes_method;
pub use world::GpuWorld;
