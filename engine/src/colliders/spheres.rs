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
//! neighbourhood is nine ranges, of which the five later in key order hold
//! its partners (the earlier four hold particles that paired with it
//! already). Otherwise (a few particles spread far apart) the cells are
//! hashed into `2^k >= 2 n` buckets and the 27 neighbouring buckets are
//! checked cell by cell.
//!
//! **Mixed sizes**: one cell size for all would be set by the largest sphere,
//! and a single radius-20 ball among radius-0.05 grains put thousands of
//! grains in each cell (a step 270 times slower, quadratic in the grains).
//! So the grid is hierarchical: a sphere of radius `r` belongs to level
//! `l = floor(log2(r_max / r))` (up to [`LEVELS`], enough for any two `f32`
//! radii), whose cells have size `2 r_max / 2^l >= 2 r`; all levels share
//! one hash table keyed by (level, cell). A sphere looks for partners in its
//! own level (those later in the sorted order) and in every coarser level
//! in use (bigger spheres: their cell size covers the contact distance
//! `r_i + r_j`), so every touching pair is found once, and the cost stays
//! linear in the number of spheres times the number of levels in use,
//! whatever the ratio of the radii (two spheres of radius 1e30 among grains
//! of 0.045 add a level, not a quadratic term). Up to 24 levels the cells
//! are placed in `f32`; a finer level places every sphere in `f64`.
//!
//! The gathered positions are a column per axis. On the dense grid the
//! narrow phase tests four candidates with one comparison against the
//! sphere as it stands; the first that touches is resolved and the test
//! resumes after it, so the result is that of testing one at a time, bit
//! for bit (the hashed and hierarchical grids test one at a time).
//!
//! Pairs are resolved one at a time (Gauss-Seidel) in that order, by slabs
//! on the dense grid (below), then written back to the rows. The same state always gives the same result, on
//! any number of threads: on the dense grid a particle's partners are in its
//! own z plane of cells or the next, so the planes are cut into at most
//! [`SLABS`](SphereCollisions::SLABS) slabs (by the grid alone, never by the
//! thread count), and the even slabs, which touch only themselves and the
//! first plane of the slab after, are solved in parallel, then the odd ones.
//! One thread keeps that order too, so the result does not depend on threads.
//! Cell coordinates are 64-bit and saturate, so particles a billion metres
//! apart need no special case; a state with a non-finite position is not
//! solved at all (the step reports it as non-finite right after).

use glam::{I64Vec3, Vec3A, Vec4};
use rayon::prelude::*;

use super::contact::Material;
use super::{Collider, ContactColumns, PairTouch};
use crate::math;
use crate::threads::ROWS_PER_JOB;

/// A touching pair found while reporting: sorted indices, the contact
/// point, the normal towards `i`, the impulse `i` received.
#[derive(Clone, Copy)]
struct SortedPair {
    i: u32,
    j: u32,
    point: Vec3A,
    normal: Vec3A,
    impulse: f32,
}

/// Largest number of grid cells per particle for which the grid is dense.
pub const DENSE_CELLS: usize = 8;

/// Levels of the hierarchical grid: enough for any two `f32` radii (the
/// largest over the smallest positive is below `2^278`), so no mix of sizes
/// puts small spheres in cells made for big ones (two grains of radius
/// 1e30 among 100 000 of radius 0.045, each in a cell of its own size, cost
/// what the grains alone cost, plus a level).
pub const LEVELS: u32 = 280;

/// Levels below this are placed in `f32` (the common case, kept bit for bit
/// as it always was); a world using a finer one places every sphere in
/// `f64`, whose range holds the cells of any `f32` sphere.
const F32_LEVELS: u16 = 24;

/// Sphere-sphere collisions with restitution, positions separated in
/// proportion to inverse mass and an impulse along the line of centres.
///
/// Its state is the material and the counts of the last step; the grid's
/// buffers are scratch, rebuilt every step from the particles, so a copy (a
/// snapshot, [`clone_from`](Clone::clone_from) into an earlier one) leaves
/// them out and allocates nothing, and equality and `Debug` ignore them.
#[derive(Default)]
pub struct SphereCollisions {
    /// Bounce between particles (friction is not used between particles).
    pub material: Material,
    /// Scratch, reused every step: grid cell and key of each row, rows in
    /// key order, the start of each key's run, and the gathered columns.
    cell: Vec<I64Vec3>,
    /// Level of each row (mixed sizes), and the same in sorted order.
    level: Vec<u16>,
    sorted_level: Vec<u16>,
    /// The levels some sphere is on, finest first.
    used_levels: Vec<u16>,
    key: Vec<u32>,
    sorted: Vec<u32>,
    /// Each row's place in the sorted order (the inverse of `sorted`).
    rank: Vec<u32>,
    starts: Vec<u32>,
    /// Gathered positions, a column per axis: the narrow phase tests four
    /// candidates with one comparison.
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    velocity: Vec<Vec3A>,
    radius: Vec<f32>,
    inverse_mass: Vec<f32>,
    sorted_cell: Vec<I64Vec3>,
    /// Where each slab of z planes starts in sorted order, then `n`.
    slab_starts: Vec<u32>,
    /// Number of contacts resolved in the last step.
    contacts: usize,
    /// Candidate pairs the broad phase handed to the narrow phase.
    tested: usize,
    /// Slabs the dense grid was cut into in the last step (0: another grid).
    slabs: usize,
    /// Whether this step records its pairs (contact reporting), and them.
    recording: bool,
    pairs: Vec<SortedPair>,
    /// The candidate pairs the last step refused to test (past
    /// [`ContactColumns::max_pairs`]), if it did.
    refused: Option<u64>,
}

impl Clone for SphereCollisions {
    fn clone(&self) -> Self {
        Self {
            material: self.material,
            contacts: self.contacts,
            tested: self.tested,
            slabs: self.slabs,
            refused: self.refused,
            ..Self::default()
        }
    }

    fn clone_from(&mut self, source: &Self) {
        self.material = source.material;
        self.contacts = source.contacts;
        self.tested = source.tested;
        self.slabs = source.slabs;
        self.refused = source.refused;
    }
}

impl PartialEq for SphereCollisions {
    fn eq(&self, other: &Self) -> bool {
        let state = |s: &Self| (s.material, s.contacts, s.tested, s.slabs, s.refused);
        state(self) == state(other)
    }
}

impl core::fmt::Debug for SphereCollisions {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("SphereCollisions")
            .field("material", &self.material)
            .field("contacts", &self.contacts)
            .field("tested", &self.tested)
            .field("slabs", &self.slabs)
            .field("refused", &self.refused)
            .finish_non_exhaustive()
    }
}

impl SphereCollisions {
    /// Most slabs the dense grid's z planes are cut into: enough to keep two
    /// or more threads busy when piles make slabs unequal, few enough that a
    /// slab holds thousands of particles.
    pub const SLABS: usize = 64;

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

    /// Slabs of z planes the dense grid was cut into in the last step, to be
    /// solved two colours at a time (0 when the grid was hashed or
    /// hierarchical, which are solved whole).
    #[must_use]
    pub fn slabs(&self) -> usize {
        self.slabs
    }

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
    fn sort_and_gather(&mut self, keys: usize, c: &ContactColumns<'_>) -> bool {
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
    fn gather_positions(&mut self, position: &[Vec3A], parallel: bool) {
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
    fn write_back(&self, c: ContactColumns<'_>) {
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

/// The gathered positions and velocities of sorted particles `base ..`, which
/// one slab (or the whole grid) resolves; radii and inverse masses are all
/// of them, read only.
struct Window<'a> {
    base: usize,
    x: &'a mut [f32],
    y: &'a mut [f32],
    z: &'a mut [f32],
    velocity: &'a mut [Vec3A],
    radius: &'a [f32],
    inverse_mass: &'a [f32],
    restitution: f32,
    tested: usize,
    contacts: usize,
    /// Where touching pairs are recorded, when reporting (serial only).
    pairs: Option<&'a mut Vec<SortedPair>>,
}

/// One sphere's state while its partners are visited, held in registers:
/// only its own pairs write it, and they are all resolved in a row.
#[derive(Clone, Copy)]
struct Sphere {
    position: Vec3A,
    velocity: Vec3A,
    radius: f32,
    inverse_mass: f32,
}

impl Sphere {
    /// Position x, y, z and radius, each in all four lanes, to test four
    /// candidates with.
    #[inline]
    fn splat(&self) -> [Vec4; 4] {
        [self.position.x, self.position.y, self.position.z, self.radius].map(Vec4::splat)
    }
}

impl<'a> Window<'a> {
    /// All the gathered columns, from sorted index 0. Takes the fields, not
    /// the collider, so the grid's other buffers stay readable beside it.
    fn whole(
        [x, y, z]: [&'a mut [f32]; 3],
        velocity: &'a mut [Vec3A],
        radius: &'a [f32],
        inverse_mass: &'a [f32],
        material: Material,
        pairs: Option<&'a mut Vec<SortedPair>>,
    ) -> Self {
        Window {
            base: 0,
            x,
            y,
            z,
            velocity,
            radius,
            inverse_mass,
            restitution: material.restitution,
            tested: 0,
            contacts: 0,
            pairs,
        }
    }

    /// The position of window row `l`.
    #[inline]
    fn position(&self, l: usize) -> Vec3A {
        Vec3A::new(self.x[l], self.y[l], self.z[l])
    }

    /// Sorted particle `i`, to visit its partners with.
    #[inline]
    fn take(&self, i: usize) -> Sphere {
        Sphere {
            position: self.position(i - self.base),
            velocity: self.velocity[i - self.base],
            radius: self.radius[i],
            inverse_mass: self.inverse_mass[i],
        }
    }

    /// Writes sorted particle `i` back after its partners were visited.
    #[inline]
    fn put(&mut self, i: usize, a: Sphere) {
        let l = i - self.base;
        (self.x[l], self.y[l], self.z[l]) = (a.position.x, a.position.y, a.position.z);
        self.velocity[l] = a.velocity;
    }

    /// Resolves the contact of sorted particles `i` and `j`, if they touch.
    #[inline]
    fn pair(&mut self, i: usize, j: usize) {
        self.tested += 1;
        let mut a = self.take(i);
        self.pair_with(&mut a, i, j);
        self.put(i, a);
    }

    /// Resolves sphere `a` (sorted particle `i`) against the candidates
    /// `partners`, in order. Four candidates are tested at once against
    /// `a` as it stands; the first that touches is resolved (which moves
    /// `a`) and the test goes on from the candidate after it, so every
    /// candidate is tested against the same `a` as one at a time would,
    /// with the same arithmetic: the same bits, with up to a quarter of the
    /// branches.
    #[inline]
    fn partners(&mut self, a: &mut Sphere, i: usize, partners: core::ops::Range<usize>) {
        let (mut j, end) = (partners.start, partners.end);
        self.tested += end.saturating_sub(j);
        // Sorted index one past the window: no lane may read beyond it.
        let window_end = self.base + self.x.len();
        let mut own = a.splat();
        while j < end {
            if j + 4 > window_end {
                self.pair_with(a, i, j);
                own = a.splat();
                j += 1;
                continue;
            }
            let l = j - self.base;
            let d = |column: &[f32], own: Vec4| Vec4::from_slice(&column[l..l + 4]) - own;
            let (dx, dy, dz) = (d(self.x, own[0]), d(self.y, own[1]), d(self.z, own[2]));
            // (x^2 + y^2) + z^2, in the order `Vec3A::length_squared` adds.
            let dist2 = dx * dx + dy * dy + dz * dz;
            let reach = own[3] + Vec4::from_slice(&self.radius[j..j + 4]);
            let lanes =
                (dist2.cmplt(reach * reach) & dist2.cmpne(Vec4::ZERO)).bitmask() & ((1u32 << (end - j).min(4)) - 1);
            if lanes == 0 {
                j += 4;
            } else {
                let k = lanes.trailing_zeros() as usize;
                self.pair_with(a, i, j + k);
                own = a.splat();
                j += k + 1;
            }
        }
    }

    /// Resolves the contact of sphere `a` (sorted particle `i`, taken from
    /// the window) with sorted particle `j`, if they touch.
    #[inline]
    fn pair_with(&mut self, a: &mut Sphere, i: usize, j: usize) {
        let lj = j - self.base;
        let d = self.position(lj) - a.position;
        let reach = a.radius + self.radius[j];
        let dist2 = d.length_squared();
        // Touching only at `dist2 < reach^2`, so a NaN distance or reach is
        // no contact; a zero distance has no normal.
        let touching = dist2 < reach * reach && dist2 != 0.0;
        if !touching {
            return;
        }
        let (wi, wj) = (a.inverse_mass, self.inverse_mass[j]);
        let w = wi + wj;
        if w == 0.0 {
            return;
        }
        self.contacts += 1;
        let dist = dist2.sqrt();
        let normal = d / dist;
        let push = normal * ((reach - dist) / w);
        a.position -= push * wi;
        let b = self.position(lj) + push * wj;
        (self.x[lj], self.y[lj], self.z[lj]) = (b.x, b.y, b.z);
        let vn = (self.velocity[lj] - a.velocity).dot(normal);
        let mut magnitude = 0.0;
        if vn < 0.0 {
            magnitude = -(1.0 + self.restitution) * vn / w;
            let impulse = normal * magnitude;
            a.velocity -= impulse * wi;
            self.velocity[lj] += impulse * wj;
        }
        if let Some(pairs) = self.pairs.as_deref_mut() {
            pairs.push(SortedPair {
                i: i as u32,
                j: j as u32,
                point: a.position + normal * a.radius,
                normal: -normal,
                impulse: magnitude,
            });
        }
    }

    /// Splits at sorted index `at` into the windows before and from it.
    fn split(self, at: usize) -> (Self, Self) {
        let (x0, x1) = self.x.split_at_mut(at - self.base);
        let (y0, y1) = self.y.split_at_mut(at - self.base);
        let (z0, z1) = self.z.split_at_mut(at - self.base);
        let (v0, v1) = self.velocity.split_at_mut(at - self.base);
        // Pairs are recorded by one window only: the right one, which the
        // odd slabs continue in (reporting solves serially, never splitting
        // both halves to solve at once).
        let Window {
            base,
            radius,
            inverse_mass,
            restitution,
            pairs,
            ..
        } = self;
        let left = Window {
            base,
            x: x0,
            y: y0,
            z: z0,
            velocity: v0,
            radius,
            inverse_mass,
            restitution,
            tested: 0,
            contacts: 0,
            pairs: None,
        };
        let right = Window {
            base: at,
            x: x1,
            y: y1,
            z: z1,
            velocity: v1,
            radius,
            inverse_mass,
            restitution,
            tested: 0,
            contacts: 0,
            pairs,
        };
        (left, right)
    }
}

/// The dense grid of cells `lo ..= lo + size - 1`, numbered `x + nx (y + ny z)`.
struct DenseGrid<'a> {
    lo: I64Vec3,
    size: I64Vec3,
    /// Sorted index of each key's first particle, then `n`.
    starts: &'a [u32],
    sorted_cell: &'a [I64Vec3],
}

impl DenseGrid<'_> {
    /// The key of a cell of the grid. In range: `size.x * size.y * size.z
    /// <= DENSE_CELLS n` fits a u32.
    #[inline]
    fn index(&self, cell: I64Vec3) -> u32 {
        let r = cell - self.lo;
        ((r.z * self.size.y + r.y) * self.size.x + r.x) as u32
    }

    /// Resolves the pairs of sorted particles `rows` with their partners
    /// later in key order: the rest of their row of cells, the row above
    /// (y + 1) and the three rows of the next z plane. Cells of earlier keys
    /// hold earlier particles, whose pairs with these were resolved already.
    fn solve(&self, rows: core::ops::Range<usize>, w: &mut Window<'_>) {
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
    fn solve_slabs(
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

/// `out[k] = f(&from[k])` for every `k`, on rayon's threads if `parallel`
/// (each element alone: the same on any number of threads).
fn map_into<T, U>(out: &mut Vec<T>, from: &[U], parallel: bool, f: impl Fn(&U) -> T + Sync)
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
fn gather<T: Copy + Default + Send + Sync>(out: &mut Vec<T>, rows: &[u32], from: &[T], parallel: bool) {
    map_into(out, rows, parallel, |&row| from[row as usize]);
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
fn hash(cell: I64Vec3, level: u16, mask: u32) -> u32 {
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

/// `2^l`, exactly (`l` below 1024).
fn power_of_two(l: u16) -> f64 {
    f64::from_bits((1023 + u64::from(l)) << 52)
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
/// infinity poisons (vectorised, in chunks on rayon's threads if `parallel`).
fn all_finite(x: &[Vec3A], parallel: bool) -> bool {
    let sum = |a: Vec3A, b: Vec3A| a + b;
    fold_all(x, parallel, Vec3A::ZERO, |total, x| total + *x * 0.0, sum)
        .cmpeq(Vec3A::ZERO)
        .all()
}

/// `items` folded with `fold` from `identity`: in chunks on rayon's threads
/// if `parallel`, the chunks' results merged with `combine`. For folds whose
/// result does not depend on the grouping (min, max, whether a sum is NaN).
fn fold_all<T: Sync, A: Copy + Send + Sync>(
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
        self.slabs = 0;
        self.refused = None;
        let n = c.position.len();
        // The largest radius and the smallest positive one (NaN is neither:
        // `max` and `min` pass it over). Min and max are exact in any
        // order, so the threads' split does not show.
        let (max_radius, min_radius) = fold_all(
            c.radius,
            c.parallel,
            (0.0f32, f32::INFINITY),
            |(max, min), &r| (max.max(r), if r > 0.0 { min.min(r) } else { min }),
            |a, b| (a.0.max(b.0), a.1.min(b.1)),
        );
        if n < 2 || max_radius <= 0.0 || !all_finite(c.position, c.parallel) {
            return;
        }
        let min_radius = min_radius.min(max_radius);
        let solved = if min_radius * 2.0 > max_radius {
            self.level.clear();
            self.resolve_one_size(&c, max_radius)
        } else {
            self.resolve_levels(&c, max_radius)
        };
        if solved {
            self.write_back(c);
        }
    }

    fn refused_pairs(&self) -> Option<u64> {
        self.refused
    }

    fn resolve_world_reporting(&mut self, c: ContactColumns<'_>, report: &mut dyn FnMut(PairTouch)) -> bool {
        // Serial, so one list records the pairs in the solve's own order
        // (the same bits as the parallel solve: the order is the grid's).
        self.pairs.clear();
        self.recording = true;
        self.resolve_world(ContactColumns { parallel: false, ..c });
        self.recording = false;
        for pair in &self.pairs {
            report(PairTouch {
                a: self.sorted[pair.i as usize] as usize,
                b: self.sorted[pair.j as usize] as usize,
                point: pair.point,
                normal: pair.normal,
                impulse: pair.impulse,
            });
        }
        true
    }
}

impl SphereCollisions {
    /// Spheres within a factor 2 of each other in radius: one grid of cells
    /// the largest diameter wide, dense when it is small enough. False if
    /// refused (see [`sort_and_gather`](Self::sort_and_gather)).
    fn resolve_one_size(&mut self, c: &ContactColumns<'_>, max_radius: f32) -> bool {
        let n = c.position.len();
        let inv_cell = 1.0 / (2.0 * max_radius);
        map_into(&mut self.cell, c.position, c.parallel, |x| cell_of(*x, inv_cell));
        let (lo, hi) = fold_all(
            &self.cell,
            c.parallel,
            (I64Vec3::MAX, I64Vec3::MIN),
            |(lo, hi), c| (lo.min(*c), hi.max(*c)),
            |a, b| (a.0.min(b.0), a.1.max(b.1)),
        );
        // Checked: saturated cells of particles a billion cells apart
        // overflow any grid size, and take the hashed path.
        let size = [0, 1, 2].map(|k| hi[k].checked_sub(lo[k]).and_then(|d| d.checked_add(1)));
        let cells = match size {
            [Some(x), Some(y), Some(z)] => x.checked_mul(y).and_then(|xy| xy.checked_mul(z)),
            _ => None,
        };
        match (cells, size) {
            (Some(cells), [Some(x), Some(y), Some(z)]) if cells <= (DENSE_CELLS * n) as i64 => {
                self.resolve_dense(c, lo, I64Vec3::new(x, y, z))
            }
            _ => self.resolve_hashed(c),
        }
    }

    fn resolve_dense(&mut self, c: &ContactColumns<'_>, lo: I64Vec3, size: I64Vec3) -> bool {
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

    fn resolve_hashed(&mut self, c: &ContactColumns<'_>) -> bool {
        let n = c.position.len();
        let buckets = (2 * n).next_power_of_two();
        let mask = (buckets - 1) as u32;
        map_into(&mut self.key, &self.cell, c.parallel, |cell| hash(*cell, 0, mask));
        if !self.sort_and_gather(buckets, c) {
            return false;
        }
        let (sorted_cell, starts) = (&self.sorted_cell, &self.starts);
        let mut w = Window::whole(
            [&mut self.x, &mut self.y, &mut self.z],
            &mut self.velocity,
            &self.radius,
            &self.inverse_mass,
            self.material,
            self.recording.then_some(&mut self.pairs),
        );
        for i in 0..n {
            let home = sorted_cell[i];
            for offset in NEIGHBOURS {
                let Some(cell) = neighbour(home, offset) else {
                    continue;
                };
                let b = hash(cell, 0, mask) as usize;
                let (first, end) = (starts[b] as usize, starts[b + 1] as usize);
                for j in first.max(i + 1)..end {
                    // Other cells share the bucket (hash collisions); and a
                    // bucket shared by two neighbouring cells is visited
                    // twice, but each partner belongs to one cell only.
                    if sorted_cell[j] == cell {
                        w.pair(i, j);
                    }
                }
            }
        }
        (self.tested, self.contacts) = (w.tested, w.contacts);
        true
    }

    /// Mixed sizes: the hierarchical grid of the module documentation.
    fn resolve_levels(&mut self, c: &ContactColumns<'_>, max_radius: f32) -> bool {
        let n = c.position.len();
        let inv_top = 1.0 / (2.0 * max_radius);
        // Level of each sphere, and its cell at that level (cells 2^l times
        // finer than the top level's). A radius of 0 touches nothing: finest.
        // The level of a radius (below 2^128 times smaller, in f32 as it
        // always was; past it, in f64, whose range holds the ratio).
        let level_of = |r: f32| -> Option<u16> {
            let ratio = max_radius / r;
            if ratio.is_finite() {
                Some(math::log2(ratio).floor() as u16)
            } else if r > 0.0 {
                Some(math::log2(f64::from(max_radius) / f64::from(r)).floor() as u16)
            } else {
                None
            }
        };
        // A radius of 0 touches only bigger spheres: the finest level in
        // use (or, as always, the 24th).
        let finest = c
            .radius
            .iter()
            .filter_map(|&r| level_of(r))
            .fold(F32_LEVELS - 1, u16::max)
            .min(LEVELS as u16 - 1);
        self.level.clear();
        self.level.extend(
            c.radius
                .iter()
                .map(|&r| level_of(r).map_or(finest, |l| l.min(LEVELS as u16 - 1))),
        );
        let mut used = [0u64; (LEVELS as usize).div_ceil(64)];
        for &l in &self.level {
            used[usize::from(l / 64)] |= 1 << (l % 64);
        }
        self.used_levels.clear();
        self.used_levels.extend(
            (0..LEVELS as u16)
                .rev()
                .filter(|l| used[usize::from(l / 64)] & (1 << (l % 64)) != 0),
        );
        self.cell.clear();
        if finest < F32_LEVELS && inv_top.is_normal() {
            let scale = |l: u16| inv_top * (1u32 << l) as f32;
            self.cell
                .extend(c.position.iter().zip(&self.level).map(|(x, &l)| cell_of(*x, scale(l))));
        } else {
            // Every cell from the same f64 product, scaled by exact powers
            // of two, so a coarser level's cell is a shift of a finer one's.
            let inv_top = 0.5 / f64::from(max_radius);
            self.cell.extend(
                c.position
                    .iter()
                    .zip(&self.level)
                    .map(|(x, &l)| (x.as_dvec3() * inv_top * power_of_two(l)).floor().as_i64vec3()),
            );
        }
        let buckets = (2 * n).next_power_of_two();
        let mask = (buckets - 1) as u32;
        self.key.clear();
        self.key
            .extend(self.cell.iter().zip(&self.level).map(|(cell, &l)| hash(*cell, l, mask)));
        if !self.sort_and_gather(buckets, c) {
            return false;
        }
        let (sorted_cell, starts, sorted_level, used_levels) =
            (&self.sorted_cell, &self.starts, &self.sorted_level, &self.used_levels);
        let mut w = Window::whole(
            [&mut self.x, &mut self.y, &mut self.z],
            &mut self.velocity,
            &self.radius,
            &self.inverse_mass,
            self.material,
            self.recording.then_some(&mut self.pairs),
        );
        for i in 0..n {
            let own = sorted_level[i];
            // Own level, then every coarser non-empty one, whose cells are
            // 2^(own - level) of this level's: the cell there is a shift.
            for &level in used_levels.iter().filter(|&&l| l <= own) {
                // Past 63 levels the shift leaves the sign: 0 or -1.
                let home = sorted_cell[i] >> i64::from((own - level).min(63));
                for offset in NEIGHBOURS {
                    let Some(cell) = neighbour(home, offset) else {
                        continue;
                    };
                    let b = hash(cell, level, mask) as usize;
                    let (first, end) = (starts[b] as usize, starts[b + 1] as usize);
                    let first = if level == own { first.max(i + 1) } else { first };
                    for j in first..end {
                        if sorted_level[j] == level && sorted_cell[j] == cell {
                            w.pair(i, j);
                        }
                    }
                }
            }
        }
        (self.tested, self.contacts) = (w.tested, w.contacts);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Sorted columns of `n` spheres crowded into a 0.3 m cube: most pairs
    /// touch, some sit at the same point (no normal), some are NaN.
    fn columns(n: usize, seed: &[f32]) -> (Vec<[f32; 3]>, Vec<Vec3A>, Vec<f32>, Vec<f32>) {
        let at = |k: usize| seed[k % seed.len()] * (1.0 + k as f32 * 0.37).fract();
        let position = (0..n)
            .map(|k| match k % 17 {
                5 => [f32::NAN, 0.0, 0.0],
                9 => [0.1, 0.1, 0.1],
                _ => [at(3 * k), at(3 * k + 1), at(3 * k + 2)].map(|x| x * 0.3),
            })
            .collect();
        let velocity = (0..n).map(|k| Vec3A::new(at(k), -at(k + 1), 0.5)).collect();
        let radius = (0..n).map(|k| 0.03 + 0.04 * at(k + 2)).collect();
        let inverse_mass = (0..n).map(|k| if k % 11 == 3 { 0.0 } else { 1.0 + at(k) }).collect();
        (position, velocity, radius, inverse_mass)
    }

    proptest! {
        /// Four candidates tested at once give the bits, contacts and
        /// counts of one candidate at a time, in every range: ones that end
        /// inside a group of four, at the window's end, or are empty; in
        /// the whole columns or either half of a split (the left half ends
        /// before the columns do: no lane may read past it).
        #[test]
        fn four_at_a_time_is_one_at_a_time(
            seed in prop::collection::vec(0.0f32..1.0, 1..40),
            n in 2usize..40,
            spans in prop::collection::vec((0usize..40, 0usize..12), 1..60),
            cut in 0usize..40,
            left in any::<bool>(),
        ) {
            let (position, mut velocity, radius, inverse_mass) = columns(n, &seed);
            let mut axes = [0, 1, 2].map(|k| position.iter().map(|p| p[k]).collect::<Vec<f32>>());
            let mut one_axes = axes.clone();
            let mut one_velocity = velocity.clone();
            let material = Material { restitution: 0.3, friction: 0.0 };
            let [x, y, z] = &mut axes;
            let mut four = Window::whole([x, y, z], &mut velocity, &radius, &inverse_mass, material, None);
            let [x, y, z] = &mut one_axes;
            let mut one = Window::whole([x, y, z], &mut one_velocity, &radius, &inverse_mass, material, None);
            let at = cut % n;
            let (lo, hi) = match (at, left) {
                (0, _) => (0, n),
                (at, true) => (0, at),
                (at, false) => (at, n),
            };
            if at > 0 {
                let (l, r) = four.split(at);
                four = if left { l } else { r };
                let (l, r) = one.split(at);
                one = if left { l } else { r };
            }
            for (i, len) in spans {
                let i = lo + i % (hi - lo);
                let partners = i + 1..(i + 1 + len).min(hi);
                let mut a = four.take(i);
                four.partners(&mut a, i, partners.clone());
                four.put(i, a);
                let mut a = one.take(i);
                one.tested += partners.len();
                for j in partners {
                    one.pair_with(&mut a, i, j);
                }
                one.put(i, a);
            }
            prop_assert_eq!((four.tested, four.contacts), (one.tested, one.contacts));
            let bits = |w: &Window<'_>| {
                (0..w.x.len())
                    .flat_map(|l| [w.x[l], w.y[l], w.z[l], w.velocity[l].x, w.velocity[l].y, w.velocity[l].z])
                    .map(f32::to_bits)
                    .collect::<Vec<u32>>()
            };
            prop_assert_eq!(bits(&four), bits(&one));
        }
    }
}
