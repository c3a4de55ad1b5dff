//! The fixed step: what happens to the world once per tick of the clock.
//!
//! ```text
//! check: the step's time; the state, if it was edited outside the steps
//! previous <-> current                      (a swap of buffers, for interpolation)
//! x, v     <- integrator(t, dt, previous, v, forces)   (into the other buffer)
//! colliders
//! check: every position and velocity finite (a failed solve: which force)
//! rigid bodies: orientations and angular velocities (then the same check)
//! lived += dt; if it reached the next death: the expired rows despawned
//! emitters and queued spawns/despawns
//! the game's fixed systems (then their queued commands)
//! ```
//!
//! When every force and collider is pointwise and the method
//! [splits](tickwork_integrators::Integrator::splits_pointwise), the
//! integration, the colliders and the finiteness check run
//! fused on the world's per-axis blocks (four particles per SIMD value), one
//! cache-sized chunk of 512 particles at a time, while the chunk sits in L1,
//! so a million-particle step reads and writes each column about once.
//! Otherwise the rows are gathered from the blocks, stepped whole and
//! written back. Above
//! [`WorldConfig::parallel_threshold`](crate::world::WorldConfig) particles,
//! contiguous lanes of chunks run on rayon's threads, each with its own copy
//! of the method; results are bit-identical to the serial step because each
//! particle's arithmetic is the same.

mod chunk;
mod diagnose;
mod error;
mod follow;
mod in_step;
mod integrate;
mod lane_step;
mod lifetimes;
mod limits;
mod reporting;
mod rigid;

pub use error::{NonFiniteCause, SimulationError};

use glam::Vec4;
use tickwork_integrators::Vec3x4;

use crate::clock::FixedStep;
use crate::layout::Vec3Column;
use crate::world::World;

/// What a step did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepReport {
    /// Force evaluations per particle.
    pub evaluations: u32,
    /// Particles whose lifetime ran out.
    pub expired: u32,
    /// Entities spawned (emitters and queued spawns).
    pub spawned: u32,
    /// Entities despawned from the queue.
    pub despawned: u32,
    /// Whether the fused chunked path ran.
    pub fused: bool,
    /// Lanes of the fused chunked path: the contiguous parts of the rows
    /// stepped at once on rayon's threads (1: one part on this thread; 0:
    /// the fused path did not run, though the plain path's passes may
    /// still have used rayon's threads).
    pub fused_lanes: u32,
    /// The first particle (in row order) that met more than
    /// [`MAX_CONTACT_EVENTS`](crate::colliders::MAX_CONTACT_EVENTS)
    /// contacts inside the step and was left to the end-of-step rule
    /// ([`ContactOverflow::EndOfStep`](crate::ContactOverflow)).
    pub contact_overflow: Option<crate::layout::Entity>,
}

/// Steps between two flushes of subnormal velocities.
pub const SUBNORMAL_FLUSH_EVERY: u64 = 64;

/// Sets velocity components of magnitude below `f32::MIN_POSITIVE`
/// (1.2e-38 m/s, subnormal numbers) to +0, as a processor's flush-to-zero
/// mode would (it keeps the sign: -0), but the same on every platform. Why: under drag `v (1 - b h)^n`
/// reaches the subnormal range after about 15 minutes of rest (b = 0.1, 60
/// Hz) and then sticks at the smallest subnormal, where each operation is
/// about 100 times slower. Run every [`SUBNORMAL_FLUSH_EVERY`] ticks (a pass
/// over the velocities every 64 steps costs nothing measurable); zeros and
/// normal numbers are left as they are.
fn flush_subnormals(velocity: &mut [Vec3x4]) {
    let smallest = Vec4::splat(f32::MIN_POSITIVE);
    let flush = |v: Vec4| Vec4::select(v.abs().cmplt(smallest) & v.cmpne(Vec4::ZERO), Vec4::ZERO, v);
    for v in velocity {
        (v.x, v.y, v.z) = (flush(v.x), flush(v.y), flush(v.z));
    }
}

impl World {
    /// Runs one fixed step on the CPU, whatever
    /// [`WorldConfig::backend`](crate::WorldConfig) says: the backend is
    /// a runner's choice (a game's stage, a scene's playback), which steps
    /// a GPU world through its GPU copy. `step` comes from the clock
    /// ([`Frame::fixed_steps`](crate::clock::Frame::fixed_steps)) or is made
    /// by hand for tools.
    ///
    /// # Errors
    /// [`SimulationError`] when the integrator fails (the particles are then
    /// unchanged by it) or a position or velocity became non-finite (the
    /// world is left as the step made it, to inspect; restore a snapshot to
    /// go on). An invalid emitter, or one due more than
    /// `max_spawns_per_step`, is refused before the step changes anything;
    /// one past `max_particles` is found after expiry has made room, and
    /// leaves the world as the step made it.
    pub fn step(&mut self, step: FixedStep) -> Result<StepReport, SimulationError> {
        self.step_with(step, |_, _| {})
    }

    /// [`step`](Self::step), running the game's fixed systems after the
    /// physics: `systems(world, step)` sees the stepped world and may queue
    /// spawns and despawns, which are applied before the step returns.
    ///
    /// # Errors
    /// As [`step`](Self::step).
    pub fn step_with(
        &mut self,
        step: FixedStep,
        systems: impl FnMut(&mut World, &FixedStep),
    ) -> Result<StepReport, SimulationError> {
        let tick = step.tick;
        self.check_step(step)?;
        let (t, dt) = (step.time as f32, step.dt as f32);
        let mut report = StepReport::default();
        for force in &mut self.forces {
            force.prepare(&self.entities);
        }
        if std::mem::take(&mut self.edited)
            && let Some(row) = Vec3Column::first_non_finite(
                self.particles.position.blocks(),
                self.particles.velocity.blocks(),
                self.particles.len(),
                0,
            )
        {
            return Err(self.non_finite(tick, row, NonFiniteCause::Start));
        }
        self.removed.clear();
        self.advance_colliders(dt);
        self.move_characters(dt);
        self.integrate(t, dt, tick, &mut report)?;
        if tick.is_multiple_of(SUBNORMAL_FLUSH_EVERY) {
            flush_subnormals(self.particles.velocity.blocks_mut());
        }
        self.step_rigid_bodies(t, dt, tick)?;
        self.turn_headings(dt);
        self.end_step(step, &mut report, systems)?;
        Ok(report)
    }

    /// Moves the kinematic colliders by their velocity over `dt` (a step's
    /// first change: its contacts meet them where they end).
    pub(crate) fn advance_colliders(&mut self, dt: f32) {
        for collider in &mut self.colliders.colliders {
            collider.advance(dt);
        }
    }

    /// What a step refuses before it changes anything: a time or length
    /// that is not finite, an invalid emitter or one due too many, a force
    /// past its pairs.
    pub(crate) fn check_step(&self, step: FixedStep) -> Result<(), SimulationError> {
        if !(step.time.is_finite() && step.dt.is_finite()) {
            return Err(SimulationError::InvalidStep {
                tick: step.tick,
                time: step.time,
                dt: step.dt,
            });
        }
        self.check_emitters(step.dt as f32, step.tick)?;
        self.check_characters(step.tick)?;
        self.check_pairs(step.tick)
    }

    /// What a step does once the particles and bodies have stepped: the
    /// lifetimes, expiry, emitters, queued commands, the tick and time,
    /// the game's systems, the sensors.
    fn end_step(
        &mut self,
        step: FixedStep,
        report: &mut StepReport,
        mut systems: impl FnMut(&mut World, &FixedStep),
    ) -> Result<(), SimulationError> {
        // Aged once the particles and bodies have stepped (a failed step
        // leaves the lived time, and the dead it would find, for the next),
        // and before the emitters, for whom expiry makes room.
        self.expired_rows.clear();
        self.particles.age(step.dt, &mut self.expired_rows);
        self.expire(report);
        self.emit(step.dt as f32, step.tick)?;
        let (spawned, despawned) = self.apply_queued();
        self.tick = step.tick + 1;
        self.time = step.time + step.dt;
        self.revision += 1;
        systems(self, &step);
        let (spawned_by_game, despawned_by_game) = self.apply_queued();
        report.spawned = spawned + spawned_by_game;
        report.despawned = despawned + despawned_by_game;
        self.find_overlaps();
        Ok(())
    }

    /// The step of a world whose particles are stepped elsewhere (a GPU
    /// world's, `gpu_step`): the same checks, then what the step does
    /// after the particles' integration (lifetimes, expiry, emitters,
    /// queued commands, tick and time), the particle state and the step's
    /// contacts (named by the caller, before the rows change) untouched. The
    /// caller has refused what this leaves out (rigid bodies, headings,
    /// sensors) and moved the kinematic colliders.
    ///
    /// # Errors
    /// As [`step`](Self::step), for what it does.
    #[cfg(feature = "render")]
    pub(crate) fn step_bookkeeping(&mut self, step: FixedStep) -> Result<StepReport, SimulationError> {
        self.check_step(step)?;
        self.edited = false;
        self.removed.clear();
        self.move_characters(step.dt as f32);
        let mut report = StepReport::default();
        self.end_step(step, &mut report, |_, _| {})?;
        Ok(report)
    }
}
