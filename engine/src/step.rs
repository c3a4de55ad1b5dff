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

use core::fmt;

use glam::{Vec3, Vec3A, Vec4};
use rayon::prelude::*;
use tickwork_integrators::angular::{Bodies, TorqueFree};
use tickwork_integrators::{StepError, Vec3x4, build};

use crate::clock::FixedStep;
use crate::colliders::{BlockColumns, Collider, ContactColumns, PairTouch, RowTouch, diff_touches};
use crate::forces::{BlockField, Force, ForceField};
use crate::world::column::{LANES, gather, scatter};
use crate::world::facts::Facts;
use crate::world::{Entity, Lane, Rows, Vec3Column, World};

/// Particles integrated together in the fused step (128 blocks of four; a
/// multiple of 4, so chunks and lanes never split a block): their previous
/// and current positions and velocities are 18 KiB, within a 32 KiB L1 data
/// cache (512 was measured best among 256 to 4096 on `Vec3A` rows; 128 and
/// 256 were no faster for the full engine step, nor was prefetching).
pub const CHUNK: usize = 512;

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
    /// Lanes (threads) the fused path used.
    pub lanes: u32,
}

/// A step that failed.
#[derive(Clone, Debug, PartialEq)]
pub enum SimulationError {
    /// The integrator refused or failed (bad `dt`, a solver that did not converge).
    Integrator {
        /// The tick of the step.
        tick: u64,
        /// What the method said.
        error: StepError,
    },
    /// An emitter's settings are invalid (changed through `emitters_mut`).
    Emitter {
        /// The tick of the step.
        tick: u64,
        /// The emitter's index.
        index: usize,
        /// The invalid setting.
        error: crate::world::SpawnError,
    },
    /// A position or velocity became NaN or infinite (an explosion: a step too
    /// large for the method's stability, or a force that divides by zero),
    /// or was already so, or a force gave a non-finite acceleration.
    NonFinite {
        /// The tick of the step.
        tick: u64,
        /// The first entity (in row order) with a non-finite value.
        entity: Entity,
        /// `"position"`, `"velocity"` or `"acceleration"`.
        field: &'static str,
        /// The value.
        value: Vec3,
        /// What is known of how it came about.
        cause: NonFiniteCause,
    },
    /// An emitter is due more particles in one step than
    /// [`WorldConfig::max_spawns_per_step`](crate::world::WorldConfig) allows.
    SpawnLimit {
        /// The tick of the step.
        tick: u64,
        /// The emitter's index.
        emitter: usize,
        /// Particles it was due.
        due: f64,
        /// The limit in force.
        limit: u32,
    },
    /// An emitter would take the world past
    /// [`WorldConfig::max_particles`](crate::world::WorldConfig).
    ParticleLimit {
        /// The tick of the step.
        tick: u64,
        /// The emitter's index.
        emitter: usize,
        /// The limit in force.
        limit: usize,
    },
    /// The fixed step itself is invalid: a time or `dt` that is not finite
    /// (`dt` not above zero is the integrator's [`StepError::InvalidTimeStep`]).
    InvalidStep {
        /// The tick of the step.
        tick: u64,
        /// Its time, in seconds.
        time: f64,
        /// Its `dt`, in seconds.
        dt: f64,
    },
}

/// How a non-finite value came about, as far as the step can tell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NonFiniteCause {
    /// The step made it: too large a step for the method's stability, or a
    /// force that diverged.
    Step,
    /// It was already non-finite when the step began: set outside the step
    /// (through `particles_mut`, a game's system).
    Start,
    /// The forces gave a non-finite acceleration at a finite state (what
    /// made an implicit or adaptive solve fail).
    Force,
}

impl fmt::Display for SimulationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Integrator { tick, error } => write!(f, "step {tick}: {error}"),
            Self::Emitter { tick, index, error } => write!(f, "step {tick}: emitter {index}: {error}"),
            Self::NonFinite {
                tick,
                entity,
                field,
                value,
                cause,
            } => {
                write!(f, "step {tick}: {entity} has a non-finite {field} {value}; ")?;
                f.write_str(match cause {
                    NonFiniteCause::Step => "the step is too large for the integrator's stability, or a force diverged",
                    NonFiniteCause::Start => {
                        "it was so before the step began: it was set outside the step (particles_mut, a game system)"
                    }
                    NonFiniteCause::Force => "the forces gave it at a finite position and velocity",
                })
            }
            Self::SpawnLimit {
                tick,
                emitter,
                due,
                limit,
            } => write!(
                f,
                "step {tick}: emitter {emitter} is due {} particles in one step, past the limit of {limit} \
                 (WorldConfig::max_spawns_per_step); lower its rate or raise the limit",
                // `due` was an f32: its shortest form, not its widening's digits.
                crate::clock::Number::from(*due as f32)
            ),
            Self::ParticleLimit { tick, emitter, limit } => write!(
                f,
                "step {tick}: emitter {emitter} would take the world past its limit of {limit} particles \
                 (WorldConfig::max_particles); give its particles a shorter lifetime, lower its rate \
                 or raise the limit"
            ),
            Self::InvalidStep { tick, time, dt } => write!(
                f,
                "step {tick}: invalid fixed step: time {} s, dt {} s (both must be finite)",
                crate::clock::Number(*time),
                crate::clock::Number(*dt)
            ),
        }
    }
}

impl std::error::Error for SimulationError {}

/// The particle columns one lane steps: `previous` holds the positions at
/// the start of the step (read), `x` receives the new ones; the vectors in
/// blocks of four particles per axis, the scalars one per particle (`rows`
/// real particles; the last block may hold padding lanes), and the facts of
/// each of the lane's chunks.
struct LaneColumns<'a> {
    x: &'a mut [Vec3x4],
    v: &'a mut [Vec3x4],
    previous: &'a [Vec3x4],
    radius: &'a [f32],
    inverse_mass: &'a [f32],
    facts: &'a [Facts],
}

#[derive(Clone, Copy, Debug, Default)]
struct LaneOutcome {
    evaluations: u32,
    first_bad: Option<usize>,
}

fn merge(a: Result<LaneOutcome, StepError>, b: Result<LaneOutcome, StepError>) -> Result<LaneOutcome, StepError> {
    let (a, b) = (a?, b?);
    Ok(LaneOutcome {
        evaluations: a.evaluations.max(b.evaluations),
        first_bad: match (a.first_bad, b.first_bad) {
            (Some(x), Some(y)) => Some(x.min(y)),
            (x, y) => x.or(y),
        },
    })
}

/// Integrate (from `previous` into `x`), collide and check one lane, chunk
/// by chunk of [`CHUNK`] particles ([`CHUNK`] / 4 blocks). Colliders that
/// `report` contacts add them to the lane's list.
#[allow(clippy::too_many_arguments)]
fn step_lane(
    lane: &mut Lane,
    forces: &[Box<dyn Force>],
    colliders: &[Box<dyn Collider>],
    report: &[bool],
    t: f32,
    dt: f32,
    offset: usize,
    c: LaneColumns<'_>,
) -> Result<LaneOutcome, StepError> {
    let mut outcome = LaneOutcome::default();
    lane.touches.clear();
    let n = c.radius.len();
    // The force sums are the same for every chunk: made once per lane.
    let whole = ForceField::new(forces, c.inverse_mass, offset);
    let mut start = 0;
    while start < n {
        let end = (start + CHUNK).min(n);
        let (rows, blocks) = (start..end, start / LANES..end.div_ceil(LANES));
        let facts = c.facts[start / CHUNK];
        let (x, v) = (&mut c.x[blocks.clone()], &mut c.v[blocks.clone()]);
        let mut field = BlockField {
            field: whole.window(start, end - start),
            rows: end - start,
            movable: facts.movable,
            scratch: &mut lane.rows,
        };
        let stats = lane.method.step_from(t, dt, &c.previous[blocks], x, v, &mut field)?;
        outcome.evaluations = outcome.evaluations.max(stats.evaluations);
        for (k, collider) in colliders.iter().enumerate() {
            let (radius, inverse_mass) = (&c.radius[rows.clone()], &c.inverse_mass[rows.clone()]);
            if report[k] {
                let touches = Reporting {
                    collider: k as u32,
                    first_row: offset + start,
                    out: &mut lane.touches,
                };
                resolve_rows(
                    collider.as_ref(),
                    x,
                    v,
                    radius,
                    inverse_mass,
                    &mut lane.rows,
                    Some(touches),
                );
                continue;
            }
            let blocks = BlockColumns {
                position: x,
                velocity: v,
                radius: &c.radius[rows.clone()],
                inverse_mass: &c.inverse_mass[rows.clone()],
                rows: end - start,
                movable: facts.movable,
                point: facts.point,
            };
            if !collider.resolve_blocks(blocks) {
                resolve_rows(collider.as_ref(), x, v, radius, inverse_mass, &mut lane.rows, None);
            }
        }
        if outcome.first_bad.is_none() {
            outcome.first_bad = Vec3Column::first_non_finite(x, v, end - start, offset + start);
        }
        start = end;
    }
    Ok(outcome)
}

/// Where a reporting collider's contacts go: its index, the global row of
/// the first row it is given, and the list.
struct Reporting<'a> {
    collider: u32,
    first_row: usize,
    out: &'a mut Vec<RowTouch>,
}

/// A collider without a block kernel (or one that reports contacts), on a
/// chunk's rows: gathered into scratch, resolved, written back.
fn resolve_rows(
    collider: &dyn Collider,
    x: &mut [Vec3x4],
    v: &mut [Vec3x4],
    radius: &[f32],
    inverse_mass: &[f32],
    scratch: &mut Rows,
    reporting: Option<Reporting<'_>>,
) {
    gather(x, radius.len(), &mut scratch.x);
    gather(v, radius.len(), &mut scratch.v);
    if reporting.is_some() {
        scratch.before_x.clone_from(&scratch.x);
        scratch.before_v.clone_from(&scratch.v);
    }
    collider.resolve_range(ContactColumns {
        position: &mut scratch.x,
        velocity: &mut scratch.v,
        radius,
        inverse_mass,
        parallel: false,
    });
    if let Some(r) = reporting {
        let s = &*scratch;
        diff_touches(
            r.collider,
            r.first_row,
            &s.before_x,
            &s.before_v,
            &s.x,
            &s.v,
            radius,
            inverse_mass,
            r.out,
        );
    }
    scatter(&scratch.x, x);
    scatter(&scratch.v, v);
}

/// A reporting collider over the whole world: its own pair reports if it
/// makes them, else the contacts found by comparing states.
fn resolve_world_reporting(
    collider: &mut dyn Collider,
    index: u32,
    c: ContactColumns<'_>,
    before_x: &mut Vec<Vec3A>,
    before_v: &mut Vec<Vec3A>,
    out: &mut Vec<RowTouch>,
) {
    let (radius, inverse_mass) = (c.radius, c.inverse_mass);
    if !collider.is_pointwise() {
        let mut report = |pair: PairTouch| {
            // One per pair, under the lower row, the normal towards it.
            let (row, other, normal) = if pair.a <= pair.b {
                (pair.a, pair.b, pair.normal)
            } else {
                (pair.b, pair.a, -pair.normal)
            };
            out.push(RowTouch {
                collider: index,
                row: row as u32,
                other: other as u32,
                point: pair.point,
                normal,
                impulse: pair.impulse,
            });
        };
        let reborrow = ContactColumns {
            position: &mut *c.position,
            velocity: &mut *c.velocity,
            radius,
            inverse_mass,
            parallel: false,
        };
        if collider.resolve_world_reporting(reborrow, &mut report) {
            return;
        }
    }
    before_x.clear();
    before_x.extend_from_slice(c.position);
    before_v.clear();
    before_v.extend_from_slice(c.velocity);
    collider.resolve_world(ContactColumns {
        position: &mut *c.position,
        velocity: &mut *c.velocity,
        ..c
    });
    diff_touches(
        index,
        0,
        before_x,
        before_v,
        c.position,
        c.velocity,
        radius,
        inverse_mass,
        out,
    );
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
        mut systems: impl FnMut(&mut World, &FixedStep),
    ) -> Result<StepReport, SimulationError> {
        let tick = step.tick;
        if !(step.time.is_finite() && step.dt.is_finite()) {
            return Err(SimulationError::InvalidStep {
                tick,
                time: step.time,
                dt: step.dt,
            });
        }
        let (t, dt) = (step.time as f32, step.dt as f32);
        self.check_emitters(dt, tick)?;
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
        for collider in &mut self.colliders.colliders {
            collider.advance(dt);
        }
        self.integrate(t, dt, tick, &mut report)?;
        if tick.is_multiple_of(SUBNORMAL_FLUSH_EVERY) {
            flush_subnormals(self.particles.velocity.blocks_mut());
        }
        self.step_rigid_bodies(t, dt, tick)?;
        // Aged once the particles and bodies have stepped (a failed step
        // leaves the lived time, and the dead it would find, for the next),
        // and before the emitters, for whom expiry makes room.
        self.expired_rows.clear();
        self.particles.age(step.dt, &mut self.expired_rows);
        self.expire(&mut report);
        self.emit(dt, tick)?;
        let (spawned, despawned) = self.apply_queued();
        self.tick = tick + 1;
        self.time = step.time + step.dt;
        self.revision += 1;
        systems(self, &step);
        let (spawned_by_game, despawned_by_game) = self.apply_queued();
        report.spawned = spawned + spawned_by_game;
        report.despawned = despawned + despawned_by_game;
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
        report.lanes = lanes as u32;
        // Stateless methods only (they split pointwise): each lane builds
        // its own copy, stepping blocks, by the world's method's name.
        let name = self.integrator.info().name;
        while self.lanes.len() < lanes {
            let Ok(method) = build::<Vec3x4>(name) else {
                unreachable!("{name} is registered: it is the world's own method")
            };
            self.lanes.push(Lane {
                method,
                rows: Rows::default(),
                touches: Vec::new(),
            });
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
        for lane in &mut self.lanes[lanes..] {
            lane.touches.clear();
        }
        if lanes == 1 {
            return step_lane(&mut self.lanes[0], forces, colliders, reports, t, dt, 0, columns);
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
                step_lane(lane, forces, colliders, reports, t, dt, k * len, c)
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
        p.previous_position.gather_into(&mut g.other);
        p.velocity.gather_into(&mut g.v);
        // The method writes every end position: what the buffer held (the
        // last plain step's positions) does not matter, so it is not cleared.
        g.x.resize(n, Vec3A::ZERO);
        let mut field = ForceField::new(&self.forces, &p.inverse_mass, 0);
        let stats = self
            .integrator
            .step_from(t, dt, &g.other, &mut g.x, &mut g.v, &mut field)?;
        self.touches.clear();
        let set = &mut self.colliders;
        for (k, collider) in set.colliders.iter_mut().enumerate() {
            let columns = ContactColumns {
                position: &mut g.x,
                velocity: &mut g.v,
                radius: &p.radius,
                inverse_mass: &p.inverse_mass,
                parallel: n >= self.config.parallel_threshold,
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
        p.position.scatter_from(&g.x);
        p.velocity.scatter_from(&g.v);
        Ok(LaneOutcome {
            evaluations: stats.evaluations,
            first_bad: Vec3Column::first_non_finite(p.position.blocks(), p.velocity.blocks(), n, 0),
        })
    }

    /// The contacts the step's colliders reported, by row (from the lanes
    /// of a fused step, in lane order, or from the plain step), sorted into
    /// the canonical order and named by entity, while the rows are still
    /// those the step found them at.
    fn name_contacts(&mut self, fused: bool) {
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
        p.position.gather_into(&mut x);
        p.velocity.gather_into(&mut v);
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
