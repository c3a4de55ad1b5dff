//! Force generators, evaluated for the whole world inside the integrator's
//! acceleration callback.
//!
//! A [`Force`] adds accelerations to a slice of particles. Forces that depend
//! only on each particle's own state (gravity, drag, wind, fixed attractors)
//! say so with [`Force::is_pointwise`]; when every force is pointwise the
//! engine steps the world in cache-sized chunks (and spreads chunks over
//! threads), which is what keeps a million-particle step near memory speed.
//! Springs and n-body gravity couple particles and are evaluated on the whole
//! trial state, so multi-stage methods (midpoint, RK4) stay correct.

mod attractor;
mod drag;
mod gpu;
mod gravity;
mod nbody;
mod springs;
mod wind;

use core::any::Any;
use core::fmt;

use glam::Vec3A;
use tickwork_integrators::{System, Vec3x4};

pub use attractor::Attractor;
pub use drag::{LinearDrag, QuadraticDrag};
pub use gpu::{GpuForce, WgslF32};
pub use gravity::Gravity;
pub use nbody::NBody;
pub use springs::{Spring, SpringEnd, Springs};
pub use wind::Wind;

use crate::layout::{Entities, LANES, Rows, gather, scatter};

/// A force generator. Accelerations are in m/s^2; a force that is physically a
/// force (springs) divides by mass with the inverse masses it is given.
pub trait Force: Send + Sync + fmt::Debug + ForceState {
    /// Short name for diagnostics and scene files (`"gravity"`).
    fn name(&self) -> &'static str;

    /// Whether a particle's acceleration depends only on its own position and
    /// velocity (default: true).
    fn is_pointwise(&self) -> bool {
        true
    }

    /// Pairs of particles one evaluation of the force visits among
    /// `particles` (default: 0, a force of each particle alone; n-body:
    /// `n (n - 1) / 2`). The step refuses to start past
    /// [`WorldConfig::max_pairs`](crate::WorldConfig), so that quadratic
    /// work is an error that names its size, not a step that runs for
    /// minutes. Saturates rather than overflowing.
    fn pairs(&self, particles: usize) -> u64 {
        let _ = particles;
        0
    }

    /// The part of the force that is linear drag `-b v`, for exponential
    /// Euler, which integrates it exactly (default: 0).
    fn linear_drag(&self) -> f32 {
        0.0
    }

    /// `Some((c, b))` when the acceleration is exactly `a = c - b v` for
    /// constants `c` and `b` (gravity, linear drag, wind), so the force field
    /// can sum all such forces into one pass `a = sum c - (sum b) v` instead
    /// of one pass each (default: `None`).
    fn affine_in_velocity(&self) -> Option<(Vec3A, f32)> {
        None
    }

    /// What the force is in the GPU step (default: [`GpuForce::Affine`]
    /// for a force [affine in velocity](Self::affine_in_velocity),
    /// [`GpuForce::None`] otherwise, so that a world with it stays on the
    /// CPU). A force that answers [`GpuForce::Term`] writes its term with
    /// [`write_wgsl`](Self::write_wgsl).
    fn gpu_form(&self) -> GpuForce {
        if self.affine_in_velocity().is_some() {
            GpuForce::Affine
        } else {
            GpuForce::None
        }
    }

    /// Writes this force's term of the GPU step's `acceleration` (for
    /// [`GpuForce::Term`]): WGSL statements that add to `a`
    /// (`var a: vec3<f32>`) from the particle's `x` and `v` (`vec3<f32>`),
    /// the same operations in the same order as
    /// [`accumulate`](Self::accumulate), with the force's values as
    /// [`WgslF32`] literals; `length_squared(d)` sums as glam's dot
    /// product does (default: nothing).
    ///
    /// # Errors
    /// Only those of `out`.
    fn write_wgsl(&self, out: &mut dyn fmt::Write) -> fmt::Result {
        let _ = out;
        Ok(())
    }

    /// Resolves entity handles to rows; called once per step before the
    /// integrator runs (handles of despawned entities are dropped here).
    fn prepare(&mut self, entities: &Entities) {
        let _ = entities;
    }

    /// Adds this force's accelerations to `out` for the particles in rows
    /// `first .. first + out.len()`, whose trial positions, velocities and
    /// inverse masses are `x`, `v`, `inverse_mass`. Non-pointwise forces are
    /// always called with the whole world (`first == 0`).
    fn accumulate(&self, t: f32, first: usize, x: &[Vec3A], v: &[Vec3A], inverse_mass: &[f32], out: &mut [Vec3A]);

    /// Potential energy of the whole world under this force, in joules, for
    /// diagnostics (default: 0, for non-conservative forces).
    fn potential_energy(&self, x: &[Vec3A], inverse_mass: &[f32]) -> f64 {
        let _ = (x, inverse_mass);
        0.0
    }
}

/// Copying a force, for world snapshots. Implemented for every `Force + Clone`.
pub trait ForceState {
    /// A boxed copy.
    fn clone_boxed(&self) -> Box<dyn Force>;
    /// The force as `Any`, to copy into a force of the same type.
    fn as_any(&self) -> &dyn Any;
    /// The force as mutable `Any`, for [`World::force_mut`](crate::World::force_mut).
    fn as_any_mut(&mut self) -> &mut dyn Any;
    /// Overwrites `self` with `source` if they are the same type, reusing
    /// buffers; returns false otherwise.
    fn copy_state_from(&mut self, source: &dyn Force) -> bool;
}

impl<T: Force + Clone + 'static> ForceState for T {
    fn clone_boxed(&self) -> Box<dyn Force> {
        Box::new(self.clone())
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
    fn copy_state_from(&mut self, source: &dyn Force) -> bool {
        source
            .as_any()
            .downcast_ref::<T>()
            .map(|s| self.clone_from(s))
            .is_some()
    }
}

impl Clone for Box<dyn Force> {
    fn clone(&self) -> Self {
        self.clone_boxed()
    }
    fn clone_from(&mut self, source: &Self) {
        if !self.copy_state_from(source.as_ref()) {
            *self = source.clone_boxed();
        }
    }
}

/// The forces affine in velocity, summed in force order from zero:
/// `(sum c, sum b)`, the acceleration `c - b v` every particle starts from
/// (the force field's, the in-step rule's and the GPU step's one sum).
pub(crate) fn affine_sum(forces: &[Box<dyn Force>]) -> (Vec3A, f32) {
    forces
        .iter()
        .filter_map(|f| f.affine_in_velocity())
        .fold((Vec3A::ZERO, 0.0), add_affine)
}

/// One affine force's `(c, b)` added to a sum of them (the sum's one
/// definition, so that every sum has the same bits).
fn add_affine((c, b): (Vec3A, f32), (fc, fb): (Vec3A, f32)) -> (Vec3A, f32) {
    (c + fc, b + fb)
}

/// The world's forces seen as the integrator's [`System`]: the sum of every
/// force, zeroed for immovable particles (inverse mass 0).
#[derive(Clone, Copy)]
pub(crate) struct ForceField<'a> {
    pub forces: &'a [Box<dyn Force>],
    /// Inverse masses of the rows the integrator is stepping.
    pub inverse_mass: &'a [f32],
    /// Row of the first particle the integrator is stepping.
    pub offset: usize,
    pub pointwise: bool,
    /// Every force is `c - b v` ([`Force::affine_in_velocity`]).
    pub all_affine: bool,
    pub drag: f32,
    /// Sum of the affine forces' `c` and `b`: every particle starts from
    /// `c - b v`.
    pub affine: (Vec3A, f32),
}

impl<'a> ForceField<'a> {
    /// The same field over `count` of its rows from row `first` (the sums
    /// are not recomputed).
    pub fn window(&self, first: usize, count: usize) -> Self {
        Self {
            inverse_mass: &self.inverse_mass[first..first + count],
            offset: self.offset + first,
            ..*self
        }
    }

    pub fn new(forces: &'a [Box<dyn Force>], inverse_mass: &'a [f32], offset: usize) -> Self {
        // One pass over the forces (it runs every step, and a small world's
        // step is mostly such fixed work): the sums in force order.
        let mut field = Self {
            forces,
            inverse_mass,
            offset,
            pointwise: true,
            all_affine: true,
            // -0.0, the identity of float addition, as `Iterator::sum`
            // starts: with no forces the sum stays -0.0, as it was.
            drag: -0.0,
            affine: (Vec3A::ZERO, 0.0),
        };
        for force in forces {
            field.pointwise &= force.is_pointwise();
            field.drag += force.linear_drag();
            match force.affine_in_velocity() {
                Some(term) => field.affine = add_affine(field.affine, term),
                None => field.all_affine = false,
            }
        }
        field
    }
}

impl System<Vec3A> for ForceField<'_> {
    fn acceleration(&mut self, t: f32, x: &[Vec3A], v: &[Vec3A], out: &mut [Vec3A]) {
        self.acceleration_range(t, 0, x, v, out);
    }

    fn acceleration_range(&mut self, t: f32, first: usize, x: &[Vec3A], v: &[Vec3A], out: &mut [Vec3A]) {
        let inverse_mass = &self.inverse_mass[first..first + out.len()];
        let (c, b) = self.affine;
        for (a, v) in out.iter_mut().zip(v) {
            *a = c - *v * b;
        }
        for force in self.forces.iter().filter(|f| f.affine_in_velocity().is_none()) {
            force.accumulate(t, self.offset + first, x, v, inverse_mass, out);
        }
        // Immovable particles do not accelerate: a select, not a branch, and
        // only in the (rare) slices that hold one; the test is a cheap
        // vectorised pass over the inverse masses.
        if !all_movable(inverse_mass) {
            for (a, &w) in out.iter_mut().zip(inverse_mass) {
                *a = if w > 0.0 { *a } else { Vec3A::ZERO };
            }
        }
    }

    fn linear_drag(&self) -> f32 {
        self.drag
    }

    fn affine_range(&self, first: usize, count: usize) -> Option<(Vec3A, f32)> {
        // The affine sum is the whole acceleration only where every particle
        // moves (immovable ones get 0).
        (self.all_affine && all_movable(&self.inverse_mass[first..first + count])).then_some(self.affine)
    }

    fn is_pointwise(&self) -> bool {
        self.pointwise
    }
}

/// The force field over blocks of four particles (per-axis rows, as the
/// world stores them), for the fused step: the affine sum `c - b v` is one
/// vector operation per axis and block; any other pointwise force is given
/// its rows through scratch (`Vec3A` per particle), so it sees exactly the
/// arguments, and gives exactly the bits, of the row-by-row [`ForceField`].
pub(crate) struct BlockField<'a> {
    pub field: ForceField<'a>,
    /// Real rows among the blocks (the last block may be padding in part).
    pub rows: usize,
    /// Every row is movable (known from the chunk's facts): no scan for
    /// immovable ones.
    pub movable: bool,
    pub scratch: &'a mut Rows,
}

impl System<Vec3x4> for BlockField<'_> {
    fn acceleration(&mut self, t: f32, x: &[Vec3x4], v: &[Vec3x4], out: &mut [Vec3x4]) {
        self.acceleration_range(t, 0, x, v, out);
    }

    fn acceleration_range(&mut self, t: f32, first: usize, x: &[Vec3x4], v: &[Vec3x4], out: &mut [Vec3x4]) {
        let (c, b) = self.field.affine;
        let c4 = Vec3x4::splat(c);
        for (a, v) in out.iter_mut().zip(v) {
            *a = c4 - *v * b;
        }
        let rows = (first * LANES..((first + out.len()) * LANES).min(self.rows)).len();
        let first_row = first * LANES;
        let inverse_mass = &self.field.inverse_mass[first_row..first_row + rows];
        if !self.field.all_affine {
            let s = &mut *self.scratch;
            gather(x, rows, &mut s.x, false);
            gather(v, rows, &mut s.v, false);
            gather(out, rows, &mut s.other, false);
            for force in self.field.forces.iter().filter(|f| f.affine_in_velocity().is_none()) {
                force.accumulate(t, self.field.offset + first_row, &s.x, &s.v, inverse_mass, &mut s.other);
            }
            scatter(&s.other, out, false);
        }
        if !(self.movable || all_movable(inverse_mass)) {
            for (row, &w) in inverse_mass.iter().enumerate() {
                // As the row path's `w > 0` select: NaN is immovable too.
                let movable = w > 0.0;
                if !movable {
                    out[row / LANES].set_lane(row % LANES, Vec3A::ZERO);
                }
            }
        }
    }

    fn linear_drag(&self) -> f32 {
        self.field.drag
    }

    fn affine_range(&self, first: usize, count: usize) -> Option<(Vec3x4, f32)> {
        let rows = first * LANES..((first + count) * LANES).min(self.rows);
        (self.field.all_affine && (self.movable || all_movable(&self.field.inverse_mass[rows])))
            .then_some((Vec3x4::splat(self.field.affine.0), self.field.affine.1))
    }

    fn is_pointwise(&self) -> bool {
        self.field.pointwise
    }
}

/// Whether no inverse mass is 0 (one branch-free, vectorised pass).
#[inline]
pub(crate) fn all_movable(inverse_mass: &[f32]) -> bool {
    inverse_mass.iter().fold(true, |all, &w| all & (w > 0.0))
}

/// `1 / w`, or 0 for an immovable particle (which is no source of gravity:
/// use an [`Attractor`] for a fixed sun).
#[inline]
pub(crate) fn mass_of(inverse_mass: f32) -> f64 {
    if inverse_mass > 0.0 {
        1.0 / f64::from(inverse_mass)
    } else {
        0.0
    }
}
