//! Swept tests for fast spheres ([`SphereCollisions::swept`]): a sphere
//! that moved more than its radius in one step can pass through another
//! between the step's two instants, where the grid, which looks at the end
//! of the step only, never sees them touch (a bullet through a ball).
//!
//! Before the grid, each such fast sphere's straight path over the step is
//! tested against every sphere whose path's box overlaps its own (a
//! sweep along x over the paths' extents, sorted once): the relative path
//! `d(s) = D + E s` meets `|d| = r_i + r_j` at the first root of
//! `|E|^2 s^2 + 2 (D . E) s + |D|^2 - (r_i + r_j)^2` in `[0, 1]`. The
//! contacts found are resolved in the order of their instants (one a
//! sphere a step): both spheres are placed where they met, exchange the
//! impulse of the bounce (restitution, inverse masses) and move on for the
//! rest of the step at their new velocities. The grid then resolves what
//! overlaps at the end, as without swept tests. The candidates are held to
//! [`ContactColumns::max_pairs`] like the grid's.

use glam::{DVec3, Vec3A};

use super::SphereCollisions;
use crate::colliders::{ContactColumns, PairTouch, StepStart};

/// A contact found along two paths: the instant (fraction of the step) and
/// the two rows, in the order they are resolved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SweptPair {
    pub s: f64,
    pub i: u32,
    pub j: u32,
}

impl SphereCollisions {
    /// The swept contacts of the fast spheres (see the module docs); false
    /// if refused (more candidates than `c.max_pairs`, recorded in
    /// `refused`).
    pub(super) fn resolve_swept(&mut self, c: &mut ContactColumns<'_>, start: StepStart<'_>) -> bool {
        let n = c.position.len();
        let x0 = start.position;
        // The paths' extents along x, in order of their low ends; and the
        // widest extent of a sphere that is not fast (its path is shorter
        // than its radius), which bounds how far before a fast sphere's low
        // end an overlapping extent may start.
        // A sphere of radius 0 touches nothing (as in the grid).
        let fast = |k: usize| c.radius[k] > 0.0 && (c.position[k] - x0[k]).length() > c.radius[k];
        self.extents.clear();
        let mut slow_width = 0.0f32;
        let mut any_fast = false;
        for k in 0..n {
            let (a, b) = (x0[k].x.min(c.position[k].x), x0[k].x.max(c.position[k].x));
            let r = c.radius[k];
            let (lo, hi) = (a - r, b + r);
            if !(lo.is_finite() && hi.is_finite()) {
                continue;
            }
            if fast(k) {
                any_fast = true;
            } else {
                slow_width = slow_width.max(hi - lo);
            }
            self.extents.push((lo, hi, k as u32));
        }
        if !any_fast {
            return true;
        }
        self.extents
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
        self.meetings.clear();
        let mut candidates = 0u64;
        for f in 0..self.extents.len() {
            let (lo, hi, i) = self.extents[f];
            let i = i as usize;
            if !fast(i) {
                continue;
            }
            // Every extent that may overlap [lo, hi]: slow ones start at
            // most `slow_width` before `lo`; fast ones are met from the
            // fast sphere earlier in this order (each fast pair once).
            let first = self.extents.partition_point(|e| e.0 < lo - slow_width);
            for g in first..self.extents.len() {
                let (other_lo, other_hi, j) = self.extents[g];
                if other_lo > hi {
                    break;
                }
                // Every extent looked at counts towards the limit.
                candidates += 1;
                let j = j as usize;
                if j == i || other_hi < lo || (fast(j) && g <= f) || c.radius[j] <= 0.0 {
                    continue;
                }
                if let Some(s) = first_meeting(x0, c, i, j) {
                    let (i, j) = (i.min(j) as u32, i.max(j) as u32);
                    self.meetings.push(SweptPair { s, i, j });
                }
            }
            if candidates > c.max_pairs {
                self.refused = Some(candidates);
                return false;
            }
        }
        self.tested += candidates as usize;
        self.meetings
            .sort_unstable_by(|a, b| a.s.total_cmp(&b.s).then(a.i.cmp(&b.i)).then(a.j.cmp(&b.j)));
        self.taken.clear();
        self.taken.resize(n, false);
        let e = f64::from(self.material.restitution);
        let dt = f64::from(start.dt);
        for pair in &self.meetings {
            let (i, j) = (pair.i as usize, pair.j as usize);
            if self.taken[i] || self.taken[j] {
                continue;
            }
            let (wi, wj) = (f64::from(c.inverse_mass[i]), f64::from(c.inverse_mass[j]));
            let w = wi + wj;
            if w <= 0.0 {
                continue;
            }
            let s = pair.s;
            let at = |k: usize| {
                let (a, b) = (x0[k].as_dvec3(), c.position[k].as_dvec3());
                a + (b - a) * s
            };
            let (pi, pj) = (at(i), at(j));
            let Some(normal) = (pj - pi).try_normalize() else {
                continue;
            };
            (self.taken[i], self.taken[j]) = (true, true);
            let (mut vi, mut vj) = (c.velocity[i].as_dvec3(), c.velocity[j].as_dvec3());
            let vn = (vj - vi).dot(normal);
            if vn < 0.0 {
                let impulse = normal * (-(1.0 + e) * vn / w);
                vi -= impulse * wi;
                vj += impulse * wj;
            }
            let rest = (1.0 - s) * dt;
            self.contacts += 1;
            if self.recording {
                let w_i = c.inverse_mass[i];
                let dv = (vi - c.velocity[i].as_dvec3()).dot(-normal);
                self.swept_touches.push(PairTouch {
                    a: i,
                    b: j,
                    point: Vec3A::from((pi + normal * f64::from(c.radius[i])).as_vec3()),
                    normal: Vec3A::from((-normal).as_vec3()),
                    impulse: if w_i > 0.0 { (dv / f64::from(w_i)) as f32 } else { 0.0 },
                    fraction: s as f32,
                });
            }
            let end = |p: DVec3, v: DVec3| Vec3A::from((p + v * rest).as_vec3());
            (c.position[i], c.velocity[i]) = (end(pi, vi), Vec3A::from(vi.as_vec3()));
            (c.position[j], c.velocity[j]) = (end(pj, vj), Vec3A::from(vj.as_vec3()));
        }
        true
    }
}

/// The first instant in `[0, 1]` at which spheres `i` and `j`, moving in
/// straight lines from their start to their end positions, touch, if they
/// do and were apart at the start (apart is the grid's to resolve).
fn first_meeting(x0: &[Vec3A], c: &ContactColumns<'_>, i: usize, j: usize) -> Option<f64> {
    let d = (x0[j] - x0[i]).as_dvec3();
    let e = (c.position[j] - x0[j]).as_dvec3() - (c.position[i] - x0[i]).as_dvec3();
    let reach = f64::from(c.radius[i]) + f64::from(c.radius[j]);
    let (a, b, c0) = (e.length_squared(), 2.0 * d.dot(e), d.length_squared() - reach * reach);
    if c0.is_nan() || c0 <= 0.0 || a == 0.0 {
        return None;
    }
    // Closing (b < 0) and close enough at the nearest approach.
    let nearest = (-b / (2.0 * a)).clamp(0.0, 1.0);
    if c0 + (b + a * nearest) * nearest > 0.0 {
        return None;
    }
    let disc = (b * b - 4.0 * a * c0).max(0.0);
    let q = -0.5 * (b + disc.sqrt().copysign(b));
    let (r1, r2) = (q / a, if q == 0.0 { 0.0 } else { c0 / q });
    let s = r1.min(r2);
    (0.0..=1.0).contains(&s).then_some(s)
}
