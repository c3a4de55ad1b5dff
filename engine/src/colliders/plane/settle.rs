//! The plane's share of contacts inside the step: the lanes it settles
//! before any path is followed (clear of it all along the step, or resting
//! on it), resolved by the end-of-step rule.

use glam::{BVec4A, Vec3A, Vec4};
use tickwork_integrators::Vec3x4;

use super::Plane;
use super::axis::{axis_mut, bounce4, frictionless_block};
use crate::colliders::BlockColumns;
use crate::colliders::settled::{for_each_bit, open_blocks};
use crate::colliders::sweep::{all_clear_axis, clear_axis_lanes, resting_at_rest4, settle_plane, starts_resting4};

impl Plane {
    /// The whole blocks of a chunk whose first block rests, resolved block
    /// after block by the end-of-step rule while each rests whole: the
    /// first block that does not (`x.len()` if all do). Frictionless
    /// (`FRICTIONLESS`), a block whose lanes also pass the rule's own rest
    /// test takes its factor -1 without asking again; `FIXED`: movable
    /// point particles, no radius or mass read.
    pub(super) fn resolve_resting<
        const AXIS: usize,
        const NEGATIVE: bool,
        const FRICTIONLESS: bool,
        const FIXED: bool,
    >(
        &self,
        c: RestingChunk<'_>,
    ) -> usize {
        let pick = along::<AXIS, NEGATIVE>;
        let slow = Vec4::splat(-c.rest_speed);
        let scalars = c.radius.chunks_exact(4).zip(c.inverse_mass.chunks_exact(4));
        let blocks = c.start.iter().zip(c.x.iter_mut()).zip(c.v.iter_mut()).zip(scalars);
        for (b, (((start, x), v), (r, w))) in blocks.enumerate() {
            let (d0, d1, vn) = (pick(start), pick(x), pick(v));
            let dv = vn * c.dt;
            let rests = if FRICTIONLESS {
                // `v >= -rest` implies `v dt >= -rest dt` (rounding is
                // monotonic): the resting test's end half is implied.
                starts_resting4(d0, d1, dv, c.rest_dt) & vn.cmpge(slow)
            } else {
                resting_at_rest4(d0, d1, dv, c.rest_dt)
            };
            if !rests.all() {
                return b;
            }
            let (r, w) = if FIXED {
                (Vec4::ZERO, Vec4::ONE)
            } else {
                (Vec4::from_slice(r), Vec4::from_slice(w))
            };
            if FRICTIONLESS {
                frictionless_block::<AXIS, NEGATIVE, true, FIXED>(x, v, r, w, self.offset, Vec4::NEG_ONE);
            } else {
                self.contact_block::<AXIS, NEGATIVE>(x, v, r, w, c.rest_speed);
            }
        }
        c.x.len()
    }

    /// [`settle_plane`] on a chunk: which lanes are clear of the plane or
    /// rest on it.
    pub(super) fn settle(&self, start: &[Vec3x4], c: &BlockColumns<'_>, dt: f32, rest_dt: f32, settled: &mut [u8]) {
        let n = Vec3A::from(self.normal);
        let (x, v) = (&*c.position, &*c.velocity);
        settle_plane(
            n,
            self.offset,
            self.speed * dt,
            start,
            x,
            v,
            c.radius,
            dt,
            rest_dt,
            settled,
        );
    }

    /// [`settle`](Self::settle) and [`resolve_axis_blocks`](Self::resolve_axis_blocks)
    /// in one pass, for a plane at rest whose normal is `±e_AXIS`: each
    /// block whose lanes all settle is resolved as soon as it is tested,
    /// while it is in registers; the others are left for the step to follow
    /// and then resolve.
    pub(super) fn settle_axis_blocks<const AXIS: usize, const NEGATIVE: bool>(
        &self,
        start: &[Vec3x4],
        mut c: BlockColumns<'_>,
        dt: f32,
        rest_dt: f32,
        settled: &mut [u8],
    ) {
        let pick = along::<AXIS, NEGATIVE>;
        const ALL: u8 = 0b1111;
        let whole = c.rows / 4;
        // Most chunks are clear of the plane or rest on it whole, and are
        // taken whole first (the first block says which): a chunk clear of
        // it by a test folded over its blocks without a branch a block, a
        // resting one resolved block after block with no bookkeeping.
        let mut b = 0;
        if whole > 1 {
            b = self.resolve_resting_from::<AXIS, NEGATIVE>(0, start, &mut c, dt, rest_dt);
            if b == 0 {
                let (x, v) = (&c.position[..whole], &c.velocity[..whole]);
                let ends = start[..whole].iter().zip(x).zip(v);
                let ends = ends.map(|((start, x), v)| (pick(start), pick(x), pick(v) * dt));
                let clear = if c.point {
                    all_clear_axis(ends.map(|(d0, d1, dv)| (d0, d1, dv, Vec4::ZERO)), self.offset)
                } else {
                    let r = c.radius[..whole * 4].chunks_exact(4).map(Vec4::from_slice);
                    all_clear_axis(ends.zip(r).map(|((d0, d1, dv), r)| (d0, d1, dv, r)), self.offset)
                };
                if clear {
                    // Clear all along the step: the end-of-step rule would
                    // leave every lane as it is (the same bits).
                    b = whole;
                }
            }
        }
        // From here block by block, a mixed chunk (a crowd that bounces,
        // a settling pile): each block's lanes settled by both tests at
        // once (clear of the plane, or resting on it), and resolved where
        // all are; the one branch a block is on that (rarely taken: the
        // lanes that meet the plane are few).
        if b < whole {
            let settle = match (c.movable && c.point, self.material.friction == 0.0) {
                (true, true) => Self::settle_mixed::<AXIS, NEGATIVE, true, true>,
                (true, false) => Self::settle_mixed::<AXIS, NEGATIVE, true, false>,
                (false, true) => Self::settle_mixed::<AXIS, NEGATIVE, false, true>,
                (false, false) => Self::settle_mixed::<AXIS, NEGATIVE, false, false>,
            };
            settle(self, b, start, &mut c, dt, rest_dt, settled);
            b = whole;
        }
        // The short last block, whose padding lanes count as settled.
        if b < c.rows.div_ceil(4) {
            let (r, w) = c.block_scalars(b);
            let (x, v) = (&mut c.position[b], &mut c.velocity[b]);
            let (d0, d1, dv) = (pick(&start[b]), pick(x), pick(v) * dt);
            let padding = 0b1111 << (c.rows - b * 4) & 0b1111;
            let lanes = clear_axis_lanes(d0, d1, dv, r, self.offset, 0.0) | resting_at_rest4(d0, d1, dv, rest_dt);
            let mask = settled[b] & (lanes.bitmask() as u8 | padding);
            settled[b] = mask;
            if mask == ALL {
                self.contact_block::<AXIS, NEGATIVE>(x, v, r, w, c.rest_speed);
            }
        }
    }

    /// [`settle_axis_blocks`](Self::settle_axis_blocks)'s whole blocks from
    /// block `first` on, in a mixed chunk (`settled`: all lanes on entry,
    /// as the step's `Sweep::resolve_chunk` gives it): each block's lanes
    /// clear of the plane or resting on it, resolved when all are and one
    /// is not clear (`FIXED`: movable point particles, no radius or mass
    /// read; `FRICTIONLESS`: the bounce of
    /// [`contact_block`](Self::contact_block)'s frictionless branch inline,
    /// the same bits).
    ///
    /// In two passes: the clear test on every block, without a branch
    /// (each block's lanes into `settled`; the blocks with a lane not
    /// clear then found from those bytes, eight at a time); then only
    /// those blocks (in a bouncing crowd about one in eight, scattered)
    /// ask whether they rest. One pass with a branch a block mispredicted at each such
    /// block, and resolved clear blocks, which the end-of-step rule leaves
    /// as they are (the same bits).
    pub(super) fn settle_mixed<const AXIS: usize, const NEGATIVE: bool, const FIXED: bool, const FRICTIONLESS: bool>(
        &self,
        first: usize,
        start: &[Vec3x4],
        c: &mut BlockColumns<'_>,
        dt: f32,
        rest_dt: f32,
        settled: &mut [u8],
    ) {
        const ALL: u8 = 0b1111;
        let pick = along::<AXIS, NEGATIVE>;
        let sign = Vec4::splat(if NEGATIVE { -1.0 } else { 1.0 });
        let whole = c.rows / 4;
        let rest = c.rest_speed;
        let radius = |c: &BlockColumns<'_>, b: usize| {
            if FIXED {
                Vec4::ZERO
            } else {
                Vec4::from_slice(&c.radius[b * 4..b * 4 + 4])
            }
        };
        let (x, v) = (&c.position[first..whole], &c.velocity[first..whole]);
        let blocks = start[first..whole].iter().zip(x).zip(v).zip(&mut settled[first..whole]);
        for (b, (((start, x), v), settled)) in (first..whole).zip(blocks) {
            let clear = clear_axis_lanes(pick(start), pick(x), pick(v) * dt, radius(c, b), self.offset, 0.0);
            *settled &= clear.bitmask() as u8;
        }
        // The blocks with a lane not clear, as bits, from the bytes eight
        // at a time (not a bit set a block in the loop above, which makes
        // each block wait on the last one's store).
        let open = open_blocks(&settled[..whole]);
        for_each_bit(&open, |b| {
            let (d0, d1, dv) = (pick(&start[b]), pick(&c.position[b]), pick(&c.velocity[b]) * dt);
            let lanes = settled[b] | resting_at_rest4(d0, d1, dv, rest_dt).bitmask() as u8;
            settled[b] = lanes;
            let whole = lanes == ALL;
            if !FRICTIONLESS && !whole {
                return;
            }
            let r = radius(c, b);
            let w = if FIXED {
                Vec4::ONE
            } else {
                Vec4::from_slice(&c.inverse_mass[b * 4..b * 4 + 4])
            };
            let (x, v) = (&mut c.position[b], &mut c.velocity[b]);
            if FRICTIONLESS {
                // Without a branch on `whole` (about one open block in
                // two rests, at random): a block not settled whole
                // takes inverse mass 0, which the rule leaves as it
                // is (its lanes are followed, then resolved).
                let w = Vec4::select(BVec4A::splat(whole), w, Vec4::ZERO);
                let vn = *axis_mut::<AXIS>(v) * sign;
                let factor = bounce4(vn, self.material.restitution, rest);
                frictionless_block::<AXIS, NEGATIVE, false, false>(x, v, r, w, self.offset, factor);
            } else {
                self.contact_block::<AXIS, NEGATIVE>(x, v, r, w, rest);
            }
        });
    }

    /// The whole blocks from block `first` on that rest on the plane,
    /// resolved while each rests whole (see [`resolve_resting`](Self::resolve_resting)):
    /// how many.
    pub(super) fn resolve_resting_from<const AXIS: usize, const NEGATIVE: bool>(
        &self,
        first: usize,
        start: &[Vec3x4],
        c: &mut BlockColumns<'_>,
        dt: f32,
        rest_dt: f32,
    ) -> usize {
        let whole = c.rows / 4;
        let rest = RestingChunk {
            start: &start[first..whole],
            x: &mut c.position[first..whole],
            v: &mut c.velocity[first..whole],
            radius: &c.radius[first * 4..whole * 4],
            inverse_mass: &c.inverse_mass[first * 4..whole * 4],
            dt,
            rest_dt,
            rest_speed: c.rest_speed,
        };
        match (self.material.friction == 0.0, c.movable && c.point) {
            (true, true) => self.resolve_resting::<AXIS, NEGATIVE, true, true>(rest),
            (true, false) => self.resolve_resting::<AXIS, NEGATIVE, true, false>(rest),
            (false, true) => self.resolve_resting::<AXIS, NEGATIVE, false, true>(rest),
            (false, false) => self.resolve_resting::<AXIS, NEGATIVE, false, false>(rest),
        }
    }
}

/// The whole blocks of a chunk that [`Plane::resolve_resting`] takes: the
/// start positions, the end states it resolves, one radius and inverse
/// mass a particle, the step and the rest speed (and times the step).
pub(super) struct RestingChunk<'a> {
    start: &'a [Vec3x4],
    x: &'a mut [Vec3x4],
    v: &'a mut [Vec3x4],
    radius: &'a [f32],
    inverse_mass: &'a [f32],
    dt: f32,
    rest_dt: f32,
    rest_speed: f32,
}

/// A block's components along the normal `±e_AXIS` (`NEGATIVE`: -).
#[inline(always)]
pub(super) fn along<const AXIS: usize, const NEGATIVE: bool>(p: &Vec3x4) -> Vec4 {
    let component = match AXIS {
        0 => p.x,
        1 => p.y,
        _ => p.z,
    };
    component * Vec4::splat(if NEGATIVE { -1.0 } else { 1.0 })
}
