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

/// Resolves a contact with a surface of outward normal `n` (unit length) when
/// the signed separation `gap` is negative: the particle is moved back onto
/// the surface and, if approaching, its normal velocity `vn` becomes
/// `-e vn` while its tangential velocity `vt` shrinks by `mu (1 + e) |vn|`
/// (not past zero). Both outcomes are computed and one is selected, so there
/// is no branch to mispredict.
#[inline(always)]
pub(crate) fn resolve(x: &mut Vec3A, v: &mut Vec3A, n: Vec3A, gap: f32, movable: bool, material: Material) {
    let vn = v.dot(n);
    let vt = *v - n * vn;
    let dvn = -(1.0 + material.restitution) * vn.min(0.0);
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
