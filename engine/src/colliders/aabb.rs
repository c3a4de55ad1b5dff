//! An axis-aligned box: a container particles stay inside, or a solid
//! obstacle they stay out of.

use glam::{DVec3, Vec3, Vec3A, Vec4};
use tickwork_integrators::Vec3x4;

use super::contact::{ContactRule, Material, resolve};
use super::sweep::{StepPath, SweptHit, clearance4, radius4};
use super::{BlockColumns, Collider, ContactColumns};

/// An axis-aligned box from `min` to `max`, at rest or kinematic: moved
/// by its `velocity` each step (a paddle, a lift), never by forces or
/// contacts, and bouncing particles in its own frame, so a moving wall
/// hands them its speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxCollider {
    /// Lower corner (default `(-0.5, -0.5, -0.5)`).
    pub min: Vec3,
    /// Upper corner (default `(0.5, 0.5, 0.5)`: a unit cube at the origin).
    pub max: Vec3,
    /// True: particles are kept inside (a container). False (default):
    /// kept outside (an obstacle).
    pub inside: bool,
    /// Bounce and friction (default [`Material::default`]).
    pub material: Material,
    /// Velocity in m/s (default zero: at rest). Each step first moves the
    /// box by `velocity dt`, then resolves contacts relative to it:
    /// `v' = u + response(v - u)`.
    pub velocity: Vec3,
    /// When contacts are found (default [`ContactRule::EndOfStep`]).
    pub contact: ContactRule,
}

impl Default for BoxCollider {
    /// A solid unit cube at the origin, at rest, of the default material:
    /// so a struct literal names only what it changes.
    fn default() -> Self {
        Self::solid(Vec3::splat(-0.5), Vec3::splat(0.5), Material::default())
    }
}

impl BoxCollider {
    /// A solid box particles stay out of (a brick, a paddle), at rest.
    #[must_use]
    pub fn solid(min: Vec3, max: Vec3, material: Material) -> Self {
        Self {
            min,
            max,
            inside: false,
            material,
            velocity: Vec3::ZERO,
            contact: ContactRule::EndOfStep,
        }
    }

    /// A container particles stay inside (the walls of a room), at rest.
    #[must_use]
    pub fn container(min: Vec3, max: Vec3, material: Material) -> Self {
        Self {
            inside: true,
            ..Self::solid(min, max, material)
        }
    }

    /// The box's centre.
    #[must_use]
    pub fn centre(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Moves the box so its centre is at `centre`, keeping its size (a
    /// teleport: the velocity is unchanged).
    pub fn set_centre(&mut self, centre: Vec3) {
        let half = (self.max - self.min) * 0.5;
        (self.min, self.max) = (centre - half, centre + half);
    }

    /// The corners `(min, max)` where a frame `alpha` steps past the last
    /// one shows a kinematic box: `velocity dt (1 - alpha)` behind its
    /// current place, the position between its last two steps (as
    /// particles are drawn).
    #[must_use]
    pub fn interpolated(&self, alpha: f32, dt: f32) -> (Vec3, Vec3) {
        use crate::interpolation::lerp;
        let step = self.velocity * dt;
        (
            lerp(self.min - step, self.min, alpha),
            lerp(self.max - step, self.max, alpha),
        )
    }

    fn resolve_one(&self, x: &mut Vec3A, v: &mut Vec3A, r: f32, movable: bool, rest: f32) {
        if self.inside {
            self.contain(x, v, r, movable, rest);
        } else {
            self.exclude(x, v, r, movable, rest);
        }
    }

    fn contain(&self, x: &mut Vec3A, v: &mut Vec3A, r: f32, movable: bool, rest: f32) {
        // Clear of all six walls (most particles, most steps): no wall's
        // gap below is negative, so none would act. The gaps are computed
        // as the walls compute them, so the skip changes no result; a NaN
        // fails the test and goes through the walls as before.
        let (min, max, radius) = (Vec3A::from(self.min), Vec3A::from(self.max), Vec3A::splat(r));
        let clear = ((*x - min) - radius).cmpge(Vec3A::ZERO) & ((max - *x) - radius).cmpge(Vec3A::ZERO);
        if !clear.all() {
            self.walls(x, v, r, movable, rest);
        }
    }

    /// Six walls, each a plane facing inwards.
    fn walls(&self, x: &mut Vec3A, v: &mut Vec3A, r: f32, movable: bool, rest: f32) {
        for axis in 0..3 {
            let mut n = Vec3A::ZERO;
            n[axis] = 1.0;
            resolve(x, v, n, x[axis] - self.min[axis] - r, movable, self.material, rest);
            resolve(x, v, -n, self.max[axis] - x[axis] - r, movable, self.material, rest);
        }
    }

    fn exclude(&self, x: &mut Vec3A, v: &mut Vec3A, r: f32, movable: bool, rest: f32) {
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
        if !inside {
            return; // no contact
        }
        // Inside: the gap is minus the depth through the shallowest face.
        resolve(x, v, n, -best, movable, self.material, rest);
    }
}

impl Collider for BoxCollider {
    fn name(&self) -> &'static str {
        "box"
    }

    fn in_step(&self) -> bool {
        self.contact == ContactRule::InStep
    }

    fn settle_blocks(&self, x0: &[Vec3x4], c: BlockColumns<'_>, dt: f32, resolve: bool, settled: &mut [u8]) -> bool {
        // Boxes rest no contact here (their faces and edges are followed):
        // only the lanes clear of the box are settled, and none is resolved.
        let _ = resolve;
        let (x, v, radius) = (&*c.position, &*c.velocity, c.radius);
        // A solid box is missed by a path that stays on the free side of
        // any one face (the contact test asks for a point within the faces);
        // a container's inside by one that stays clear of all six.
        let faces: [(Vec3A, f32, f32); 6] = core::array::from_fn(|k| {
            let (axis, outward) = (k / 2, if k % 2 == 0 { -1.0f32 } else { 1.0 });
            let mut n = Vec3A::ZERO;
            n[axis] = if self.inside { -outward } else { outward };
            let face = if outward < 0.0 { self.min[axis] } else { self.max[axis] };
            (n, n[axis] * face, n.dot(Vec3A::from(self.velocity)) * dt)
        });
        for (b, mask) in settled.iter_mut().enumerate() {
            let r = radius4(radius, b);
            let (mut any, mut all) = (0u8, 0b1111u8);
            for &(n, offset, travel) in &faces {
                let lanes = clearance4(n, offset, travel, &x0[b], &x[b], &v[b], r, dt)
                    .cmpgt(Vec4::ZERO)
                    .bitmask() as u8;
                any |= lanes;
                all &= lanes;
            }
            *mask &= if self.inside { all } else { any };
        }
        false
    }

    fn first_contact(&self, path: &StepPath, radius: f32) -> Option<SweptHit> {
        // Each face is a plane moving with the box; a container's faces
        // face inwards (every crossing is a contact), a solid box's
        // outwards (a crossing is a contact where the path then is within
        // the face, the box grown by the radius).
        let (min, max) = (self.min.as_dvec3(), self.max.as_dvec3());
        let u = self.velocity.as_dvec3();
        let r = f64::from(radius);
        let mut best: Option<SweptHit> = None;
        for axis in 0..3 {
            for outward in [-1.0, 1.0] {
                let mut n = DVec3::ZERO;
                n[axis] = if self.inside { -outward } else { outward };
                // The face's plane n . x = offset at the step's end.
                let face = if outward < 0.0 { min[axis] } else { max[axis] };
                let offset = n[axis] * face;
                let travel = n.dot(u) * path.dt;
                let Some(s) = path.first_crossing(n, offset, travel, r) else {
                    continue;
                };
                if best.is_some_and(|b| b.fraction <= s) {
                    continue;
                }
                if !self.inside {
                    // Within the face: the other axes inside the grown box,
                    // where the box is at that instant.
                    let at = path.at(s) - u * path.dt * (1.0 - s);
                    let within = (0..3)
                        .filter(|&k| k != axis)
                        .all(|k| at[k] >= min[k] - r && at[k] <= max[k] + r);
                    if !within {
                        continue;
                    }
                }
                best = Some(SweptHit {
                    fraction: s,
                    normal: n,
                    offset,
                    velocity: u,
                    material: self.material,
                });
            }
        }
        best
    }

    fn resolve_range(&self, mut c: ContactColumns<'_>) {
        let rest = c.rest_speed;
        if self.velocity == Vec3::ZERO {
            for (x, v, r, w) in c.rows() {
                self.resolve_one(x, v, r, w > 0.0, rest);
            }
            return;
        }
        // Moving: the contact in the box's frame, where it is at rest.
        let u = Vec3A::from(self.velocity);
        for (x, v, r, w) in c.rows() {
            let mut relative = *v - u;
            let before = relative;
            self.resolve_one(x, &mut relative, r, w > 0.0, rest);
            if relative != before {
                *v = relative + u;
            }
        }
    }

    fn advance(&mut self, dt: f32) {
        if self.velocity != Vec3::ZERO {
            let d = self.velocity * dt;
            (self.min, self.max) = (self.min + d, self.max + d);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skipping_particles_clear_of_the_walls_changes_no_bit() {
        let b = BoxCollider {
            min: Vec3::new(-1.0, 0.0, -2.0),
            max: Vec3::new(1.0, 3.0, 2.0),
            inside: true,
            material: Material {
                restitution: 0.4,
                friction: 0.3,
            },
            velocity: Vec3::ZERO,
            contact: ContactRule::EndOfStep,
        };
        // A lattice through and around the box, including points exactly a
        // radius from a wall (the boundary of the skip).
        let mut compared = 0;
        for i in -30..=30 {
            for j in -5..=35 {
                for k in -25..=25 {
                    let x0 = Vec3A::new(i as f32 * 0.05, j as f32 * 0.1, k as f32 * 0.1);
                    let v0 = Vec3A::new(0.3 * i as f32, -0.2 * j as f32, 0.1 * k as f32);
                    for r in [0.0, 0.05, 0.1] {
                        let (mut x1, mut v1) = (x0, v0);
                        let (mut x2, mut v2) = (x0, v0);
                        b.contain(&mut x1, &mut v1, r, true, 0.0);
                        b.walls(&mut x2, &mut v2, r, true, 0.0);
                        assert_eq!(
                            (x1.to_array().map(f32::to_bits), v1.to_array().map(f32::to_bits)),
                            (x2.to_array().map(f32::to_bits), v2.to_array().map(f32::to_bits)),
                            "x {x0}, v {v0}, r {r}"
                        );
                        compared += 1;
                    }
                }
            }
        }
        assert!(compared > 300_000);
    }
}
