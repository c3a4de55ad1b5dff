//! A chunk of particles as the in-step pass holds it: the blocks of four it
//! changes, with one radius and inverse mass a particle and the chunk's
//! facts; shared by the general pass (`in_step.rs`) and the plane's lanes
//! (`follow.rs`).

use core::ops::Range;

use tickwork_integrators::Vec3x4;

use crate::colliders::BlockColumns;

/// A chunk of particles in blocks of four, as the in-step pass changes it:
/// the method's end state, one radius and inverse mass per particle (the
/// last block may be short), and the chunk's facts (see [`BlockColumns`]).
pub(super) struct Chunk<'a> {
    pub x: &'a mut [Vec3x4],
    pub v: &'a mut [Vec3x4],
    pub radius: &'a [f32],
    pub inverse_mass: &'a [f32],
    pub movable: bool,
    pub point: bool,
}

impl Chunk<'_> {
    /// Blocks `blocks` of the chunk as a collider takes them.
    pub(super) fn blocks(&mut self, blocks: Range<usize>, rest_speed: f32) -> BlockColumns<'_> {
        let rows = blocks.start * 4..(blocks.end * 4).min(self.radius.len());
        BlockColumns {
            position: &mut self.x[blocks.clone()],
            velocity: &mut self.v[blocks],
            radius: &self.radius[rows.clone()],
            inverse_mass: &self.inverse_mass[rows.clone()],
            rows: rows.len(),
            movable: self.movable,
            point: self.point,
            rest_speed,
        }
    }
}
