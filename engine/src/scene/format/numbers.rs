//! Checked numbers: `f32`s of the scene file that are refused while read
//! unless finite (and above zero, not negative or from 0 to 1, as the type
//! says), so the error points at the bad number.

use serde::de::{self, Deserializer};
use serde::{Deserialize, Serialize};

macro_rules! checked_f32 {
    ($(#[$doc:meta])* $name:ident, $check:expr, $expected:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Serialize)]
        pub struct $name(pub f32);

        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let value = f32::deserialize(d)?;
                let check: fn(f32) -> bool = $check;
                if check(value) {
                    Ok(Self(value))
                } else {
                    Err(de::Error::custom(format_args!(concat!("expected ", $expected, ", got {}"), value)))
                }
            }
        }
    };
}

checked_f32!(
    /// A finite number.
    Finite,
    |v| v.is_finite(),
    "a finite number"
);
checked_f32!(
    /// A finite number above zero.
    Positive,
    |v| v.is_finite() && v > 0.0,
    "a finite number above zero"
);
checked_f32!(
    /// A finite number, not negative.
    NonNegative,
    |v| v.is_finite() && v >= 0.0,
    "a finite number, not negative"
);
checked_f32!(
    /// A number in `[0, 1]`.
    Unit,
    |v| (0.0..=1.0).contains(&v),
    "a number from 0 to 1"
);

pub(super) fn zero() -> NonNegative {
    NonNegative(0.0)
}
