//! Step scratch: one [`Lane`] per thread of a fused step, with its copy of
//! the method and its scratch [`Rows`], kept in the world between steps so
//! a steady step allocates nothing.

use glam::Vec3A;
use tickwork_integrators::{Integrator, Vec3x4};

use crate::colliders::RowTouch;

/// One thread's share of a fused step: its copy of the method (stepping
/// blocks of four particles) and its scratch rows. Kept between steps so
/// nothing is allocated.
pub(crate) struct Lane {
    pub method: Box<dyn Integrator<Vec3x4>>,
    pub rows: Rows,
    /// The lane's contacts, for colliders that report them.
    pub touches: Vec<RowTouch>,
}

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

impl Clone for Lane {
    fn clone(&self) -> Self {
        Self {
            method: self.method.clone_boxed(),
            rows: Rows::default(),
            touches: Vec::new(),
        }
    }
}
