//! The small vector abstraction every method is written against.
//!
//! A method only needs to add, subtract and scale states, plus a dot product
//! for the norms of the implicit and adaptive solvers. Keeping the surface this
//! small means one method file serves `f64` (accuracy tests), `f32` and glam's
//! `Vec2`, `Vec3`, `Vec3A`, `DVec2`, `DVec3` (games) with no glam types leaking
//! into the method files.

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// A floating-point scalar: `f32` or `f64`.
pub trait Real:
    Copy
    + Default
    + Debug
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + Send
    + Sync
    + 'static
{
    /// Zero.
    const ZERO: Self;
    /// One.
    const ONE: Self;
    /// Converts from `f64`, rounding to the nearest representable value.
    fn from_f64(value: f64) -> Self;
    /// Converts to `f64` exactly.
    fn to_f64(self) -> f64;
    /// Square root.
    fn sqrt(self) -> Self;
    /// `e^self`, from the `libm` crate: the same bits on every platform
    /// (the platform's own `exp` differs between x86_64 and wasm32).
    fn exp(self) -> Self;
    /// `e^self - 1`, accurate for small arguments (`libm`, as [`Real::exp`]).
    fn exp_m1(self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// True unless NaN or infinite.
    fn is_finite(self) -> bool;
    /// Machine epsilon, used to size finite-difference increments.
    fn epsilon() -> Self;
}

macro_rules! impl_real {
    ($t:ty) => {
        impl Real for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            #[inline]
            fn from_f64(value: f64) -> Self {
                value as $t
            }
            #[inline]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline]
            fn exp(self) -> Self {
                libm::Libm::<$t>::exp(self)
            }
            #[inline]
            fn exp_m1(self) -> Self {
                libm::Libm::<$t>::expm1(self)
            }
            #[inline]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline]
            fn epsilon() -> Self {
                <$t>::EPSILON
            }
        }
    };
}
impl_real!(f32);
impl_real!(f64);

/// A position, velocity or acceleration of one particle.
///
/// Implemented for `f32`, `f64` (one-dimensional problems) and glam's `Vec2`,
/// `Vec3`, `Vec3A`, `DVec2`, `DVec3`.
pub trait Vector:
    Copy
    + Default
    + Debug
    + PartialEq
    + Add<Output = Self>
    + Sub<Output = Self>
    + Neg<Output = Self>
    + Mul<<Self as Vector>::Real, Output = Self>
    + AddAssign
    + SubAssign
    + Send
    + Sync
    + 'static
{
    /// The scalar type (and the type of time).
    type Real: Real;
    /// The zero vector.
    const ZERO: Self;
    /// Number of scalar components (for RMS norms).
    const DIM: usize;
    /// Dot product, for the norms of the implicit and adaptive solvers.
    fn dot(self, other: Self) -> Self::Real;
    /// True when every component is finite.
    fn is_finite(self) -> bool;
    /// Squared Euclidean length.
    #[inline]
    fn length_squared(self) -> Self::Real {
        self.dot(self)
    }
}

impl Vector for f32 {
    type Real = f32;
    const ZERO: Self = 0.0;
    const DIM: usize = 1;
    #[inline]
    fn dot(self, other: Self) -> f32 {
        self * other
    }
    #[inline]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
}

impl Vector for f64 {
    type Real = f64;
    const ZERO: Self = 0.0;
    const DIM: usize = 1;
    #[inline]
    fn dot(self, other: Self) -> f64 {
        self * other
    }
    #[inline]
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
}

macro_rules! impl_glam_vector {
    ($t:ty, $r:ty, $dim:expr) => {
        impl Vector for $t {
            type Real = $r;
            const ZERO: Self = <$t>::ZERO;
            const DIM: usize = $dim;
            #[inline]
            fn dot(self, other: Self) -> $r {
                <$t>::dot(self, other)
            }
            #[inline]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
        }
    };
}
impl_glam_vector!(glam::Vec2, f32, 2);
impl_glam_vector!(glam::Vec3, f32, 3);
impl_glam_vector!(glam::Vec3A, f32, 3);
impl_glam_vector!(glam::DVec2, f64, 2);
impl_glam_vector!(glam::DVec3, f64, 3);

/// `Real::from_f64` for a constant, shorter at call sites in formulas.
#[inline]
pub(crate) fn c<R: Real>(value: f64) -> R {
    R::from_f64(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axpy<V: Vector>(a: V, s: V::Real, b: V) -> V {
        a * s + b
    }

    #[test]
    fn every_vector_type_adds_scales_and_dots() {
        assert_eq!(axpy(2.0f64, 3.0, 1.0), 7.0);
        assert_eq!(axpy(2.0f32, 3.0, 1.0), 7.0);
        assert_eq!(axpy(glam::Vec2::ONE, 2.0, glam::Vec2::X), glam::Vec2::new(3.0, 2.0));
        assert_eq!(glam::Vec3A::ONE.length_squared(), 3.0);
        assert_eq!(glam::DVec3::new(1.0, 2.0, 2.0).length_squared(), 9.0);
        assert_eq!(<glam::DVec2 as Vector>::DIM, 2);
        assert!(!Vector::is_finite(glam::Vec3::new(0.0, f32::NAN, 0.0)));
    }
}
