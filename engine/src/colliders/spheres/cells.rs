//! Grid cells of the sphere collisions: a position's cell, the 27 cells
//! around one, and the spatial hash that folds a cell (and its level) to a
//! bucket. Cell coordinates are 64-bit and saturate, so particles a
//! billion metres apart need no special case: a cell at the edge of `i64`
//! has no neighbour past it.

use glam::{I64Vec3, Vec3A};

/// The 27 cells around and including a cell.
pub(super) const NEIGHBOURS: [I64Vec3; 27] = {
    let mut cells = [I64Vec3::ZERO; 27];
    let mut m = 0;
    while m < 27 {
        cells[m as usize] = I64Vec3::new(m % 3 - 1, (m / 3) % 3 - 1, m / 9 - 1);
        m += 1;
    }
    cells
};

/// The spatial hash of Teschner et al. (2003) on 64-bit cells, with the
/// level mixed in, folded to a bucket.
#[inline]
pub(super) fn hash(cell: I64Vec3, level: u16, mask: u32) -> u32 {
    let h = cell.x.wrapping_mul(73_856_093)
        ^ cell.y.wrapping_mul(19_349_663)
        ^ cell.z.wrapping_mul(83_492_791)
        ^ i64::from(level).wrapping_mul(2_654_435_761);
    ((h ^ (h >> 32)) as u32) & mask
}

/// The cell of `x` for cells of size `1 / inv_cell`: saturating (far-away
/// particles share the outermost cells, where the distance test still
/// decides), and 0 for NaN (never reached: non-finite states are not solved).
#[inline]
pub(super) fn cell_of(x: Vec3A, inv_cell: f32) -> I64Vec3 {
    (x * inv_cell).floor().as_i64vec3()
}

/// The cell at `offset` from `home`, or `None` past the edge of i64 (a
/// particle 1e18 m out, whose cell saturated): no cell is there, and a
/// saturating sum would visit one of the others twice.
#[inline]
pub(super) fn neighbour(home: I64Vec3, offset: I64Vec3) -> Option<I64Vec3> {
    Some(I64Vec3::new(
        home.x.checked_add(offset.x)?,
        home.y.checked_add(offset.y)?,
        home.z.checked_add(offset.z)?,
    ))
}
