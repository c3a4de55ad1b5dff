//! The contact response shared by the colliders.

use glam::{BVec3A, Vec3A};

/// How a surface responds to an impact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Fraction of the normal speed kept by a bounce, in `[0, 1]`: kinetic
    /// energy of the normal motion is kept in the fraction `e^2` (default: `0.5`).
    pub restitution: f32,
    /// Coulomb friction coefficient `mu`, not negative: the tangential speed
    /// drops by at most `mu` times the normal speed change (default: `0.0`).
    pub friction: f32,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            restitution: 0.5,
            friction: 0.0,
        }
    }
}

/// When a plane or a box finds its contacts.
///
/// A fixed step is "a mere sequence of instants, without the precise
/// instant of bouncing": found only at the end of a step, a contact moves a
/// particle that ended inside back to the surface, so a particle faster
/// than a wall is thick per step passes through it, and an elastic bounce
/// gains the energy of the depth it was found at. Found inside the step,
/// it happens where the step's path meets the surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ContactRule {
    /// At the end of the step: a particle found inside is moved back to
    /// the surface and its velocity reflected there. The older rule, kept
    /// for comparison (the lab shows both); a particle may pass through a
    /// wall thinner than its travel in one step, and bounces are off by
    /// the depth found.
    EndOfStep,
    /// Inside the step (default): the first instant the step's path (the curve the
    /// renderer draws, exact for constant acceleration) meets the surface,
    /// the bounce there, and the rest of the step along the method's own
    /// path from it, again looking for contacts (up to
    /// [`MAX_CONTACT_EVENTS`](crate::colliders::MAX_CONTACT_EVENTS) a
    /// particle a step). No tunnelling at any speed; an elastic bounce
    /// keeps its height. An approach slower than
    /// [`WorldConfig::rest_speed`](crate::WorldConfig) does not bounce: the
    /// particle comes to rest on the surface (no Zeno cascade of ever
    /// smaller bounces). A particle already inside at the start of the step
    /// is resolved at its end, as [`EndOfStep`](Self::EndOfStep) does.
    #[default]
    InStep,
}

/// The response of a contact with a surface of outward unit normal `n`,
/// on the velocity relative to the surface: the normal part `vn`, if
/// approaching, becomes `-e vn`, and the tangential part shrinks by
/// `mu (1 + e) |vn|` (not past zero). `resolve` applies the same rule.
#[must_use]
pub(crate) fn bounce(v: glam::DVec3, n: glam::DVec3, restitution: f64, friction: f64) -> glam::DVec3 {
    let vn = v.dot(n);
    let vt = v - n * vn;
    let dvn = -(1.0 + restitution) * vn.min(0.0);
    let speed2 = vt.length_squared();
    let brake = friction * dvn;
    let keep_t = if brake * brake >= speed2 {
        0.0
    } else {
        (1.0 - brake / speed2.sqrt().max(f64::MIN_POSITIVE)).max(0.0)
    };
    vt * keep_t + n * (vn + dvn)
}

/// Resolves a contact with a surface of outward normal `n` (unit length) when
/// the signed separation `gap` is negative: the particle is moved back onto
/// the surface and, if approaching, its normal velocity `vn` becomes
/// `-e vn` while its tangential velocity `vt` shrinks by `mu (1 + e) |vn|`
/// (not past zero). An approach no faster than `rest` (m/s; 0 for the
/// end-of-step rule) rests: `e = 0`. Both outcomes are computed and one is
/// selected, so there is no branch to mispredict.
#[inline(always)]
pub(crate) fn resolve(x: &mut Vec3A, v: &mut Vec3A, n: Vec3A, gap: f32, movable: bool, material: Material, rest: f32) {
    let vn = v.dot(n);
    let vt = *v - n * vn;
    let e = if vn >= -rest { 0.0 } else { material.restitution };
    let dvn = -(1.0 + e) * vn.min(0.0);
    let speed2 = vt.length_squared();
    let brake = material.friction * dvn;
    // Friction stops the sliding outright when mu dvn >= |v_t|.
    let keep_t = if brake * brake >= speed2 {
        0.0
    } else {
        (1.0 - brake / speed2.sqrt().max(f32::MIN_POSITIVE)).max(0.0)
    };
    let v_after = vt * keep_t + n * (vn + dvn);
    let x_after = *x - n * gap;
    let hit = BVec3A::splat(gap < 0.0 && movable);
    *x = Vec3A::select(hit, x_after, *x);
    *v = Vec3A::select(hit, v_after, *v);
}
