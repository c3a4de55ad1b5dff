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
pub mod math;
mod newton_krylov;
mod registry;
mod system;
mod vector;

pub use block::Vec3x4;
pub use chunks::CHUNK;
pub use integrator::{Integrator, IntegratorState, MethodInfo, StepError, StepStats};
pub use newton_krylov::NewtonKrylovConfig;
pub use registry::{UnknownMethod, build, find};
pub use system::System;
pub use vector::{Real, Vector};

/// Registers the methods in one place. Each entry names a method's file
/// (under `methods/`) and type, and the registry entries it gives: an
/// `INFO` constant and the constructor that builds it. From this one list
/// come the `methods` modules, the re-exports of the types, [`METHODS`]
/// (in the list's order) and the constructor behind [`build`]; adding a
/// method is one line here and its file.
macro_rules! methods {
    ($($module:ident :: $ty:ident { $($info:ident => $constructor:ident),* $(,)? }),* $(,)?) => {
        /// One file per method. Each opens with its update formula, order,
        /// cost and stability, then its registry entry and implementation.
        pub mod methods {
            $(pub mod $module;)*
        }

        $(pub use methods::$module::$ty;)*

        /// Every method, in the order of the lecture (first-order,
        /// second-order, higher-order), then the methods beyond it.
        pub const METHODS: &[MethodInfo] = &[$($(methods::$module::$info,)*)*];

        /// The method registered under the canonical `name`.
        fn construct<V: Vector>(name: &str) -> Option<Box<dyn Integrator<V>>> {
            $($(if name == methods::$module::$info.name {
                return Some(Box::new(methods::$module::$ty::$constructor()));
            })*)*
            None
        }
    };
}

methods! {
    explicit_euler::ExplicitEuler { INFO => new },
    semi_implicit_euler::SemiImplicitEuler { INFO => new },
    implicit_euler::ImplicitEuler { INFO => new },
    implicit_drag_euler::ImplicitDragEuler { INFO => new },
    predictor_corrector_euler::PredictorCorrectorEuler { INFO => new },
    exponential_euler::ExponentialEuler { INFO => new },
    midpoint::Midpoint { INFO => new },
    heun::Heun { INFO => new },
    trapezoidal::Trapezoidal { INFO => new },
    leapfrog::Leapfrog { INFO => new },
    position_verlet::PositionVerlet { INFO => new },
    velocity_verlet::VelocityVerlet { INFO => new },
    beeman::Beeman { INFO => new },
    newmark_beta::NewmarkBeta {
        INFO => new,
        LINEAR_ACCELERATION => linear_acceleration,
        CENTRAL_DIFFERENCE => central_difference,
    },
    rk4::Rk4 { INFO => new },
    adams_bashforth::AdamsBashforth {},
    adams_bashforth2::AdamsBashforth2 { INFO => new },
    adams_bashforth3::AdamsBashforth3 { INFO => new },
    adams_bashforth4::AdamsBashforth4 { INFO => new },
    forest_ruth::ForestRuth { INFO => new },
    dormand_prince::DormandPrince { INFO => new },
}
