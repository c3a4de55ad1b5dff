//! Particle-particle collisions of spheres, found through a uniform grid.
//!
//! Each step the particles are bucketed by grid cell (cell size = the largest
//! diameter, so touching spheres are in the same or adjacent cells) with a
//! counting sort, and their positions, velocities, radii and inverse masses
//! are gathered in that order, so neighbours sit next to each other in
//! memory. When the particles' bounding box holds at most [`DENSE_CELLS`]
//! cells per particle the grid is dense: cells are numbered `x + nx (y + ny
//! z)`, so the three cells along x of each neighbouring row are one
//! contiguous range, and a particle's neighbourhood is nine ranges. Otherwise
//! (a few particles spread far apart) the cells are hashed into `2^k >= 2 n`
//! buckets and the 27 neighbouring buckets are checked cell by cell.
//!
//! Pairs are found once (the partner comes later in the sorted order) and
//! resolved one at a time in that order (Gauss-Seidel), then scattered back
//! to the rows. The same state always gives the same result. The cost is O(n)
//! for evenly spread particles.

use glam::{IVec3, Vec3A};

use super::contact::Material;
use super::{Collider, ContactColumns};

/// Largest number of grid cells per particle for which the grid is dense.
pub const DENSE_CELLS: usize = 8;

/// Sphere-sphere collisions with restitution, positions separated in
/// proportion to inverse mass and an impulse along the line of centres.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SphereCollisions {
    /// Bounce between particles (friction is not used between particles).
    pub material: Material,
    /// Scratch, reused every step: grid cell and key of each row, rows in
    /// key order, the start of each key's run, and the gathered columns.
    cell: Vec<IVec3>,
    key: Vec<u32>,
    sorted: Vec<u32>,
    starts: Vec<u32>,
    position: Vec<Vec3A>,
    velocity: Vec<Vec3A>,
    radius: Vec<f32>,
    inverse_mass: Vec<f32>,
    sorted_cell: Vec<IVec3>,
    /// Number of contacts resolved in the last step.
    contacts: usize,
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
    }

    /// Resolves the contact of sorted particles `i` and `j`, if they touch.
    #[inline]
    fn pair(&mut self, i: usize, j: usize) {
        let d = self.position[j] - self.position[i];
        let reach = self.radius[i] + self.radius[j];
        let dist2 = d.length_squared();
        if dist2 >= reach * reach || dist2 == 0.0 {
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
const NEIGHBOURS: [IVec3; 27] = {
    let mut cells = [IVec3::ZERO; 27];
    let mut m = 0;
    while m < 27 {
        cells[m as usize] = IVec3::new(m % 3 - 1, (m / 3) % 3 - 1, m / 9 - 1);
        m += 1;
    }
    cells
};

#[inline]
fn hash(cell: IVec3, mask: u32) -> u32 {
    // Teschner et al. 2003 spatial hash.
    ((cell.x.wrapping_mul(73_856_093)) ^ (cell.y.wrapping_mul(19_349_663)) ^ (cell.z.wrapping_mul(83_492_791))) as u32
        & mask
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
        let n = c.position.len();
        let max_radius = c.radius.iter().copied().fold(0.0f32, f32::max);
        if n < 2 || max_radius <= 0.0 {
            return;
        }
        let inv_cell = 1.0 / (2.0 * max_radius);
        self.cell.clear();
        self.cell
            .extend(c.position.iter().map(|x| (*x * inv_cell).floor().as_ivec3()));
        let (lo, hi) = self
            .cell
            .iter()
            .fold((IVec3::MAX, IVec3::MIN), |(lo, hi), c| (lo.min(*c), hi.max(*c)));
        let size = (hi - lo + IVec3::ONE).as_i64vec3();
        let cells = size.x.saturating_mul(size.y).saturating_mul(size.z);
        if cells <= (DENSE_CELLS * n) as i64 {
            self.resolve_dense(&c, lo, size.as_ivec3());
        } else {
            self.resolve_hashed(&c);
        }
        for (k, &row) in self.sorted.iter().enumerate() {
            c.position[row as usize] = self.position[k];
            c.velocity[row as usize] = self.velocity[k];
        }
    }
}

impl SphereCollisions {
    fn resolve_dense(&mut self, c: &ContactColumns<'_>, lo: IVec3, size: IVec3) {
        let index = |cell: IVec3| {
            let r = cell - lo;
            ((r.z * size.y + r.y) * size.x + r.x) as u32
        };
        self.key.clear();
        self.key.extend(self.cell.iter().map(|cell| index(*cell)));
        let keys = (size.x * size.y * size.z) as usize;
        self.sort_and_gather(keys, c);
        for i in 0..self.position.len() {
            let home = self.sorted_cell[i];
            let (x0, x1) = ((home.x - 1).max(lo.x), (home.x + 1).min(lo.x + size.x - 1));
            for dz in -1..=1 {
                let z = home.z + dz;
                if z < lo.z || z >= lo.z + size.z {
                    continue;
                }
                for dy in -1..=1 {
                    let y = home.y + dy;
                    if y < lo.y || y >= lo.y + size.y {
                        continue;
                    }
                    // Cells x0..=x1 of this row are consecutive keys.
                    let first = self.starts[index(IVec3::new(x0, y, z)) as usize] as usize;
                    let end = self.starts[index(IVec3::new(x1, y, z)) as usize + 1] as usize;
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
        self.key.extend(self.cell.iter().map(|cell| hash(*cell, mask)));
        self.sort_and_gather(buckets, c);
        for i in 0..n {
            let home = self.sorted_cell[i];
            for offset in NEIGHBOURS {
                let cell = home + offset;
                let b = hash(cell, mask) as usize;
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
}
