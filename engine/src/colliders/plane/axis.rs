//! A plane along an axis, four particles at a time: the end-of-step rule on
//! component lanes, and the lane helpers the in-step pass shares.

use glam::{Mat4, Vec3A, Vec4};
use tickwork_integrators::Vec3x4;

use super::Plane;
use crate::colliders::{BlockColumns, ContactColumns};

impl Plane {
    /// [`resolve`] for the normal `sign * e_AXIS`, four particles at a time:
    /// the four positions and velocities are transposed into component
    /// lanes (`x` of all four, `y` of all four, ...), so the contact test, the
    /// friction factor's square root and division and the selects are single
    /// packed instructions instead of per-particle horizontal dot products.
    /// A tail of fewer than four is padded into a block of four, so every
    /// particle sees exactly the same arithmetic whatever the chunking
    /// (which keeps steps bit-identical across thread counts).
    pub(super) fn resolve_axis<const AXIS: usize>(&self, c: ContactColumns<'_>, sign: f32) {
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
    pub(super) fn resolve_axis_frictionless<const AXIS: usize>(&self, c: ContactColumns<'_>, sign: f32) {
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
    pub(super) fn contact4<const AXIS: usize>(
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
    pub(super) fn contact_lanes<const AXIS: usize>(
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
    pub(super) fn resolve_axis_blocks<const AXIS: usize, const NEGATIVE: bool>(&self, c: BlockColumns<'_>) {
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
    pub(super) fn contact_block<const AXIS: usize, const NEGATIVE: bool>(
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

/// The lanes of axis `AXIS` of a block.
#[inline(always)]
pub(super) fn axis_mut<const AXIS: usize>(b: &mut Vec3x4) -> &mut Vec4 {
    match AXIS {
        0 => &mut b.x,
        1 => &mut b.y,
        _ => &mut b.z,
    }
}

/// The factor `-(1 + e)` of each lane's normal velocity: `-1` (no bounce)
/// where the approach `vn` is no faster than `rest` (a resting contact;
/// `rest` 0 changes nothing, `min(vn, 0)` being 0 there).
#[inline(always)]
pub(super) fn bounce4(vn: Vec4, e: f32, rest: f32) -> Vec4 {
    Vec4::select(vn.cmpge(Vec4::splat(-rest)), Vec4::NEG_ONE, Vec4::splat(-(1.0 + e)))
}

/// `if condition { a } else { b }` by bit masks, which the compiler cannot
/// turn back into a branch.
#[inline(always)]
pub(super) fn select(condition: bool, a: f32, b: f32) -> f32 {
    let mask = 0u32.wrapping_sub(u32::from(condition));
    f32::from_bits((a.to_bits() & mask) | (b.to_bits() & !mask))
}

/// A frictionless block's contact with the factor `-(1 + e)` or `-1`
/// (no bounce) of each lane's normal velocity given: what
/// [`Plane::contact_block`] computes for it. `RESTING`: every lane
/// approaches no faster than the rest speed (the factor is -1 in every
/// lane, NaN excluded by the rest test), and `v_n + (-1) min(v_n, 0)`,
/// `+0` for an approach and `v_n` otherwise, is taken by a select: the
/// same bits. `MOVABLE`: every lane is movable (`w > 0` not asked).
#[inline(always)]
pub(super) fn frictionless_block<const AXIS: usize, const NEGATIVE: bool, const RESTING: bool, const MOVABLE: bool>(
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
