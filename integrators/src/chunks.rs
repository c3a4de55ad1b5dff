//! Chunked stepping for pointwise systems.
//!
//! A whole-slice step of a multi-stage method streams every scratch buffer
//! through memory once per stage; at a million particles those buffers do not
//! fit in cache and the step is bound by memory bandwidth several times over.
//! When the system is pointwise ([`System::is_pointwise`]) particles do not
//! interact, so the same step can run on chunks of [`CHUNK`] particles whose
//! scratch stays in the L2 cache: the state is then read and written about
//! once per step, whatever the number of stages. Each particle sees exactly
//! the same arithmetic, so the results are bit-identical.

use crate::system::System;
use crate::vector::Vector;

/// Particles per chunk: 2048 particles of `Vec3A` in eight buffers is 256 KiB,
/// well inside a 1 MiB L2 cache, and long enough to amortise the per-chunk
/// dynamic calls.
pub(crate) const CHUNK: usize = 2048;

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
