//! The dense grid, for spheres of one size close together: when the
//! particles' bounding box holds at most [`DENSE_CELLS`](super::DENSE_CELLS) cells per particle,
//! cells are numbered `x + nx (y + ny z)`, so the three cells along x of
//! each neighbouring row are one contiguous range, and a particle's
//! neighbourhood is nine ranges, of which the five later in key order hold
//! its partners (the earlier four hold particles that paired with it
//! already).
//!
//! A particle's partners are in its own z plane of cells or the next, so
//! the planes are cut into at most [`SLABS`](SphereCollisions::SLABS) slabs
//! (by the grid alone, never by the thread count), and the even slabs,
//! which touch only themselves and the first plane of the slab after, are
//! solved in parallel, then the odd ones. One thread keeps that order too,
//! so the result does not depend on threads.

use glam::I64Vec3;

use super::SphereCollisions;
use super::columns::map_into;
use super::narrow::Window;
use crate::colliders::ContactColumns;

/// The dense grid of cells `lo ..= lo + size - 1`, numbered `x + nx (y + ny z)`.
pub(super) struct DenseGrid<'a> {
    pub(super) lo: I64Vec3,
    pub(super) size: I64Vec3,
    /// Sorted index of each key's first particle, then `n`.
    pub(super) starts: &'a [u32],
    pub(super) sorted_cell: &'a [I64Vec3],
}

impl DenseGrid<'_> {
    /// The key of a cell of the grid. In range: `size.x * size.y * size.z
    /// <= DENSE_CELLS n` fits a u32.
    #[inline]
    pub(super) fn index(&self, cell: I64Vec3) -> u32 {
        let r = cell - self.lo;
        ((r.z * self.size.y + r.y) * self.size.x + r.x) as u32
    }

    /// Resolves the pairs of sorted particles `rows` with their partners
    /// later in key order: the rest of their row of cells, the row above
    /// (y + 1) and the three rows of the next z plane. Cells of earlier keys
    /// hold earlier particles, whose pairs with these were resolved already.
    pub(super) fn solve(&self, rows: core::ops::Range<usize>, w: &mut Window<'_>) {
        // `lo + size - 1` is the highest cell.
        let hi = self.lo + (self.size - I64Vec3::ONE);
        for i in rows {
            let home = self.sorted_cell[i];
            // Saturating: a cell at the edge of i64 (a particle 1e18 m out)
            // has no neighbour past it.
            let (x0, x1) = (
                home.x.saturating_sub(1).max(self.lo.x),
                home.x.saturating_add(1).min(hi.x),
            );
            let mut a = w.take(i);
            for (dy, dz) in [(0, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
                let (y, z) = (home.y.saturating_add(dy), home.z.saturating_add(dz));
                let saturated = (dz != 0 && z == home.z) || (dy != 0 && y == home.y);
                if saturated || y < self.lo.y || y > hi.y || z > hi.z {
                    continue;
                }
                // Cells x0..=x1 of this row are consecutive keys.
                let first = self.starts[self.index(I64Vec3::new(x0, y, z)) as usize] as usize;
                let end = self.starts[self.index(I64Vec3::new(x1, y, z)) as usize + 1] as usize;
                w.partners(&mut a, i, first.max(i + 1)..end);
            }
            w.put(i, a);
        }
    }

    /// Solves `count` slabs of one colour, `first`, `first + 2`, ..., whose
    /// sorted ranges `slabs` bounds; `w` starts at the first of them and
    /// holds every slab up to the end. Halves of the list are disjoint
    /// windows (a slab's pairs reach only the slab after it, which the next
    /// of the colour does not touch), solved on two threads when `parallel`.
    /// Returns candidate pairs tested and contacts resolved.
    pub(super) fn solve_slabs(
        &self,
        slabs: &[u32],
        first: usize,
        count: usize,
        parallel: bool,
        mut w: Window<'_>,
    ) -> (usize, usize) {
        if count > 1 && parallel {
            let half = count / 2;
            let middle = first + 2 * half;
            let (left, right) = w.split(slabs[middle] as usize);
            let (a, b) = rayon::join(
                || self.solve_slabs(slabs, first, half, parallel, left),
                || self.solve_slabs(slabs, middle, count - half, parallel, right),
            );
            return (a.0 + b.0, a.1 + b.1);
        }
        for k in (first..first + 2 * count).step_by(2) {
            self.solve(slabs[k] as usize..slabs[k + 1] as usize, &mut w);
        }
        (w.tested, w.contacts)
    }
}

impl SphereCollisions {
    pub(super) fn resolve_dense(&mut self, c: &ContactColumns<'_>, lo: I64Vec3, size: I64Vec3) -> bool {
        let grid = DenseGrid {
            lo,
            size,
            starts: &[],
            sorted_cell: &[],
        };
        map_into(&mut self.key, &self.cell, c.parallel, |cell| grid.index(*cell));
        let keys = (size.x * size.y * size.z) as usize;
        if !self.sort_and_gather(keys, c) {
            return false;
        }
        let n = self.x.len();
        // Slabs of `thickness` z planes, each starting at its first cell's key.
        let planes = size.z as usize;
        let thickness = planes.div_ceil(Self::SLABS);
        self.slab_starts.clear();
        for z in (0..planes).step_by(thickness) {
            let first = grid.index(I64Vec3::new(lo.x, lo.y, lo.z + z as i64));
            self.slab_starts.push(self.starts[first as usize]);
        }
        self.slab_starts.push(n as u32);
        let slabs = self.slab_starts.len() - 1;
        self.slabs = slabs;
        let parallel = c.parallel && rayon::current_num_threads() > 1;
        let grid = DenseGrid {
            starts: &self.starts,
            sorted_cell: &self.sorted_cell,
            ..grid
        };
        for colour in [0, 1] {
            let count = (slabs + 1 - colour) / 2;
            if count == 0 {
                continue;
            }
            let mut w = Window::whole(
                [&mut self.x, &mut self.y, &mut self.z],
                &mut self.velocity,
                &self.radius,
                &self.inverse_mass,
                self.material,
                self.recording.then_some(&mut self.pairs),
            );
            if colour == 1 {
                w = w.split(self.slab_starts[1] as usize).1;
            }
            let (tested, contacts) = grid.solve_slabs(&self.slab_starts, colour, count, parallel, w);
            self.tested += tested;
            self.contacts += contacts;
        }
        true
    }
}
