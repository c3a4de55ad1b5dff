//! The time line: which exact simulated time each tick starts at, across
//! changes of rate.

use super::rate::{Rate, gcd};
use super::wide::mul_div_round;

/// Nanoseconds in a second: a rate's units are `1 / (1e9 denom)` seconds.
const NANOS: u128 = 1_000_000_000;

/// Maps ticks to exact simulated times: `epoch + (tick - epoch_tick) * step`.
///
/// The epoch moves when the rate changes, so time stays continuous. It is
/// kept in the units of the rate in force, `1 / (1e9 denom)` seconds (the
/// accumulator's), re-based at each change: exact within a rate, and
/// rounded to the nearest new unit at a change, so the time differs from
/// the sum of its steps by at most half a nanosecond per change. Keeping the epoch as an exact
/// fraction instead made its denominator the least common multiple of every
/// rate ever used, which overflowed `u128` after a dozen changes between
/// prime rates (the control panel's rate box makes one per edit) and then
/// made simulated time jump.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timeline {
    pub(super) epoch_units: u128,
    pub(super) epoch_tick: u64,
    pub(super) rate: Rate,
}

impl Timeline {
    /// Units of `1 / (1e9 denom)` seconds in one step: `numer * 1e9`.
    pub(super) fn step_units(&self) -> u128 {
        u128::from(self.rate.fraction().0) * NANOS
    }

    /// Units per second: `1e9 denom`.
    fn units_per_second(&self) -> u128 {
        u128::from(self.rate.fraction().1) * NANOS
    }

    /// The exact simulated time at the start of `tick`, as `(numer, denom)` seconds.
    #[must_use]
    pub fn exact_time_of(&self, tick: u64) -> (u128, u128) {
        let k = u128::from(tick.saturating_sub(self.epoch_tick));
        // Saturates only past 10^29 s of simulated time.
        let numer = self.epoch_units.saturating_add(k.saturating_mul(self.step_units()));
        let denom = self.units_per_second();
        let g = gcd(numer, denom);
        (numer / g, denom / g)
    }

    /// The simulated time at the start of `tick`, in seconds.
    #[must_use]
    pub fn time_of(&self, tick: u64) -> f64 {
        let (n, d) = self.exact_time_of(tick);
        // Split to keep full precision for large numerators.
        (n / d) as f64 + (n % d) as f64 / d as f64
    }

    /// The same time line from `tick` on at `rate`: the epoch is the time
    /// reached at `tick`, re-based into the new rate's units.
    pub(super) fn rebased(&self, tick: u64, rate: Rate) -> Self {
        let (numer, denom) = self.exact_time_of(tick);
        let units_per_second = u128::from(rate.fraction().1) * NANOS;
        Self {
            epoch_units: mul_div_round(numer, units_per_second, denom),
            epoch_tick: tick,
            rate,
        }
    }

    /// The step in force.
    #[must_use]
    pub fn rate(&self) -> Rate {
        self.rate
    }
}
