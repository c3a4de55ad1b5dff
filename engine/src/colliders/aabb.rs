//! An axis-aligned box: a container particles stay inside, or a solid
//! obstacle they stay out of.

use glam::{Vec3, Vec3A};

use super::contact::{Material, resolve};
use super::{Collider, ContactColumns};

/// An axis-aligned box from `min` to `max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxCollider {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
    /// True: particles are kept inside (a container). False: kept outside (an obstacle).
    pub inside: bool,
    /// Bounce and friction.
    pub material: Material,
}

impl BoxCollider {
    fn contain(&self, x: &mut Vec3A, v: &mut Vec3A, r: f32, movable: bool) {
        // Six walls, each a plane facing inwards.
        for axis in 0..3 {
            let mut n = Vec3A::ZERO;
            n[axis] = 1.0;
            resolve(x, v, n, x[axis] - self.min[axis] - r, movable, self.material);
            resolve(x, v, -n, self.max[axis] - x[axis] - r, movable, self.material);
        }
    }

    fn exclude(&self, x: &mut Vec3A, v: &mut Vec3A, r: f32, movable: bool) {
        // Penetration depth through each face; the shallowest face wins.
        let lo = Vec3A::from(self.min) - Vec3A::splat(r);
        let hi = Vec3A::from(self.max) + Vec3A::splat(r);
        let below = *x - lo; // depth through the min faces
        let above = hi - *x; // depth through the max faces
        let mut best = f32::INFINITY;
        let mut n = Vec3A::ZERO;
        for axis in 0..3 {
            if below[axis] < best {
                best = below[axis];
                n = Vec3A::ZERO;
                n[axis] = -1.0;
            }
            if above[axis] < best {
                best = above[axis];
                n = Vec3A::ZERO;
                n[axis] = 1.0;
            }
        }
        let inside = below.min_element() > 0.0 && above.min_element() > 0.0;
        // The gap is minus the depth when inside; positive (no contact) otherwise.
        let gap = if inside { -best } else { 1.0 };
        resolve(x, v, n, gap, movable, self.material);
    }
}

impl Collider for BoxCollider {
    fn name(&self) -> &'static str {
        "box"
    }

    fn resolve_range(&self, mut c: ContactColumns<'_>) {
        for (x, v, r, w) in c.rows() {
            if self.inside {
                self.contain(x, v, r, w > 0.0);
            } else {
                self.exclude(x, v, r, w > 0.0);
            }
        }
    }
}
