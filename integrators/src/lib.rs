//! Numerical time integrators for particle systems: every method of the
//! game-loop lecture, each verified to its stated order.
//!
//! Design priorities, in order:
//! 1. **Correct to the stated order**, including under velocity-dependent
//!    forces, and honest where a method's order drops (the registry says so).
//! 2. **Whole-slice stepping through one callback**: a method advances all
//!    particles at once and calls [`System::acceleration`] on whole trial
//!    states, so coupled forces (springs, n-body) are right in multi-stage
//!    methods.
//! 3. **No allocation in steady state**: scratch and history buffers belong to
//!    the method, grow with the particle count and follow `swap_remove`.
//! 4. **Generic over the vector type** ([`Vector`]): `f64`/`DVec3` for accuracy,
//!    `f32`/`Vec3A` for games, with no glam types in the method files.
//!
//! ```
//! use tickwork_integrators::{build, Integrator};
//!
//! // A unit harmonic oscillator, x'' = -x, stepped by name.
//! let mut method = build::<f64>("velocity_verlet").unwrap();
//! let (mut x, mut v) = (vec![1.0], vec![0.0]);
//! let mut spring = |_t: f64, x: &[f64], _v: &[f64], a: &mut [f64]| {
//!     for (a, x) in a.iter_mut().zip(x) {
//!         *a = -*x;
//!     }
//! };
//! let dt = 0.01;
//! for n in 0..628 {
//!     method.step(n as f64 * dt, dt, &mut x, &mut v, &mut spring).unwrap();
//! }
//! assert!((x[0] - 6.28f64.cos()).abs() < 1e-4);
//! ```
//!
//! Angular motion (orientation quaternions and torque-free rigid bodies) has
//! its own, smaller interface in [`angular`].
#![warn(missing_docs)]
// Update formulas index several parallel columns (x, v, a, history) by particle;
// zip chains of five slices would hide the formula the loop implements.
#![allow(clippy::needless_range_loop)]

pub mod angular;
mod block;
mod chunks;
mod history;
mod integrator;
pub mod methods;
mod newton_krylov;
mod registry;
mod system;
mod vector;

pub use block::Vec3x4;
pub use chunks::CHUNK;
pub use integrator::{Integrator, IntegratorState, MethodInfo, StepError, StepStats};
pub use methods::adams_bashforth::AdamsBashforth;
pub use methods::adams_bashforth2::AdamsBashforth2;
pub use methods::adams_bashforth3::AdamsBashforth3;
pub use methods::adams_bashforth4::AdamsBashforth4;
pub use methods::beeman::Beeman;
pub use methods::dormand_prince::DormandPrince;
pub use methods::explicit_euler::ExplicitEuler;
pub use methods::exponential_euler::ExponentialEuler;
pub use methods::forest_ruth::ForestRuth;
pub use methods::heun::Heun;
pub use methods::implicit_drag_euler::ImplicitDragEuler;
pub use methods::implicit_euler::ImplicitEuler;
pub use methods::leapfrog::Leapfrog;
pub use methods::midpoint::Midpoint;
pub use methods::newmark_beta::NewmarkBeta;
pub use methods::position_verlet::PositionVerlet;
pub use methods::predictor_corrector_euler::PredictorCorrectorEuler;
pub use methods::rk4::Rk4;
pub use methods::semi_implicit_euler::SemiImplicitEuler;
pub use methods::trapezoidal::Trapezoidal;
pub use methods::velocity_verlet::VelocityVerlet;
pub use newton_krylov::NewtonKrylovConfig;
pub use registry::{METHODS, UnknownMethod, build, find};
pub use system::System;
pub use vector::{Real, Vector};
