//! A column of 3-vectors, one per particle row, stored per axis in blocks
//! of four rows.
//!
//! ```text
//! rows 0..4:  x0 x1 x2 x3 | y0 y1 y2 y3 | z0 z1 z2 z3     one Vec3x4 (48 bytes)
//! rows 4..8:  x4 ..                                        the next
//! ```
//!
//! Why per axis: one SIMD operation then steps four particles (a `Vec3A`
//! row uses three of its four lanes for one particle), and a particle costs
//! 12 bytes, not 16. The integrators step blocks as they step vectors
//! (`tickwork_integrators::Vec3x4`, lane for lane the same bits). The last
//! block's unused lanes (`len` up to the next multiple of 4) are padding:
//! zero when made, stepped along with their block by pointwise kernels,
//! and never read as rows (not by `get`, `iter`, equality or the state hash).
//!
//! Games, tests and the renderer read and write rows through
//! [`get`](Vec3Column::get), [`set`](Vec3Column::set),
//! [`update_row`](Vec3Column::update_row), [`update`](Vec3Column::update)
//! and [`iter`](Vec3Column::iter) (an example: [`RowsMut`]); the step's
//! kernels take the blocks.

use glam::Vec3A;
use rayon::prelude::*;
use tickwork_integrators::Vec3x4;

use crate::threads::ROWS_PER_JOB;

/// Rows per block.
pub const LANES: usize = 4;

/// One 3-vector per particle row (positions, velocities, previous
/// positions): `get(row)`, `set(row, value)`, `iter()` in row order.
#[derive(Default)]
pub struct Vec3Column {
    blocks: Vec<Vec3x4>,
    len: usize,
}

impl Clone for Vec3Column {
    fn clone(&self) -> Self {
        Self {
            blocks: self.blocks.clone(),
            len: self.len,
        }
    }
    /// Reuses the buffer (world snapshots copy into their last copy).
    fn clone_from(&mut self, source: &Self) {
        self.blocks.clone_from(&source.blocks);
        self.len = source.len;
    }
}

/// The rows (padding lanes are not shown, as they do not compare).
impl core::fmt::Debug for Vec3Column {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

/// Write access to a column's rows that cannot change its length (which
/// must stay the world's row count): what [`World::query_mut`](crate::World::query_mut) hands out.
///
/// Read a row with [`get`](Self::get), change one with
/// [`update_row`](Self::update_row), every row with
/// [`update`](Self::update), and read them all with [`iter`](Self::iter):
///
/// ```
/// use glam::{Vec3, Vec3A};
/// use tickwork_engine::{Particle, World};
///
/// /// A game's column: how hard each particle is pushed.
/// #[derive(Clone, Default)]
/// struct Boost(f32);
///
/// let mut world = World::default();
/// world.register::<Boost>();
/// let ship = world.spawn(Particle { velocity: Vec3::X, ..Particle::default() })?;
/// world.insert(ship, Boost(2.0))?;
/// let row = world.row(ship)?;
///
/// let mut query = world.query_mut::<Boost>()?;
/// // One row: doubled by its boost.
/// let boost = query.component[row].0;
/// assert_eq!(query.velocity.update_row(row, |v| v * boost), Some(Vec3A::new(2.0, 0.0, 0.0)));
/// // Every row, with its row index: nothing moves up.
/// query.velocity.update(|_, v| v * Vec3A::new(1.0, 0.0, 1.0));
/// assert!(query.velocity.iter().all(|v| v.y == 0.0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct RowsMut<'a> {
    column: &'a mut Vec3Column,
}

impl<'a> RowsMut<'a> {
    pub(crate) fn new(column: &'a mut Vec3Column) -> Self {
        Self { column }
    }

    /// Number of rows.
    #[must_use]
    pub fn len(&self) -> usize {
        self.column.len()
    }

    /// Whether there are no rows.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.column.is_empty()
    }

    /// Row `row`'s vector, or `None` past the last row.
    #[must_use]
    pub fn get(&self, row: usize) -> Option<Vec3A> {
        self.column.get(row)
    }

    /// Sets row `row`'s vector; false (nothing changed) past the last row.
    pub fn set(&mut self, row: usize, value: Vec3A) -> bool {
        self.column.set(row, value)
    }

    /// Every row's vector, in row order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = Vec3A> + '_ {
        self.column.iter()
    }

    /// Applies `f` to every row's vector, in row order, with its row.
    pub fn update(&mut self, f: impl FnMut(usize, Vec3A) -> Vec3A) {
        self.column.update(f);
    }

    /// Replaces row `row`'s vector `v` with `f(v)` and returns the new
    /// vector; `None` (and `f` not called) past the last row.
    pub fn update_row(&mut self, row: usize, f: impl FnOnce(Vec3A) -> Vec3A) -> Option<Vec3A> {
        self.column.update_row(row, f)
    }
}

/// Rows compare (as `f32`s); padding lanes do not.
impl PartialEq for Vec3Column {
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && self.iter().eq(other.iter())
    }
}

impl Vec3Column {
    /// Number of rows.
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there are no rows.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Row `row`'s vector, or `None` past the last row.
    #[must_use]
    pub fn get(&self, row: usize) -> Option<Vec3A> {
        (row < self.len).then(|| self.row(row))
    }

    /// Sets row `row`'s vector; returns false (and changes nothing) past the
    /// last row.
    pub fn set(&mut self, row: usize, value: Vec3A) -> bool {
        if row >= self.len {
            return false;
        }
        self.blocks[row / LANES].set_lane(row % LANES, value);
        true
    }

    /// Every row's vector, in row order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = Vec3A> + '_ {
        (0..self.len).map(|row| self.row(row))
    }

    /// Applies `f` to every row's vector, in row order, with its row.
    pub fn update(&mut self, mut f: impl FnMut(usize, Vec3A) -> Vec3A) {
        for row in 0..self.len {
            let block = &mut self.blocks[row / LANES];
            block.set_lane(row % LANES, f(row, block.lane(row % LANES)));
        }
    }

    /// Replaces row `row`'s vector `v` with `f(v)` and returns the new
    /// vector; `None` (and `f` not called) past the last row.
    pub fn update_row(&mut self, row: usize, f: impl FnOnce(Vec3A) -> Vec3A) -> Option<Vec3A> {
        if row >= self.len {
            return None;
        }
        let block = &mut self.blocks[row / LANES];
        let value = f(block.lane(row % LANES));
        block.set_lane(row % LANES, value);
        Some(value)
    }

    /// Row `row` (`row < len`, or a padding lane of the last block).
    #[inline]
    pub(crate) fn row(&self, row: usize) -> Vec3A {
        self.blocks[row / LANES].lane(row % LANES)
    }

    /// The blocks, padding lanes included, for the step's kernels.
    pub(crate) fn blocks(&self) -> &[Vec3x4] {
        &self.blocks
    }

    /// The blocks, mutable, for the step's kernels.
    pub(crate) fn blocks_mut(&mut self) -> &mut [Vec3x4] {
        &mut self.blocks
    }

    pub(crate) fn push(&mut self, value: Vec3A) {
        if self.len.is_multiple_of(LANES) {
            self.blocks.push(Vec3x4::ZERO);
        }
        self.len += 1;
        self.set(self.len - 1, value);
    }

    /// `Vec::swap_remove`: the last row moves into `row` (`row < len`); its
    /// lane becomes padding (zero), and an emptied last block goes.
    pub(crate) fn swap_remove(&mut self, row: usize) {
        let last = self.len - 1;
        let moved = self.row(last);
        self.blocks[last / LANES].set_lane(last % LANES, Vec3A::ZERO);
        if row != last {
            self.blocks[row / LANES].set_lane(row % LANES, moved);
        }
        self.len = last;
        self.blocks.truncate(self.len.div_ceil(LANES));
    }

    /// Copies the rows into `out` (resized to `len`; its buffer is reused),
    /// for the parts of the step that take one `Vec3A` per row; on rayon's
    /// threads if `parallel`.
    pub(crate) fn gather_into(&self, out: &mut Vec<Vec3A>, parallel: bool) {
        gather(&self.blocks, self.len, out, parallel);
    }

    /// Writes `rows` (one per row, `len` of them) back into the blocks; on
    /// rayon's threads if `parallel`.
    pub(crate) fn scatter_from(&mut self, rows: &[Vec3A], parallel: bool) {
        scatter(rows, &mut self.blocks, parallel);
    }

    /// [`first_non_finite`](Self::first_non_finite) over the whole columns,
    /// in pieces of [`ROWS_PER_JOB`] rows on rayon's threads if `parallel`:
    /// the first bad row of the first piece that has one, so the same answer.
    pub(crate) fn first_non_finite_in(
        blocks: &[Vec3x4],
        other: &[Vec3x4],
        rows: usize,
        parallel: bool,
    ) -> Option<usize> {
        if !parallel {
            return Self::first_non_finite(blocks, other, rows, 0);
        }
        let per_job = ROWS_PER_JOB / LANES;
        blocks
            .par_chunks(per_job)
            .zip(other.par_chunks(per_job))
            .enumerate()
            .find_map_first(|(k, (blocks, other))| {
                let first = k * per_job * LANES;
                Self::first_non_finite(blocks, other, rows.saturating_sub(first).min(per_job * LANES), first)
            })
    }

    /// The first row (from `first`, in order) whose vector is not finite,
    /// among the rows of `blocks` (a window of some column starting at row
    /// `first`, `rows` rows of it real). One pass of plain arithmetic for the
    /// common all-finite case: a sum of finite values is finite, and one
    /// infinity or NaN among the terms makes it infinite or NaN; the tail
    /// block's padding is left out.
    pub(crate) fn first_non_finite(blocks: &[Vec3x4], other: &[Vec3x4], rows: usize, first: usize) -> Option<usize> {
        let whole = rows / LANES;
        // The sum of every value, four lanes at a time: finite when all are
        // (or infinite when finite values overflow it: past f32::MAX, 3.4e38,
        // over the window, e.g. values of 1e33 over 100 000 rows; that
        // only sends the check to the search below, which finds nothing).
        // Six additions per block; two sums over alternate blocks keep the
        // additions' latency off the loop.
        let mut sums = [glam::Vec4::ZERO; 2];
        let total = |a: &Vec3x4, b: &Vec3x4| ((a.x + b.x) + (a.y + b.y)) + (a.z + b.z);
        let (pairs_a, pairs_b) = (blocks[..whole].chunks_exact(2), other[..whole].chunks_exact(2));
        if let (Some(a), Some(b)) = (pairs_a.remainder().first(), pairs_b.remainder().first()) {
            sums[0] += total(a, b);
        }
        for (a, b) in pairs_a.zip(pairs_b) {
            sums[0] += total(&a[0], &b[0]);
            sums[1] += total(&a[1], &b[1]);
        }
        let sum = sums[0] + sums[1];
        let tail_bad = (whole * LANES..rows).any(|row| {
            let (a, b) = (
                blocks[row / LANES].lane(row % LANES),
                other[row / LANES].lane(row % LANES),
            );
            !a.is_finite() || !b.is_finite()
        });
        if sum.is_finite() && !tail_bad {
            return None;
        }
        (0..rows)
            .find(|&row| {
                let (a, b) = (
                    blocks[row / LANES].lane(row % LANES),
                    other[row / LANES].lane(row % LANES),
                );
                !a.is_finite() || !b.is_finite()
            })
            .map(|row| first + row)
    }
}

/// The first `rows` rows of `blocks`, one `Vec3A` each, into `out` (its
/// buffer reused).
/// Whole blocks are transposed four rows at a time (plain moves, no lane
/// indexing), the part-filled last block lane by lane.
pub(crate) fn gather(blocks: &[Vec3x4], rows: usize, out: &mut Vec<Vec3A>, parallel: bool) {
    // Every row is written below: only new rows need a value first.
    debug_assert!(blocks.len() >= rows.div_ceil(LANES), "rows without blocks");
    out.resize(rows, Vec3A::ZERO);
    let whole = (rows / LANES).min(blocks.len());
    let copy = |(block, out): (&Vec3x4, &mut [Vec3A])| {
        let (x, y, z) = (block.x.to_array(), block.y.to_array(), block.z.to_array());
        for k in 0..LANES {
            out[k] = Vec3A::new(x[k], y[k], z[k]);
        }
    };
    let (four, tail) = out.split_at_mut(whole * LANES);
    if parallel {
        blocks[..whole]
            .par_iter()
            .zip(four.par_chunks_exact_mut(LANES))
            .with_min_len(ROWS_PER_JOB / LANES)
            .for_each(copy);
    } else {
        blocks[..whole].iter().zip(four.chunks_exact_mut(LANES)).for_each(copy);
    }
    if let Some(block) = blocks.get(rows / LANES) {
        for (k, out) in tail.iter_mut().enumerate() {
            *out = block.lane(k);
        }
    }
}

/// `rows` back into the lanes of `blocks` (padding lanes untouched): whole
/// blocks four rows at a time, the part-filled last one lane by lane.
pub(crate) fn scatter(rows: &[Vec3A], blocks: &mut [Vec3x4], parallel: bool) {
    let whole = (rows.len() / LANES).min(blocks.len());
    let (four, tail) = rows.split_at(whole * LANES);
    let copy = |(block, r): (&mut Vec3x4, &[Vec3A])| {
        block.x = glam::Vec4::new(r[0].x, r[1].x, r[2].x, r[3].x);
        block.y = glam::Vec4::new(r[0].y, r[1].y, r[2].y, r[3].y);
        block.z = glam::Vec4::new(r[0].z, r[1].z, r[2].z, r[3].z);
    };
    if parallel {
        blocks[..whole]
            .par_iter_mut()
            .zip(four.par_chunks_exact(LANES))
            .with_min_len(ROWS_PER_JOB / LANES)
            .for_each(copy);
    } else {
        blocks[..whole].iter_mut().zip(four.chunks_exact(LANES)).for_each(copy);
    }
    if let Some(block) = blocks.get_mut(rows.len() / LANES) {
        for (k, &value) in tail.iter().enumerate() {
            block.set_lane(k, value);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn column(n: usize) -> Vec3Column {
        let mut c = Vec3Column::default();
        for k in 0..n {
            c.push(Vec3A::new(k as f32, 10.0 + k as f32, -(k as f32)));
        }
        c
    }

    #[test]
    fn rows_live_in_blocks_of_four_with_zero_padding() {
        let c = column(6);
        assert_eq!((c.len(), c.blocks().len()), (6, 2));
        assert_eq!(c.get(5), Some(Vec3A::new(5.0, 15.0, -5.0)));
        assert_eq!(c.get(6), None, "padding is not a row");
        assert_eq!(c.blocks()[1].lane(2), Vec3A::ZERO);
        assert_eq!(c.blocks()[1].x.to_array(), [4.0, 5.0, 0.0, 0.0]);
        assert_eq!(c.iter().count(), 6);
    }

    #[test]
    fn update_row_changes_one_row_and_nothing_past_the_last() {
        let mut c = column(6);
        assert_eq!(c.update_row(5, |v| v * 2.0), Some(Vec3A::new(10.0, 30.0, -10.0)));
        assert_eq!(c.get(5), Some(Vec3A::new(10.0, 30.0, -10.0)));
        assert_eq!(c.get(4), Some(Vec3A::new(4.0, 14.0, -4.0)), "its neighbour unchanged");
        let mut called = false;
        assert_eq!(
            c.update_row(6, |v| {
                called = true;
                v
            }),
            None
        );
        assert!(!called, "no call past the last row (padding is not a row)");
        assert_eq!(c.blocks()[1].lane(2), Vec3A::ZERO);
    }

    #[test]
    fn swap_remove_moves_the_last_row_and_drops_an_empty_block() {
        let mut c = column(5);
        c.swap_remove(1);
        assert_eq!(c.iter().map(|v| v.x).collect::<Vec<_>>(), [0.0, 4.0, 2.0, 3.0]);
        assert_eq!(c.blocks().len(), 1);
        c.swap_remove(3);
        assert_eq!(c.iter().map(|v| v.x).collect::<Vec<_>>(), [0.0, 4.0, 2.0]);
        assert_eq!(c.blocks()[0].lane(3), Vec3A::ZERO, "the freed lane is zero padding");
        let mut one = column(1);
        one.swap_remove(0);
        assert!(one.is_empty() && one.blocks().is_empty());
    }

    #[test]
    fn set_past_the_last_row_changes_nothing() {
        let mut c = column(3);
        assert!(c.set(2, Vec3A::ONE));
        assert!(!c.set(3, Vec3A::ONE));
        assert_eq!(c.blocks()[0].lane(3), Vec3A::ZERO);
        assert_eq!(c.get(2), Some(Vec3A::ONE));
    }

    #[test]
    fn equality_ignores_padding_lanes() {
        let (a, mut b) = (column(3), column(3));
        b.blocks_mut()[0].set_lane(3, Vec3A::splat(f32::NAN));
        assert_eq!(a, b);
        b.set(0, Vec3A::ONE);
        assert_ne!(a, b);
    }

    #[test]
    fn gather_and_scatter_round_trip_rows() {
        let c = column(7);
        let mut rows = Vec::new();
        c.gather_into(&mut rows, false);
        assert_eq!(rows, c.iter().collect::<Vec<_>>());
        let mut d = column(7);
        rows.iter_mut().for_each(|v| *v *= 2.0);
        d.scatter_from(&rows, false);
        assert_eq!(d.iter().collect::<Vec<_>>(), rows);
        assert_eq!(d.blocks()[1].lane(3), Vec3A::ZERO, "padding untouched");
    }

    #[test]
    fn parallel_gathers_scatters_and_checks_match_the_serial_ones() {
        // Several jobs' worth of rows and a part-filled last block.
        let n = 3 * ROWS_PER_JOB + 7;
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("a pool");
        pool.install(|| {
            let c = column(n);
            let (mut serial, mut parallel) = (Vec::new(), vec![Vec3A::NAN; 5]);
            c.gather_into(&mut serial, false);
            c.gather_into(&mut parallel, true);
            assert_eq!(serial, parallel);
            let mut d = column(n);
            parallel.iter_mut().for_each(|v| *v = -*v);
            d.scatter_from(&parallel, true);
            assert_eq!(d.iter().collect::<Vec<_>>(), parallel);
            assert_eq!(d.blocks()[n / LANES].lane(3), Vec3A::ZERO, "padding untouched");
            let first_bad = |x: &Vec3Column, v: &Vec3Column, parallel| {
                Vec3Column::first_non_finite_in(x.blocks(), v.blocks(), n, parallel)
            };
            assert_eq!(first_bad(&c, &d, true), None);
            // Two bad rows in different jobs: the earlier is named.
            d.set(2 * ROWS_PER_JOB + 5, Vec3A::new(0.0, f32::INFINITY, 0.0));
            d.set(ROWS_PER_JOB + 1, Vec3A::new(f32::NAN, 0.0, 0.0));
            assert_eq!(first_bad(&c, &d, true), Some(ROWS_PER_JOB + 1));
            assert_eq!(first_bad(&c, &d, false), Some(ROWS_PER_JOB + 1));
            // The last row, in the part-filled block.
            let mut e = column(n);
            e.set(n - 1, Vec3A::splat(f32::NEG_INFINITY));
            assert_eq!(first_bad(&e, &c, true), Some(n - 1));
        });
    }

    #[test]
    fn the_first_non_finite_row_is_found_and_padding_is_ignored() {
        for n in [1, 4, 5, 8, 9, 13, 600] {
            let (mut x, v) = (column(n), column(n));
            let last = x.blocks().len() - 1;
            // Padding (where there is any) may be anything.
            if n % LANES != 0 {
                x.blocks_mut()[last].set_lane(LANES - 1, Vec3A::splat(f32::NAN));
            }
            assert_eq!(
                Vec3Column::first_non_finite(x.blocks(), v.blocks(), n, 100),
                None,
                "n = {n}"
            );
            for bad in [0, n / 2, n - 1] {
                let mut v = column(n);
                v.set(bad, Vec3A::new(0.0, f32::INFINITY, 0.0));
                assert_eq!(
                    Vec3Column::first_non_finite(x.blocks(), v.blocks(), n, 100),
                    Some(100 + bad)
                );
            }
        }
        // Finite values whose sum overflows are not reported.
        let mut big = column(8);
        big.update(|_, _| Vec3A::splat(f32::MAX));
        assert_eq!(Vec3Column::first_non_finite(big.blocks(), big.blocks(), 8, 0), None);
    }
}
