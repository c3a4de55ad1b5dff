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
mod error;
mod follow;
mod in_step;
mod lane_step;
mod reporting;

pub use error::{NonFiniteCause, SimulationError};
use in_step::Sweep;
use lane_step::{LaneColumns, LaneOutcome, merge, step_lane};
use reporting::resolve_world_reporting;

use glam::{Vec3A, Vec4};
use rayon::prelude::*;
use tickwork_integrators::angular::{Bodies, TorqueFree};
use tickwork_integrators::{StepError, Vec3x4, build};

use crate::clock::FixedStep;
use crate::colliders::{ContactColumns, RowTouch};
use crate::forces::ForceField;
use crate::layout::{CHUNK, LANES, Vec3Column};
use crate::world::{Lane, Removal, RemovalCause, World};

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
    /// Runs one fixed step. `step` comes from the clock
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
        self.integrate(t, dt, tick, &mut report)?;
        if tick.is_multiple_of(SUBNORMAL_FLUSH_EVERY) {
            flush_subnormals(self.particles.velocity.blocks_mut());
        }
        self.step_rigid_bodies(t, dt, tick)?;
        self.turn_headings(dt);
        self.end_step(step, &mut report, systems)?;
        Ok(report)
    }

    /// What a step does once the particles and bodies have stepped: the
    /// lifetimes, expiry, emitters, queued commands, the tick and time,
    /// the game's systems, the sensors.
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
        self.check_pairs(step.tick)
    }

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
        let mut report = StepReport::default();
        self.end_step(step, &mut report, |_, _| {})?;
        Ok(report)
    }

    fn integrate(&mut self, t: f32, dt: f32, tick: u64, report: &mut StepReport) -> Result<(), SimulationError> {
        let fused = self.integrator.splits_pointwise()
            && self.forces.iter().all(|f| f.is_pointwise())
            && self.colliders.colliders.iter().all(|c| c.is_pointwise());
        // Double buffering: the positions at the start of the step become
        // the previous positions (for interpolation) by a swap, and the step
        // writes the new positions into the other buffer; nothing is copied.
        let p = &mut self.particles;
        core::mem::swap(&mut p.position, &mut p.previous_position);
        let outcome = if fused {
            self.integrate_fused(t, dt, report)
        } else {
            self.integrate_rows(t, dt)
        };
        let outcome = match outcome {
            Ok(outcome) => outcome,
            Err(error) => {
                // The method left the state as it was: put the buffers back.
                let p = &mut self.particles;
                core::mem::swap(&mut p.position, &mut p.previous_position);
                // A solve that failed on a non-finite value says which.
                return Err(self
                    .diagnose(t, tick)
                    .unwrap_or(SimulationError::Integrator { tick, error }));
            }
        };
        report.evaluations = outcome.evaluations;
        self.name_contacts(fused);
        if let Some(row) = outcome.first_bad {
            return Err(self.non_finite(tick, row, NonFiniteCause::Step));
        }
        if let Some(overflow) = outcome.overflow
            && self.config.contact_overflow == crate::ContactOverflow::EndOfStep
        {
            report.contact_overflow = Some(self.entities.rows()[overflow.row]);
        } else if let Some(overflow) = outcome.overflow {
            let collider = &self.colliders.colliders[overflow.collider];
            return Err(SimulationError::ContactEventLimit {
                tick,
                entity: self.entities.rows()[overflow.row],
                collider: collider.name(),
                index: overflow.collider,
                limit: crate::colliders::MAX_CONTACT_EVENTS,
            });
        }
        for (index, collider) in self.colliders.colliders.iter().enumerate() {
            if let Some(pairs) = collider.refused_pairs() {
                return Err(SimulationError::ContactPairLimit {
                    tick,
                    collider: collider.name(),
                    index,
                    particles: self.particles.len(),
                    pairs,
                    limit: self.config.max_pairs,
                });
            }
        }
        Ok(())
    }

    /// The fused step on the blocks: integration, colliders and the
    /// finiteness check chunk by chunk, in lanes above the threshold.
    fn integrate_fused(&mut self, t: f32, dt: f32, report: &mut StepReport) -> Result<LaneOutcome, StepError> {
        let p = &mut self.particles;
        let n = p.len();
        let wanted = if n >= self.config.parallel_threshold {
            rayon::current_num_threads().min(n.div_ceil(CHUNK)).max(1)
        } else {
            1
        };
        // Rows per lane: whole chunks, so the split is fixed by particle
        // index (never by thread count) and no block straddles two lanes.
        // Whole chunks can leave fewer parts than wanted lanes (3 lanes,
        // 1 537 rows: 2 parts): only the parts run.
        let (lanes, len) = if wanted > 1 {
            let len = n.div_ceil(wanted).div_ceil(CHUNK) * CHUNK;
            (n.div_ceil(len), len)
        } else {
            (1, n)
        };
        report.fused = true;
        report.fused_lanes = lanes as u32;
        // Stateless methods only (they split pointwise): each lane builds
        // its own copy, stepping blocks, by the world's method's name.
        while self.lanes.len() < lanes {
            let name = self.integrator.info().name;
            let Ok(method) = build::<Vec3x4>(name) else {
                unreachable!("{name} is registered: it is the world's own method")
            };
            self.lanes.push(Lane::new(method));
        }
        let columns = LaneColumns {
            facts: p.facts.refresh(&p.radius, &p.inverse_mass),
            x: p.position.blocks_mut(),
            v: p.velocity.blocks_mut(),
            previous: p.previous_position.blocks(),
            radius: &p.radius,
            inverse_mass: &p.inverse_mass,
        };
        let (forces, colliders) = (&self.forces[..], &self.colliders.colliders[..]);
        let reports = &self.colliders.reports[..];
        let sweep = Sweep::new(colliders, reports, forces, dt, self.config.rest_speed);
        for lane in &mut self.lanes[lanes..] {
            lane.touches.clear();
        }
        if lanes == 1 {
            return step_lane(&mut self.lanes[0], forces, colliders, reports, sweep, t, dt, 0, columns);
        }
        columns
            .x
            .par_chunks_mut(len / LANES)
            .zip(columns.v.par_chunks_mut(len / LANES))
            .zip(columns.previous.par_chunks(len / LANES))
            .zip(columns.radius.par_chunks(len))
            .zip(columns.inverse_mass.par_chunks(len))
            .zip(columns.facts.par_chunks(len / CHUNK))
            .zip(self.lanes.par_iter_mut())
            .enumerate()
            .map(|(k, ((((((x, v), previous), radius), inverse_mass), facts), lane))| {
                let c = LaneColumns {
                    x,
                    v,
                    previous,
                    radius,
                    inverse_mass,
                    facts,
                };
                step_lane(lane, forces, colliders, reports, sweep, t, dt, k * len, c)
            })
            .reduce(|| Ok(LaneOutcome::default()), merge)
    }

    /// The plain step, on rows gathered from the blocks (methods with
    /// history, implicit and adaptive ones, coupled forces, sphere
    /// collisions): the method steps the whole world at once, then each
    /// collider; the rows go back into the blocks.
    fn integrate_rows(&mut self, t: f32, dt: f32) -> Result<LaneOutcome, StepError> {
        let p = &mut self.particles;
        let g = &mut self.gathered;
        let n = p.len();
        let parallel = n >= self.config.parallel_threshold;
        p.previous_position.gather_into(&mut g.other, parallel);
        p.velocity.gather_into(&mut g.v, parallel);
        // The method writes every end position: what the buffer held (the
        // last plain step's positions) does not matter, so it is not cleared.
        g.x.resize(n, Vec3A::ZERO);
        let mut field = ForceField::new(&self.forces, &p.inverse_mass, 0);
        let stats = self
            .integrator
            .step_from(t, dt, &g.other, &mut g.x, &mut g.v, &mut field)?;
        self.touches.clear();
        let overflow = self.resolve_in_step(dt, parallel);
        let p = &mut self.particles;
        let g = &mut self.gathered;
        let set = &mut self.colliders;
        // The in-step colliders acted above; the others, in order.
        for (k, collider) in set.colliders.iter_mut().enumerate() {
            if collider.in_step() {
                continue;
            }
            let columns = ContactColumns {
                position: &mut g.x,
                velocity: &mut g.v,
                radius: &p.radius,
                inverse_mass: &p.inverse_mass,
                parallel,
                max_pairs: self.config.max_pairs,
                start: Some(crate::colliders::StepStart { position: &g.other, dt }),
                rest_speed: 0.0,
            };
            if set.reports[k] {
                resolve_world_reporting(
                    collider.as_mut(),
                    k as u32,
                    columns,
                    &mut g.before_x,
                    &mut g.before_v,
                    &mut self.touches,
                );
            } else {
                collider.resolve_world(columns);
            }
        }
        p.position.scatter_from(&g.x, parallel);
        p.velocity.scatter_from(&g.v, parallel);
        Ok(LaneOutcome {
            evaluations: stats.evaluations,
            first_bad: Vec3Column::first_non_finite_in(p.position.blocks(), p.velocity.blocks(), n, parallel),
            overflow,
        })
    }

    /// The contacts the step's colliders reported, by row (from the lanes
    /// of a fused step, in lane order, or from the plain step), sorted into
    /// the canonical order and named by entity, while the rows are still
    /// those the step found them at.
    /// The step's contacts by entity, from its touches by row (`fused`:
    /// gathered from the lanes first), sorted as every path sorts them.
    pub(crate) fn name_contacts(&mut self, fused: bool) {
        self.contacts.clear();
        if !self.colliders.any_reports() {
            return;
        }
        if fused {
            self.touches.clear();
            for lane in &self.lanes {
                self.touches.extend_from_slice(&lane.touches);
            }
        }
        // Keys are unique (one touch per row and collider, one per pair),
        // so an unstable sort, which allocates nothing, is deterministic.
        self.touches.sort_unstable_by_key(RowTouch::key);
        let rows = self.entities.rows();
        let ids = &self.colliders.ids;
        self.contacts
            .extend(self.touches.iter().map(|t| crate::colliders::Contact {
                entity: rows[t.row as usize],
                touched: if t.other == u32::MAX {
                    crate::colliders::Touched::Collider(ids[t.collider as usize])
                } else {
                    crate::colliders::Touched::Entity(rows[t.other as usize])
                },
                point: t.point.into(),
                normal: t.normal.into(),
                impulse: t.impulse,
                fraction: t.fraction,
            }));
    }

    /// The error for row `row`'s non-finite position or velocity.
    fn non_finite(&self, tick: u64, row: usize, cause: NonFiniteCause) -> SimulationError {
        let p = &self.particles;
        let (x, v) = (p.position.row(row), p.velocity.row(row));
        let (field, value) = if x.is_finite() {
            ("velocity", v)
        } else {
            ("position", x)
        };
        SimulationError::NonFinite {
            tick,
            entity: self.entities.rows()[row],
            field,
            value: value.into(),
            cause,
        }
    }

    /// After a failed integrator step: the first particle whose state, or
    /// whose acceleration at that state, is not finite (so a NaN force is
    /// named, not reported as a solve that "did not converge"). Only on the
    /// error path, so its scratch buffer may allocate.
    fn diagnose(&self, t: f32, tick: u64) -> Option<SimulationError> {
        let p = &self.particles;
        if let Some(row) = Vec3Column::first_non_finite(p.position.blocks(), p.velocity.blocks(), p.len(), 0) {
            return Some(self.non_finite(tick, row, NonFiniteCause::Start));
        }
        let (mut x, mut v) = (Vec::new(), Vec::new());
        p.position.gather_into(&mut x, false);
        p.velocity.gather_into(&mut v, false);
        let mut accelerations = vec![Vec3A::ZERO; p.len()];
        let mut field = ForceField::new(&self.forces, &p.inverse_mass, 0);
        tickwork_integrators::System::acceleration(&mut field, t, &x, &v, &mut accelerations);
        let row = accelerations.iter().position(|a| !a.is_finite())?;
        Some(SimulationError::NonFinite {
            tick,
            entity: self.entities.rows()[row],
            field: "acceleration",
            value: accelerations[row].into(),
            cause: NonFiniteCause::Force,
        })
    }

    fn step_rigid_bodies(&mut self, t: f32, dt: f32, tick: u64) -> Result<(), SimulationError> {
        if self.rigid.is_empty() {
            return Ok(());
        }
        let r = &mut self.rigid;
        r.previous_orientation.copy_from_slice(&r.orientation);
        let bodies = Bodies {
            orientations: &mut r.orientation,
            angular_velocities: &mut r.angular_velocity,
            inertia: &r.inertia,
        };
        self.angular
            .step(t, dt, bodies, &mut TorqueFree)
            .map_err(|error| SimulationError::Integrator { tick, error })?;
        if let Some(k) = r
            .orientation
            .iter()
            .zip(&r.angular_velocity)
            .position(|(q, w)| !q.is_finite() || !w.is_finite())
        {
            let row = r.owner[k] as usize;
            return Err(SimulationError::NonFinite {
                tick,
                entity: self.entities.rows()[row],
                field: "angular_velocity",
                value: r.angular_velocity[k],
                cause: NonFiniteCause::Step,
            });
        }
        Ok(())
    }

    fn expire(&mut self, report: &mut StepReport) {
        if self.expired_rows.is_empty() {
            return;
        }
        // Rows ascend (one scan in row order); turn them into handles
        // first, since each despawn moves the last row.
        self.expired.clear();
        let rows = self.entities.rows();
        self.expired
            .extend(self.expired_rows.iter().map(|&row| rows[row as usize]));
        for k in 0..self.expired.len() {
            let entity = self.expired[k];
            if self.despawn(entity).is_ok() {
                report.expired += 1;
                self.removed.push(Removal {
                    entity,
                    cause: RemovalCause::Expired,
                });
            }
        }
    }

    /// Emitter settings and the spawns they are due this step, checked
    /// before the step changes anything (`emitters_mut` lets a game change
    /// settings between steps); `due` is computed as [`Emitter::due`] will.
    fn check_emitters(&self, dt: f32, tick: u64) -> Result<(), SimulationError> {
        for (k, emitter) in self.emitters.iter().enumerate() {
            emitter
                .validate()
                .map_err(|error| SimulationError::Emitter { tick, index: k, error })?;
            let due = emitter.peek_due(dt);
            let limit = self.config.max_spawns_per_step;
            if due.is_nan() || due > limit as f32 {
                return Err(SimulationError::SpawnLimit {
                    tick,
                    emitter: k,
                    due: f64::from(due),
                    limit,
                });
            }
        }
        Ok(())
    }

    /// The pairs each force would visit among the world's particles,
    /// against [`WorldConfig::max_pairs`](crate::WorldConfig): checked
    /// before the step changes anything (the world grows between steps,
    /// by spawns and emitters, and forces are added between them).
    fn check_pairs(&self, tick: u64) -> Result<(), SimulationError> {
        self.check_force_pairs(tick)?;
        let (particles, limit) = (self.entities.len(), self.config.max_pairs);
        let pairs = self.sensor_pairs();
        if pairs > limit {
            return Err(SimulationError::SensorPairLimit {
                tick,
                sensors: self.sensors.list.len(),
                particles,
                pairs,
                limit,
            });
        }
        Ok(())
    }

    /// The forces' part of [`check_pairs`](Self::check_pairs): also asked
    /// before the energy's potentials visit their pairs.
    pub(crate) fn check_force_pairs(&self, tick: u64) -> Result<(), SimulationError> {
        let particles = self.entities.len();
        let limit = self.config.max_pairs;
        for force in &self.forces {
            let pairs = force.pairs(particles);
            if pairs > limit {
                return Err(SimulationError::PairLimit {
                    tick,
                    force: force.name(),
                    particles,
                    pairs,
                    limit,
                });
            }
        }
        Ok(())
    }

    fn emit(&mut self, dt: f32, tick: u64) -> Result<(), SimulationError> {
        for k in 0..self.emitters.len() {
            let due = self.emitters[k].due(dt);
            // Known only now, after expiry has made room: past the limit,
            // the world is left as the step made it (as for `NonFinite`).
            if self.check_room(due as usize).is_err() {
                return Err(SimulationError::ParticleLimit {
                    tick,
                    emitter: k,
                    limit: self.config.max_particles,
                });
            }
            for _ in 0..due as u32 {
                let particle = self.emitters[k].particle(&mut self.rng);
                let entity = self.entities.reserve();
                self.queue.push(crate::world::Command::Spawn(entity, particle));
            }
            self.queued_spawns += due as usize;
        }
        Ok(())
    }
}
