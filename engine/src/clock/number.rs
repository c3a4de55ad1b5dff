//! Numbers in messages: every error of the engine that shows a value shows
//! it through [`Number`], so a huge or tiny one reads as `1e308`, not 309
//! digits.

use core::fmt;

/// A number as a person reads it in a message: plain when it is of an
/// ordinary size, in scientific notation when huge or tiny (`1e308`, not 309
/// digits).
#[derive(Clone, Copy, Debug)]
pub struct Number(pub f64);

impl From<f32> for Number {
    /// Through its shortest decimal form, so that `3e38_f32` reads `3e38`,
    /// not the `3.0000000054977558e38` of its exact widening.
    fn from(v: f32) -> Self {
        Self(v.to_string().parse().unwrap_or(f64::from(v)))
    }
}

impl fmt::Display for Number {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        if v.is_finite() && v != 0.0 && !(1e-4..1e7).contains(&v.abs()) {
            write!(f, "{v:e}")
        } else {
            write!(f, "{v}")
        }
    }
}
