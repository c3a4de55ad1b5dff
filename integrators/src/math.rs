//! Transcendental functions with the same bits on every platform.
//!
//! `+ - * /` and `sqrt` are IEEE operations: correctly rounded, so x86_64
//! and wasm32 agree to the bit. `sin`, `cos`, `exp`, `powf` and friends are
//! not: Rust's `f32::sin` calls the platform's C library on native targets
//! and another implementation on wasm32, and they differ in the last bits,
//! which a simulation then grows into different states. These functions
//! come from the [`libm`] crate (pure Rust, compiled the same everywhere),
//! so a step that uses them gives the same checksum natively and in the
//! browser. The workspace's clippy configuration refuses `f32::sin` and the
//! others in Tickwork's own code; a game that wants its checksums to match
//! across platforms calls these too (`tickwork::math::sin(angle)`).
//!
//! ```
//! use tickwork_integrators::math;
//!
//! let (s, c) = math::sin_cos(0.5_f32);
//! assert!((s * s + c * c - 1.0).abs() < 1e-6);
//! assert_eq!(math::exp(0.0_f64), 1.0);
//! ```

use libm::Libm;

/// `f32` or `f64`: the types these functions take. Sealed: implemented for
/// those two only.
pub trait Float: Copy + sealed::Sealed {
    #[doc(hidden)]
    fn libm_sin(self) -> Self;
    #[doc(hidden)]
    fn libm_cos(self) -> Self;
    #[doc(hidden)]
    fn libm_tan(self) -> Self;
    #[doc(hidden)]
    fn libm_asin(self) -> Self;
    #[doc(hidden)]
    fn libm_acos(self) -> Self;
    #[doc(hidden)]
    fn libm_atan2(self, x: Self) -> Self;
    #[doc(hidden)]
    fn libm_exp(self) -> Self;
    #[doc(hidden)]
    fn libm_expm1(self) -> Self;
    #[doc(hidden)]
    fn libm_ln(self) -> Self;
    #[doc(hidden)]
    fn libm_log2(self) -> Self;
    #[doc(hidden)]
    fn libm_log10(self) -> Self;
    #[doc(hidden)]
    fn libm_pow(self, y: Self) -> Self;
    #[doc(hidden)]
    fn libm_cbrt(self) -> Self;
    #[doc(hidden)]
    fn libm_hypot(self, y: Self) -> Self;
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

macro_rules! impl_float {
    ($t:ty) => {
        impl Float for $t {
            fn libm_sin(self) -> Self {
                Libm::<$t>::sin(self)
            }
            fn libm_cos(self) -> Self {
                Libm::<$t>::cos(self)
            }
            fn libm_tan(self) -> Self {
                Libm::<$t>::tan(self)
            }
            fn libm_asin(self) -> Self {
                Libm::<$t>::asin(self)
            }
            fn libm_acos(self) -> Self {
                Libm::<$t>::acos(self)
            }
            fn libm_atan2(self, x: Self) -> Self {
                Libm::<$t>::atan2(self, x)
            }
            fn libm_exp(self) -> Self {
                Libm::<$t>::exp(self)
            }
            fn libm_expm1(self) -> Self {
                Libm::<$t>::expm1(self)
            }
            fn libm_ln(self) -> Self {
                Libm::<$t>::log(self)
            }
            fn libm_log2(self) -> Self {
                Libm::<$t>::log2(self)
            }
            fn libm_log10(self) -> Self {
                Libm::<$t>::log10(self)
            }
            fn libm_pow(self, y: Self) -> Self {
                Libm::<$t>::pow(self, y)
            }
            fn libm_cbrt(self) -> Self {
                Libm::<$t>::cbrt(self)
            }
            fn libm_hypot(self, y: Self) -> Self {
                Libm::<$t>::hypot(self, y)
            }
        }
    };
}
impl_float!(f32);
impl_float!(f64);

/// Sine of `x` radians.
#[inline]
pub fn sin<T: Float>(x: T) -> T {
    x.libm_sin()
}

/// Cosine of `x` radians.
#[inline]
pub fn cos<T: Float>(x: T) -> T {
    x.libm_cos()
}

/// `(sin x, cos x)`.
#[inline]
pub fn sin_cos<T: Float>(x: T) -> (T, T) {
    (x.libm_sin(), x.libm_cos())
}

/// Tangent of `x` radians.
#[inline]
pub fn tan<T: Float>(x: T) -> T {
    x.libm_tan()
}

/// Arcsine, in radians.
#[inline]
pub fn asin<T: Float>(x: T) -> T {
    x.libm_asin()
}

/// Arccosine, in radians.
#[inline]
pub fn acos<T: Float>(x: T) -> T {
    x.libm_acos()
}

/// The angle of the point `(x, y)`, in radians, in `[-pi, pi]`.
#[inline]
pub fn atan2<T: Float>(y: T, x: T) -> T {
    y.libm_atan2(x)
}

/// `e^x`.
#[inline]
pub fn exp<T: Float>(x: T) -> T {
    x.libm_exp()
}

/// `e^x - 1`, accurate for small `x`.
#[inline]
pub fn exp_m1<T: Float>(x: T) -> T {
    x.libm_expm1()
}

/// Natural logarithm.
#[inline]
pub fn ln<T: Float>(x: T) -> T {
    x.libm_ln()
}

/// Base-2 logarithm.
#[inline]
pub fn log2<T: Float>(x: T) -> T {
    x.libm_log2()
}

/// Base-10 logarithm.
#[inline]
pub fn log10<T: Float>(x: T) -> T {
    x.libm_log10()
}

/// `x^y`.
#[inline]
pub fn powf<T: Float>(x: T, y: T) -> T {
    x.libm_pow(y)
}

/// Cube root.
#[inline]
pub fn cbrt<T: Float>(x: T) -> T {
    x.libm_cbrt()
}

/// `sqrt(x^2 + y^2)` without overflow or underflow on the way.
#[inline]
pub fn hypot<T: Float>(x: T, y: T) -> T {
    x.libm_hypot(y)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values every correct libm gives to the last bit (exact or
    /// correctly-rounded cases), so the module's wiring is checked without
    /// depending on which libm the platform has.
    #[test]
    fn exact_cases() {
        assert_eq!(sin(0.0_f32), 0.0);
        assert_eq!(cos(0.0_f64), 1.0);
        assert_eq!(exp(0.0_f32), 1.0);
        assert_eq!(exp_m1(0.0_f64), 0.0);
        assert_eq!(ln(1.0_f64), 0.0);
        assert_eq!(log2(8.0_f32), 3.0);
        assert_eq!(log10(1000.0_f64), 3.0);
        assert_eq!(powf(2.0_f64, 10.0), 1024.0);
        assert_eq!(cbrt(27.0_f32), 3.0);
        assert_eq!(hypot(3.0_f64, 4.0), 5.0);
        assert_eq!(atan2(0.0_f32, 1.0), 0.0);
        assert_eq!(asin(0.0_f64), 0.0);
        assert_eq!(acos(1.0_f32), 0.0);
        assert_eq!(tan(0.0_f64), 0.0);
    }

    /// The functions are libm's own, bit for bit (what makes them the same
    /// on every platform), and agree with the platform's to a few ulps.
    #[test]
    fn libm_bits_close_to_the_platform() {
        for k in 0..1000 {
            let x = -20.0 + 0.04 * f64::from(k);
            assert_eq!(sin(x).to_bits(), libm::sin(x).to_bits());
            assert_eq!(exp(x as f32).to_bits(), libm::expf(x as f32).to_bits());
            #[allow(clippy::disallowed_methods)]
            let platform = x.sin();
            assert!((sin(x) - platform).abs() <= 4.0 * f64::EPSILON * platform.abs().max(1.0));
        }
    }
}
