//! Contacts inside the step, for the colliders that ask for them
//! ([`ContactRule::InStep`](crate::colliders::ContactRule)).
//!
//! After the method has stepped every particle, each movable particle's
//! path over the step (the renderer's curve through its start and end,
//! [`StepPath`]: `q(s) = x0 + b s + a s^2`) is tested against those
//! colliders. At the first contact, fraction `s` of what is left of the
//! step:
//!
//! ```text
//! x_c = q(s),  v_c = q'(s) / dt                 the state at the instant
//! v'  = u + bounce(v_c - u)                      restitution, friction, in the surface's frame
//!       (e = 0 when the approach is slower than rest_speed: resting;
//!       on a path that leaves out the acceleration, the e that keeps
//!       the method's own energy: kept_restitution)
//! x = x_c + v' r + a_q r^2 / 2,  v = v' + a_q r  the rest of the step, r = (1 - s) dt,
//!                                                on the path's own acceleration a_q = 2 a / dt^2
//! ```
//!
//! and the rest of the step is tested again, up to
//! [`MAX_CONTACT_EVENTS`]. The rest of the step continues the method's
//! own path (its constant acceleration) rather than stepping the method
//! again from the contact: for velocity Verlet under gravity that path is
//! the exact parabola, so an elastic ball keeps its height; semi-implicit
//! Euler's path runs straight at the step's end velocity (its velocity is
//! half a step ahead of its position), and stepping it again from the
//! contact lost `|v| dt` of height at every bounce (0.22 m a bounce from
//! 10 m at 60 Hz, measured). Continuing its path and reflecting the
//! velocity there kept its shifted energy only on average, and short hops,
//! which come back at the same fraction of a step, gained at each bounce
//! what restitution took (they hopped on forever); the step's first
//! bounce therefore scales that energy by `e^2`, as restitution scales a
//! real ball's ([`kept_restitution`]): an elastic ball keeps its apex,
//! and a ball with `e < 1` comes to rest. A resting particle ends
//! the step on the surface with no normal velocity into it, and meets no
//! further contact that step.
//!
//! Most particles need none of this: before any path is followed, each
//! in-step collider settles the lanes of each block of four it can by one
//! vector test ([`Collider::settle_blocks`]): clear of its surfaces, or
//! resting on a plane (the path's speed into it below the world's rest
//! speed at both ends of the step, so all along it); a lone floor takes a
//! chunk that is clear of it, or rests on it, whole. Only the others are
//! followed; then the collider's end-of-step rule resolves what rests
//! (restitution 0) and what started inside. Where the world's only in-step
//! collider is a plane at rest along an axis, the lanes that cross it are
//! followed four at a time in `f32` ([`PlaneLanes`], `follow.rs`), and only
//! what those cannot decide comes to [`Sweep::row`]. Each particle's result
//! depends on its own lanes only, so any chunking and any number of threads
//! give the same bits.

use core::ops::Range;

use glam::{DVec3, Vec3A};
use tickwork_integrators::Vec3x4;

use super::chunk::Chunk;
use super::follow::PlaneLanes;
use super::reporting::{Reporting, resolve_rows};
use crate::colliders::seams::at_seam;
use crate::colliders::{Collider, EventOverflow, MAX_CONTACT_EVENTS, RowTouch, StepPath, SweptHit, bounce};
use crate::forces::{Force, affine_sum};
use crate::layout::{CHUNK, Rows};
use crate::world::World;

/// The in-step contacts of one step: the colliders, which of them report,
/// the step's length and the world's rest speed.
#[derive(Clone, Copy)]
pub(super) struct Sweep<'a> {
    pub colliders: &'a [Box<dyn Collider>],
    pub reports: &'a [bool],
    pub dt: f32,
    /// The world's rest speed, m/s (0 where it is NaN or negative: none
    /// rests).
    pub rest_speed: f32,
    /// The forces affine in velocity, summed (gravity, drag, wind: the
    /// acceleration `c - b v`), for what a contact's path leaves out of
    /// them ([`kept_restitution`]).
    pub affine: (Vec3A, f32),
    /// The in-step collider, where it is the only one and does not report:
    /// it settles and resolves a chunk in one pass
    /// ([`Collider::settle_blocks`] with `resolve`).
    pub lone: Option<usize>,
    /// The only in-step collider's plane, where it is a plane at rest
    /// along an axis (reporting or not): the paths that meet it are
    /// followed four at a time ([`PlaneLanes`]).
    pub plane: Option<PlaneLanes>,
}

/// The lanes of block `b` past the chunk's `rows` particles, as bits.
fn padding(rows: usize, b: usize) -> u8 {
    let real = rows.saturating_sub(b * 4).min(4);
    (0b1111u8 << real) & 0b1111
}

impl<'a> Sweep<'a> {
    /// The in-step contacts of a step of `dt` seconds among `colliders`
    /// (`reports`: which of them report), under `forces`: `None` when no
    /// collider finds contacts inside the step. A NaN or negative rest
    /// speed rests none; an infinite one is taken as `f32::MAX`.
    pub fn new(
        colliders: &'a [Box<dyn Collider>],
        reports: &'a [bool],
        forces: &[Box<dyn Force>],
        dt: f32,
        rest_speed: f32,
    ) -> Option<Self> {
        let mut in_step = colliders
            .iter()
            .enumerate()
            .filter(|(_, c)| c.in_step())
            .map(|(k, _)| k);
        let first = in_step.next()?;
        // The only in-step collider, if it is; lone where it does not report.
        let only = in_step.next().is_none().then_some(first);
        let lone = only.filter(|&k| !reports[k]);
        // Finite: an infinite rest speed rests every finite approach as
        // f32::MAX does, and an infinite one on every path alike.
        let rest_speed = if rest_speed >= 0.0 {
            rest_speed.min(f32::MAX)
        } else {
            0.0
        };
        let affine = affine_sum(forces);
        let plane = only.and_then(|k| colliders[k].axis_plane().map(|plane| (k, plane)));
        let plane = plane.map(|(collider, plane)| PlaneLanes::new(plane, collider, dt, rest_speed, affine));
        Some(Self {
            colliders,
            reports,
            dt,
            rest_speed,
            affine,
            lone,
            plane,
        })
    }

    /// The in-step colliders' contacts on a chunk (rows `first_row ..`,
    /// `start`: the blocks' start positions): every collider settles the
    /// lanes it can (clear of it, or resting on it: one vector test a
    /// block); the other lanes are followed along their paths
    /// ([`row`](Self::row)); then each in-step collider's end-of-step rule
    /// resolves the chunk (what started inside, what rests), contacts
    /// slower than the rest speed resting. A lone in-step collider that
    /// does not report resolves the blocks it settled whole in the same
    /// pass ([`Collider::settle_blocks`]). The first row that met too many
    /// contacts is returned; every row is stepped.
    pub fn resolve_chunk(
        &self,
        first_row: usize,
        start: &[Vec3x4],
        mut c: Chunk<'_>,
        scratch: &mut Rows,
        settled: &mut Vec<u8>,
        touches: &mut Vec<RowTouch>,
    ) -> Option<EventOverflow> {
        const ALL: u8 = 0b1111;
        let (blocks, rows) = (c.x.len(), c.radius.len());
        // Every entry is `ALL` between chunks (a chunk that clears some
        // puts them back), so most chunks write none.
        if settled.len() < blocks {
            settled.resize(blocks, ALL);
        }
        let settled = &mut settled[..blocks];
        let in_step = || self.colliders.iter().enumerate().filter(|(_, c)| c.in_step());
        let mut folded = None;
        if let Some(k) = self.lone {
            let collider = &self.colliders[k];
            if collider.settle_blocks(start, c.blocks(0..blocks, self.rest_speed), self.dt, true, settled) {
                folded = Some(k);
            }
        } else {
            for (_, collider) in in_step() {
                collider.settle_blocks(start, c.blocks(0..blocks, self.rest_speed), self.dt, false, settled);
            }
        }
        // The padding lanes of a short last block count as settled.
        if let Some(last) = settled.last_mut() {
            *last |= padding(rows, blocks - 1);
        }
        // Most chunks, most steps: every lane settled (an AND over the
        // bytes, which vectorises), and nothing to follow.
        let all_settled = |settled: &[u8]| settled.iter().fold(ALL, |all, &lanes| all & lanes) == ALL;
        if !all_settled(settled)
            && let Some(plane) = self.plane
        {
            // The lanes that meet the only in-step collider, a plane:
            // followed four at a time; where it settled and resolved blocks
            // whole, each block whose lanes are then all decided is
            // resolved too.
            let follow = match plane.plane.axis {
                0 => PlaneLanes::follow_chunk::<0>,
                1 => PlaneLanes::follow_chunk::<1>,
                _ => PlaneLanes::follow_chunk::<2>,
            };
            let reports = self.reports[plane.collider];
            follow(
                &plane,
                reports,
                folded.is_some(),
                first_row,
                start,
                &mut c,
                settled,
                touches,
            );
        }
        if all_settled(settled) {
            if folded.is_none() {
                for (k, collider) in in_step() {
                    self.end_of_step(k, collider.as_ref(), first_row, &mut c, 0..blocks, scratch, touches);
                }
            }
            return None;
        }
        let mut first = None;
        for (b, &lanes) in settled.iter().enumerate() {
            if lanes == ALL {
                continue;
            }
            for k in 0..(rows - b * 4).min(4) {
                if lanes & (1 << k) != 0 {
                    continue;
                }
                let row = b * 4 + k;
                let (mut xk, mut vk) = (c.x[b].lane(k), c.v[b].lane(k));
                let outcome = self.row(
                    first_row + row,
                    start[b].lane(k),
                    &mut xk,
                    &mut vk,
                    c.radius[row],
                    c.inverse_mass[row],
                    touches,
                );
                c.x[b].set_lane(k, xk);
                c.v[b].set_lane(k, vk);
                if let Err(overflow) = outcome {
                    first = first.or(Some(overflow));
                }
            }
        }
        for (k, collider) in in_step() {
            if folded == Some(k) {
                // Only the blocks it left for the paths to be followed.
                for b in 0..blocks {
                    if settled[b] != ALL {
                        self.end_of_step(k, collider.as_ref(), first_row, &mut c, b..b + 1, scratch, touches);
                    }
                }
            } else {
                self.end_of_step(k, collider.as_ref(), first_row, &mut c, 0..blocks, scratch, touches);
            }
        }
        settled.fill(ALL);
        first
    }

    /// In-step collider `k`'s end-of-step rule on `blocks` of the chunk
    /// (whose first row is `first_row`), reporting its contacts if asked.
    #[allow(clippy::too_many_arguments)]
    fn end_of_step(
        &self,
        k: usize,
        collider: &dyn Collider,
        first_row: usize,
        c: &mut Chunk<'_>,
        blocks: Range<usize>,
        scratch: &mut Rows,
        touches: &mut Vec<RowTouch>,
    ) {
        let rows = blocks.start * 4..(blocks.end * 4).min(c.radius.len());
        if !self.reports[k] && collider.resolve_blocks(c.blocks(blocks.clone(), self.rest_speed)) {
            return;
        }
        let reporting = self.reports[k].then(|| Reporting {
            collider: k as u32,
            first_row: first_row + rows.start,
            out: touches,
        });
        resolve_rows(
            collider,
            &mut c.x[blocks.clone()],
            &mut c.v[blocks],
            &c.radius[rows.clone()],
            &c.inverse_mass[rows],
            self.rest_speed,
            scratch,
            reporting,
        );
    }

    /// The in-step contacts of one particle (row `row`, of `radius` and
    /// inverse mass `w`) that stepped from `x0` to `x` with end velocity
    /// `v`: both changed in place.
    #[allow(clippy::too_many_arguments)]
    pub fn row(
        &self,
        row: usize,
        x0: Vec3A,
        x: &mut Vec3A,
        v: &mut Vec3A,
        radius: f32,
        w: f32,
        touches: &mut Vec<RowTouch>,
    ) -> Result<(), EventOverflow> {
        if w.is_nan() || w <= 0.0 {
            return Ok(());
        }
        let dt = f64::from(self.dt);
        let mut path = StepPath::new(x0, *x, *v, self.dt);
        // The fraction of the step before the path's start.
        let mut done = 0.0f64;
        let mut events = 0;
        // The collider the particle came to rest on this step, if any: it
        // is on its surface for the rest of the step (the end-of-step rule
        // keeps it there); the others are still looked for.
        let mut resting_on = None;
        while let Some((k, hit)) = first_hit(self.colliders, &path, radius, resting_on) {
            events += 1;
            if events > MAX_CONTACT_EVENTS {
                return Err(EventOverflow { row, collider: k });
            }
            let s = hit.fraction;
            let at = path.at(s);
            let arriving = path.velocity(s);
            let relative = arriving - hit.velocity;
            let approach = -relative.dot(hit.normal);
            let resting = approach <= f64::from(self.rest_speed);
            let mut restitution = f64::from(hit.material.restitution);
            if resting {
                restitution = 0.0;
            } else if events == 1 {
                // The step's first contact, on the method's own path: no
                // bounce where none keeps the method's energy (the path's
                // rest then meets the surface again, slowly, and rests).
                let (c, b) = self.affine;
                let forces = c.as_dvec3() - arriving * f64::from(b);
                let missing = path.acceleration() - forces;
                restitution =
                    kept_restitution(restitution, approach, forces, missing, hit.normal, s, path.dt).unwrap_or(0.0);
            }
            let after = hit.velocity + bounce(relative, hit.normal, restitution, f64::from(hit.material.friction));
            let fraction = done + s * (1.0 - done);
            if self.reports[k] {
                touches.push(RowTouch {
                    collider: k as u32,
                    row: row as u32,
                    other: u32::MAX,
                    point: (at - hit.normal * f64::from(radius)).as_vec3a(),
                    normal: hit.normal.as_vec3a(),
                    impulse: ((after - arriving).dot(hit.normal) / f64::from(w)) as f32,
                    fraction: fraction as f32,
                    event: events,
                });
            }
            // The rest of the step, from the contact, on the path's own
            // acceleration.
            let rest = (1.0 - fraction) * dt;
            let (mut end, mut velocity) = (at, after);
            if rest > 0.0 {
                let a = path.acceleration();
                end = at + after * rest + a * (rest * rest / 2.0);
                velocity = after + a * rest;
            }
            if resting {
                // On the surface, with nothing left going into it.
                let gap = hit.normal.dot(end) - hit.offset - f64::from(radius);
                if gap < 0.0 {
                    end -= hit.normal * gap;
                }
                let into = (velocity - hit.velocity).dot(hit.normal);
                if into < 0.0 {
                    velocity -= hit.normal * into;
                }
            }
            *x = end.as_vec3a();
            *v = velocity.as_vec3a();
            if rest <= 0.0 {
                break;
            }
            if resting {
                resting_on = Some(k);
            }
            // The rest of the step's path, in f64 (no rounding of its ends
            // to f32 magnified by a short rest).
            path = StepPath::through(at, end, velocity, rest);
            done = fraction;
        }
        Ok(())
    }
}

impl World {
    /// The in-step contacts of the plain step: its rows (`gathered`: the
    /// method's end state) go into the blocks, where the fused step's pass
    /// runs on them chunk by chunk (the same bits), and back.
    pub(super) fn resolve_in_step(&mut self, dt: f32, parallel: bool) -> Option<EventOverflow> {
        let colliders = &self.colliders;
        let sweep = Sweep::new(
            &colliders.colliders,
            &colliders.reports,
            &self.forces,
            dt,
            self.config.rest_speed,
        )?;
        let (p, g) = (&mut self.particles, &mut self.gathered);
        p.position.scatter_from(&g.x, parallel);
        p.velocity.scatter_from(&g.v, parallel);
        let n = p.len();
        let (x, v) = (p.position.blocks_mut(), p.velocity.blocks_mut());
        let start = p.previous_position.blocks();
        let mut first = None;
        for begin in (0..n).step_by(CHUNK) {
            let end = (begin + CHUNK).min(n);
            let blocks = begin / 4..end.div_ceil(4);
            let chunk = Chunk {
                x: &mut x[blocks.clone()],
                v: &mut v[blocks.clone()],
                radius: &p.radius[begin..end],
                inverse_mass: &p.inverse_mass[begin..end],
                movable: false,
                point: false,
            };
            let scratch = &mut self.sweep;
            let overflow = sweep.resolve_chunk(
                begin,
                &start[blocks],
                chunk,
                &mut scratch.rows,
                &mut scratch.settled,
                &mut self.touches,
            );
            first = first.or(overflow);
        }
        p.position.gather_into(&mut g.x, parallel);
        p.velocity.gather_into(&mut g.v, parallel);
        first
    }
}

/// The first contact along `path` among the in-step colliders, and its
/// collider's index (the lower index on a tie).
fn first_hit(
    colliders: &[Box<dyn Collider>],
    path: &StepPath,
    radius: f32,
    skip: Option<usize>,
) -> Option<(usize, SweptHit)> {
    let mut best: Option<(usize, SweptHit)> = None;
    for (k, collider) in colliders.iter().enumerate() {
        if !collider.in_step() || skip == Some(k) {
            continue;
        }
        let mut keep = |hit: &SweptHit| !at_seam(colliders, k, hit, path, radius);
        if let Some(hit) = collider.first_contact_kept(path, radius, &mut keep)
            && best.is_none_or(|(_, b)| hit.fraction < b.fraction)
        {
            best = Some((k, hit));
        }
    }
    best
}

/// The restitution that makes a bounce at fraction `s` of a path of `dt`
/// seconds scale the method's own energy by `e^2`, as restitution `e`
/// scales a real ball's, where the path leaves out part of the
/// acceleration into the surface: `None` when no bounce can (the particle
/// does not bounce).
///
/// Semi-implicit Euler's step is a straight move at its end velocity (its
/// path has no acceleration), and in free fall under an acceleration `a`
/// it keeps `E = |v|^2 / 2 - a . x + (dt / 2) a . v` exactly, not the
/// energy. A bounce that reflects the path's velocity at the instant
/// (`w = e u`, `u` the approach speed) changes the normal part of `E` by
///
/// ```text
/// dE = -(1 - e^2) u^2 / 2 + (1 + e) u g dt (1/2 - s)      g = -a . n, into the surface
/// ```
///
/// a gain where `s < 1/2` that averages out over the bounces of a ball
/// dropped from high up, but not in short hops, which come back at the
/// same fraction of a step: there the gain balances restitution's loss
/// at an approach of about `g dt / (1 - e)` (0.8 m/s for `e` = 0.8 at
/// 60 Hz, 1.6 m/s for 0.9: above the rest speed), and a ball bounces
/// forever. The normal part of `E` at the step's start, measured from the
/// surface, is `u^2 / 2 - k u` with `k = g dt (1/2 - s)`; scaling it by
/// `e^2` gives the outgoing speed
///
/// ```text
/// w^2 / 2 + k w = e^2 (u^2 / 2 - k u),   w = -k + sqrt(k^2 + e^2 (u^2 - 2 k u))
/// ```
///
/// (`w = e u` where `k` is 0: `e` itself is returned.) An elastic bounce
/// keeps `E` exactly, so the apex, and every bounce with `e < 1` shrinks
/// it by `e^2`, so short hops die out and the particle comes to rest;
/// restitution 0 stays 0. `g` is the part of the acceleration into the
/// surface that the path leaves out (`missing = a_path - a`, along `n`,
/// no more than `a` has into it, and taken as 0 below 1% of it: rounding
/// in a path that carries it): all of it for a straight path, nothing for
/// a path that carries it (velocity Verlet's exact parabola).
fn kept_restitution(e: f64, u: f64, forces: DVec3, missing: DVec3, n: DVec3, s: f64, dt: f64) -> Option<f64> {
    let into = (-forces.dot(n)).max(0.0);
    let g = missing.dot(n).max(0.0).min(into);
    let k = if g < 0.01 * into { 0.0 } else { g * dt * (0.5 - s) };
    if k == 0.0 || e == 0.0 {
        return Some(e);
    }
    let w = -k + (k * k + e * e * (u * u - 2.0 * k * u)).sqrt();
    // A NaN (no real root, or a NaN state) fails too.
    (w > 0.0).then(|| w / u)
}
