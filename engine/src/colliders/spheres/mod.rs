//! Particle-particle collisions of spheres, found through a grid.
//!
//! Each step the particles are bucketed by grid cell with a counting sort,
//! and their positions, velocities, radii and inverse masses are gathered in
//! that order, so neighbours sit next to each other in memory
//! ([`columns`]). Spheres within a factor 2 of each other in radius (the
//! common case) share one grid of cells the largest diameter wide, so
//! touching spheres are in the same or adjacent cells: a dense grid when the
//! particles' bounding box is small enough ([`dense`]), else a hashed one
//! ([`hashed`]). Mixed sizes use a hierarchical grid, a level per size
//! ([`levels`]). The narrow phase tests candidates and resolves each
//! touching pair at once, Gauss-Seidel, in the sorted order ([`narrow`]);
//! the solved columns are then written back to the rows.
//!
//! The same state always gives the same result, on any number of threads
//! (the dense grid's parallel slabs are cut by the grid alone). Cell
//! coordinates are 64-bit and saturate, so particles a billion metres apart
//! need no special case ([`cells`]); a state with a non-finite position is
//! not solved at all (the step reports it as non-finite right after). The
//! spheres sharing a cell are counted before any pair is tested: past
//! [`ContactColumns::max_pairs`] the step is refused, not quadratic.

mod cells;
mod columns;
mod dense;
mod hashed;
mod levels;
mod narrow;
mod swept;

use glam::{I64Vec3, Vec3A};

use super::contact::Material;
use super::{Collider, ContactColumns, PairTouch};
use cells::cell_of;
use columns::{all_finite, fold_all, map_into};
use narrow::SortedPair;

/// Largest number of grid cells per particle for which the grid is dense.
pub(super) const DENSE_CELLS: usize = 8;

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
    /// Swept tests for fast spheres (default `false`): a sphere that moves
    /// more than its radius in a step is tested along its path against the
    /// spheres near it, so a bullet cannot pass through a ball it should
    /// hit between two instants (see `spheres/swept.rs`). Costs a sort of
    /// the paths along x in steps where some sphere is fast.
    pub swept: bool,
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
    /// Swept tests' scratch: each path's extent along x with its row, the
    /// contacts found along the paths, which rows met one, and the
    /// contacts to report.
    extents: Vec<(f32, f32, u32)>,
    meetings: Vec<swept::SweptPair>,
    taken: Vec<bool>,
    swept_touches: Vec<PairTouch>,
}

impl Clone for SphereCollisions {
    fn clone(&self) -> Self {
        Self {
            material: self.material,
            swept: self.swept,
            contacts: self.contacts,
            tested: self.tested,
            slabs: self.slabs,
            refused: self.refused,
            ..Self::default()
        }
    }

    fn clone_from(&mut self, source: &Self) {
        self.material = source.material;
        self.swept = source.swept;
        self.contacts = source.contacts;
        self.tested = source.tested;
        self.slabs = source.slabs;
        self.refused = source.refused;
    }
}

impl PartialEq for SphereCollisions {
    fn eq(&self, other: &Self) -> bool {
        let state = |s: &Self| (s.material, s.swept, s.contacts, s.tested, s.slabs, s.refused);
        state(self) == state(other)
    }
}

impl core::fmt::Debug for SphereCollisions {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("SphereCollisions")
            .field("material", &self.material)
            .field("swept", &self.swept)
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
}

impl Collider for SphereCollisions {
    fn name(&self) -> &'static str {
        "spheres"
    }

    fn gpu_form(&self) -> crate::colliders::GpuCollider {
        crate::colliders::GpuCollider::None {
            reason: "sphere-sphere collisions stay on the CPU (the GPU step resolves planes and boxes)",
        }
    }

    fn is_pointwise(&self) -> bool {
        false
    }

    fn resolve_world(&mut self, mut c: ContactColumns<'_>) {
        self.contacts = 0;
        self.tested = 0;
        self.slabs = 0;
        self.refused = None;
        self.swept_touches.clear();
        if self.swept
            && let Some(start) = c.start
            && c.position.len() == start.position.len()
            && !self.resolve_swept(&mut c, start)
        {
            return;
        }
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
        for touch in &self.swept_touches {
            report(*touch);
        }
        for pair in &self.pairs {
            report(PairTouch {
                a: self.sorted[pair.i as usize] as usize,
                b: self.sorted[pair.j as usize] as usize,
                point: pair.point,
                normal: pair.normal,
                impulse: pair.impulse,
                fraction: 1.0,
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
}
