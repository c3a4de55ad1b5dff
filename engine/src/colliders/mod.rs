//! Colliders: contact responses applied after each integration step.
//!
//! Pointwise colliders (a plane, a box) treat each particle alone and run
//! inside the engine's cache-sized chunks, right after the chunk is
//! integrated. Their response is computed for every particle and selected by
//! the contact test rather than branched on: when particles rest on a floor
//! the contact test flips unpredictably, and a mispredicted branch made the
//! whole step about 3x slower in measurements.
//!
//! Particle-particle collisions need neighbours and run once over the world
//! through a uniform grid ([`SphereCollisions`]).

mod aabb;
mod contact;
mod contacts;
mod gpu;
mod plane;
pub mod seams;
pub(crate) mod set;
pub(crate) mod settled;
mod spheres;
pub mod sweep;

use core::any::Any;
use core::fmt;

use glam::{Vec3A, Vec4};
use rayon::prelude::*;
use tickwork_integrators::Vec3x4;

use crate::threads::ROWS_PER_JOB;

pub use aabb::BoxCollider;
pub(crate) use contact::bounce;
pub use contact::{ContactRule, Material};
pub use contacts::{ColliderId, Contact, PairTouch, Touched};
pub(crate) use contacts::{RowTouch, diff_touches};
pub use gpu::GpuCollider;
pub use plane::{AxisPlane, Plane};
pub use set::ColliderError;
pub use spheres::SphereCollisions;
pub(crate) use sweep::EventOverflow;
pub use sweep::{MAX_CONTACT_EVENTS, StepPath, SweptHit};

/// The particle columns a collider may read and change.
#[derive(Debug)]
pub struct ContactColumns<'a> {
    /// Positions (moved out of contact).
    pub position: &'a mut [Vec3A],
    /// Velocities (reflected with restitution and friction).
    pub velocity: &'a mut [Vec3A],
    /// Radii.
    pub radius: &'a [f32],
    /// Inverse masses (0 = immovable, never moved).
    pub inverse_mass: &'a [f32],
    /// Whether the collider may spread its work over rayon's threads: the
    /// world holds at least
    /// [`WorldConfig::parallel_threshold`](crate::world::WorldConfig)
    /// particles. False for a chunk of a lane, already one thread's share.
    pub parallel: bool,
    /// The candidate pairs a collider of pairs may test in one step
    /// ([`WorldConfig::max_pairs`](crate::world::WorldConfig)): past it,
    /// it resolves nothing and says so through
    /// [`Collider::refused_pairs`] (the step then fails with
    /// [`SimulationError::ContactPairLimit`](crate::SimulationError)).
    pub max_pairs: u64,
    /// Where the particles started the step, and its length, where the
    /// step has them for the collider (the whole-world step of a collider
    /// of pairs; `None` for chunks): what swept tests need
    /// ([`SphereCollisions::swept`]).
    pub start: Option<StepStart<'a>>,
    /// Contacts approaching no faster than this (m/s) rest, restitution 0:
    /// [`WorldConfig::rest_speed`](crate::WorldConfig) for a collider that
    /// finds contacts inside the step, 0 (every approach bounces) for the
    /// others.
    pub rest_speed: f32,
}

/// The positions the particles started the step from, and the step's
/// length in seconds.
#[derive(Clone, Copy, Debug)]
pub struct StepStart<'a> {
    /// Each particle's position at the start of the step.
    pub position: &'a [Vec3A],
    /// The step's length, seconds.
    pub dt: f32,
}

impl ContactColumns<'_> {
    /// Calls `f` on consecutive pieces of [`ROWS_PER_JOB`] rows, on
    /// rayon's threads (each piece with `parallel` false).
    fn for_each_job(self, f: impl Fn(ContactColumns<'_>) + Sync) {
        self.position
            .par_chunks_mut(ROWS_PER_JOB)
            .zip(self.velocity.par_chunks_mut(ROWS_PER_JOB))
            .zip(self.radius.par_chunks(ROWS_PER_JOB))
            .zip(self.inverse_mass.par_chunks(ROWS_PER_JOB))
            .for_each(|(((position, velocity), radius), inverse_mass)| {
                f(ContactColumns {
                    position,
                    velocity,
                    radius,
                    inverse_mass,
                    parallel: false,
                    max_pairs: self.max_pairs,
                    start: None,
                    rest_speed: self.rest_speed,
                });
            });
    }

    /// Each particle's position and velocity (to change) with its radius and
    /// inverse mass: the loop every pointwise collider runs.
    pub fn rows(&mut self) -> impl Iterator<Item = (&mut Vec3A, &mut Vec3A, f32, f32)> {
        self.position
            .iter_mut()
            .zip(self.velocity.iter_mut())
            .zip(self.radius)
            .zip(self.inverse_mass)
            .map(|(((x, v), &r), &w)| (x, v, r, w))
    }
}

/// A chunk of the world as the fused step holds it: positions and
/// velocities in blocks of four particles per axis
/// ([`Vec3x4`]: `x0 x1 x2 x3, y0 .., z0 ..`), for colliders with a block
/// kernel ([`Collider::resolve_blocks`]).
#[derive(Debug)]
#[non_exhaustive]
pub struct BlockColumns<'a> {
    /// Positions, four particles per block (moved out of contact).
    pub position: &'a mut [Vec3x4],
    /// Velocities, four particles per block.
    pub velocity: &'a mut [Vec3x4],
    /// Radii, one per real particle (`rows` of them).
    pub radius: &'a [f32],
    /// Inverse masses, one per real particle (0 = immovable, never moved).
    pub inverse_mass: &'a [f32],
    /// Real particles: the last block's lanes past `rows` are padding,
    /// to be left unchanged or changed harmlessly (give them `inverse_mass`
    /// 0, as [`BlockColumns::block_scalars`] does).
    pub rows: usize,
    /// Every real row's inverse mass is above 0: a kernel may skip reading
    /// `inverse_mass` (the padding lanes are still to be left harmless).
    pub movable: bool,
    /// Every real row's radius is `+0.0`: a kernel may skip reading `radius`
    /// (and its subtraction, which changes no bits).
    pub point: bool,
    /// Contacts approaching no faster than this (m/s) rest, restitution 0:
    /// [`WorldConfig::rest_speed`](crate::WorldConfig) for a collider that
    /// finds contacts inside the step, 0 (every approach bounces) for the
    /// others.
    pub rest_speed: f32,
}

impl BlockColumns<'_> {
    /// Block `k`'s radii and inverse masses as lanes; padding lanes get
    /// radius 0 and inverse mass 0 (immovable: no contact moves them).
    #[inline]
    #[must_use]
    pub fn block_scalars(&self, k: usize) -> (Vec4, Vec4) {
        let first = k * 4;
        if first + 4 <= self.rows {
            return (
                Vec4::from_slice(&self.radius[first..first + 4]),
                Vec4::from_slice(&self.inverse_mass[first..first + 4]),
            );
        }
        let (mut r, mut w) = ([0.0; 4], [0.0; 4]);
        let tail = self.rows - first;
        r[..tail].copy_from_slice(&self.radius[first..self.rows]);
        w[..tail].copy_from_slice(&self.inverse_mass[first..self.rows]);
        (Vec4::from_array(r), Vec4::from_array(w))
    }
}

/// A collider.
pub trait Collider: Send + Sync + fmt::Debug + ColliderState {
    /// Short name for diagnostics and scene files (`"plane"`).
    fn name(&self) -> &'static str;

    /// Whether each particle is resolved alone (default: true). If so,
    /// [`resolve_range`](Self::resolve_range) is called on chunks, possibly
    /// from several threads; otherwise [`resolve_world`](Self::resolve_world)
    /// once per step.
    fn is_pointwise(&self) -> bool {
        true
    }

    /// Resolves contacts of the particles in `columns` (a chunk of the world).
    fn resolve_range(&self, columns: ContactColumns<'_>) {
        let _ = columns;
    }

    /// Resolves contacts of the particles of a chunk held in blocks of four
    /// per axis, as [`resolve_range`](Self::resolve_range) would on their
    /// rows (the same bits), and returns true; or returns false (the
    /// default) to have the engine hand `resolve_range` the chunk's rows.
    /// For pointwise colliders whose contact is per-axis arithmetic
    /// (axis-aligned planes), which then costs one vector operation per
    /// four particles.
    fn resolve_blocks(&self, columns: BlockColumns<'_>) -> bool {
        let _ = columns;
        false
    }

    /// Resolves contacts over the whole world (default: `resolve_range`,
    /// on pieces of the world on rayon's threads when the collider is
    /// pointwise and `columns.parallel`: each particle alone, so the same
    /// bits on any number of threads).
    fn resolve_world(&mut self, columns: ContactColumns<'_>) {
        if columns.parallel && self.is_pointwise() {
            let this: &Self = self;
            columns.for_each_job(|piece| this.resolve_range(piece));
        } else {
            self.resolve_range(columns);
        }
    }

    /// For colliders that resolve pairs of particles (not pointwise):
    /// resolves as [`resolve_world`](Self::resolve_world) does, the same
    /// bits, calling `report` for each pair that touched, and returns true;
    /// or returns false (the default) to have the engine find the contacts
    /// by comparing states (each then touches the collider itself). Called
    /// only when the collider reports contacts.
    fn resolve_world_reporting(&mut self, columns: ContactColumns<'_>, report: &mut dyn FnMut(PairTouch)) -> bool {
        let _ = (columns, report);
        false
    }

    /// The candidate pairs the last [`resolve_world`](Self::resolve_world)
    /// would have had to test, when they were past
    /// [`ContactColumns::max_pairs`] and it therefore resolved nothing
    /// (default: `None`, a collider that never refuses). The step turns
    /// this into [`SimulationError::ContactPairLimit`](crate::SimulationError),
    /// so quadratic work (every sphere overlapping every other) is an error
    /// naming the limit rather than a step that runs for minutes.
    fn refused_pairs(&self) -> Option<u64> {
        None
    }

    /// Whether this collider finds its contacts inside the step
    /// ([`ContactRule::InStep`]): the step then asks
    /// [`first_contact`](Self::first_contact) along each particle's path,
    /// before [`resolve_world`](Self::resolve_world) resolves what is left
    /// at the end of the step (particles that started inside). Default:
    /// false.
    fn in_step(&self) -> bool {
        false
    }

    /// The first contact of a particle of `radius` moving along `path`
    /// (part or all of a step, ending at the step's end, where the collider
    /// now is), or `None` (the default). Asked only when
    /// [`in_step`](Self::in_step).
    fn first_contact(&self, path: &StepPath, radius: f32) -> Option<SweptHit> {
        let _ = (path, radius);
        None
    }

    /// As [`first_contact`](Self::first_contact), leaving out each
    /// surface whose hit `keep` refuses (the step refuses the hit of a
    /// box's face at a seam with a flush box: [`seams`]), so that a later
    /// surface of the same collider still counts. Default: `first_contact`'s
    /// hit, if `keep` takes it.
    fn first_contact_kept(
        &self,
        path: &StepPath,
        radius: f32,
        keep: &mut dyn FnMut(&SweptHit) -> bool,
    ) -> Option<SweptHit> {
        self.first_contact(path, radius).filter(|hit| keep(hit))
    }

    /// For [`in_step`](Self::in_step) colliders, on a chunk in blocks of
    /// four particles (`start`: their start positions; `columns`: the
    /// method's end state): clears in `settled[b]` the bits of the lanes of
    /// block `b` whose paths may meet this collider's surfaces this step
    /// faster than [`BlockColumns::rest_speed`]; the step follows those
    /// exactly ([`first_contact`](Self::first_contact)). The lanes left set
    /// certainly stay clear of the surfaces (a conservative test, see
    /// [`sweep::clearance4`]) or rest on them, and the end-of-step rule
    /// resolves them: a particle far from every surface, or resting on one,
    /// costs one vector test, not `first_contact`.
    ///
    /// With `resolve`, the collider may also resolve, by its end-of-step
    /// rule, each block whose lanes it left all set, and return true: the
    /// step then resolves only the other blocks, after following their
    /// lanes' paths (the same result, one pass fewer over the chunk).
    /// Default: clears every bit (every particle is followed) and returns
    /// false.
    fn settle_blocks(
        &self,
        start: &[Vec3x4],
        columns: BlockColumns<'_>,
        dt: f32,
        resolve: bool,
        settled: &mut [u8],
    ) -> bool {
        let _ = (start, columns, dt, resolve);
        settled.fill(0);
        false
    }

    /// The plane at rest along an axis this collider is, if it is one and
    /// finds its contacts inside the step (default: `None`). The step then
    /// follows the paths that meet it four particles at a time, in `f32`
    /// lanes, where this collider is the world's only in-step one and does
    /// not report (see [`AxisPlane`]); `first_contact` follows the rest.
    fn axis_plane(&self) -> Option<AxisPlane> {
        None
    }

    /// What this collider is in the GPU step (default: none, so that a
    /// world with it stays on the CPU, the error naming the collider).
    fn gpu_form(&self) -> GpuCollider {
        GpuCollider::None {
            reason: "the GPU step resolves planes and boxes only",
        }
    }

    /// Moves a kinematic collider by its own velocity over a step of `dt`
    /// seconds, before the step's contacts (default: it does not move).
    fn advance(&mut self, dt: f32) {
        let _ = dt;
    }
}

/// Copying a collider, for world snapshots. Implemented for every `Collider + Clone`.
pub trait ColliderState {
    /// A boxed copy.
    fn clone_boxed(&self) -> Box<dyn Collider>;
    /// The collider as `Any`, to copy into a collider of the same type.
    fn as_any(&self) -> &dyn Any;
    /// The collider as `Any`, to change it through its type
    /// ([`World::collider_mut`](crate::World::collider_mut)).
    fn as_any_mut(&mut self) -> &mut dyn Any;
    /// Overwrites `self` with `source` if they are the same type, reusing
    /// buffers; returns false otherwise.
    fn copy_state_from(&mut self, source: &dyn Collider) -> bool;
}

impl<T: Collider + Clone + 'static> ColliderState for T {
    fn clone_boxed(&self) -> Box<dyn Collider> {
        Box::new(self.clone())
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
    fn copy_state_from(&mut self, source: &dyn Collider) -> bool {
        source
            .as_any()
            .downcast_ref::<T>()
            .map(|s| self.clone_from(s))
            .is_some()
    }
}

impl Clone for Box<dyn Collider> {
    fn clone(&self) -> Self {
        self.clone_boxed()
    }
    fn clone_from(&mut self, source: &Self) {
        if !self.copy_state_from(source.as_ref()) {
            *self = source.clone_boxed();
        }
    }
}
