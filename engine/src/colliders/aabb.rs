//! An axis-aligned box: a container particles stay inside, or a solid
//! obstacle they stay out of.

use glam::{DVec3, Vec3, Vec3A, Vec4};
use tickwork_integrators::Vec3x4;

use super::contact::{ContactRule, Material, resolve};
use super::sweep::{StepPath, SweptHit, clear_axis_lanes, radius4, resting4};
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
    /// When contacts are found (default [`ContactRule::InStep`]).
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
            contact: ContactRule::InStep,
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

/// One face of a box as a block's lanes see it: its axis, its normal's
/// sign along it (towards the free side: outward for a solid box, inward
/// for a container), its plane `n . x = offset` at the step's end and its
/// travel `n . u dt` over the step, and the lanes' start and end
/// components and `dt` times their end velocity along the normal.
struct Face {
    axis: usize,
    /// The max face of its axis (else the min face).
    max: bool,
    offset: f32,
    travel: f32,
    d0: Vec4,
    d1: Vec4,
    dv: Vec4,
}

impl Face {
    /// The lanes certainly clear of the face's plane all along the step
    /// ([`clear_axis_lanes`]: [`clearance4`](super::sweep::clearance4)'s
    /// bound on the one component).
    fn clear(&self, r: Vec4) -> u8 {
        clear_axis_lanes(self.d0, self.d1, self.dv, r, self.offset, self.travel).bitmask() as u8
    }

    /// The lanes whose path's speed into the face is at most `rest_dt / dt`
    /// at both ends, so all along it ([`resting4`]; the face at rest).
    fn resting(&self, rest_dt: f32) -> u8 {
        resting4(self.d0, self.d1, self.dv, 0.0, rest_dt).bitmask() as u8
    }
}

/// Component `axis` of a block's lanes.
fn component(p: &Vec3x4, axis: usize) -> Vec4 {
    match axis {
        0 => p.x,
        1 => p.y,
        _ => p.z,
    }
}

impl BoxCollider {
    /// Face `k` (`k / 2` its axis, `k % 2` 0 for the min face, 1 for the
    /// max) as the lanes `(x0, x1, v1)` of a block see it over a step of
    /// `dt`.
    fn face(&self, k: usize, (x0, x1, v1): (&Vec3x4, &Vec3x4, &Vec3x4), dt: f32) -> Face {
        let (axis, max) = (k / 2, k % 2 == 1);
        let outward = if max { 1.0f32 } else { -1.0 };
        let sign = if self.inside { -outward } else { outward };
        let plane = if max { self.max[axis] } else { self.min[axis] };
        Face {
            axis,
            max,
            offset: sign * plane,
            travel: sign * self.velocity[axis] * dt,
            d0: component(x0, axis) * sign,
            d1: component(x1, axis) * sign,
            dv: component(v1, axis) * (sign * dt),
        }
    }

    /// The lanes of a block (start positions, end positions and velocities)
    /// resting on `face` of this solid box at rest: the path's speed into
    /// the face at most `rest_dt / dt` at both ends ([`resting4`]), in the
    /// face's half of the box all along (so it cannot have come through
    /// the opposite face), within the box grown by the radius on the other
    /// two axes all along (so it meets no side face), and at the end no
    /// deeper through this face than through any other (so the end-of-step
    /// rule resolves it against this face, with restitution 0). The
    /// in-step rule would rest it on this face at its instant; the
    /// end-of-step rule rests it on the face at the step's end instead.
    fn resting_on_face(
        &self,
        face: &Face,
        (x0, x1, v1): (&Vec3x4, &Vec3x4, &Vec3x4),
        r: Vec4,
        dt: f32,
        rest_dt: f32,
    ) -> u8 {
        let Face { axis, d0, d1, dv, .. } = *face;
        let half = face.offset - (self.max[axis] - self.min[axis]) * 0.5;
        // The path is (1 - s) x0 + s x1 - A s (1 - s): within A / 4 of
        // its ends' range.
        let bend = dv - (d1 - d0);
        let lowest = d0.min(d1) - bend.max(Vec4::ZERO) * 0.25;
        let mut lanes = face.resting(rest_dt) & (lowest.cmpgt(Vec4::splat(half)).bitmask() as u8);
        if lanes == 0 {
            return 0;
        }
        // Its depth through this face at the end, as the end-of-step rule
        // computes it (`hi - x` or `x - lo` of the box grown by r), less
        // than through the opposite face (ties go to the min face there).
        let depth = (Vec4::splat(face.offset) + r) - d1;
        let (lo, hi) = (Vec4::splat(self.min[axis]) - r, Vec4::splat(self.max[axis]) + r);
        let end = component(x1, axis);
        let opposite = if face.max { end - lo } else { hi - end };
        lanes &= opposite.cmpgt(depth).bitmask() as u8;
        for b in (0..3).filter(|&b| b != axis) {
            let (lo, hi) = (Vec4::splat(self.min[b]) - r, Vec4::splat(self.max[b]) + r);
            let (e0, e1) = (component(x0, b), component(x1, b));
            let bend = component(v1, b) * dt - (e1 - e0);
            let (low, high) = (e0.min(e1), e0.max(e1));
            // Inside the grown slab all along, and the side faces deeper
            // at the end than this one.
            let inside = (low - bend.max(Vec4::ZERO) * 0.25).cmpgt(lo)
                & (high - bend.min(Vec4::ZERO) * 0.25).cmplt(hi)
                & (e1 - lo).cmpgt(depth)
                & (hi - e1).cmpgt(depth);
            lanes &= inside.bitmask() as u8;
        }
        lanes
    }
}

impl Collider for BoxCollider {
    fn name(&self) -> &'static str {
        "box"
    }

    fn gpu_form(&self) -> super::GpuCollider {
        super::GpuCollider::Box {
            min: self.min,
            max: self.max,
            inside: self.inside,
            velocity: self.velocity,
            material: self.material,
        }
    }

    fn in_step(&self) -> bool {
        self.contact == ContactRule::InStep
    }

    fn settle_blocks(&self, x0: &[Vec3x4], c: BlockColumns<'_>, dt: f32, resolve: bool, settled: &mut [u8]) -> bool {
        // The lanes clear of the box, and (a box at rest) those resting on
        // a face; none is resolved here.
        let _ = resolve;
        let (x, v, radius) = (&*c.position, &*c.velocity, c.radius);
        let rest_dt = c.rest_speed * dt;
        let at_rest = self.velocity == Vec3::ZERO;
        const ALL: u8 = 0b1111;
        // The face that settled the last block goes first (neighbours are
        // usually alike: resting on the same face, or clear of it), and
        // where the last block rested on it, its resting test goes first:
        // a resting lane is never clear of the face it rests on, so the
        // clear test would settle none (the same lanes either way: the
        // union of both tests).
        let mut first = 0;
        let mut rested = false;
        for (b, mask) in settled.iter_mut().enumerate() {
            let r = radius4(radius, b);
            let ends = (&x0[b], &x[b], &v[b]);
            let lanes = if self.inside {
                // A container's inside is left by no path that stays clear
                // of all six walls, or rests on some of them and is clear of
                // the others (slowly: none is passed, and a fast approach
                // to another wall is neither).
                let mut lanes = ALL;
                for k in 0..6 {
                    let face = self.face(k, ends, dt);
                    let mut wall = face.clear(r);
                    if wall != ALL && at_rest {
                        wall |= face.resting(rest_dt);
                    }
                    lanes &= wall;
                    if lanes == 0 {
                        break;
                    }
                }
                lanes
            } else {
                // A solid box is missed by a path that stays on the free
                // side of any one face (the contact test asks for a point
                // within the faces), or rests on one.
                let mut lanes = 0;
                let mut on_face = false;
                for j in 0..6 {
                    let k = (first + j) % 6;
                    let face = self.face(k, ends, dt);
                    if j == 0 && rested {
                        lanes = self.resting_on_face(&face, ends, r, dt, rest_dt);
                        if lanes == ALL {
                            on_face = true;
                            break;
                        }
                    }
                    lanes |= face.clear(r);
                    if at_rest && lanes != ALL {
                        lanes |= self.resting_on_face(&face, ends, r, dt, rest_dt);
                        on_face = lanes == ALL;
                    }
                    if lanes == ALL {
                        first = k;
                        break;
                    }
                }
                rested = at_rest && on_face;
                lanes
            };
            *mask &= lanes;
        }
        false
    }

    fn first_contact(&self, path: &StepPath, radius: f32) -> Option<SweptHit> {
        self.first_contact_kept(path, radius, &mut |_| true)
    }

    fn first_contact_kept(
        &self,
        path: &StepPath,
        radius: f32,
        keep: &mut dyn FnMut(&SweptHit) -> bool,
    ) -> Option<SweptHit> {
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
                    let at = path.at(s) + u * path.dt * (1.0 - s);
                    let within = (0..3)
                        .filter(|&k| k != axis)
                        .all(|k| at[k] >= min[k] - r && at[k] <= max[k] + r);
                    if !within {
                        continue;
                    }
                }
                let hit = SweptHit {
                    fraction: s,
                    normal: n,
                    offset,
                    velocity: u,
                    material: self.material,
                };
                if keep(&hit) {
                    best = Some(hit);
                }
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
