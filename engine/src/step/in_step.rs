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
//!       (e = 0 when the approach is slower than rest_speed: resting)
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
//! 10 m at 60 Hz, measured), while continuing its path keeps its shifted
//! energy to within `|v| dt`, never accumulating. A resting particle ends
//! the step on the surface with no normal velocity into it, and meets no
//! further contact that step.
//!
//! The pass runs over the rows in order, serially, so it gives the same
//! bits on any number of threads; a particle that touches nothing costs
//! one path test a collider.

use glam::Vec3A;
use tickwork_integrators::Vec3x4;

use crate::colliders::{Collider, EventOverflow, MAX_CONTACT_EVENTS, RowTouch, StepPath, SweptHit, bounce};
use crate::world::World;

/// The in-step contacts of one step: the colliders, which of them report,
/// the step's length and the world's rest speed.
#[derive(Clone, Copy)]
pub(super) struct Sweep<'a> {
    pub colliders: &'a [Box<dyn Collider>],
    pub reports: &'a [bool],
    pub dt: f32,
    pub rest_speed: f64,
}

impl Sweep<'_> {
    /// Whether any collider finds contacts inside the step.
    pub fn wanted(colliders: &[Box<dyn Collider>]) -> bool {
        colliders.iter().any(|c| c.in_step())
    }

    /// The in-step contacts of a chunk of blocks of four particles (rows
    /// `first_row ..`, `radius.len()` of them): lanes every collider's
    /// conservative test leaves clear (most, most steps) cost that test
    /// alone; the others go through [`row`](Self::row), whose result they
    /// would have had. Every row is stepped; the first that met too many
    /// contacts is returned.
    #[allow(clippy::too_many_arguments)]
    pub fn chunk(
        &self,
        first_row: usize,
        x0: &[Vec3x4],
        x: &mut [Vec3x4],
        v: &mut [Vec3x4],
        radius: &[f32],
        inverse_mass: &[f32],
        clear: &mut Vec<u8>,
        touches: &mut Vec<RowTouch>,
    ) -> Option<EventOverflow> {
        clear.clear();
        clear.resize(x.len(), 0b1111);
        for collider in self.colliders.iter().filter(|c| c.in_step()) {
            collider.clear_blocks(x0, x, v, radius, self.dt, clear);
        }
        let mut first = None;
        for (b, &lanes) in clear.iter().enumerate() {
            if lanes == 0b1111 {
                continue;
            }
            for k in 0..(radius.len() - b * 4).min(4) {
                if lanes & (1 << k) != 0 {
                    continue;
                }
                let row = b * 4 + k;
                let (mut xk, mut vk) = (x[b].lane(k), v[b].lane(k));
                let outcome = self.row(
                    first_row + row,
                    x0[b].lane(k),
                    &mut xk,
                    &mut vk,
                    radius[row],
                    inverse_mass[row],
                    touches,
                );
                x[b].set_lane(k, xk);
                v[b].set_lane(k, vk);
                if let Err(overflow) = outcome {
                    first = first.or(Some(overflow));
                }
            }
        }
        first
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
            let resting = -relative.dot(hit.normal) <= self.rest_speed;
            let restitution = if resting {
                0.0
            } else {
                f64::from(hit.material.restitution)
            };
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
    /// The in-step contacts of every movable particle, on the gathered
    /// rows of the plain step (`other`: start positions; `x`, `v`: the
    /// method's end state, changed in place).
    pub(super) fn resolve_in_step(&mut self, dt: f32) -> Option<EventOverflow> {
        if !Sweep::wanted(&self.colliders.colliders) {
            return None;
        }
        let sweep = Sweep {
            colliders: &self.colliders.colliders,
            reports: &self.colliders.reports,
            dt,
            // NaN or negative: none rests.
            rest_speed: f64::from(self.config.rest_speed).max(0.0),
        };
        let (p, g) = (&self.particles, &mut self.gathered);
        let mut first = None;
        for row in 0..g.x.len() {
            let (x, v) = (&mut g.x[row], &mut g.v[row]);
            let outcome = sweep.row(
                row,
                g.other[row],
                x,
                v,
                p.radius[row],
                p.inverse_mass[row],
                &mut self.touches,
            );
            // The rest still step (as on the fused path's other lanes).
            if let Err(overflow) = outcome {
                first = first.or(Some(overflow));
            }
        }
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
        if let Some(hit) = collider.first_contact(path, radius)
            && best.is_none_or(|(_, b)| hit.fraction < b.fraction)
        {
            best = Some((k, hit));
        }
    }
    best
}
