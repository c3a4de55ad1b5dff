//! Paths that meet one plane at rest along an axis, four particles at a
//! time: the in-step rule of [`Sweep::row`](super::in_step::Sweep::row) in
//! `f32` lanes, for a world whose only in-step collider is a floor, a wall
//! or a ceiling (the default world of a game) and does not report.
//!
//! Along the normal `n = ±e_axis`, the path `q(s) = x0 + b s + a s^2` has
//! the gap `g(s) = c + b_n s + a_n s^2`, `c = n . x0 - offset - r`. A lane
//! that crosses (`c > m`, `g(1) < -m`, `m` a margin of rounding) meets the
//! plane once in the step, at
//!
//! ```text
//! s  = c / q  or  q / a_n,   q = -(b_n + sign(b_n) sqrt(b_n^2 - 4 a_n c)) / 2   (the root in [0, 1])
//! x_c = q(s),  v_c = (b + 2 a s) / dt,  a_q = 2 a / dt^2
//! v' = bounce(v_c; e', friction)      e' = 0 resting, else the restitution that keeps the method's energy
//! x = x_c + v' r + a_q r^2 / 2,   v = v' + a_q r,   r = (1 - s) dt
//! ```
//!
//! exactly [`Sweep::row`](super::in_step::Sweep::row)'s first contact
//! (the same formulas, [`kept_restitution`](super::in_step) included), in
//! `f32` rather than `f64`. A lane is decided here only where that
//! arithmetic decides it with room to spare: it crossed, or started inside
//! (no contact in the step), and after its one contact it rests, or leaves
//! the surface and ends the step above it by more than the margin. Every
//! other lane (a graze within the margin, a dip below and back inside the
//! step, a hop that comes back within the step, a non-finite value) is
//! left to `row`, in `f64`, one at a time. Each lane's answer depends on
//! its own values only, so any chunking and any number of threads give
//! the same bits.

use glam::{BVec4A, Vec3A, Vec4};
use tickwork_integrators::Vec3x4;

use super::chunk::Chunk;
use crate::colliders::settled::{for_each_bit, open_blocks};
use crate::colliders::sweep::radius4;
use crate::colliders::{AxisPlane, RowTouch};
use crate::layout::CHUNK;

/// One step's in-step rule against one plane at rest along an axis, for
/// blocks of four particles.
#[derive(Clone, Copy, Debug)]
pub(super) struct PlaneLanes {
    /// The plane.
    pub plane: AxisPlane,
    /// Its index among the world's colliders.
    pub collider: usize,
    /// The step, seconds.
    pub dt: f32,
    /// Its inverse.
    pub inv_dt: f32,
    /// The world's rest speed, m/s (finite, at least 0).
    pub rest_speed: f32,
    /// The forces affine in velocity, summed: the acceleration `c - b v`.
    pub affine: (Vec3A, f32),
}

impl PlaneLanes {
    /// The rule of one step of `dt` seconds against `plane`, collider
    /// `collider` of the world.
    pub fn new(plane: AxisPlane, collider: usize, dt: f32, rest_speed: f32, affine: (Vec3A, f32)) -> Self {
        Self {
            plane,
            collider,
            dt,
            inv_dt: 1.0 / dt,
            rest_speed,
            affine,
        }
    }
}

/// What [`PlaneLanes::follow`] decided for a block: which lanes, which of
/// them met the plane, and the contacts they met (as a reporting collider
/// reports them: the point on the surface, the impulse per unit mass over
/// the inverse mass, the instant).
#[derive(Clone, Copy, Debug)]
struct Followed {
    /// The lanes decided (bits): met the plane, or left alone.
    pub decided: u8,
    /// The lanes that met the plane (bits), their states changed.
    pub met: u8,
    /// Where each met it, on the surface.
    pub point: [Vec4; 3],
    /// The change of each contact's velocity along the normal (its
    /// impulse times the inverse mass).
    pub impulse_w: Vec4,
    /// The fraction of the step each met it at.
    pub fraction: Vec4,
}

impl Followed {
    /// The lanes of `bits` as a lane mask.
    fn lanes(bits: u8) -> BVec4A {
        BVec4A::new(bits & 1 != 0, bits & 2 != 0, bits & 4 != 0, bits & 8 != 0)
    }

    /// Lane `k`'s contact point.
    pub fn point(&self, k: usize) -> Vec3A {
        Vec3A::new(self.point[0][k], self.point[1][k], self.point[2][k])
    }

    /// The plane's normal as a vector.
    pub fn normal<const AXIS: usize>(plane: &AxisPlane) -> Vec3A {
        let mut n = Vec3A::ZERO;
        n[AXIS] = if plane.negative { -1.0 } else { 1.0 };
        n
    }
}

/// The three components of a block, by axis.
#[inline(always)]
fn parts(p: &Vec3x4) -> [Vec4; 3] {
    [p.x, p.y, p.z]
}

/// `if mask { a } else { b }` lane by lane.
#[inline(always)]
fn pick(mask: BVec4A, a: Vec4, b: Vec4) -> Vec4 {
    Vec4::select(mask, a, b)
}

impl PlaneLanes {
    /// Follows lanes `todo` (bits) of one block (`start`: the start
    /// positions; `x`, `v`: the method's end state, changed in place for
    /// the lanes that meet the plane; `r`, `w`: radii and inverse masses)
    /// along their paths against the plane of normal `±e_AXIS`: the lanes
    /// decided here and the contacts met. The others are unchanged, for
    /// [`Sweep::row`](super::in_step::Sweep::row).
    #[inline(always)]
    fn follow<const AXIS: usize>(
        &self,
        start: &Vec3x4,
        x: &mut Vec3x4,
        v: &mut Vec3x4,
        r: Vec4,
        w: Vec4,
        todo: u8,
    ) -> Followed {
        let sign = if self.plane.negative { -1.0 } else { 1.0 };
        let along = |p: Vec4| p * sign;
        let (dt, inv_dt) = (self.dt, self.inv_dt);
        let (x0, x1, v1) = (parts(start), parts(x), parts(v));
        // The path's coefficients, per component.
        let mut b = [Vec4::ZERO; 3];
        let mut a = [Vec4::ZERO; 3];
        for i in 0..3 {
            let delta = x1[i] - x0[i];
            let vdt = v1[i] * dt;
            b[i] = delta + delta - vdt;
            a[i] = vdt - delta;
        }
        let offset = Vec4::splat(self.plane.offset);
        let d0 = along(x0[AXIS]);
        let c = d0 - offset - r;
        let (bn, an) = (along(b[AXIS]), along(a[AXIS]));
        let end_gap = c + bn + an;
        // Each term is rounded a few times at its own magnitude.
        let scale = d0.abs() + along(x1[AXIS]).abs() + (v1[AXIS] * dt).abs() + r + offset.abs();
        let margin = scale * 1e-6 + Vec4::splat(f32::MIN_POSITIVE);
        // Immovable (or NaN inverse mass): the rule leaves it alone.
        let movable = w.cmpgt(Vec4::ZERO);
        let inside = c.cmplt(-margin);
        let crossing = c.cmpgt(margin) & end_gap.cmplt(-margin);
        // The root in [0, 1], without cancellation (with a_n = 0 it is
        // c / q = -c / b_n, and q / a_n is infinite).
        let disc = (bn * bn - an * c * 4.0).max(Vec4::ZERO);
        let root = disc.sqrt();
        let q = (bn + pick(bn.cmplt(Vec4::ZERO), -root, root)) * -0.5;
        let (r1, r2) = (q / an, c / q);
        let within = |s: Vec4| s.cmpge(Vec4::ZERO) & s.cmple(Vec4::ONE);
        let (in1, in2) = (within(r1), within(r2));
        let s = pick(in2 & (!in1 | r2.cmple(r1)), r2, r1);
        let found = in1 | in2;
        let s = s.clamp(Vec4::ZERO, Vec4::ONE);
        // The state at the instant, and the path's acceleration.
        let mut at = [Vec4::ZERO; 3];
        let mut arriving = [Vec4::ZERO; 3];
        let mut accel = [Vec4::ZERO; 3];
        for i in 0..3 {
            at[i] = x0[i] + (b[i] + a[i] * s) * s;
            arriving[i] = (b[i] + (a[i] + a[i]) * s) * inv_dt;
            accel[i] = (a[i] + a[i]) * (inv_dt * inv_dt);
        }
        let vn = along(arriving[AXIS]);
        let approach = -vn;
        let resting = approach.cmple(Vec4::splat(self.rest_speed));
        // The restitution that keeps the method's own energy (see
        // `kept_restitution`): the part of the acceleration into the
        // plane that the path leaves out.
        let (cf, bf) = self.affine;
        let forces_n = along(Vec4::splat(cf[AXIS]) - arriving[AXIS] * bf);
        let missing_n = along(accel[AXIS]) - forces_n;
        let into = (-forces_n).max(Vec4::ZERO);
        let g = missing_n.max(Vec4::ZERO).min(into);
        let k = pick(g.cmplt(into * 0.01), Vec4::ZERO, g * dt * (Vec4::splat(0.5) - s));
        let e = Vec4::splat(self.plane.material.restitution);
        let u = approach;
        let out = -k + (k * k + e * e * (u * u - k * u * 2.0)).sqrt();
        let kept = pick(
            k.cmpeq(Vec4::ZERO) | e.cmpeq(Vec4::ZERO),
            e,
            pick(out.cmpgt(Vec4::ZERO), out / u, Vec4::ZERO),
        );
        let restitution = pick(resting, Vec4::ZERO, kept);
        // The bounce: the normal part reflected, the tangential braked by
        // friction (not past zero).
        let dvn = -(restitution + 1.0) * vn.min(Vec4::ZERO);
        let mut speed2 = Vec4::ZERO;
        for (i, t) in arriving.iter().enumerate() {
            if i != AXIS {
                speed2 += *t * *t;
            }
        }
        let friction = self.plane.material.friction;
        let brake = dvn * friction;
        let stops = (brake * brake).cmpge(speed2);
        // Without friction `1 - 0 / |v_t|` is 1 (a NaN speed aside, which
        // no lane decided here has).
        let slides = if friction == 0.0 {
            Vec4::ONE
        } else {
            (Vec4::ONE - brake / speed2.sqrt().max(Vec4::splat(f32::MIN_POSITIVE))).max(Vec4::ZERO)
        };
        let keep_t = pick(stops, Vec4::ZERO, slides);
        let rest = (Vec4::ONE - s) * dt;
        let half = rest * rest * 0.5;
        let mut end = [Vec4::ZERO; 3];
        let mut velocity = [Vec4::ZERO; 3];
        let after_n = along(vn + dvn);
        for i in 0..3 {
            let after = if i == AXIS { after_n } else { arriving[i] * keep_t };
            end[i] = at[i] + after * rest + accel[i] * half;
            velocity[i] = after + accel[i] * rest;
        }
        // A resting lane ends on the surface with nothing going into it.
        let gap = along(end[AXIS]) - offset - r;
        end[AXIS] = pick(resting & gap.cmplt(Vec4::ZERO), end[AXIS] - along(gap), end[AXIS]);
        let into_v = along(velocity[AXIS]);
        velocity[AXIS] = pick(
            resting & into_v.cmplt(Vec4::ZERO),
            velocity[AXIS] - along(into_v),
            velocity[AXIS],
        );
        // One contact settles it: it rests, the step ends at it, or it
        // leaves the surface and ends the step clear of it (its path,
        // starting on the surface and moving away, stays above it: an
        // arc's lowest point is at an end).
        let end_margin = (along(end[AXIS]).abs() + r + offset.abs()) * 1e-6 + Vec4::splat(f32::MIN_POSITIVE);
        let leaves = (vn + dvn).cmpgt(Vec4::ZERO) & gap.cmpgt(end_margin);
        let settles = resting | s.cmpge(Vec4::ONE) | leaves;
        let met = movable & crossing & found & settles;
        let met_bits = met.bitmask() as u8 & todo;
        if met_bits != 0 {
            let lanes = Followed::lanes(met_bits);
            x.x = pick(lanes, end[0], x.x);
            x.y = pick(lanes, end[1], x.y);
            x.z = pick(lanes, end[2], x.z);
            v.x = pick(lanes, velocity[0], v.x);
            v.y = pick(lanes, velocity[1], v.y);
            v.z = pick(lanes, velocity[2], v.z);
        }
        let unchanged = (!movable | inside).bitmask() as u8;
        let mut point = at;
        point[AXIS] -= along(r);
        Followed {
            decided: (met_bits | unchanged) & todo,
            met: met_bits,
            point,
            impulse_w: along(after_n - arriving[AXIS]),
            fraction: s,
        }
    }
}

impl PlaneLanes {
    /// [`follow`](Self::follow) on a chunk's lanes not settled, four at a
    /// time: their bits in `settled` set where it decides them, the
    /// contacts met reported if the plane `reports`. Then, with `resolve`,
    /// the plane's end-of-step rule on each block whose lanes are now all
    /// decided (the others are resolved after their paths are followed, by
    /// [`Sweep::row`](super::in_step::Sweep::row)).
    ///
    /// A block of a crowd rarely has more than one such lane, and which
    /// one is random: the lanes are first listed (by row, without a branch
    /// a lane), then gathered four rows at a time into one block, and
    /// every gathered lane is written back whether it changed or not (a
    /// lane `follow` leaves alone keeps its own bits), so no branch depends
    /// on a lane but the reports'. A short last group repeats its last
    /// row, which gives that row the same answer twice.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn follow_chunk<const AXIS: usize>(
        &self,
        reports: bool,
        resolve: bool,
        first_row: usize,
        start: &[Vec3x4],
        c: &mut Chunk<'_>,
        settled: &mut [u8],
        touches: &mut Vec<RowTouch>,
    ) {
        const ALL: u8 = 0b1111;
        let normal = Followed::normal::<AXIS>(&self.plane);
        let open = open_blocks(settled);
        // Their lanes, by row in the chunk: each lane of an open block
        // written, and kept where it is not settled.
        let mut rows = [0u16; CHUNK];
        let mut count = 0;
        for_each_bit(&open, |b| {
            let lanes = !settled[b];
            for j in 0..4 {
                rows[count] = (b * 4 + j) as u16;
                count += usize::from(lanes >> j & 1);
            }
        });
        for group in rows[..count].chunks(4) {
            let last = group.len() - 1;
            let row = |lane: usize| usize::from(group[lane.min(last)]);
            let at = [row(0), row(1), row(2), row(3)];
            let (x0, mut x, mut v, r, w) = gather(start, c, at);
            let followed = self.follow::<AXIS>(&x0, &mut x, &mut v, r, w, ALL);
            for (lane, &row) in at.iter().enumerate() {
                let (b, j) = (row / 4, row % 4);
                settled[b] |= (followed.decided >> lane & 1) << j;
                let (xb, vb) = (&mut c.x[b], &mut c.v[b]);
                xb.x.as_mut()[j] = x.x.as_ref()[lane];
                xb.y.as_mut()[j] = x.y.as_ref()[lane];
                xb.z.as_mut()[j] = x.z.as_ref()[lane];
                vb.x.as_mut()[j] = v.x.as_ref()[lane];
                vb.y.as_mut()[j] = v.y.as_ref()[lane];
                vb.z.as_mut()[j] = v.z.as_ref()[lane];
                if reports && lane <= last && followed.met & (1 << lane) != 0 {
                    touches.push(RowTouch {
                        collider: self.collider as u32,
                        row: (first_row + row) as u32,
                        other: u32::MAX,
                        point: followed.point(lane),
                        normal,
                        impulse: followed.impulse_w[lane] / c.inverse_mass[row],
                        fraction: followed.fraction[lane],
                        event: 1,
                    });
                }
            }
        }
        if !resolve {
            return;
        }
        // The blocks that had lanes to follow and are now decided whole:
        // the end-of-step rule (those still open are resolved after `row`).
        // (A point chunk's radii are +0 and a movable one's `w > 0`, all
        // the rule asks of them: their cold columns are not read, but for
        // a short last block, whose padding lanes keep `w` 0 and are left
        // alone.)
        let rest = self.rest_speed;
        let rows = c.inverse_mass.len();
        for_each_bit(&open, |b| {
            if settled[b] == ALL {
                let r = if c.point { Vec4::ZERO } else { radius4(c.radius, b) };
                let w = if c.movable && b * 4 + 4 <= rows {
                    Vec4::ONE
                } else {
                    radius4(c.inverse_mass, b)
                };
                self.plane.resolve_block::<AXIS>(&mut c.x[b], &mut c.v[b], r, w, rest);
            }
        });
    }
}

/// Rows `at` of a chunk (`start`: its start positions) gathered into one
/// block: start and end positions, end velocities, radii and inverse
/// masses. A chunk of point particles has radius +0 and a movable one
/// `w > 0` (all [`PlaneLanes::follow`] asks of it) in every lane: their
/// columns, which the settling pass leaves cold, are not read.
#[inline(always)]
fn gather(start: &[Vec3x4], c: &Chunk<'_>, at: [usize; 4]) -> (Vec3x4, Vec3x4, Vec3x4, Vec4, Vec4) {
    let [r0, r1, r2, r3] = at;
    let (b, j) = ([r0 / 4, r1 / 4, r2 / 4, r3 / 4], [r0 % 4, r1 % 4, r2 % 4, r3 % 4]);
    let axis = |blocks: &[Vec3x4], pick: fn(&Vec3x4) -> &Vec4| {
        Vec4::new(
            pick(&blocks[b[0]]).as_ref()[j[0]],
            pick(&blocks[b[1]]).as_ref()[j[1]],
            pick(&blocks[b[2]]).as_ref()[j[2]],
            pick(&blocks[b[3]]).as_ref()[j[3]],
        )
    };
    let block = |blocks: &[Vec3x4]| Vec3x4 {
        x: axis(blocks, |p| &p.x),
        y: axis(blocks, |p| &p.y),
        z: axis(blocks, |p| &p.z),
    };
    let column = |values: &[f32]| Vec4::new(values[r0], values[r1], values[r2], values[r3]);
    let r = if c.point { Vec4::ZERO } else { column(c.radius) };
    let w = if c.movable { Vec4::ONE } else { column(c.inverse_mass) };
    (block(start), block(c.x), block(c.v), r, w)
}

#[cfg(test)]
mod tests;
