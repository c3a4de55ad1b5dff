//! The fixed step as an exact rational number of seconds.

use core::fmt;
use std::time::Duration;

use super::ClockError;

/// The length of one fixed step, stored exactly as `numer / denom` seconds.
///
/// Why rational: `1/60` has no exact binary representation, so summing an
/// `f64` step drifts (after an hour at 60 Hz the sum is off by microseconds
/// and, worse, depends on how the sum was grouped). The clock counts whole
/// steps instead and converts `ticks * numer / denom` only when asked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rate {
    numer: u64,
    denom: u64,
}

impl Default for Rate {
    /// 60 Hz, the display rate most games are tuned for.
    fn default() -> Self {
        Self { numer: 1, denom: 60 }
    }
}

/// The accepted steps, for every constructor: from a microsecond (a million
/// steps per second) to an hour. Outside it a rate is an error that says
/// so, never a silent substitute (a tiny rate once became 1 Hz).
const RANGE_HZ: &str = "from 1/3600 (a step of an hour) to 1e6 (a step of a microsecond) steps per second";
const RANGE_SECONDS: &str = "from 1e-6 (a microsecond) to 3600 (an hour) seconds";

impl Rate {
    /// The most steps per second.
    pub const MAX_HZ: f64 = 1e6;
    /// The longest step, in seconds.
    pub const MAX_STEP_SECONDS: f64 = 3600.0;

    /// `hz` steps per second, exactly.
    ///
    /// # Errors
    /// [`ClockError::InvalidRate`] for zero or more than [`Rate::MAX_HZ`].
    pub fn hz(hz: u32) -> Result<Self, ClockError> {
        if hz == 0 || f64::from(hz) > Self::MAX_HZ {
            return Err(ClockError::InvalidRate {
                what: "rate in Hz",
                value: f64::from(hz),
                expected: RANGE_HZ,
            });
        }
        Ok(Self::reduced(1, u64::from(hz)))
    }

    /// A fractional rate such as 59.94 Hz, approximated by the closest fraction
    /// with a denominator of at most one million (exact for decimal rates).
    ///
    /// # Errors
    /// [`ClockError::InvalidRate`] for a rate that is not finite, or outside
    /// `1/3600 ..= 1e6` steps per second.
    pub fn hz_f64(hz: f64) -> Result<Self, ClockError> {
        let error = ClockError::InvalidRate {
            what: "rate in Hz",
            value: hz,
            expected: RANGE_HZ,
        };
        if !(hz.is_finite() && (1.0 / Self::MAX_STEP_SECONDS..=Self::MAX_HZ).contains(&hz)) {
            return Err(error);
        }
        let (p, q) = best_fraction(hz, 1_000_000).ok_or(error)?;
        // A step is 1/hz = q/p seconds.
        Ok(Self::reduced(q, p))
    }

    /// A step of `seconds`, approximated by the closest fraction with a
    /// denominator of at most one million (exact for `0.01`, `1/128` ...).
    ///
    /// # Errors
    /// [`ClockError::InvalidRate`] for a step that is not finite, shorter
    /// than a microsecond or longer than an hour.
    pub fn seconds(seconds: f64) -> Result<Self, ClockError> {
        let error = ClockError::InvalidRate {
            what: "step in seconds",
            value: seconds,
            expected: RANGE_SECONDS,
        };
        if !(seconds.is_finite() && (1.0 / Self::MAX_HZ..=Self::MAX_STEP_SECONDS).contains(&seconds)) {
            return Err(error);
        }
        let (p, q) = best_fraction(seconds, 1_000_000).ok_or(error)?;
        Ok(Self::reduced(p, q))
    }

    /// A step of exactly `duration` (nanosecond resolution).
    ///
    /// # Errors
    /// [`ClockError::InvalidRate`] for a duration shorter than a microsecond
    /// or longer than an hour.
    pub fn duration(duration: Duration) -> Result<Self, ClockError> {
        let nanos = duration.as_nanos();
        if !(1_000..=3_600_000_000_000).contains(&nanos) {
            return Err(ClockError::InvalidRate {
                what: "step duration in seconds",
                value: duration.as_secs_f64(),
                expected: RANGE_SECONDS,
            });
        }
        Ok(Self::reduced(nanos as u64, 1_000_000_000))
    }

    /// Numerator and denominator of the step in seconds, in lowest terms.
    #[must_use]
    pub fn fraction(self) -> (u64, u64) {
        (self.numer, self.denom)
    }

    /// The step in seconds (rounded to `f64`).
    #[must_use]
    pub fn step_seconds(self) -> f64 {
        self.numer as f64 / self.denom as f64
    }

    /// Steps per second (rounded to `f64`).
    #[must_use]
    pub fn hz_value(self) -> f64 {
        self.denom as f64 / self.numer as f64
    }

    fn reduced(numer: u64, denom: u64) -> Self {
        let g = gcd(u128::from(numer), u128::from(denom)) as u64;
        Self {
            numer: numer / g,
            denom: denom / g,
        }
    }
}

impl fmt::Display for Rate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.numer == 1 {
            write!(f, "{} Hz", self.denom)
        } else {
            write!(f, "{:.6} Hz ({}/{} s)", self.hz_value(), self.numer, self.denom)
        }
    }
}

/// Greatest common divisor (Euclid).
pub(crate) fn gcd(mut a: u128, mut b: u128) -> u128 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a.max(1)
}

/// The fraction `p/q` closest to `x > 0` with `q <= max_denom`, from the
/// continued-fraction convergents (exact for terminating decimals); `None`
/// when no such fraction is above zero (`x` below `1 / max_denom`).
fn best_fraction(x: f64, max_denom: u64) -> Option<(u64, u64)> {
    let (mut p0, mut q0, mut p1, mut q1) = (0u64, 1u64, 1u64, 0u64);
    let mut rest = x;
    for _ in 0..64 {
        let a = rest.floor();
        if a > u32::MAX as f64 {
            break;
        }
        let a = a as u64;
        let (p2, q2) = (
            a.saturating_mul(p1).saturating_add(p0),
            a.saturating_mul(q1).saturating_add(q0),
        );
        if q2 > max_denom {
            break;
        }
        (p0, q0, p1, q1) = (p1, q1, p2, q2);
        let frac = rest - a as f64;
        if frac < 1e-12 || (p1 as f64 / q1 as f64 - x).abs() <= x * 1e-15 {
            break;
        }
        rest = 1.0 / frac;
    }
    if q1 == 0 {
        // x is above u32::MAX: never reached, the callers' ranges exclude it.
        return None;
    }
    (p1 > 0).then_some((p1, q1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rates_are_exact_fractions() {
        assert_eq!(Rate::hz(60).map(Rate::fraction), Ok((1, 60)));
        assert_eq!(Rate::seconds(0.01).map(Rate::fraction), Ok((1, 100)));
        assert_eq!(Rate::seconds(1.0 / 128.0).map(Rate::fraction), Ok((1, 128)));
        assert_eq!(Rate::hz_f64(59.94).map(Rate::fraction), Ok((50, 2997)));
        assert_eq!(
            Rate::duration(Duration::from_millis(20)).map(Rate::fraction),
            Ok((1, 50))
        );
        assert_eq!(Rate::default().fraction(), (1, 60));
    }

    #[test]
    fn bad_rates_are_errors() {
        assert!(Rate::hz(0).is_err());
        assert!(Rate::hz_f64(f64::NAN).is_err());
        assert!(Rate::hz_f64(-60.0).is_err());
        assert!(Rate::seconds(0.0).is_err());
        assert!(Rate::seconds(f64::INFINITY).is_err());
        let message = Rate::hz_f64(-60.0).map(|_| ()).unwrap_err().to_string();
        assert_eq!(
            message,
            "invalid rate in Hz: -60 (accepted: from 1/3600 (a step of an hour) to 1e6 (a step of a microsecond) steps per second)"
        );
    }

    #[test]
    fn rates_outside_the_range_are_errors_that_state_it_never_a_substitute() {
        // 5e-7 Hz once became 1 Hz silently.
        for hz in [5e-7, 1e7, 1e308, f64::MIN_POSITIVE] {
            let error = Rate::hz_f64(hz).map(|_| ()).unwrap_err().to_string();
            assert!(error.contains("accepted: from 1/3600"), "{error}");
        }
        assert_eq!(
            Rate::hz_f64(1e308).map(|_| ()).unwrap_err().to_string(),
            "invalid rate in Hz: 1e308 (accepted: from 1/3600 (a step of an hour) to 1e6 (a step of a microsecond) steps per second)"
        );
        for seconds in [1e-7, 3601.0, -0.0] {
            let error = Rate::seconds(seconds).map(|_| ()).unwrap_err().to_string();
            assert!(
                error.contains("accepted: from 1e-6 (a microsecond) to 3600 (an hour) seconds"),
                "{error}"
            );
        }
        assert!(Rate::hz(2_000_000).is_err());
        assert!(Rate::duration(Duration::from_nanos(999)).is_err());
        // The edges are accepted, exactly.
        assert_eq!(Rate::hz_f64(1.0 / 3600.0).map(Rate::fraction), Ok((3600, 1)));
        assert_eq!(Rate::seconds(1e-6).map(Rate::fraction), Ok((1, 1_000_000)));
        assert_eq!(Rate::hz_f64(1e6).map(Rate::fraction), Ok((1, 1_000_000)));
    }
}
