//! The sphere grid's gathered columns: the counting sort of the rows by
//! key (cell or hash bucket), the gather of positions (a column per axis),
//! velocities, radii and inverse masses in that order, the write back to
//! the rows, and the maps and folds that do it on rayon's threads (each
//! element alone, or folds whose result does not depend on the grouping,
//! so the result is the same on any number of threads).

use glam::Vec3A;
use rayon::prelude::*;

use super::SphereCollisions;
use crate::colliders::ContactColumns;
use crate::threads::ROWS_PER_JOB;

impl SphereCollisions {
    /// Counting sort of the rows by `key` (stable: equal keys keep row order),
    /// then gathers the columns in that order; or, when the spheres sharing
    /// a key make more pairs than `c.max_pairs`, refuses: records them in
    /// `refused` and returns false, having sorted and gathered nothing.
    ///
    /// Spheres sharing a key (a cell, or a bucket of the hash) are all
    /// tested against each other, so those pairs are a lower bound on the
    /// narrow phase's work, and, with the 27 neighbouring keys, bound it
    /// (`sum c_k c_m <= 27 sum c_k^2`): a world whose grains all overlap, or
    /// that another collider piled into one cell, is refused here, in time
    /// linear in the keys, rather than tested pair by pair.
    #[must_use]
    pub(super) fn sort_and_gather(&mut self, keys: usize, c: &ContactColumns<'_>) -> bool {
        let n = self.key.len();
        self.starts.clear();
        self.starts.resize(keys + 1, 0);
        for &k in &self.key {
            self.starts[k as usize + 1] += 1;
        }
        // At most n(n-1)/2 < 2^64 for n below 2^32.
        let mut pairs = 0u64;
        for i in 0..keys {
            let count = u64::from(self.starts[i + 1]);
            pairs += count * count.saturating_sub(1) / 2;
            self.starts[i + 1] += self.starts[i];
        }
        if pairs > c.max_pairs {
            self.refused = Some(pairs);
            return false;
        }
        self.sorted.clear();
        self.sorted.resize(n, 0);
        self.rank.clear();
        self.rank.resize(n, 0);
        // Fill using the starts as cursors, then shift them back.
        for (row, &k) in self.key.iter().enumerate() {
            let slot = &mut self.starts[k as usize];
            self.sorted[*slot as usize] = row as u32;
            self.rank[row] = *slot;
            *slot += 1;
        }
        for i in (1..=keys).rev() {
            self.starts[i] = self.starts[i - 1];
        }
        self.starts[0] = 0;
        let parallel = c.parallel;
        self.gather_positions(c.position, parallel);
        let rows = &self.sorted;
        gather(&mut self.velocity, rows, c.velocity, parallel);
        gather(&mut self.radius, rows, c.radius, parallel);
        gather(&mut self.inverse_mass, rows, c.inverse_mass, parallel);
        gather(&mut self.sorted_cell, rows, &self.cell, parallel);
        if self.level.is_empty() {
            self.sorted_level.clear();
        } else {
            gather(&mut self.sorted_level, rows, &self.level, parallel);
        }
        true
    }

    /// `x, y, z = position[sorted[k]]` for every `k`: [`gather`] into a
    /// column per axis.
    pub(super) fn gather_positions(&mut self, position: &[Vec3A], parallel: bool) {
        let n = self.sorted.len();
        for axis in [&mut self.x, &mut self.y, &mut self.z] {
            axis.resize(n, 0.0);
        }
        let copy = |(((x, y), z), &row): (((&mut f32, &mut f32), &mut f32), &u32)| {
            let p = position[row as usize];
            (*x, *y, *z) = (p.x, p.y, p.z);
        };
        if parallel {
            self.x
                .par_iter_mut()
                .zip(self.y.par_iter_mut())
                .zip(self.z.par_iter_mut())
                .zip(self.sorted.par_iter())
                .with_min_len(ROWS_PER_JOB)
                .for_each(copy);
        } else {
            self.x
                .iter_mut()
                .zip(self.y.iter_mut())
                .zip(self.z.iter_mut())
                .zip(&self.sorted)
                .for_each(copy);
        }
    }

    /// Writes the solved positions and velocities back to their rows: a
    /// gather through each row's rank in the sorted order, so it runs on
    /// rayon's threads like [`gather`] when the world allows it.
    pub(super) fn write_back(&self, c: ContactColumns<'_>) {
        let (px, py, pz, velocity) = (&self.x, &self.y, &self.z, &self.velocity);
        let copy = |((x, v), &k): ((&mut Vec3A, &mut Vec3A), &u32)| {
            let k = k as usize;
            *x = Vec3A::new(px[k], py[k], pz[k]);
            *v = velocity[k];
        };
        if c.parallel {
            c.position
                .par_iter_mut()
                .zip(c.velocity.par_iter_mut())
                .zip(self.rank.par_iter())
                .with_min_len(ROWS_PER_JOB)
                .for_each(copy);
        } else {
            c.position
                .iter_mut()
                .zip(c.velocity.iter_mut())
                .zip(&self.rank)
                .for_each(copy);
        }
    }
}

/// `out[k] = f(&from[k])` for every `k`, on rayon's threads if `parallel`
/// (each element alone: the same on any number of threads).
pub(super) fn map_into<T, U>(out: &mut Vec<T>, from: &[U], parallel: bool, f: impl Fn(&U) -> T + Sync)
where
    T: Copy + Default + Send,
    U: Sync,
{
    out.resize(from.len(), T::default());
    if parallel {
        out.par_iter_mut()
            .zip(from.par_iter())
            .with_min_len(ROWS_PER_JOB)
            .for_each(|(out, x)| *out = f(x));
    } else {
        for (out, x) in out.iter_mut().zip(from) {
            *out = f(x);
        }
    }
}

/// `out[k] = from[rows[k]]`: a gather through [`map_into`].
pub(super) fn gather<T: Copy + Default + Send + Sync>(out: &mut Vec<T>, rows: &[u32], from: &[T], parallel: bool) {
    map_into(out, rows, parallel, |&row| from[row as usize]);
}

/// Whether every position is finite: a sum of `0 * x`, which a NaN or an
/// infinity poisons (vectorised, in chunks on rayon's threads if `parallel`).
pub(super) fn all_finite(x: &[Vec3A], parallel: bool) -> bool {
    let sum = |a: Vec3A, b: Vec3A| a + b;
    fold_all(x, parallel, Vec3A::ZERO, |total, x| total + *x * 0.0, sum)
        .cmpeq(Vec3A::ZERO)
        .all()
}

/// `items` folded with `fold` from `identity`: in chunks on rayon's threads
/// if `parallel`, the chunks' results merged with `combine`. For folds whose
/// result does not depend on the grouping (min, max, whether a sum is NaN).
pub(super) fn fold_all<T: Sync, A: Copy + Send + Sync>(
    items: &[T],
    parallel: bool,
    identity: A,
    fold: impl Fn(A, &T) -> A + Sync,
    combine: impl Fn(A, A) -> A + Sync,
) -> A {
    if parallel {
        items
            .par_chunks(ROWS_PER_JOB)
            .map(|chunk| chunk.iter().fold(identity, &fold))
            .reduce(|| identity, &combine)
    } else {
        items.iter().fold(identity, fold)
    }
}
