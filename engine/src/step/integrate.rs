//! The particles' integration: the fused, chunked path on the blocks, or
//! the rows gathered and stepped whole, then the contacts named.

use glam::Vec3A;
use rayon::prelude::*;
use tickwork_integrators::{StepError, Vec3x4, build};

use super::in_step::Sweep;
use super::lane_step::{LaneColumns, LaneOutcome, merge, step_lane};
use super::reporting::resolve_world_reporting;
use super::{NonFiniteCause, SimulationError, StepReport};
use crate::colliders::{ContactColumns, RowTouch};
use crate::forces::ForceField;
use crate::layout::{CHUNK, LANES, Vec3Column};
use crate::world::{Lane, World};

impl World {
    pub(super) fn integrate(
        &mut self,
        t: f32,
        dt: f32,
        tick: u64,
        report: &mut StepReport,
    ) -> Result<(), SimulationError> {
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
    pub(super) fn integrate_fused(
        &mut self,
        t: f32,
        dt: f32,
        report: &mut StepReport,
    ) -> Result<LaneOutcome, StepError> {
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
    pub(super) fn integrate_rows(&mut self, t: f32, dt: f32) -> Result<LaneOutcome, StepError> {
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
}
