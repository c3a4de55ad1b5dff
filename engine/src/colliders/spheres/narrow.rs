//! The sphere grid's narrow phase: a window on the gathered columns, whose
//! spheres are tested against their candidate partners and resolved one
//! pair at a time (Gauss-Seidel), with restitution, positions separated in
//! proportion to inverse mass and an impulse along the line of centres.
//!
//! The gathered positions are a column per axis. On the dense grid the
//! narrow phase tests four candidates with one comparison against the
//! sphere as it stands; the first that touches is resolved and the test
//! resumes after it, so the result is that of testing one at a time, bit
//! for bit (the hashed and hierarchical grids test one at a time).

use glam::{Vec3A, Vec4};

use crate::colliders::contact::Material;

/// A touching pair found while reporting: sorted indices, the contact
/// point, the normal towards `i`, the impulse `i` received.
#[derive(Clone, Copy)]
pub(super) struct SortedPair {
    pub(super) i: u32,
    pub(super) j: u32,
    pub(super) point: Vec3A,
    pub(super) normal: Vec3A,
    pub(super) impulse: f32,
}

/// The gathered positions and velocities of sorted particles `base ..`, which
/// one slab (or the whole grid) resolves; radii and inverse masses are all
/// of them, read only.
pub(super) struct Window<'a> {
    pub(super) base: usize,
    pub(super) x: &'a mut [f32],
    pub(super) y: &'a mut [f32],
    pub(super) z: &'a mut [f32],
    pub(super) velocity: &'a mut [Vec3A],
    pub(super) radius: &'a [f32],
    pub(super) inverse_mass: &'a [f32],
    pub(super) restitution: f32,
    pub(super) tested: usize,
    pub(super) contacts: usize,
    /// Where touching pairs are recorded, when reporting (serial only).
    pub(super) pairs: Option<&'a mut Vec<SortedPair>>,
}

/// One sphere's state while its partners are visited, held in registers:
/// only its own pairs write it, and they are all resolved in a row.
#[derive(Clone, Copy)]
pub(super) struct Sphere {
    pub(super) position: Vec3A,
    pub(super) velocity: Vec3A,
    pub(super) radius: f32,
    pub(super) inverse_mass: f32,
}

impl Sphere {
    /// Position x, y, z and radius, each in all four lanes, to test four
    /// candidates with.
    #[inline]
    pub(super) fn splat(&self) -> [Vec4; 4] {
        [self.position.x, self.position.y, self.position.z, self.radius].map(Vec4::splat)
    }
}

impl<'a> Window<'a> {
    /// All the gathered columns, from sorted index 0. Takes the fields, not
    /// the collider, so the grid's other buffers stay readable beside it.
    pub(super) fn whole(
        [x, y, z]: [&'a mut [f32]; 3],
        velocity: &'a mut [Vec3A],
        radius: &'a [f32],
        inverse_mass: &'a [f32],
        material: Material,
        pairs: Option<&'a mut Vec<SortedPair>>,
    ) -> Self {
        Window {
            base: 0,
            x,
            y,
            z,
            velocity,
            radius,
            inverse_mass,
            restitution: material.restitution,
            tested: 0,
            contacts: 0,
            pairs,
        }
    }

    /// The position of window row `l`.
    #[inline]
    pub(super) fn position(&self, l: usize) -> Vec3A {
        Vec3A::new(self.x[l], self.y[l], self.z[l])
    }

    /// Sorted particle `i`, to visit its partners with.
    #[inline]
    pub(super) fn take(&self, i: usize) -> Sphere {
        Sphere {
            position: self.position(i - self.base),
            velocity: self.velocity[i - self.base],
            radius: self.radius[i],
            inverse_mass: self.inverse_mass[i],
        }
    }

    /// Writes sorted particle `i` back after its partners were visited.
    #[inline]
    pub(super) fn put(&mut self, i: usize, a: Sphere) {
        let l = i - self.base;
        (self.x[l], self.y[l], self.z[l]) = (a.position.x, a.position.y, a.position.z);
        self.velocity[l] = a.velocity;
    }

    /// Resolves the contact of sorted particles `i` and `j`, if they touch.
    #[inline]
    pub(super) fn pair(&mut self, i: usize, j: usize) {
        self.tested += 1;
        let mut a = self.take(i);
        self.pair_with(&mut a, i, j);
        self.put(i, a);
    }

    /// Resolves sphere `a` (sorted particle `i`) against the candidates
    /// `partners`, in order. Four candidates are tested at once against
    /// `a` as it stands; the first that touches is resolved (which moves
    /// `a`) and the test goes on from the candidate after it, so every
    /// candidate is tested against the same `a` as one at a time would,
    /// with the same arithmetic: the same bits, with up to a quarter of the
    /// branches.
    #[inline]
    pub(super) fn partners(&mut self, a: &mut Sphere, i: usize, partners: core::ops::Range<usize>) {
        let (mut j, end) = (partners.start, partners.end);
        self.tested += end.saturating_sub(j);
        // Sorted index one past the window: no lane may read beyond it.
        let window_end = self.base + self.x.len();
        let mut own = a.splat();
        while j < end {
            if j + 4 > window_end {
                self.pair_with(a, i, j);
                own = a.splat();
                j += 1;
                continue;
            }
            let l = j - self.base;
            let d = |column: &[f32], own: Vec4| Vec4::from_slice(&column[l..l + 4]) - own;
            let (dx, dy, dz) = (d(self.x, own[0]), d(self.y, own[1]), d(self.z, own[2]));
            // (x^2 + y^2) + z^2, in the order `Vec3A::length_squared` adds.
            let dist2 = dx * dx + dy * dy + dz * dz;
            let reach = own[3] + Vec4::from_slice(&self.radius[j..j + 4]);
            let lanes =
                (dist2.cmplt(reach * reach) & dist2.cmpne(Vec4::ZERO)).bitmask() & ((1u32 << (end - j).min(4)) - 1);
            if lanes == 0 {
                j += 4;
            } else {
                let k = lanes.trailing_zeros() as usize;
                self.pair_with(a, i, j + k);
                own = a.splat();
                j += k + 1;
            }
        }
    }

    /// Resolves the contact of sphere `a` (sorted particle `i`, taken from
    /// the window) with sorted particle `j`, if they touch.
    #[inline]
    pub(super) fn pair_with(&mut self, a: &mut Sphere, i: usize, j: usize) {
        let lj = j - self.base;
        let d = self.position(lj) - a.position;
        let reach = a.radius + self.radius[j];
        let dist2 = d.length_squared();
        // Touching only at `dist2 < reach^2`, so a NaN distance or reach is
        // no contact; a zero distance has no normal.
        let touching = dist2 < reach * reach && dist2 != 0.0;
        if !touching {
            return;
        }
        let (wi, wj) = (a.inverse_mass, self.inverse_mass[j]);
        let w = wi + wj;
        if w == 0.0 {
            return;
        }
        self.contacts += 1;
        let dist = dist2.sqrt();
        let normal = d / dist;
        let push = normal * ((reach - dist) / w);
        a.position -= push * wi;
        let b = self.position(lj) + push * wj;
        (self.x[lj], self.y[lj], self.z[lj]) = (b.x, b.y, b.z);
        let vn = (self.velocity[lj] - a.velocity).dot(normal);
        let mut magnitude = 0.0;
        if vn < 0.0 {
            magnitude = -(1.0 + self.restitution) * vn / w;
            let impulse = normal * magnitude;
            a.velocity -= impulse * wi;
            self.velocity[lj] += impulse * wj;
        }
        if let Some(pairs) = self.pairs.as_deref_mut() {
            pairs.push(SortedPair {
                i: i as u32,
                j: j as u32,
                point: a.position + normal * a.radius,
                normal: -normal,
                impulse: magnitude,
            });
        }
    }

    /// Splits at sorted index `at` into the windows before and from it.
    pub(super) fn split(self, at: usize) -> (Self, Self) {
        let (x0, x1) = self.x.split_at_mut(at - self.base);
        let (y0, y1) = self.y.split_at_mut(at - self.base);
        let (z0, z1) = self.z.split_at_mut(at - self.base);
        let (v0, v1) = self.velocity.split_at_mut(at - self.base);
        // Pairs are recorded by one window only: the right one, which the
        // odd slabs continue in (reporting solves serially, never splitting
        // both halves to solve at once).
        let Window {
            base,
            radius,
            inverse_mass,
            restitution,
            pairs,
            ..
        } = self;
        let left = Window {
            base,
            x: x0,
            y: y0,
            z: z0,
            velocity: v0,
            radius,
            inverse_mass,
            restitution,
            tested: 0,
            contacts: 0,
            pairs: None,
        };
        let right = Window {
            base: at,
            x: x1,
            y: y1,
            z: z1,
            velocity: v1,
            radius,
            inverse_mass,
            restitution,
            tested: 0,
            contacts: 0,
            pairs,
        };
        (left, right)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Sorted columns of `n` spheres crowded into a 0.3 m cube: most pairs
    /// touch, some sit at the same point (no normal), some are NaN.
    fn columns(n: usize, seed: &[f32]) -> (Vec<[f32; 3]>, Vec<Vec3A>, Vec<f32>, Vec<f32>) {
        let at = |k: usize| seed[k % seed.len()] * (1.0 + k as f32 * 0.37).fract();
        let position = (0..n)
            .map(|k| match k % 17 {
                5 => [f32::NAN, 0.0, 0.0],
                9 => [0.1, 0.1, 0.1],
                _ => [at(3 * k), at(3 * k + 1), at(3 * k + 2)].map(|x| x * 0.3),
            })
            .collect();
        let velocity = (0..n).map(|k| Vec3A::new(at(k), -at(k + 1), 0.5)).collect();
        let radius = (0..n).map(|k| 0.03 + 0.04 * at(k + 2)).collect();
        let inverse_mass = (0..n).map(|k| if k % 11 == 3 { 0.0 } else { 1.0 + at(k) }).collect();
        (position, velocity, radius, inverse_mass)
    }

    proptest! {
        /// Four candidates tested at once give the bits, contacts and
        /// counts of one candidate at a time, in every range: ones that end
        /// inside a group of four, at the window's end, or are empty; in
        /// the whole columns or either half of a split (the left half ends
        /// before the columns do: no lane may read past it).
        #[test]
        fn four_at_a_time_is_one_at_a_time(
            seed in prop::collection::vec(0.0f32..1.0, 1..40),
            n in 2usize..40,
            spans in prop::collection::vec((0usize..40, 0usize..12), 1..60),
            cut in 0usize..40,
            left in any::<bool>(),
        ) {
            let (position, mut velocity, radius, inverse_mass) = columns(n, &seed);
            let mut axes = [0, 1, 2].map(|k| position.iter().map(|p| p[k]).collect::<Vec<f32>>());
            let mut one_axes = axes.clone();
            let mut one_velocity = velocity.clone();
            let material = Material { restitution: 0.3, friction: 0.0 };
            let [x, y, z] = &mut axes;
            let mut four = Window::whole([x, y, z], &mut velocity, &radius, &inverse_mass, material, None);
            let [x, y, z] = &mut one_axes;
            let mut one = Window::whole([x, y, z], &mut one_velocity, &radius, &inverse_mass, material, None);
            let at = cut % n;
            let (lo, hi) = match (at, left) {
                (0, _) => (0, n),
                (at, true) => (0, at),
                (at, false) => (at, n),
            };
            if at > 0 {
                let (l, r) = four.split(at);
                four = if left { l } else { r };
                let (l, r) = one.split(at);
                one = if left { l } else { r };
            }
            for (i, len) in spans {
                let i = lo + i % (hi - lo);
                let partners = i + 1..(i + 1 + len).min(hi);
                let mut a = four.take(i);
                four.partners(&mut a, i, partners.clone());
                four.put(i, a);
                let mut a = one.take(i);
                one.tested += partners.len();
                for j in partners {
                    one.pair_with(&mut a, i, j);
                }
                one.put(i, a);
            }
            prop_assert_eq!((four.tested, four.contacts), (one.tested, one.contacts));
            let bits = |w: &Window<'_>| {
                (0..w.x.len())
                    .flat_map(|l| [w.x[l], w.y[l], w.z[l], w.velocity[l].x, w.velocity[l].y, w.velocity[l].z])
                    .map(f32::to_bits)
                    .collect::<Vec<u32>>()
            };
            prop_assert_eq!(bits(&four), bits(&one));
        }
    }
}
