//! What holds for every row of a chunk of [`CHUNK`] particles, so the fused
//! step's kernels can take a shorter path where it does.
//!
//! - **movable**: every inverse mass is above 0 (`w > 0`, so NaN is not).
//!   The force field then need not zero immovable particles' accelerations
//!   (a scan of the chunk's masses on every step), and a contact need not
//!   read the masses.
//! - **point**: every radius is `+0.0` (bit for bit: `x - 0 == x` for every
//!   `x`, so a kernel that drops the subtraction gives the same bits). A
//!   contact then need not read the radii.
//!
//! Facts are derived from the radius and inverse-mass columns, recomputed
//! at the start of a fused step only for the chunks from the first row
//! changed since (a spawn touches the last chunk, a despawn its row's chunk
//! and every later one, `particles_mut` everything): a world whose
//! particles are not spawned, despawned or edited recomputes nothing, and
//! one that is pays a pass over 8 bytes a particle from that row on (what
//! the immovable scan cost every step before).

use core::fmt;

use crate::forces::all_movable;
use crate::layout::CHUNK;

/// The facts of one chunk.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Facts {
    /// Every particle of the chunk moves (inverse mass above 0).
    pub movable: bool,
    /// Every particle of the chunk has radius `+0.0`.
    pub point: bool,
}

impl Facts {
    /// The facts of one chunk's rows.
    fn of(radius: &[f32], inverse_mass: &[f32]) -> Self {
        // Branch-free folds the compiler vectorises.
        let movable = all_movable(inverse_mass);
        let point = radius.iter().fold(0u32, |any, &r| any | r.to_bits()) == 0;
        Self { movable, point }
    }
}

/// Facts per chunk, and the first row changed since they were computed.
#[derive(Default)]
pub(crate) struct ChunkFacts {
    chunks: Vec<Facts>,
    /// Rows from here on may have changed (`None`: all current).
    stale_from: Option<usize>,
}

impl ChunkFacts {
    /// Row `row` (and the last chunk, if it shrank or grew) changed.
    pub fn touch(&mut self, row: usize) {
        self.stale_from = Some(self.stale_from.map_or(row, |from| from.min(row)));
    }

    /// Brings the facts up to date with the columns and returns them, one
    /// per chunk (`radius.len().div_ceil(CHUNK)`).
    pub fn refresh(&mut self, radius: &[f32], inverse_mass: &[f32]) -> &[Facts] {
        let n = radius.len();
        let chunks = n.div_ceil(CHUNK);
        if let Some(from) = self.stale_from.take() {
            self.chunks.resize(chunks, Facts::default());
            for k in (from / CHUNK).min(chunks)..chunks {
                let rows = k * CHUNK..((k + 1) * CHUNK).min(n);
                self.chunks[k] = Facts::of(&radius[rows.clone()], &inverse_mass[rows]);
            }
        }
        debug_assert_eq!(self.chunks.len(), chunks, "a change to the columns was not touched");
        &self.chunks
    }
}

/// `clone_from` reuses the buffer (a snapshot every step allocates nothing).
impl Clone for ChunkFacts {
    fn clone(&self) -> Self {
        Self {
            chunks: self.chunks.clone(),
            stale_from: self.stale_from,
        }
    }
    fn clone_from(&mut self, source: &Self) {
        self.chunks.clone_from(&source.chunks);
        self.stale_from = source.stale_from;
    }
}

/// Derived data, not state: every world with the same columns has the same
/// facts once refreshed, so equality ignores them.
impl PartialEq for ChunkFacts {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl fmt::Debug for ChunkFacts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("ChunkFacts")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn facts_follow_the_rows_that_changed() {
        let n = CHUNK * 2 + 3;
        let (mut radius, mut mass) = (vec![0.0; n], vec![1.0; n]);
        let mut facts = ChunkFacts::default();
        facts.touch(0);
        let all = Facts {
            movable: true,
            point: true,
        };
        assert_eq!(facts.refresh(&radius, &mass), &[all; 3]);
        // An immovable particle in the second chunk, a -0 radius in the third.
        mass[CHUNK + 5] = 0.0;
        radius[2 * CHUNK + 1] = -0.0;
        facts.touch(CHUNK + 5);
        let expected = [
            all,
            Facts {
                movable: false,
                point: true,
            },
            Facts {
                movable: true,
                point: false,
            },
        ];
        assert_eq!(facts.refresh(&radius, &mass), &expected);
        // NaN is not movable; a shrinking world drops its chunks.
        mass[0] = f32::NAN;
        facts.touch(0);
        assert!(!facts.refresh(&radius[..10], &mass[..10])[0].movable);
        assert_eq!(facts.refresh(&radius[..10], &mass[..10]).len(), 1);
    }
}
