//! Chunked stepping for pointwise systems.
//!
//! A whole-slice step of a multi-stage method streams every scratch buffer
//! through memory once per stage; at a million particles those buffers do not
//! fit in cache and the step is bound by memory bandwidth several times over.
//! When the system is pointwise ([`System::is_pointwise`]) particles do not
//! interact, so the same step can run on chunks of [`CHUNK`] particles whose
//! scratch stays in the L1 or L2 cache: the state is then read and written about
//! once per step, whatever the number of stages. Each particle sees exactly
//! the same arithmetic, so the results are bit-identical.

use crate::system::System;
use crate::vector::Vector;

/// Particles per chunk, here and in the engine's fused step (128 blocks of
/// four: a multiple of 4, so chunks never split a block). 512 `Vec3A`
/// particles are 8 KiB per buffer, so a one-stage method's buffers stay in
/// the 32 KiB L1 and RK4's in L2; the fused step's previous and current
/// positions and velocities are 18 KiB. Measured at 1M particles on CI's
/// kind of machine: semi-implicit Euler ran about twice as fast with 512 as
/// with 2048 or 4096, RK4 about 10% faster than with 256 or 1024, and 128
/// or 256 were no faster for the full engine step, nor was prefetching.
pub const CHUNK: usize = 512;

/// A view of a pointwise system restricted to the particles from `first` on.
struct Range<'a, V: Vector> {
    system: &'a mut dyn System<V>,
    first: usize,
}

impl<V: Vector> System<V> for Range<'_, V> {
    fn acceleration(&mut self, t: V::Real, positions: &[V], velocities: &[V], out: &mut [V]) {
        self.system
            .acceleration_range(t, self.first, positions, velocities, out);
    }

    fn linear_drag(&self) -> V::Real {
        self.system.linear_drag()
    }

    fn is_pointwise(&self) -> bool {
        true
    }

    fn affine_range(&self, first: usize, count: usize) -> Option<(V, V::Real)> {
        self.system.affine_range(self.first + first, count)
    }

    fn acceleration_range(&mut self, t: V::Real, first: usize, positions: &[V], velocities: &[V], out: &mut [V]) {
        self.system
            .acceleration_range(t, self.first + first, positions, velocities, out);
    }
}

/// [`for_each_chunk`] for [`Integrator::step_from`](crate::Integrator::step_from):
/// the start positions are read from `start`, the end positions written into `x`.
pub(crate) fn for_each_chunk_from<V: Vector>(
    start: &[V],
    x: &mut [V],
    v: &mut [V],
    system: &mut dyn System<V>,
    mut step: impl FnMut(&[V], &mut [V], &mut [V], &mut dyn System<V>),
) {
    if !system.is_pointwise() || x.len() <= CHUNK {
        step(start, x, v, system);
        return;
    }
    let chunks = start.chunks(CHUNK).zip(x.chunks_mut(CHUNK)).zip(v.chunks_mut(CHUNK));
    for (k, ((start, x), v)) in chunks.enumerate() {
        let mut range = Range {
            system: &mut *system,
            first: k * CHUNK,
        };
        step(start, x, v, &mut range);
    }
}

/// Runs `step` on the whole slices, or on chunks of them when the system is
/// pointwise and the slices are longer than one chunk.
pub(crate) fn for_each_chunk<V: Vector>(
    x: &mut [V],
    v: &mut [V],
    system: &mut dyn System<V>,
    mut step: impl FnMut(&mut [V], &mut [V], &mut dyn System<V>),
) {
    if !system.is_pointwise() || x.len() <= CHUNK {
        step(x, v, system);
        return;
    }
    for (k, (x, v)) in x.chunks_mut(CHUNK).zip(v.chunks_mut(CHUNK)).enumerate() {
        let mut range = Range {
            system: &mut *system,
            first: k * CHUNK,
        };
        step(x, v, &mut range);
    }
}
