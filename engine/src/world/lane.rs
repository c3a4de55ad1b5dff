//! Step scratch: one [`Lane`] per thread of a fused step, with its copy of
//! the method and its scratch [`Rows`], kept in the world between steps so
//! a steady step allocates nothing.

use tickwork_integrators::{Integrator, Vec3x4};

use crate::colliders::RowTouch;
use crate::layout::Rows;

/// One thread's share of a fused step: its copy of the method (stepping
/// blocks of four particles) and its scratch rows. Kept between steps so
/// nothing is allocated.
pub(crate) struct Lane {
    pub method: Box<dyn Integrator<Vec3x4>>,
    pub rows: Rows,
    /// The lane's contacts, for colliders that report them.
    pub touches: Vec<RowTouch>,
    /// Per block of a chunk, the lanes every in-step collider settled this
    /// step (bit `k` for lane `k`): clear of it, or resting on it. Every
    /// entry is `0b1111` between chunks.
    pub settled: Vec<u8>,
}

impl Lane {
    /// A lane stepping with `method`, its scratch empty.
    pub fn new(method: Box<dyn Integrator<Vec3x4>>) -> Self {
        Self {
            method,
            rows: Rows::default(),
            touches: Vec::new(),
            // A page of its own (a chunk needs 128 bytes): the lanes' settled
            // bytes, written for chunks not settled whole, never share a cache line
            // between threads (2 threads' resting step measured 1.15-1.28x
            // the end-of-step rule's with the buffers side by side, 1.12-1.14x
            // apart).
            settled: Vec::with_capacity(4096),
        }
    }
}

impl Clone for Lane {
    fn clone(&self) -> Self {
        Self::new(self.method.clone_boxed())
    }
}

/// The plain step's scratch for contacts inside the step (the fused step's
/// lanes hold their own): rows for reporting colliders, and the settled
/// lanes of a chunk's blocks (every entry `0b1111` between chunks).
#[derive(Clone, Debug, Default)]
pub(crate) struct SweepScratch {
    pub rows: Rows,
    pub settled: Vec<u8>,
}
