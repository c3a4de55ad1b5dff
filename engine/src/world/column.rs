//! A column of 3-vectors, one per particle row, read and written by row.
//!
//! Why a type and not a `Vec<Vec3A>`: the step is to store four particles
//! per SIMD value (per axis: `x0 x1 x2 x3, y0 .., z0 ..`), which cannot hand
//! out a `&mut Vec3A` for a row. Games, tests and the renderer read and
//! write through [`get`](Vec3Column::get), [`set`](Vec3Column::set) and
//! [`iter`](Vec3Column::iter), which stay the same whatever the layout.

use glam::Vec3A;

/// One 3-vector per particle row (positions, velocities, previous
/// positions): `get(row)`, `set(row, value)`, `iter()` in row order.
#[derive(Debug, Default, PartialEq)]
pub struct Vec3Column {
    values: Vec<Vec3A>,
}

impl Clone for Vec3Column {
    fn clone(&self) -> Self {
        Self {
            values: self.values.clone(),
        }
    }
    /// Reuses the buffer (world snapshots copy into their last copy).
    fn clone_from(&mut self, source: &Self) {
        self.values.clone_from(&source.values);
    }
}

impl Vec3Column {
    /// Number of rows.
    #[must_use]
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether there are no rows.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Row `row`'s vector, or `None` past the last row.
    #[must_use]
    pub fn get(&self, row: usize) -> Option<Vec3A> {
        self.values.get(row).copied()
    }

    /// Sets row `row`'s vector; returns false (and changes nothing) past the
    /// last row.
    pub fn set(&mut self, row: usize, value: Vec3A) -> bool {
        match self.values.get_mut(row) {
            Some(slot) => {
                *slot = value;
                true
            }
            None => false,
        }
    }

    /// Every row's vector, in row order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = Vec3A> + '_ {
        self.values.iter().copied()
    }

    /// Applies `f` to every row's vector, in row order, with its row.
    pub fn update(&mut self, mut f: impl FnMut(usize, Vec3A) -> Vec3A) {
        for (row, value) in self.values.iter_mut().enumerate() {
            *value = f(row, *value);
        }
    }

    /// The rows as a slice, for the step's kernels.
    pub(crate) fn as_slice(&self) -> &[Vec3A] {
        &self.values
    }

    /// The rows as a mutable slice, for the step's kernels.
    pub(crate) fn as_mut_slice(&mut self) -> &mut [Vec3A] {
        &mut self.values
    }

    pub(crate) fn push(&mut self, value: Vec3A) {
        self.values.push(value);
    }

    /// `Vec::swap_remove`: the last row moves into `row`.
    pub(crate) fn swap_remove(&mut self, row: usize) {
        self.values.swap_remove(row);
    }
}
