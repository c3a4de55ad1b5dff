//! Four 3-vectors stored per axis, `(x0 x1 x2 x3, y0 .., z0 ..)`: a state
//! for stepping four particles per SIMD operation.
//!
//! ```text
//! (a + b).x = a.x + b.x     lane by lane, the same operation a Vec3A does
//! (a * s).x = a.x * s       on each of its components
//! ```
//!
//! Every method file steps these as it steps `Vec3A`, and the explicit
//! methods give, lane for lane, the bits they give on `Vec3A` (tested): the
//! groundwork of a per-axis particle layout. The dot product sums the four
//! lanes, so norms (implicit solvers, adaptive error) see four particles per
//! value: the same accuracy, other rounding.

use core::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

use glam::{Vec3A, Vec4};

use crate::vector::Vector;

/// Four 3-vectors, one [`Vec4`] per axis: `(a + b).x = a.x + b.x` lane by
/// lane, the operations a `Vec3A` does on each component, so a method steps
/// four particles per operation and gives each lane the bits it gives on
/// `Vec3A` (explicit methods; tested). The dot product sums the lanes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec3x4 {
    /// The four x components.
    pub x: Vec4,
    /// The four y components.
    pub y: Vec4,
    /// The four z components.
    pub z: Vec4,
}

impl Vec3x4 {
    /// All lanes zero.
    pub const ZERO: Self = Self {
        x: Vec4::ZERO,
        y: Vec4::ZERO,
        z: Vec4::ZERO,
    };

    /// The same vector in every lane.
    #[must_use]
    pub fn splat(v: Vec3A) -> Self {
        Self {
            x: Vec4::splat(v.x),
            y: Vec4::splat(v.y),
            z: Vec4::splat(v.z),
        }
    }

    /// Four vectors, one per lane.
    #[must_use]
    pub fn from_lanes(lanes: [Vec3A; 4]) -> Self {
        Self {
            x: Vec4::from_array(lanes.map(|v| v.x)),
            y: Vec4::from_array(lanes.map(|v| v.y)),
            z: Vec4::from_array(lanes.map(|v| v.z)),
        }
    }

    /// Lane `k`'s vector (`k < 4`).
    #[inline]
    #[must_use]
    pub fn lane(&self, k: usize) -> Vec3A {
        Vec3A::new(self.x[k], self.y[k], self.z[k])
    }

    /// Sets lane `k`'s vector (`k < 4`), leaving the other lanes as they are.
    #[inline]
    pub fn set_lane(&mut self, k: usize, v: Vec3A) {
        self.x[k] = v.x;
        self.y[k] = v.y;
        self.z[k] = v.z;
    }

    /// The four vectors, lane by lane.
    #[must_use]
    pub fn lanes(self) -> [Vec3A; 4] {
        let (x, y, z) = (self.x.to_array(), self.y.to_array(), self.z.to_array());
        core::array::from_fn(|k| Vec3A::new(x[k], y[k], z[k]))
    }
}

impl Add for Vec3x4 {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl Sub for Vec3x4 {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl Neg for Vec3x4 {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

impl Mul<f32> for Vec3x4 {
    type Output = Self;
    #[inline]
    fn mul(self, s: f32) -> Self {
        let s = Vec4::splat(s);
        Self {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

impl AddAssign for Vec3x4 {
    #[inline]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl SubAssign for Vec3x4 {
    #[inline]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

impl Vector for Vec3x4 {
    type Real = f32;
    const ZERO: Self = Self::ZERO;
    /// Twelve components per value: norms averaged per component stay
    /// comparable with `Vec3A`'s.
    const DIM: usize = 12;

    /// The sum over lanes of each lane's `(x x' + y y') + z z'`.
    #[inline]
    fn dot(self, o: Self) -> f32 {
        let lanes = (self.x * o.x + self.y * o.y) + self.z * o.z;
        lanes.x + lanes.y + lanes.z + lanes.w
    }

    #[inline]
    fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
}
