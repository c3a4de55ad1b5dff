//! An infinite plane: particles stay on the side its normal points to; at
//! rest, or kinematic (moved along its normal each step: a piston, a
//! rising floor).

use glam::{Mat4, Vec3, Vec3A, Vec4};
use tickwork_integrators::Vec3x4;

use super::contact::{ContactRule, Material, resolve};
use super::sweep::{
    StepPath, SweptHit, all_clear_axis, clear_axis_lanes, resting_at_rest4, settle_plane, starts_resting4,
};
use super::{BlockColumns, Collider, ContactColumns};

/// The half-space `n . x >= offset` is free; a particle of radius `r` touches
/// the plane when `n . x - offset - r < 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// Unit normal pointing into the free side (default `(0, 1, 0)`: a floor).
    pub normal: Vec3,
    /// Signed distance of the plane from the origin along the normal
    /// (default `0.0`).
    pub offset: f32,
    /// Bounce and friction (default [`Material::default`]).
    pub material: Material,
    /// Speed along the normal in m/s (default zero: at rest; moving along
    /// itself would change nothing). Each step first moves the plane,
    /// `offset += speed dt`, then resolves contacts in its frame, where it
    /// is at rest: `v' = u + response(v - u)` with `u = speed n`.
    pub speed: f32,
    /// When contacts are found (default [`ContactRule::InStep`]).
    pub contact: ContactRule,
}

impl Default for Plane {
    /// A floor at height 0, at rest, of the default material: so a struct
    /// literal names only what it changes (`Plane { normal: Vec3::X,
    /// ..Plane::default() }`).
    fn default() -> Self {
        Self::floor(0.0, Material::default())
    }
}

impl Plane {
    /// A floor at height `y`, at rest.
    #[must_use]
    pub fn floor(y: f32, material: Material) -> Self {
        Self {
            normal: Vec3::Y,
            offset: y,
            material,
            speed: 0.0,
            contact: ContactRule::InStep,
        }
    }

    /// The offset a frame `alpha` steps past the last one shows a moving
    /// plane at: between its last two steps (as particles are drawn).
    #[must_use]
    pub fn interpolated_offset(&self, alpha: f32, dt: f32) -> f32 {
        self.offset - self.speed * dt * (1.0 - alpha)
    }
}

/// A plane at rest whose normal is an axis, `n = ±e_axis` (a floor, a
/// wall, a ceiling), as [`Collider::axis_plane`] describes it: the free
/// side is `n . x >= offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisPlane {
    /// The axis of the normal: 0 (x), 1 (y) or 2 (z).
    pub axis: usize,
    /// Whether the normal is `-e_axis` (a ceiling, for axis 1).
    pub negative: bool,
    /// The plane's offset along its normal.
    pub offset: f32,
    /// Its bounce and friction.
    pub material: Material,
}

impl AxisPlane {
    /// The plane's end-of-step rule on one block of four particles (radii
    /// `r`, inverse masses `w`; approaches no faster than `rest` m/s rest):
    /// the same bits as [`Plane::resolve_blocks`] on that block.
    #[inline]
    pub(crate) fn resolve_block<const AXIS: usize>(&self, x: &mut Vec3x4, v: &mut Vec3x4, r: Vec4, w: Vec4, rest: f32) {
        let mut normal = Vec3::ZERO;
        normal[AXIS] = if self.negative { -1.0 } else { 1.0 };
        let plane = Plane {
            normal,
            offset: self.offset,
            material: self.material,
            speed: 0.0,
            contact: ContactRule::InStep,
        };
        if self.negative {
            plane.contact_block::<AXIS, true>(x, v, r, w, rest);
        } else {
            plane.contact_block::<AXIS, false>(x, v, r, w, rest);
        }
    }
}

/// `(axis, sign)` when the normal is `sign * e_axis` exactly.
fn axis_of(n: Vec3) -> Option<(usize, f32)> {
    let a = n.to_array();
    let axis = a.iter().position(|c| c.abs() == 1.0)?;
    let others_zero = a.iter().enumerate().all(|(k, c)| k == axis || *c == 0.0);
    others_zero.then_some((axis, a[axis]))
}

impl Plane {
    /// [`resolve`] for the normal `sign * e_AXIS`, four particles at a time:
    /// the four positions and velocities are transposed into component
    /// lanes (`x` of all four, `y` of all four, ...), so the contact test, the
    /// friction factor's square root and division and the selects are single
    /// packed instructions instead of per-particle horizontal dot products.
    /// A tail of fewer than four is padded into a block of four, so every
    /// particle sees exactly the same arithmetic whatever the chunking
    /// (which keeps steps bit-identical across thread counts).
    fn resolve_axis<const AXIS: usize>(&self, c: ContactColumns<'_>, sign: f32) {
        let rest = c.rest_speed;
        let n = c.position.len();
        let whole = n - n % 4;
        for i in (0..whole).step_by(4) {
            let x: &mut [Vec3A; 4] = (&mut c.position[i..i + 4])
                .try_into()
                .unwrap_or_else(|_| unreachable!());
            let v: &mut [Vec3A; 4] = (&mut c.velocity[i..i + 4])
                .try_into()
                .unwrap_or_else(|_| unreachable!());
            self.contact4::<AXIS>(
                x,
                v,
                Vec4::from_slice(&c.radius[i..]),
                Vec4::from_slice(&c.inverse_mass[i..]),
                sign,
                rest,
            );
        }
        if whole < n {
            let tail = n - whole;
            let (mut x, mut v, mut r, mut w) = ([Vec3A::ZERO; 4], [Vec3A::ZERO; 4], [0.0; 4], [0.0; 4]);
            x[..tail].copy_from_slice(&c.position[whole..]);
            v[..tail].copy_from_slice(&c.velocity[whole..]);
            r[..tail].copy_from_slice(&c.radius[whole..]);
            w[..tail].copy_from_slice(&c.inverse_mass[whole..]);
            self.contact4::<AXIS>(&mut x, &mut v, Vec4::from_array(r), Vec4::from_array(w), sign, rest);
            c.position[whole..].copy_from_slice(&x[..tail]);
            c.velocity[whole..].copy_from_slice(&v[..tail]);
        }
    }

    /// [`resolve_axis`](Self::resolve_axis) without friction: only the
    /// normal component of each particle changes, so no transposition and no
    /// tangential arithmetic are needed. Four particles at a time, their
    /// normal components gathered into one vector (the tail one at a time,
    /// with the same arithmetic lane for lane), the contact selected by bit
    /// masks (never a branch: resting particles flip the test unpredictably).
    fn resolve_axis_frictionless<const AXIS: usize>(&self, c: ContactColumns<'_>, sign: f32) {
        let n = c.position.len();
        let whole = n - n % 4;
        let (s, offset) = (Vec4::splat(sign), Vec4::splat(self.offset));
        let (e, rest) = (self.material.restitution, c.rest_speed);
        for i in (0..whole).step_by(4) {
            let (x, v) = (&mut c.position[i..i + 4], &mut c.velocity[i..i + 4]);
            let xa = Vec4::new(x[0][AXIS], x[1][AXIS], x[2][AXIS], x[3][AXIS]);
            let va = Vec4::new(v[0][AXIS], v[1][AXIS], v[2][AXIS], v[3][AXIS]);
            let gap = xa * s - offset - Vec4::from_slice(&c.radius[i..i + 4]);
            let vn = va * s;
            // min(vn, 0) as `vn < 0 ? vn : 0`, the same in the scalar tail.
            let dvn = bounce4(vn, e, rest) * Vec4::select(vn.cmplt(Vec4::ZERO), vn, Vec4::ZERO);
            let hit = gap.cmplt(Vec4::ZERO) & Vec4::from_slice(&c.inverse_mass[i..i + 4]).cmpgt(Vec4::ZERO);
            let new_v = Vec4::select(hit, (vn + dvn) * s, va).to_array();
            let new_x = Vec4::select(hit, xa - gap * s, xa).to_array();
            for k in 0..4 {
                x[k][AXIS] = new_x[k];
                v[k][AXIS] = new_v[k];
            }
        }
        let mut tail = ContactColumns {
            position: &mut c.position[whole..],
            velocity: &mut c.velocity[whole..],
            radius: &c.radius[whole..],
            inverse_mass: &c.inverse_mass[whole..],
            parallel: false,
            max_pairs: c.max_pairs,
            start: None,
            rest_speed: rest,
        };
        for (x, v, r, w) in tail.rows() {
            let gap = x[AXIS] * sign - self.offset - r;
            let vn = v[AXIS] * sign;
            let bounce = -(1.0 + if vn >= -rest { 0.0 } else { e });
            let dvn = bounce * select(vn < 0.0, vn, 0.0);
            let hit = gap < 0.0 && w > 0.0;
            v[AXIS] = select(hit, (vn + dvn) * sign, v[AXIS]);
            x[AXIS] = select(hit, x[AXIS] - gap * sign, x[AXIS]);
        }
    }

    #[inline(always)]
    fn contact4<const AXIS: usize>(
        &self,
        x: &mut [Vec3A; 4],
        v: &mut [Vec3A; 4],
        r: Vec4,
        w: Vec4,
        sign: f32,
        rest: f32,
    ) {
        let lanes = |p: &[Vec3A; 4]| {
            let t = Mat4::from_cols(p[0].extend(0.0), p[1].extend(0.0), p[2].extend(0.0), p[3].extend(0.0)).transpose();
            [t.x_axis, t.y_axis, t.z_axis]
        };
        let (mut xc, mut vc) = (lanes(x), lanes(v));
        self.contact_lanes::<AXIS>(&mut xc, &mut vc, r, w, sign, rest);
        let back = |c: [Vec4; 3], p: &mut [Vec3A; 4]| {
            let t = Mat4::from_cols(c[0], c[1], c[2], Vec4::ZERO).transpose();
            *p = [t.x_axis, t.y_axis, t.z_axis, t.w_axis].map(Vec3A::from_vec4);
        };
        back(xc, x);
        back(vc, v);
    }

    /// [`resolve`] for four particles held per axis (`xc[AXIS]` = their
    /// normal coordinates), the normal `sign * e_AXIS`; approaches no
    /// faster than `rest` rest.
    #[inline(always)]
    fn contact_lanes<const AXIS: usize>(
        &self,
        xc: &mut [Vec4; 3],
        vc: &mut [Vec4; 3],
        r: Vec4,
        w: Vec4,
        sign: f32,
        rest: f32,
    ) {
        let s = Vec4::splat(sign);
        let gap = xc[AXIS] * s - Vec4::splat(self.offset) - r;
        let vn = vc[AXIS] * s;
        let dvn = bounce4(vn, self.material.restitution, rest) * vn.min(Vec4::ZERO);
        let (t1, t2) = ((AXIS + 1) % 3, (AXIS + 2) % 3);
        let speed2 = vc[t1] * vc[t1] + vc[t2] * vc[t2];
        let brake = Vec4::splat(self.material.friction) * dvn;
        // Friction stops the sliding when mu dvn >= |v_t|: the tangential
        // velocity becomes 0, as in `resolve`. Only where a contact slides on
        // is the factor 1 - mu dvn / |v_t| needed, with its square root and
        // division; resting and free-flying particles skip them (the test is
        // per block of four, and each lane's result does not depend on it).
        let stops = (brake * brake).cmpge(speed2);
        let hit = gap.cmplt(Vec4::ZERO) & w.cmpgt(Vec4::ZERO);
        let keep = if (hit & !stops).any() {
            let speed = speed2.sqrt().max(Vec4::splat(f32::MIN_POSITIVE));
            Vec4::select(stops, Vec4::ZERO, (Vec4::ONE - brake / speed).max(Vec4::ZERO))
        } else {
            Vec4::ZERO
        };
        vc[t1] = Vec4::select(hit, vc[t1] * keep, vc[t1]);
        vc[t2] = Vec4::select(hit, vc[t2] * keep, vc[t2]);
        vc[AXIS] = Vec4::select(hit, (vn + dvn) * s, vc[AXIS]);
        xc[AXIS] = Vec4::select(hit, xc[AXIS] - gap * s, xc[AXIS]);
    }

    /// The axis-aligned contact on blocks of four particles per axis: the
    /// arithmetic of [`resolve_axis`](Self::resolve_axis) and
    /// [`resolve_axis_frictionless`](Self::resolve_axis_frictionless), lane
    /// for lane, with no transposition (the blocks are already per axis).
    /// Without friction only the normal axis's lanes are read and written.
    /// The sign is a constant (`x * 1` and `x * -1` fold away). Chunks of
    /// movable point particles (the common case: a rain of sparks) skip the
    /// radius and mass lanes: `gap - 0` and `w > 0` are then known, and the
    /// same bits come out.
    fn resolve_axis_blocks<const AXIS: usize, const NEGATIVE: bool>(&self, c: BlockColumns<'_>) {
        let whole = c.rows / 4;
        let rest = c.rest_speed;
        let (x, v) = (&mut c.position[..whole], &mut c.velocity[..whole]);
        if c.movable && c.point {
            for (x, v) in x.iter_mut().zip(v.iter_mut()) {
                self.contact_block::<AXIS, NEGATIVE>(x, v, Vec4::ZERO, Vec4::ONE, rest);
            }
        } else {
            let scalars = c.radius.chunks_exact(4).zip(c.inverse_mass.chunks_exact(4));
            for ((x, v), (r, w)) in x.iter_mut().zip(v.iter_mut()).zip(scalars) {
                self.contact_block::<AXIS, NEGATIVE>(x, v, Vec4::from_slice(r), Vec4::from_slice(w), rest);
            }
        }
        if whole * 4 < c.rows {
            let (r, w) = c.block_scalars(whole);
            self.contact_block::<AXIS, NEGATIVE>(&mut c.position[whole], &mut c.velocity[whole], r, w, rest);
        }
    }

    /// One block's contact (see [`resolve_axis_blocks`](Self::resolve_axis_blocks)).
    #[inline(always)]
    fn contact_block<const AXIS: usize, const NEGATIVE: bool>(
        &self,
        x: &mut Vec3x4,
        v: &mut Vec3x4,
        r: Vec4,
        w: Vec4,
        rest: f32,
    ) {
        let sign = if NEGATIVE { -1.0 } else { 1.0 };
        if self.material.friction == 0.0 {
            let vn = *axis_mut::<AXIS>(v) * Vec4::splat(sign);
            let factor = bounce4(vn, self.material.restitution, rest);
            frictionless_block::<AXIS, NEGATIVE, false, false>(x, v, r, w, self.offset, factor);
        } else {
            let (mut xc, mut vc) = ([x.x, x.y, x.z], [v.x, v.y, v.z]);
            self.contact_lanes::<AXIS>(&mut xc, &mut vc, r, w, sign, rest);
            [x.x, x.y, x.z] = xc;
            [v.x, v.y, v.z] = vc;
        }
    }
}

impl Plane {
    /// The whole blocks of a chunk whose first block rests, resolved block
    /// after block by the end-of-step rule while each rests whole: the
    /// first block that does not (`x.len()` if all do). Frictionless
    /// (`FRICTIONLESS`), a block whose lanes also pass the rule's own rest
    /// test takes its factor -1 without asking again; `FIXED`: movable
    /// point particles, no radius or mass read.
    fn resolve_resting<const AXIS: usize, const NEGATIVE: bool, const FRICTIONLESS: bool, const FIXED: bool>(
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
    fn settle(&self, start: &[Vec3x4], c: &BlockColumns<'_>, dt: f32, rest_dt: f32, settled: &mut [u8]) {
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
    fn settle_axis_blocks<const AXIS: usize, const NEGATIVE: bool>(
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
    /// block `first` on, in a mixed chunk: each block's lanes clear of the
    /// plane or resting on it, resolved when all are (`FIXED`: movable point
    /// particles, no radius or mass read; `FRICTIONLESS`: the bounce of
    /// [`contact_block`](Self::contact_block)'s frictionless branch inline,
    /// the same bits).
    fn settle_mixed<const AXIS: usize, const NEGATIVE: bool, const FIXED: bool, const FRICTIONLESS: bool>(
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
        let (x, v) = (&mut c.position[first..whole], &mut c.velocity[first..whole]);
        let blocks = start[first..whole].iter().zip(x.iter_mut()).zip(v.iter_mut());
        let blocks = blocks.zip(settled[first..whole].iter_mut());
        for (b, (((start, x), v), settled)) in (first..whole).zip(blocks) {
            let (d0, d1, dv) = (pick(start), pick(x), pick(v) * dt);
            let (r, w) = if FIXED {
                (Vec4::ZERO, Vec4::ONE)
            } else {
                let first = b * 4;
                (
                    Vec4::from_slice(&c.radius[first..first + 4]),
                    Vec4::from_slice(&c.inverse_mass[first..first + 4]),
                )
            };
            let lanes = clear_axis_lanes(d0, d1, dv, r, self.offset, 0.0) | resting_at_rest4(d0, d1, dv, rest_dt);
            let mask = *settled & lanes.bitmask() as u8;
            if mask != ALL {
                *settled = mask;
            } else if FRICTIONLESS {
                let vn = *axis_mut::<AXIS>(v) * sign;
                let factor = bounce4(vn, self.material.restitution, rest);
                frictionless_block::<AXIS, NEGATIVE, false, false>(x, v, r, w, self.offset, factor);
            } else {
                self.contact_block::<AXIS, NEGATIVE>(x, v, r, w, rest);
            }
        }
    }

    /// The whole blocks from block `first` on that rest on the plane,
    /// resolved while each rests whole (see [`resolve_resting`](Self::resolve_resting)):
    /// how many.
    fn resolve_resting_from<const AXIS: usize, const NEGATIVE: bool>(
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

/// A frictionless block's contact with the factor `-(1 + e)` or `-1`
/// (no bounce) of each lane's normal velocity given: what
/// [`Plane::contact_block`] computes for it. `RESTING`: every lane
/// approaches no faster than the rest speed (the factor is -1 in every
/// lane, NaN excluded by the rest test), and `v_n + (-1) min(v_n, 0)`,
/// `+0` for an approach and `v_n` otherwise, is taken by a select: the
/// same bits. `MOVABLE`: every lane is movable (`w > 0` not asked).
#[inline(always)]
fn frictionless_block<const AXIS: usize, const NEGATIVE: bool, const RESTING: bool, const MOVABLE: bool>(
    x: &mut Vec3x4,
    v: &mut Vec3x4,
    r: Vec4,
    w: Vec4,
    offset: f32,
    factor: Vec4,
) {
    let s = Vec4::splat(if NEGATIVE { -1.0 } else { 1.0 });
    let (xa, va) = (axis_mut::<AXIS>(x), axis_mut::<AXIS>(v));
    let gap = *xa * s - Vec4::splat(offset) - r;
    let vn = *va * s;
    let approach = vn.cmplt(Vec4::ZERO);
    // `MOVABLE`: every lane's `w > 0` is known.
    let hit = if MOVABLE {
        gap.cmplt(Vec4::ZERO)
    } else {
        gap.cmplt(Vec4::ZERO) & w.cmpgt(Vec4::ZERO)
    };
    if RESTING {
        // `(vn + (-1) min(vn, 0)) s` is a zero of the normal's sign where
        // the lane approaches and `vn s`, the velocity itself, elsewhere:
        // one select where it hits.
        let zero = Vec4::splat(if NEGATIVE { -0.0 } else { 0.0 });
        *va = Vec4::select(hit & approach, zero, *va);
    } else {
        let after = vn + factor * Vec4::select(approach, vn, Vec4::ZERO);
        *va = Vec4::select(hit, after * s, *va);
    }
    *xa = Vec4::select(hit, *xa - gap * s, *xa);
}

/// The whole blocks of a chunk that [`Plane::resolve_resting`] takes: the
/// start positions, the end states it resolves, one radius and inverse
/// mass a particle, the step and the rest speed (and times the step).
struct RestingChunk<'a> {
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
fn along<const AXIS: usize, const NEGATIVE: bool>(p: &Vec3x4) -> Vec4 {
    let component = match AXIS {
        0 => p.x,
        1 => p.y,
        _ => p.z,
    };
    component * Vec4::splat(if NEGATIVE { -1.0 } else { 1.0 })
}

/// The lanes of axis `AXIS` of a block.
#[inline(always)]
fn axis_mut<const AXIS: usize>(b: &mut Vec3x4) -> &mut Vec4 {
    match AXIS {
        0 => &mut b.x,
        1 => &mut b.y,
        _ => &mut b.z,
    }
}

impl Collider for Plane {
    fn name(&self) -> &'static str {
        "plane"
    }

    fn in_step(&self) -> bool {
        self.contact == ContactRule::InStep
    }

    fn settle_blocks(&self, start: &[Vec3x4], c: BlockColumns<'_>, dt: f32, resolve: bool, settled: &mut [u8]) -> bool {
        let rest_dt = c.rest_speed * dt;
        if resolve && self.speed == 0.0 {
            match axis_of(self.normal) {
                Some((0, sign)) if sign < 0.0 => self.settle_axis_blocks::<0, true>(start, c, dt, rest_dt, settled),
                Some((0, _)) => self.settle_axis_blocks::<0, false>(start, c, dt, rest_dt, settled),
                Some((1, sign)) if sign < 0.0 => self.settle_axis_blocks::<1, true>(start, c, dt, rest_dt, settled),
                Some((1, _)) => self.settle_axis_blocks::<1, false>(start, c, dt, rest_dt, settled),
                Some((_, sign)) if sign < 0.0 => self.settle_axis_blocks::<2, true>(start, c, dt, rest_dt, settled),
                Some((_, _)) => self.settle_axis_blocks::<2, false>(start, c, dt, rest_dt, settled),
                None => {
                    self.settle(start, &c, dt, rest_dt, settled);
                    return false;
                }
            }
            return true;
        }
        self.settle(start, &c, dt, rest_dt, settled);
        false
    }

    fn axis_plane(&self) -> Option<AxisPlane> {
        if self.contact != ContactRule::InStep || self.speed != 0.0 {
            return None;
        }
        let (axis, sign) = axis_of(self.normal)?;
        Some(AxisPlane {
            axis,
            negative: sign < 0.0,
            offset: self.offset,
            material: self.material,
        })
    }

    fn first_contact(&self, path: &StepPath, radius: f32) -> Option<SweptHit> {
        let n = self.normal.as_dvec3();
        let speed = f64::from(self.speed);
        let offset = f64::from(self.offset);
        let fraction = path.first_crossing(n, offset, speed * path.dt, f64::from(radius))?;
        Some(SweptHit {
            fraction,
            normal: n,
            offset,
            velocity: n * speed,
            material: self.material,
        })
    }

    fn resolve_blocks(&self, c: BlockColumns<'_>) -> bool {
        if self.speed != 0.0 {
            return false;
        }
        match axis_of(self.normal) {
            Some((0, sign)) if sign < 0.0 => self.resolve_axis_blocks::<0, true>(c),
            Some((0, _)) => self.resolve_axis_blocks::<0, false>(c),
            Some((1, sign)) if sign < 0.0 => self.resolve_axis_blocks::<1, true>(c),
            Some((1, _)) => self.resolve_axis_blocks::<1, false>(c),
            Some((_, sign)) if sign < 0.0 => self.resolve_axis_blocks::<2, true>(c),
            Some((_, _)) => self.resolve_axis_blocks::<2, false>(c),
            None => return false,
        }
        true
    }

    fn resolve_range(&self, mut c: ContactColumns<'_>) {
        let n = Vec3A::from(self.normal);
        let rest = c.rest_speed;
        if self.speed != 0.0 {
            // Moving: the contact in the plane's frame, where it is at rest.
            let u = n * self.speed;
            for (x, v, r, w) in c.rows() {
                let gap = n.dot(*x) - self.offset - r;
                let mut relative = *v - u;
                let before = relative;
                resolve(x, &mut relative, n, gap, w > 0.0, self.material, rest);
                if relative != before {
                    *v = relative + u;
                }
            }
            return;
        }
        // Floors and walls are usually axis-aligned: their contact needs no
        // dot products, which halves the collider's cost (measured).
        let frictionless = self.material.friction == 0.0;
        match axis_of(self.normal) {
            Some((0, sign)) if frictionless => self.resolve_axis_frictionless::<0>(c, sign),
            Some((1, sign)) if frictionless => self.resolve_axis_frictionless::<1>(c, sign),
            Some((_, sign)) if frictionless => self.resolve_axis_frictionless::<2>(c, sign),
            Some((0, sign)) => self.resolve_axis::<0>(c, sign),
            Some((1, sign)) => self.resolve_axis::<1>(c, sign),
            Some((_, sign)) => self.resolve_axis::<2>(c, sign),
            None => {
                for (x, v, r, w) in c.rows() {
                    let gap = n.dot(*x) - self.offset - r;
                    resolve(x, v, n, gap, w > 0.0, self.material, rest);
                }
            }
        }
    }

    fn advance(&mut self, dt: f32) {
        if self.speed != 0.0 {
            self.offset += self.speed * dt;
        }
    }
}

/// The factor `-(1 + e)` of each lane's normal velocity: `-1` (no bounce)
/// where the approach `vn` is no faster than `rest` (a resting contact;
/// `rest` 0 changes nothing, `min(vn, 0)` being 0 there).
#[inline(always)]
fn bounce4(vn: Vec4, e: f32, rest: f32) -> Vec4 {
    Vec4::select(vn.cmpge(Vec4::splat(-rest)), Vec4::NEG_ONE, Vec4::splat(-(1.0 + e)))
}

/// `if condition { a } else { b }` by bit masks, which the compiler cannot
/// turn back into a branch.
#[inline(always)]
fn select(condition: bool, a: f32, b: f32) -> f32 {
    let mask = 0u32.wrapping_sub(u32::from(condition));
    f32::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The four-lane path for axis-aligned planes, and the frictionless
    /// path, give the same results as the general contact (up to the sign of
    /// zero).
    #[test]
    fn axis_fast_paths_equal_the_general_contact() {
        for friction in [0.3, 0.0] {
            // Every approach bounces, and (a rest speed) the slow ones rest.
            for rest in [0.0, 0.8] {
                axis_fast_path_equals_the_general_contact(friction, rest);
            }
        }
    }

    fn axis_fast_path_equals_the_general_contact(friction: f32, rest: f32) {
        let material = Material {
            restitution: 0.7,
            friction,
        };
        let mut seed = 12345u32;
        let mut random = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1 << 24) as f32 * 2.0 - 1.0
        };
        for (normal, axis) in [(Vec3::Y, 1), (Vec3::NEG_X, 0), (Vec3::Z, 2)] {
            let plane = Plane {
                normal,
                offset: 0.1,
                material,
                ..Plane::default()
            };
            let n = 23; // five blocks of four and a padded tail of three
            let mut x: Vec<Vec3A> = (0..n).map(|_| Vec3A::new(random(), random(), random()) * 0.3).collect();
            let mut v: Vec<Vec3A> = (0..n).map(|_| Vec3A::new(random(), random(), random()) * 3.0).collect();
            let radius: Vec<f32> = (0..n).map(|_| random().abs() * 0.1).collect();
            let inverse_mass: Vec<f32> = (0..n).map(|k| if k % 5 == 0 { 0.0 } else { 1.0 }).collect();
            let (mut x2, mut v2) = (x.clone(), v.clone());
            let nn = Vec3A::from(normal);
            for k in 0..n {
                let gap = nn.dot(x2[k]) - plane.offset - radius[k];
                resolve(&mut x2[k], &mut v2[k], nn, gap, inverse_mass[k] > 0.0, material, rest);
            }
            let columns = ContactColumns {
                position: &mut x,
                velocity: &mut v,
                radius: &radius,
                inverse_mass: &inverse_mass,
                parallel: false,
                max_pairs: u64::MAX,
                start: None,
                rest_speed: rest,
            };
            assert_eq!(axis_of(normal).map(|a| a.0), Some(axis));
            plane.resolve_range(columns);
            assert_eq!(x, x2, "positions, normal {normal}");
            assert_eq!(v, v2, "velocities, normal {normal}");
            assert!(
                x.iter().zip(&radius).any(|(x, r)| (nn.dot(*x) - 0.1 - r).abs() < 1e-6),
                "some contacts"
            );
            // A slow approach rests: on the surface, no normal velocity.
            let rested = (0..n).any(|k| (nn.dot(x[k]) - 0.1 - radius[k]).abs() < 1e-6 && nn.dot(v[k]) == 0.0);
            assert_eq!(rested, rest > 0.0, "rest speed {rest}, normal {normal}");
        }
        assert_eq!(axis_of(Vec3::new(0.6, 0.8, 0.0)), None);
    }

    /// A lane whose `v dt` passes the resting test's bound while `v` is
    /// past the rest speed by a rounding: the resting chunk must not
    /// resolve it without its bounce, as the end-of-step rule gives it.
    #[test]
    fn a_resting_chunk_is_resolved_as_the_end_of_step_rule_resolves_it_at_the_rest_speeds_edge() {
        // (A rest speed of a power of two, as the default 0.5, scales
        // exactly: no such edge.)
        let edge = (1..400).map(|k| 0.1 + k as f32 * 0.0137).find_map(|rest| {
            [1.0f32 / 60.0, 1.0 / 30.0, 1.0 / 240.0, 0.01, 0.003]
                .into_iter()
                .find_map(|dt| {
                    let mut vn = -rest;
                    for _ in 0..256 {
                        vn = f32::from_bits(vn.to_bits() + 1);
                        if vn * dt >= -(rest * dt) && vn < -rest {
                            return Some((rest, dt, vn));
                        }
                    }
                    None
                })
        });
        let (rest, dt, edge) =
            edge.expect("a rest speed and step whose rounding puts v dt inside the bound, v outside");
        let plane = Plane::floor(
            0.0,
            Material {
                restitution: 0.7,
                friction: 0.0,
            },
        );
        // Eight blocks on the floor, each particle at y = 0 at the start
        // and sinking at -0.1 m/s (resting), one at the edge speed.
        let blocks = 8;
        let lanes = |y: f32| Vec3x4 {
            x: Vec4::ZERO,
            y: Vec4::splat(y),
            z: Vec4::ZERO,
        };
        let start = vec![lanes(0.0); blocks];
        let mut v = vec![lanes(-0.1); blocks];
        v[5].y = Vec4::new(-0.1, edge, -0.1, -0.1);
        let mut x: Vec<Vec3x4> = v
            .iter()
            .map(|v| Vec3x4 {
                x: Vec4::ZERO,
                y: v.y * dt,
                z: Vec4::ZERO,
            })
            .collect();
        let (mut x_end, mut v_end) = (x.clone(), v.clone());
        for (x, v) in x_end.iter_mut().zip(v_end.iter_mut()) {
            plane.contact_block::<1, false>(x, v, Vec4::ZERO, Vec4::ONE, rest);
        }
        assert!(v_end[5].y.y > 0.0, "the edge lane bounces by the end-of-step rule");
        let (radius, inverse_mass) = (vec![0.0; blocks * 4], vec![1.0; blocks * 4]);
        let mut settled = vec![0b1111u8; blocks];
        let columns = BlockColumns {
            position: &mut x,
            velocity: &mut v,
            radius: &radius,
            inverse_mass: &inverse_mass,
            rows: blocks * 4,
            movable: true,
            point: true,
            rest_speed: rest,
        };
        assert!(plane.settle_blocks(&start, columns, dt, true, &mut settled));
        // Every block as the end-of-step rule left it: the edge lane's
        // bounces (its block taken block by block, whole blocks of
        // resting lanes resolved by the rule's own test).
        for b in 0..blocks {
            assert_eq!((x[b], v[b]), (x_end[b], v_end[b]), "block {b}");
        }
    }

    #[test]
    fn a_particle_gets_the_same_bits_in_a_block_of_four_and_in_the_tail() {
        // Which path a particle takes depends on the particles around it
        // (its place in the chunk); its result must not. Resting, sinking,
        // rising, -0 and NaN velocities, an immovable particle.
        let plane = Plane::floor(
            0.0,
            Material {
                restitution: 0.6,
                friction: 0.0,
            },
        );
        let x = [0.01, -0.02, 0.03, -0.0, 0.5, -0.3, f32::NAN, 0.02].map(|y| Vec3A::new(0.1, y, -0.2));
        let v = [-0.0, -1.0, 2.0, -3.0, 0.0, f32::NAN, -1.0, -0.5].map(|y| Vec3A::new(0.3, y, 0.0));
        let radius = [0.02; 8];
        let inverse_mass = [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0];
        let (mut xb, mut vb) = (x, v);
        plane.resolve_range(ContactColumns {
            position: &mut xb,
            velocity: &mut vb,
            radius: &radius,
            inverse_mass: &inverse_mass,
            parallel: false,
            max_pairs: u64::MAX,
            start: None,
            rest_speed: 0.0,
        });
        for k in 0..8 {
            let (mut xt, mut vt) = ([x[k]], [v[k]]);
            plane.resolve_range(ContactColumns {
                position: &mut xt,
                velocity: &mut vt,
                radius: &radius[k..=k],
                inverse_mass: &inverse_mass[k..=k],
                parallel: false,
                max_pairs: u64::MAX,
                start: None,
                rest_speed: 0.0,
            });
            let bits = |a: Vec3A| a.to_array().map(f32::to_bits);
            assert_eq!(bits(xb[k]), bits(xt[0]), "position {k}");
            assert_eq!(bits(vb[k]), bits(vt[0]), "velocity {k}");
        }
        assert!(xb[1].y > 0.0 && vb[1].y > 0.0, "a sinking particle bounces");
    }
}
