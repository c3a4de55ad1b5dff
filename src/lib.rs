//! Tickwork: a fixed-timestep game loop with pluggable, verified numerical
//! integrators. This facade re-exports the workspace's crates:
//!
//! - [`integrators`]: every time-integration method, by name, verified to its order;
//! - [`engine`]: the clock, world, forces, scenes and renderer.
#![warn(missing_docs)]

#[doc(inline)]
pub use tickwork_engine as engine;
/// The math crate games use for vectors and rotations.
pub use tickwork_engine::glam;
#[doc(inline)]
pub use tickwork_integrators as integrators;
/// `sin`, `cos`, `exp`, ... with the same bits natively and in the browser:
/// call these in `fixed_update` for checksums that match across platforms.
pub use tickwork_integrators::math;

/// The README's examples, compiled and run as doctests so they never rot.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// The guide's examples, run as doctests too.
#[doc = include_str!("../docs/guide.md")]
#[cfg(doctest)]
pub struct GuideDoctests;

pub use tickwork_engine::app::{exit_code, run};

/// What a game needs, in one import: `use tickwork::prelude::*;`.
pub mod prelude {
    pub use crate::glam::{Quat, Vec2, Vec3};
    pub use crate::math;
    pub use tickwork_engine::app::{
        Draw, Game, GameError, Key, OnFailure, RunOptions, RunSummary, Settings, Sound, Stage, TickInput, Viewport,
        WorldId, exit_code, parse_args, run,
    };
    pub use tickwork_engine::input::{PadAxis, PadButton};
    pub use tickwork_engine::interpolation::Interpolated;
    pub use tickwork_engine::render::{Anchor, Camera, Cap, Fit, Join, Line, Stroke, Texture};
    pub use tickwork_engine::{
        Attractor, BoxCollider, ColliderId, Contact, ContactRule, Emitter, Entity, FixedStep, Gravity, Heading,
        LinearDrag, Material, Overlap, OverlapPhase, Particle, Plane, QuadraticDrag, Rate, Removal, RemovalCause,
        RigidBody, Sensor, SensorId, SphereCollisions, Spring, SpringEnd, Springs, StableHasher, Touched, Wind, World,
        WorldConfig,
    };
}
