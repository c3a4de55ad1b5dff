//! Scratch rows, one `Vec3A` per particle, for the parts of a step that
//! take rows rather than blocks.

use glam::Vec3A;

/// Scratch rows, one `Vec3A` per particle, for the parts of a step that take
/// rows rather than blocks (forces and colliders without a block kernel,
/// the methods that keep history); buffers reused from step to step.
#[derive(Clone, Debug, Default)]
pub(crate) struct Rows {
    pub x: Vec<Vec3A>,
    pub v: Vec<Vec3A>,
    pub other: Vec<Vec3A>,
    /// Positions and velocities before a reporting collider ran.
    pub before_x: Vec<Vec3A>,
    pub before_v: Vec<Vec3A>,
}
