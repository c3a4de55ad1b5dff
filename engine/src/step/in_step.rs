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

use crate::colliders::{Collider, EventOverflow, MAX_CONTACT_EVENTS, RowTouch, StepPath, SweptHit, bounce};
use crate::world::World;

impl World {
    /// The in-step contacts of every movable particle, on the gathered
    /// rows of the plain step (`other`: start positions; `x`, `v`: the
    /// method's end state, changed in place).
    pub(super) fn resolve_in_step(&mut self, dt: f32) -> Option<EventOverflow> {
        let colliders = &self.colliders.colliders;
        if !colliders.iter().any(|c| c.in_step()) {
            return None;
        }
        let p = &self.particles;
        let g = &mut self.gathered;
        let rest_speed = f64::from(self.config.rest_speed);
        let reports = &self.colliders.reports;
        for row in 0..g.x.len() {
            let w = p.inverse_mass[row];
            if w.is_nan() || w <= 0.0 {
                continue;
            }
            let radius = p.radius[row];
            let mut path = StepPath::new(g.other[row], g.x[row], g.v[row], dt);
            // The fraction of the step before the path's start.
            let mut done = 0.0f64;
            let mut events = 0;
            while let Some((k, hit)) = first_hit(colliders, &path, radius) {
                events += 1;
                if events > MAX_CONTACT_EVENTS {
                    return Some(EventOverflow { row, collider: k });
                }
                let s = hit.fraction;
                let at = path.at(s);
                let relative = path.velocity(s) - hit.velocity;
                let approach = -relative.dot(hit.normal);
                let resting = approach <= rest_speed;
                let restitution = if resting {
                    0.0
                } else {
                    f64::from(hit.material.restitution)
                };
                let after = hit.velocity + bounce(relative, hit.normal, restitution, f64::from(hit.material.friction));
                let fraction = done + s * (1.0 - done);
                if reports[k] {
                    let dv = after - path.velocity(s);
                    let w = f64::from(w);
                    let normal = hit.normal.as_vec3a();
                    self.touches.push(RowTouch {
                        collider: k as u32,
                        row: row as u32,
                        other: u32::MAX,
                        point: (at - hit.normal * f64::from(radius)).as_vec3a(),
                        normal,
                        impulse: (dv.dot(hit.normal) / w) as f32,
                        fraction: fraction as f32,
                    });
                }
                // The rest of the step, from the contact.
                let rest = (1.0 - fraction) * f64::from(dt);
                let (mut x, mut v) = (at, after);
                if rest > 0.0 {
                    let a = path.acceleration();
                    x = at + after * rest + a * (rest * rest / 2.0);
                    v = after + a * rest;
                }
                if resting {
                    // On the surface, with nothing left going into it.
                    let gap = hit.normal.dot(x) - hit.offset - f64::from(radius);
                    if gap < 0.0 {
                        x -= hit.normal * gap;
                    }
                    let into = (v - hit.velocity).dot(hit.normal);
                    if into < 0.0 {
                        v -= hit.normal * into;
                    }
                }
                g.x[row] = x.as_vec3a();
                g.v[row] = v.as_vec3a();
                if resting || rest <= 0.0 {
                    break;
                }
                path = StepPath::new(at.as_vec3a(), g.x[row], g.v[row], rest as f32);
                done = fraction;
            }
        }
        None
    }
}

/// The first contact along `path` among the in-step colliders, and its
/// collider's index (the lower index on a tie).
fn first_hit(colliders: &[Box<dyn Collider>], path: &StepPath, radius: f32) -> Option<(usize, SweptHit)> {
    let mut best: Option<(usize, SweptHit)> = None;
    for (k, collider) in colliders.iter().enumerate() {
        if !collider.in_step() {
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
