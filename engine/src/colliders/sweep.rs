//! The precise instant of a contact inside a step.
//!
//! A particle's path over one step of `dt` is taken to be the curve the
//! renderer draws between the step's two states: the quadratic through the
//! start position `x0` and the end position `x1` whose velocity at the end
//! is `v1`,
//!
//! ```text
//! q(s) = x0 + b s + a s^2,   s in [0, 1],
//! a = v1 dt - (x1 - x0),     b = 2 (x1 - x0) - v1 dt,
//! q'(s) / dt = (b + 2 a s) / dt   (the velocity along it).
//! ```
//!
//! It is exact for constant acceleration (a ball under gravity stepped by
//! velocity Verlet, or any method that lands on the exact parabola), and
//! needs only the end state and the start position, which the step keeps
//! anyway (for interpolation). The gap to a plane along it is a quadratic
//! in `s` too, whose first root in `[0, 1]` is the instant of contact:
//! found in closed form, in `f64` (correctly rounded on every platform, so
//! the same bits natively and in a page).

use glam::{BVec4A, DVec3, Vec3A, Vec4};
use tickwork_integrators::Vec3x4;

use super::contact::Material;

/// Most contacts one particle may meet in one step ([`ContactRule::InStep`](super::ContactRule)):
/// a particle that would need more (squeezed between two surfaces closing
/// in, or bouncing between walls closer than its travel a step many times
/// over) is left to the end-of-step rule and named in the step's report, or
/// with [`ContactOverflow::Error`](crate::ContactOverflow) is
/// [`SimulationError::ContactEventLimit`](crate::SimulationError), naming
/// the entity, the collider and this limit; never a hang.
pub const MAX_CONTACT_EVENTS: u32 = 16;

/// Where a path first meets a collider's surface: the plane it meets there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweptHit {
    /// The fraction of the path, in `[0, 1]`.
    pub fraction: f64,
    /// The surface's unit normal, towards the free side.
    pub normal: DVec3,
    /// The surface's plane at the end of the step: `normal . x = offset`.
    pub offset: f64,
    /// The surface's velocity (a kinematic collider's), m/s.
    pub velocity: DVec3,
    /// Its bounce and friction.
    pub material: Material,
}

/// One step's path: `q(s) = start + b s + a s^2` over `s` in `[0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepPath {
    /// Position at `s = 0`.
    pub start: DVec3,
    /// Coefficient of `s`.
    pub b: DVec3,
    /// Coefficient of `s^2`.
    pub a: DVec3,
    /// The step's length in seconds.
    pub dt: f64,
}

impl StepPath {
    /// The path from `x0` to `x1` arriving with velocity `v1` after `dt`
    /// seconds (the renderer's curve).
    #[must_use]
    pub fn new(x0: Vec3A, x1: Vec3A, v1: Vec3A, dt: f32) -> Self {
        Self::through(x0.as_dvec3(), x1.as_dvec3(), v1.as_dvec3(), f64::from(dt))
    }

    /// [`new`](Self::new) in `f64`: the path from `x0` to `x1` arriving with
    /// velocity `v1` after `dt` seconds.
    #[must_use]
    pub fn through(x0: DVec3, x1: DVec3, v1: DVec3, dt: f64) -> Self {
        let delta = x1 - x0;
        let vdt = v1 * dt;
        Self {
            start: x0,
            b: 2.0 * delta - vdt,
            a: vdt - delta,
            dt,
        }
    }

    /// The position at fraction `s` of the step.
    #[must_use]
    pub fn at(&self, s: f64) -> DVec3 {
        self.start + (self.b + self.a * s) * s
    }

    /// The velocity at fraction `s` of the step.
    #[must_use]
    pub fn velocity(&self, s: f64) -> DVec3 {
        (self.b + 2.0 * self.a * s) / self.dt
    }

    /// The path's (constant) acceleration.
    #[must_use]
    pub fn acceleration(&self) -> DVec3 {
        2.0 * self.a / (self.dt * self.dt)
    }

    /// The first fraction `s` in `[0, 1]` at which the gap to the plane
    /// `n . x = offset` (minus `radius`) reaches zero from above, the plane
    /// moving by `travel` along `n` over the step and at `offset` at its
    /// end; `None` if the path stays clear, or starts inside (a particle
    /// already through the surface is left to the end-of-step projection).
    #[must_use]
    pub fn first_crossing(&self, n: DVec3, offset: f64, travel: f64, radius: f64) -> Option<f64> {
        // gap(s) = c + b s + a s^2, the plane at offset - travel (1 - s).
        let c = n.dot(self.start) - (offset - travel) - radius;
        let b = n.dot(self.b) - travel;
        let a = n.dot(self.a);
        first_root(a, b, c)
    }
}

/// A lower bound on the gap between four paths (blocks of the start and
/// end positions and end velocities, as the fused step holds them) and the
/// plane `n . x = offset` moving `travel` along `n` over the step, less a
/// margin for `f32` rounding: a lane above zero certainly does not touch
/// it in the step (the exact test, [`StepPath::first_crossing`], would find
/// nothing), so it is skipped. Along the path the gap is
/// `(1 - s) g0 + s g1 - A s (1 - s)`, at least `min(g0, g1) - max(A, 0) / 4`.
#[must_use]
#[allow(clippy::too_many_arguments)]
pub fn clearance4(
    n: Vec3A,
    offset: f32,
    travel: f32,
    x0: &Vec3x4,
    x1: &Vec3x4,
    v1: &Vec3x4,
    radius: Vec4,
    dt: f32,
) -> Vec4 {
    let dot = |p: &Vec3x4| p.x * n.x + p.y * n.y + p.z * n.z;
    // The rounding of a dot product is that of its terms' magnitudes.
    let size = |p: &Vec3x4| p.x.abs() * n.x.abs() + p.y.abs() * n.y.abs() + p.z.abs() * n.z.abs();
    let (d0, d1, dv) = (dot(x0), dot(x1), dot(v1) * dt);
    let g0 = d0 - Vec4::splat(offset - travel) - radius;
    let g1 = d1 - Vec4::splat(offset) - radius;
    let a = dv - (d1 - d0);
    let bound = g0.min(g1) - a.max(Vec4::ZERO) * 0.25;
    // Each term is rounded once or twice at its own magnitude.
    let scale = size(x0) + size(x1) + size(v1) * dt + radius + Vec4::splat(offset.abs() + travel.abs());
    bound - scale * 1e-6 - Vec4::splat(f32::MIN_POSITIVE)
}

/// Radii of block `b` as lanes (0 past the end of `radius`).
#[inline]
#[must_use]
pub fn radius4(radius: &[f32], b: usize) -> Vec4 {
    let first = b * 4;
    if first + 4 <= radius.len() {
        return Vec4::from_slice(&radius[first..first + 4]);
    }
    let mut out = [0.0; 4];
    let tail = radius.len().saturating_sub(first).min(4);
    out[..tail].copy_from_slice(&radius[first..first + tail]);
    Vec4::from_array(out)
}

/// The lanes of a block whose path's speed into a surface is at most
/// `rest_dt / dt` at both ends of the step, so all along it (the path's
/// velocity is linear in `s`): `d0`, `d1` are the start and end positions
/// along the normal, `dv` the end velocity along it times `dt`, `travel`
/// the surface's own travel along it over the step. Into the surface at
/// `s = 0`: `travel - (2 (d1 - d0) - dv)`; at `s = 1`: `travel - dv`.
/// Such a path touches the surface no faster than the world's rest speed:
/// the contact rests (restitution 0) and the end-of-step rule resolves it
/// (on the surface at the step's end; between, the path dips at most
/// `rest_dt` into it).
#[inline(always)]
#[must_use]
pub fn resting4(d0: Vec4, d1: Vec4, dv: Vec4, travel: f32, rest_dt: f32) -> BVec4A {
    let travel = Vec4::splat(travel);
    let start = travel - ((d1 - d0) * 2.0 - dv);
    let end = travel - dv;
    // Both at most the limit (a NaN fails: `max` would drop it).
    start.cmple(Vec4::splat(rest_dt)) & end.cmple(Vec4::splat(rest_dt))
}

/// [`resting4`] for a surface at rest (`travel` 0), in fewer operations:
/// `0 - y <= r` is `y >= -r` (negation is exact, and a NaN fails both).
#[inline(always)]
#[must_use]
pub fn resting_at_rest4(d0: Vec4, d1: Vec4, dv: Vec4, rest_dt: f32) -> BVec4A {
    starts_resting4(d0, d1, dv, rest_dt) & dv.cmpge(Vec4::splat(-rest_dt))
}

/// The start half of [`resting_at_rest4`]: the path's speed into the
/// surface at the step's start is at most the rest speed.
#[inline(always)]
#[must_use]
pub fn starts_resting4(d0: Vec4, d1: Vec4, dv: Vec4, rest_dt: f32) -> BVec4A {
    let moved = d1 - d0;
    ((moved + moved) - dv).cmpge(Vec4::splat(-rest_dt))
}

/// The lanes of a block settled against a plane whose normal is an axis
/// (`d0`, `d1`, `dv`: start and end positions and `dt` times the end
/// velocity along the normal; the plane at `offset - travel` at the start
/// and `offset` at the end): certainly clear of it ([`clearance4`]'s bound
/// on one component: `0 * x` terms add +0 or -0, which change no sum, so
/// the same lanes clear), or resting on it ([`resting4`]). As a bit mask.
#[inline(always)]
#[must_use]
pub fn settled_axis4(d0: Vec4, d1: Vec4, dv: Vec4, r: Vec4, offset: f32, travel: f32, rest_dt: f32) -> u8 {
    let clear = clear_axis4(d0, d1, dv, r, offset, travel);
    // Most blocks away from a surface: no need to ask whether they rest.
    if clear == 0b1111 {
        return clear;
    }
    clear | resting4(d0, d1, dv, travel, rest_dt).bitmask() as u8
}

/// The lanes of a block certainly clear of a plane whose normal is an
/// axis, all along the step (the first half of [`settled_axis4`]). A clear
/// lane also ends the step outside the plane by more than its radius, so
/// the end-of-step rule leaves it as it is.
#[inline(always)]
#[must_use]
pub fn clear_axis4(d0: Vec4, d1: Vec4, dv: Vec4, r: Vec4, offset: f32, travel: f32) -> u8 {
    clear_axis_lanes(d0, d1, dv, r, offset, travel).bitmask() as u8
}

/// [`clear_axis4`] as a lane mask, for folding over many blocks without
/// a branch on each.
#[inline(always)]
#[must_use]
pub fn clear_axis_lanes(d0: Vec4, d1: Vec4, dv: Vec4, r: Vec4, offset: f32, travel: f32) -> BVec4A {
    let g0 = d0 - Vec4::splat(offset - travel) - r;
    let g1 = d1 - Vec4::splat(offset) - r;
    let a = dv - (d1 - d0);
    let bound = g0.min(g1) - a.max(Vec4::ZERO) * 0.25;
    // Each term is rounded once or twice at its own magnitude.
    let fixed = (offset.abs() + travel.abs()) * 1e-6 + f32::MIN_POSITIVE;
    let margin = (d0.abs() + d1.abs() + dv.abs() + r) * 1e-6 + Vec4::splat(fixed);
    bound.cmpgt(margin)
}

/// Whether every lane of some blocks is certainly clear of a plane at rest
/// whose normal is an axis, all along the step (`lanes`: each block's
/// `d0`, `d1`, `dv` and radii, as for [`clear_axis_lanes`]): that
/// test's bound taken over all the lanes at once, from the least of their
/// ends' components, the greatest `a`, radius and magnitude, 32 blocks at a
/// time (a chunk that meets the plane stops early). Each operation rounds
/// monotonically, so the bound is no larger than each lane's own, and the
/// margin no smaller: a chunk clear by it has every lane clear by
/// [`clear_axis_lanes`], in about half its operations a block. A
/// non-finite component (their running sum is then not finite) fails it.
#[inline(always)]
#[must_use]
pub fn all_clear_axis(lanes: impl Iterator<Item = (Vec4, Vec4, Vec4, Vec4)>, offset: f32) -> bool {
    let (mut extent, mut taken) = (Extent::EMPTY, 0);
    for lane in lanes {
        extent.add(lane);
        taken += 1;
        if taken == 32 {
            if !extent.clear_of(offset) {
                return false;
            }
            (extent, taken) = (Extent::EMPTY, 0);
        }
    }
    taken == 0 || extent.clear_of(offset)
}

/// Running extremes over lanes, for [`all_clear_axis`].
#[derive(Clone, Copy)]
struct Extent {
    /// Least of `d0` and `d1`.
    low: Vec4,
    /// Greatest of `|d0|`, `|d1|` and `|dv|`.
    size: Vec4,
    /// Greatest `a = dv - (d1 - d0)` and radius.
    a: Vec4,
    r: Vec4,
    /// The sum of every `a` and radius: finite only if every component
    /// added was (a non-finite `d0`, `d1` or `dv` makes `a` non-finite).
    sum: Vec4,
}

impl Extent {
    const EMPTY: Self = Self {
        low: Vec4::INFINITY,
        size: Vec4::ZERO,
        a: Vec4::NEG_INFINITY,
        r: Vec4::ZERO,
        sum: Vec4::ZERO,
    };

    #[inline(always)]
    fn add(&mut self, (d0, d1, dv, r): (Vec4, Vec4, Vec4, Vec4)) {
        self.low = self.low.min(d0.min(d1));
        self.size = self.size.max(d0.abs().max(d1.abs()).max(dv.abs()));
        let a = dv - (d1 - d0);
        self.a = self.a.max(a);
        self.r = self.r.max(r);
        self.sum = self.sum + a + r;
    }

    /// [`clear_axis_lanes`]'s test (at rest: no travel) on the extremes.
    #[inline(always)]
    fn clear_of(&self, offset: f32) -> bool {
        if !self.sum.is_finite() {
            return false;
        }
        let (low, m) = (self.low.min_element(), self.size.max_element());
        let (a, r) = (self.a.max_element(), self.r.max_element());
        let bound = (low - offset - r) - a.max(0.0) * 0.25;
        let fixed = offset.abs() * 1e-6 + f32::MIN_POSITIVE;
        let margin = (m + m + m + r) * 1e-6 + fixed;
        bound > margin
    }
}

/// Over a chunk, `settled[b]` keeps only the lanes of block `b` that
/// certainly stay clear of the plane `n . x = offset` (moving `travel`
/// along `n` over the step), or that rest on it ([`resting4`], `rest_dt`
/// the rest speed times `dt`).
#[allow(clippy::too_many_arguments)]
pub fn settle_plane(
    n: Vec3A,
    offset: f32,
    travel: f32,
    x0: &[Vec3x4],
    x: &[Vec3x4],
    v: &[Vec3x4],
    radius: &[f32],
    dt: f32,
    rest_dt: f32,
    settled: &mut [u8],
) {
    let axis = [n.x, n.y, n.z].iter().position(|c| c.abs() == 1.0);
    let along_axis = axis.is_some_and(|a| (0..3).all(|k| k == a || n[k] == 0.0));
    match axis {
        Some(a) if along_axis => {
            let sign = n[a];
            let pick = |p: &Vec3x4| match a {
                0 => p.x,
                1 => p.y,
                _ => p.z,
            } * sign;
            for (b, mask) in settled.iter_mut().enumerate() {
                let (d0, d1, dv) = (pick(&x0[b]), pick(&x[b]), pick(&v[b]) * dt);
                *mask &= settled_axis4(d0, d1, dv, radius4(radius, b), offset, travel, rest_dt);
            }
        }
        _ => {
            let dot = |p: &Vec3x4| p.x * n.x + p.y * n.y + p.z * n.z;
            for (b, mask) in settled.iter_mut().enumerate() {
                let gap = clearance4(n, offset, travel, &x0[b], &x[b], &v[b], radius4(radius, b), dt);
                let rests = resting4(dot(&x0[b]), dot(&x[b]), dot(&v[b]) * dt, travel, rest_dt);
                *mask &= (gap.cmpgt(Vec4::ZERO) | rests).bitmask() as u8;
            }
        }
    }
}

/// The first `s` in `[0, 1]` where `c + b s + a s^2` falls to zero from
/// `c >= 0`, or `None`.
fn first_root(a: f64, b: f64, c: f64) -> Option<f64> {
    // A non-finite path meets nothing (the step reports it non-finite).
    if !(a.is_finite() && b.is_finite() && c.is_finite()) || c < 0.0 {
        return None;
    }
    let end = c + b + a;
    if end >= 0.0 {
        // Clear at both ends: inside in between only for a path that dips
        // (a > 0) with its lowest point inside the step and below zero.
        if a <= 0.0 {
            return None;
        }
        let lowest = -b / (2.0 * a);
        if !(0.0..1.0).contains(&lowest) || c + (b + a * lowest) * lowest >= 0.0 {
            return None;
        }
    }
    // A root exists in [0, 1]: the smaller root of the quadratic (or the
    // linear one), computed without cancellation.
    let root = if a == 0.0 {
        -c / b
    } else {
        let disc = (b * b - 4.0 * a * c).max(0.0);
        let q = -0.5 * (b + disc.sqrt().copysign(b));
        let (r1, r2) = (q / a, if q == 0.0 { 0.0 } else { c / q });
        let (lo, hi) = if r1 <= r2 { (r1, r2) } else { (r2, r1) };
        if lo >= 0.0 { lo } else { hi }
    };
    (!root.is_nan()).then(|| root.clamp(0.0, 1.0))
}

/// A particle that met more contacts in one step than
/// [`MAX_CONTACT_EVENTS`]: its row and the collider of the last one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct EventOverflow {
    pub row: usize,
    pub collider: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_resting_test_at_rest_is_the_general_one_with_no_travel() {
        let values = [
            0.0f32,
            -0.0,
            1e-3,
            -1e-3,
            0.02,
            -0.02,
            0.5,
            -0.5,
            3.0,
            -7.0,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e-40,
            -1e-40,
        ];
        let mut checked = 0;
        for &d0 in &values {
            for &d1 in &values {
                for &dv in &values {
                    for rest_dt in [0.0, 1e-3, 0.0083] {
                        let (a, b) = (Vec4::splat(d0), Vec4::splat(d1));
                        let general = resting4(a, b, Vec4::splat(dv), 0.0, rest_dt).bitmask();
                        let at_rest = resting_at_rest4(a, b, Vec4::splat(dv), rest_dt).bitmask();
                        assert_eq!(general, at_rest, "d0 {d0}, d1 {d1}, dv {dv}, rest_dt {rest_dt}");
                        checked += usize::from(general != 0);
                    }
                }
            }
        }
        assert!(checked > 100, "some rest: {checked}");
    }

    #[test]
    fn a_chunk_clear_as_a_whole_has_every_lane_clear() {
        let mut seed = 0x1234_5678u32;
        let mut random = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        let specials = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -0.0, 0.0, 1e-40, f32::MAX];
        let (mut whole, mut tried) = (0, 0);
        for case in 0..20_000 {
            let blocks = 1 + case % 40;
            // Spreads from 1e-6 to 100, a power of ten each; a path's bend
            // (`a`) a tenth of it or as large.
            let spreads = [1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 0.1, 1.0, 10.0, 100.0];
            let (height, spread) = (random() * 4.0 - 0.5, spreads[case % spreads.len()]);
            let bend = if (case / 7) % 2 == 0 { 0.1 } else { 1.0 };
            let offset = [0.0, 0.3, -2.0, 1e4][case % 4];
            let point = case % 3 == 0;
            let mut data: Vec<[Vec4; 4]> = (0..blocks)
                .map(|_| {
                    let mut lane = || offset + height + (random() - 0.5) * spread;
                    let d0 = Vec4::new(lane(), lane(), lane(), lane());
                    let d1 = Vec4::new(lane(), lane(), lane(), lane());
                    let dv = d1 - d0 + Vec4::splat((random() - 0.5) * spread * bend);
                    let r = if point { Vec4::ZERO } else { Vec4::splat(random() * 0.1) };
                    [d0, d1, dv, r]
                })
                .collect();
            if case % 50 == 7 {
                let special = specials[(case / 50) % specials.len()];
                let b = case % blocks;
                let which = case % 3;
                data[b][which] = Vec4::new(data[b][which].x, special, data[b][which].z, data[b][which].w);
            }
            let lanes = data.iter().map(|&[d0, d1, dv, r]| (d0, d1, dv, r));
            tried += 1;
            if all_clear_axis(lanes, offset) {
                whole += 1;
                for (b, [d0, d1, dv, r]) in data.iter().enumerate() {
                    assert!(
                        clear_axis_lanes(*d0, *d1, *dv, *r, offset, 0.0).all(),
                        "case {case}, block {b}: {d0} {d1} {dv} {r}, offset {offset}"
                    );
                }
            }
        }
        // Not vacuous: many chunks are clear as a whole, and not all.
        assert!(
            whole > tried / 4 && whole < tried,
            "{whole} of {tried} clear as a whole"
        );
    }

    #[test]
    fn the_path_is_exact_for_constant_acceleration() {
        // x(t) = x0 + v0 t + g t^2 / 2 over dt: the quadratic through the
        // ends with the end velocity is that parabola.
        let (x0, v0, g, dt) = (
            Vec3A::new(1.0, 10.0, -2.0),
            Vec3A::new(3.0, 0.5, 1.0),
            Vec3A::new(0.0, -9.81, 0.0),
            0.125f32,
        );
        let x1 = x0 + v0 * dt + g * (dt * dt / 2.0);
        let v1 = v0 + g * dt;
        let path = StepPath::new(x0, x1, v1, dt);
        for s in [0.0, 0.25, 0.5, 1.0] {
            let t = s * f64::from(dt);
            let exact = x0.as_dvec3() + v0.as_dvec3() * t + g.as_dvec3() * (t * t / 2.0);
            assert!((path.at(s) - exact).length() < 1e-6, "at {s}");
            let v = v0.as_dvec3() + g.as_dvec3() * t;
            assert!((path.velocity(s) - v).length() < 1e-5, "velocity at {s}");
        }
        assert!((path.acceleration() - g.as_dvec3()).length() < 1e-3);
    }

    #[test]
    fn a_falling_ball_meets_the_floor_when_theory_says() {
        // Dropped from rest at height 1 with radius 0.1 under g: it touches
        // y = 0 when 1 - g t^2 / 2 = 0.1, t = sqrt(1.8 / g).
        let g = 9.81f32;
        let touch = (1.8 / f64::from(g)).sqrt();
        let dt = 0.5f32;
        let x1 = Vec3A::new(0.0, 1.0 - g * dt * dt / 2.0, 0.0);
        let path = StepPath::new(Vec3A::Y, x1, Vec3A::new(0.0, -g * dt, 0.0), dt);
        let s = path.first_crossing(DVec3::Y, 0.0, 0.0, 0.1).expect("a contact");
        assert!(
            (s * f64::from(dt) - touch).abs() < 1e-6,
            "{} vs {touch}",
            s * f64::from(dt)
        );
    }

    #[test]
    fn crossings_through_a_thin_wall_at_any_speed_are_found() {
        // A straight path from x = -5 to far past a plane at x = 0.
        for speed in [10.0f32, 100.0, 1e3, 1e4, 1e6] {
            let dt = 1.0 / 60.0;
            let x0 = Vec3A::new(-5.0, 0.0, 0.0);
            let v = Vec3A::new(speed, 0.0, 0.0);
            let path = StepPath::new(x0, x0 + v * dt, v, dt);
            let hit = path.first_crossing(-DVec3::X, 0.0, 0.0, 0.01);
            let wanted = (5.0 - 0.01) / (f64::from(speed) * f64::from(dt));
            match hit {
                Some(s) => assert!(
                    (s - wanted).abs() < 1e-6 * wanted.max(1e-3),
                    "speed {speed}: {s} vs {wanted}"
                ),
                None => assert!(wanted > 1.0, "speed {speed} reaches the wall in the step"),
            }
        }
    }

    #[test]
    fn a_moving_plane_is_met_where_both_are() {
        // A particle at rest at x = 0; a plane with normal -x (free side
        // x <= -offset) moving from x = 2 towards it at 4 m/s over a step
        // of 1 s, 4 m along its normal, to x = -2 (offset 2): the gap
        // 2 - 4 s - 0.5 closes at s = 0.375.
        let path = StepPath::new(Vec3A::ZERO, Vec3A::ZERO, Vec3A::ZERO, 1.0);
        let s = path.first_crossing(-DVec3::X, 2.0, 4.0, 0.5).expect("met");
        assert!((s - 0.375).abs() < 1e-12, "{s}");
    }

    #[test]
    fn clear_paths_and_paths_that_start_inside_have_no_crossing() {
        // Rising away from a floor.
        let path = StepPath::new(Vec3A::Y, Vec3A::Y * 2.0, Vec3A::Y, 1.0);
        assert_eq!(path.first_crossing(DVec3::Y, 0.0, 0.0, 0.1), None);
        // Already through the floor at the start.
        let path = StepPath::new(-Vec3A::Y, -Vec3A::Y * 2.0, -Vec3A::Y, 1.0);
        assert_eq!(path.first_crossing(DVec3::Y, 0.0, 0.0, 0.1), None);
        // A NaN start.
        let path = StepPath::new(Vec3A::splat(f32::NAN), Vec3A::ZERO, Vec3A::ZERO, 1.0);
        assert_eq!(path.first_crossing(DVec3::Y, 0.0, 0.0, 0.1), None);
        // A NaN or infinite end off the normal's axis (0 * NaN is NaN): no
        // crossing, as the fused path's one-component test finds.
        for bad in [f32::NAN, f32::INFINITY] {
            let path = StepPath::new(Vec3A::Y, Vec3A::new(bad, -1.0, 0.0), Vec3A::new(bad, -1.0, 0.0), 1.0);
            assert_eq!(path.first_crossing(DVec3::Y, 0.0, 0.0, 0.1), None);
        }
    }

    #[test]
    fn a_path_that_rises_through_and_back_within_the_step_is_caught() {
        // Thrown up at 6 m/s under g = 10 for 1 s: y = 6 t - 5 t^2 ends at
        // 1, below a ceiling at 1.5 (the free side y <= 1.5), but its top
        // (1.8, at t = 0.6) is above: it meets the ceiling at
        // t = (6 - sqrt 6) / 10.
        let path = StepPath::new(Vec3A::ZERO, Vec3A::new(0.0, 1.0, 0.0), Vec3A::new(0.0, -4.0, 0.0), 1.0);
        let s = path.first_crossing(-DVec3::Y, -1.5, 0.0, 0.0).expect("met");
        assert!((s - (6.0 - 6f64.sqrt()) / 10.0).abs() < 1e-12, "{s}");
    }
}
