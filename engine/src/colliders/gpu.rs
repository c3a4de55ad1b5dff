//! What a collider is in the GPU step ([`GpuCollider`]): the shapes the
//! step's shader resolves, described by the collider itself
//! ([`Collider::gpu_form`](super::Collider::gpu_form)), so that the GPU
//! step reads no collider's type.

use glam::Vec3;

use super::Material;

/// What a collider is in the GPU step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GpuCollider {
    /// No GPU form: the GPU step refuses a world with it, naming the
    /// collider and this reason.
    None {
        /// Why, for the error (`"sphere-sphere collisions stay on the CPU"`).
        reason: &'static str,
    },
    /// A plane `n . x >= offset`, moving along its normal at `speed` m/s
    /// (its normal must be an axis).
    Plane {
        /// Its unit normal, into the free side.
        normal: Vec3,
        /// Its offset along the normal, where it stands after the step's move.
        offset: f32,
        /// Its speed along the normal (0: at rest).
        speed: f32,
        /// Its bounce and friction.
        material: Material,
    },
    /// An axis-aligned box that keeps particles inside (`inside`) or out,
    /// moving at `velocity`.
    Box {
        /// Its least corner, where it stands after the step's move.
        min: Vec3,
        /// Its greatest corner.
        max: Vec3,
        /// Whether it keeps particles inside (a container) or out (solid).
        inside: bool,
        /// Its velocity (zero: at rest).
        velocity: Vec3,
        /// Its bounce and friction.
        material: Material,
    },
}
