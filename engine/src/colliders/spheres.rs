//! Particle-particle collisions of spheres, found through a uniform grid.
//!
//! Each step the particles are bucketed by grid cell with a counting sort,
//! and their positions, velocities, radii and inverse masses are gathered in
//! that order, so neighbours sit next to each other in memory.
//!
//! **One size** (the common case): the cell size is the largest diameter, so
//! touching spheres are in the same or adjacent cells. When the particles'
//! bounding box holds at most [`DENSE_CELLS`] cells per particle the grid is
//! dense: cells are numbered `x + nx (y + ny z)`, so the three cells along x
//! of each neighbouring row are one contiguous range, and a particle's
//! neighbourhood is nine ranges. Otherwise (a few particles spread far apart)
//! the cells are hashed into `2^k >= 2 n` buckets and the 27 neighbouring
//! buckets are checked cell by cell.
//!
//! **Mixed sizes**: one cell size for all would be set by the largest sphere,
//! and a single radius-20 ball among radius-0.05 grains put thousands of
//! grains in each cell (a step 270 times slower, quadratic in the grains).
//! So the grid is hierarchical: a sphere of radius `r` belongs to level
//! `l = floor(log2(r_max / r))` (at most [`LEVELS`] levels), whose cells have
//! size `2 r_max / 2^l >= 2 r`; all levels share one hash table keyed by
//! (level, cell). A sphere looks for partners in its own level (those later
//! in the sorted order) and in every coarser, non-empty level (bigger
//! spheres: their cell size covers the contact distance `r_i + r_j`), so every
//! touching pair is found once, and the cost stays linear in the number of
//! spheres times the number of levels.
//!
//! Pairs are resolved one at a time in that order (Gauss-Seidel), then
//! scattered back to the rows. The same state always gives the same result.
//! Cell coordinates are 64-bit and saturate, so particles a billion metres
//! apart need no special case; a state with a non-finite position is not
//! solved at all (the step reports it as non-finite right after).

use glam::{I64Vec3, Vec3A};

use super::contact::Material;
use super::{Collider, ContactColumns};

/// Largest number of grid cells per particle for which the grid is dense.
pub const DENSE_CELLS: usize = 8;

/// Levels of the hierarchical grid: spheres smaller than `2^-(LEVELS - 1)`
/// of the largest share the finest level (its cells are then larger than
/// they need be, which costs time, never a contact).
pub const LEVELS: u32 = 24;

/// Sphere-sphere collisions with restitution, positions separated in
/// proportion to inverse mass and an impulse along the line of centres.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SphereCollisions {
    /// Bounce between particles (friction is not used between particles).
    pub material: Material,
    /// Scratch, reused every step: grid cell and key of each row, rows in
    /// key order, the start of each key's run, and the gathered columns.
    cell: Vec<I64Vec3>,
    /// Level of each row (mixed sizes), and the same in sorted order.
    level: Vec<u8>,
    sorted_level: Vec<u8>,
    key: Vec<u32>,
    sorted: Vec<u32>,
    starts: Vec<u32>,
    position: Vec<Vec3A>,
    velocity: Vec<Vec3A>,
    radius: Vec<f32>,
    inverse_mass: Vec<f32>,
    sorted_cell: Vec<I64Vec3>,
    /// Number of contacts resolved in the last step.
    contacts: usize,
    /// Candidate pairs the broad phase handed to the narrow phase.
    tested: usize,
}

impl SphereCollisions {
    /// Collisions with `material`.
    #[must_use]
    pub fn new(material: Material) -> Self {
        Self {
            material,
            ..Self::default()
        }
    }

    /// Contacts resolved in the last step.
    #[must_use]
    pub fn contacts(&self) -> usize {
        self.contacts
    }

    /// Candidate pairs the broad phase tested in the last step: its cost,
    /// as a count (a grid that degrades shows here first).
    #[must_use]
    pub fn pairs_tested(&self) -> usize {
        self.tested
    }

    /// Counting sort of the rows by `key` (stable: equal keys keep row order),
    /// then gathers the columns in that order.
    fn sort_and_gather(&mut self, keys: usize, c: &ContactColumns<'_>) {
        let n = self.key.len();
        self.starts.clear();
        self.starts.resize(keys + 1, 0);
        for &k in &self.key {
            self.starts[k as usize + 1] += 1;
        }
        for i in 0..keys {
            self.starts[i + 1] += self.starts[i];
        }
        self.sorted.clear();
        self.sorted.resize(n, 0);
        // Fill using the starts as cursors, then shift them back.
        for (row, &k) in self.key.iter().enumerate() {
            let slot = &mut self.starts[k as usize];
            self.sorted[*slot as usize] = row as u32;
            *slot += 1;
        }
        for i in (1..=keys).rev() {
            self.starts[i] = self.starts[i - 1];
        }
        self.starts[0] = 0;
        let rows = &self.sorted;
        self.position.clear();
        self.position.extend(rows.iter().map(|&r| c.position[r as usize]));
        self.velocity.clear();
        self.velocity.extend(rows.iter().map(|&r| c.velocity[r as usize]));
        self.radius.clear();
        self.radius.extend(rows.iter().map(|&r| c.radius[r as usize]));
        self.inverse_mass.clear();
        self.inverse_mass
            .extend(rows.iter().map(|&r| c.inverse_mass[r as usize]));
        self.sorted_cell.clear();
        self.sorted_cell.extend(rows.iter().map(|&r| self.cell[r as usize]));
        self.sorted_level.clear();
        if !self.level.is_empty() {
            self.sorted_level.extend(rows.iter().map(|&r| self.level[r as usize]));
        }
    }

    /// Resolves the contact of sorted particles `i` and `j`, if they touch.
    #[inline]
    fn pair(&mut self, i: usize, j: usize) {
        self.tested += 1;
        let d = self.position[j] - self.position[i];
        let reach = self.radius[i] + self.radius[j];
        let dist2 = d.length_squared();
        // A NaN distance is no contact either.
        if dist2.is_nan() || dist2 >= reach * reach || dist2 == 0.0 {
            return;
        }
        let (wi, wj) = (self.inverse_mass[i], self.inverse_mass[j]);
        let w = wi + wj;
        if w == 0.0 {
            return;
        }
        self.contacts += 1;
        let dist = dist2.sqrt();
        let normal = d / dist;
        let push = normal * ((reach - dist) / w);
        self.position[i] -= push * wi;
        self.position[j] += push * wj;
        let vn = (self.velocity[j] - self.velocity[i]).dot(normal);
        if vn < 0.0 {
            let impulse = normal * (-(1.0 + self.material.restitution) * vn / w);
            self.velocity[i] -= impulse * wi;
            self.velocity[j] += impulse * wj;
        }
    }
}

/// The 27 cells around and including a cell.
const NEIGHBOURS: [I64Vec3; 27] = {
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
fn hash(cell: I64Vec3, level: u8, mask: u32) -> u32 {
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
fn cell_of(x: Vec3A, inv_cell: f32) -> I64Vec3 {
    (x * inv_cell).floor().as_i64vec3()
}

/// The cell at `offset` from `home`, or `None` past the edge of i64 (a
/// particle 1e18 m out, whose cell saturated): no cell is there, and a
/// saturating sum would visit one of the others twice.
#[inline]
fn neighbour(home: I64Vec3, offset: I64Vec3) -> Option<I64Vec3> {
    Some(I64Vec3::new(
        home.x.checked_add(offset.x)?,
        home.y.checked_add(offset.y)?,
        home.z.checked_add(offset.z)?,
    ))
}

/// Whether every position is finite: a sum of `0 * x`, which a NaN or an
/// infinity poisons (one vectorised pass).
fn all_finite(x: &[Vec3A]) -> bool {
    x.iter()
        .fold(Vec3A::ZERO, |sum, x| sum + *x * 0.0)
        .cmpeq(Vec3A::ZERO)
        .all()
}

impl Collider for SphereCollisions {
    fn name(&self) -> &'static str {
        "spheres"
    }

    fn is_pointwise(&self) -> bool {
        false
    }

    fn resolve_world(&mut self, c: ContactColumns<'_>) {
        self.contacts = 0;
        self.tested = 0;
        let n = c.position.len();
        let max_radius = c.radius.iter().copied().fold(0.0f32, f32::max);
        if n < 2 || max_radius <= 0.0 || !all_finite(c.position) {
            return;
        }
        let min_radius = c.radius.iter().copied().filter(|r| *r > 0.0).fold(max_radius, f32::min);
        if min_radius * 2.0 > max_radius {
            self.level.clear();
            self.resolve_one_size(&c, max_radius);
        } else {
            self.resolve_levels(&c, max_radius);
        }
        for (k, &row) in self.sorted.iter().enumerate() {
            c.position[row as usize] = self.position[k];
            c.velocity[row as usize] = self.velocity[k];
        }
    }
}

impl SphereCollisions {
    /// Spheres within a factor 2 of each other in radius: one grid of cells
    /// the largest diameter wide, dense when it is small enough.
    fn resolve_one_size(&mut self, c: &ContactColumns<'_>, max_radius: f32) {
        let n = c.position.len();
        let inv_cell = 1.0 / (2.0 * max_radius);
        self.cell.clear();
        self.cell.extend(c.position.iter().map(|x| cell_of(*x, inv_cell)));
        let (lo, hi) = self
            .cell
            .iter()
            .fold((I64Vec3::MAX, I64Vec3::MIN), |(lo, hi), c| (lo.min(*c), hi.max(*c)));
        // Checked: saturated cells of particles a billion cells apart
        // overflow any grid size, and take the hashed path.
        let size = [0, 1, 2].map(|k| hi[k].checked_sub(lo[k]).and_then(|d| d.checked_add(1)));
        let cells = match size {
            [Some(x), Some(y), Some(z)] => x.checked_mul(y).and_then(|xy| xy.checked_mul(z)),
            _ => None,
        };
        match (cells, size) {
            (Some(cells), [Some(x), Some(y), Some(z)]) if cells <= (DENSE_CELLS * n) as i64 => {
                self.resolve_dense(c, lo, I64Vec3::new(x, y, z));
            }
            _ => self.resolve_hashed(c),
        }
    }

    fn resolve_dense(&mut self, c: &ContactColumns<'_>, lo: I64Vec3, size: I64Vec3) {
        // In range: size.x * size.y * size.z <= DENSE_CELLS n fits a u32 index.
        let index = |cell: I64Vec3| {
            let r = cell - lo;
            ((r.z * size.y + r.y) * size.x + r.x) as u32
        };
        self.key.clear();
        self.key.extend(self.cell.iter().map(|cell| index(*cell)));
        let keys = (size.x * size.y * size.z) as usize;
        self.sort_and_gather(keys, c);
        for i in 0..self.position.len() {
            let home = self.sorted_cell[i];
            // Saturating: a cell at the edge of i64 (a particle 1e18 m out)
            // has no neighbour past it. `lo + size - 1` is the highest cell.
            let hi = lo + (size - I64Vec3::ONE);
            let (x0, x1) = (home.x.saturating_sub(1).max(lo.x), home.x.saturating_add(1).min(hi.x));
            for dz in -1..=1 {
                let z = home.z.saturating_add(dz);
                if z < lo.z || z > hi.z || (dz != 0 && z == home.z) {
                    continue;
                }
                for dy in -1..=1 {
                    let y = home.y.saturating_add(dy);
                    if y < lo.y || y > hi.y || (dy != 0 && y == home.y) {
                        continue;
                    }
                    // Cells x0..=x1 of this row are consecutive keys.
                    let first = self.starts[index(I64Vec3::new(x0, y, z)) as usize] as usize;
                    let end = self.starts[index(I64Vec3::new(x1, y, z)) as usize + 1] as usize;
                    for j in first.max(i + 1)..end {
                        self.pair(i, j);
                    }
                }
            }
        }
    }

    fn resolve_hashed(&mut self, c: &ContactColumns<'_>) {
        let n = c.position.len();
        let buckets = (2 * n).next_power_of_two();
        let mask = (buckets - 1) as u32;
        self.key.clear();
        self.key.extend(self.cell.iter().map(|cell| hash(*cell, 0, mask)));
        self.sort_and_gather(buckets, c);
        for i in 0..n {
            let home = self.sorted_cell[i];
            for offset in NEIGHBOURS {
                let Some(cell) = neighbour(home, offset) else {
                    continue;
                };
                let b = hash(cell, 0, mask) as usize;
                let (first, end) = (self.starts[b] as usize, self.starts[b + 1] as usize);
                for j in first.max(i + 1)..end {
                    // Other cells share the bucket (hash collisions); and a
                    // bucket shared by two neighbouring cells is visited
                    // twice, but each partner belongs to one cell only.
                    if self.sorted_cell[j] == cell {
                        self.pair(i, j);
                    }
                }
            }
        }
    }

    /// Mixed sizes: the hierarchical grid of the module documentation.
    fn resolve_levels(&mut self, c: &ContactColumns<'_>, max_radius: f32) {
        let n = c.position.len();
        let inv_top = 1.0 / (2.0 * max_radius);
        // Level of each sphere, and its cell at that level (cells 2^l times
        // finer than the top level's). A radius of 0 touches nothing: finest.
        self.level.clear();
        self.level.extend(c.radius.iter().map(|&r| {
            let ratio = max_radius / r;
            if ratio.is_finite() {
                (ratio.log2().floor() as u32).min(LEVELS - 1) as u8
            } else {
                (LEVELS - 1) as u8
            }
        }));
        let mut used = 0u32;
        for &l in &self.level {
            used |= 1 << l;
        }
        self.cell.clear();
        let scale = |l: u8| inv_top * (1u32 << l) as f32;
        self.cell
            .extend(c.position.iter().zip(&self.level).map(|(x, &l)| cell_of(*x, scale(l))));
        let buckets = (2 * n).next_power_of_two();
        let mask = (buckets - 1) as u32;
        self.key.clear();
        self.key
            .extend(self.cell.iter().zip(&self.level).map(|(cell, &l)| hash(*cell, l, mask)));
        self.sort_and_gather(buckets, c);
        for i in 0..n {
            let own = self.sorted_level[i];
            // Own level, then every coarser non-empty one, whose cells are
            // 2^(own - level) of this level's: the cell there is a shift.
            for level in (0..=own).rev().filter(|l| used & (1 << l) != 0) {
                let home = self.sorted_cell[i] >> i64::from(own - level);
                for offset in NEIGHBOURS {
                    let Some(cell) = neighbour(home, offset) else {
                        continue;
                    };
                    let b = hash(cell, level, mask) as usize;
                    let (first, end) = (self.starts[b] as usize, self.starts[b + 1] as usize);
                    let first = if level == own { first.max(i + 1) } else { first };
                    for j in first..end {
                        if self.sorted_level[j] == level && self.sorted_cell[j] == cell {
                            self.pair(i, j);
                        }
                    }
                }
            }
        }
    }
}
