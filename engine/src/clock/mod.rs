//! The fixed-step clock: frame durations in, whole steps and an interpolation
//! factor out.
//!
//! This is the accumulator of Glenn Fiedler's "Fix Your Timestep!": real time
//! is poured into an accumulator each frame, whole fixed steps are drained
//! from it, and what is left (less than one step) becomes `alpha`, the factor
//! the renderer blends the previous and current states with. The simulation
//! therefore always advances by the same `dt`, whatever the display does, and
//! its results do not depend on frame timing.
//!
//! Three things make it drift-free and safe:
//! - **Integer time.** The accumulator counts integer units of
//!   `1 / (1e9 * denom)` seconds, where the step is `numer / denom` seconds
//!   ([`Rate`]); simulated time is `ticks * numer / denom` computed exactly.
//!   After N steps simulated time is exactly N steps, never an `f64` sum.
//! - **A hitch guard.** A frame longer than `max_frame_time` (a debugger
//!   pause, a stall) counts as `max_frame_time`, and no frame runs more than
//!   `max_steps_per_frame` steps, so a slow step cannot cause more steps next
//!   frame (the "spiral of death"). What happens to the excess is a
//!   [`HitchPolicy`].
//! - **Time scale changes the count, not the size.** Slow motion runs fewer
//!   steps of the same `dt`, so a run in slow motion ends in the same state
//!   as a run at full speed.
//!
//! The clock knows nothing of the world: it is pure and is driven by any
//! [`TimeSource`] (real time, a fixed display cadence, a recorded sequence).

mod rate;
mod time_source;

use core::fmt;
use std::time::Duration;

pub use rate::Rate;
pub use time_source::{FixedCadence, JitteryCadence, RealTime, RecordedFrames, TimeSource};

use rate::gcd;

const NANOS: u128 = 1_000_000_000;

/// What to do with time that the step cap did not let a frame simulate.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum HitchPolicy {
    /// Throw it away (default): after a stall the game continues at normal
    /// speed from where it was, and the frame reports the time as dropped.
    #[default]
    Drop,
    /// Throw it away and slow the game down: the clock lowers an internal
    /// speed factor to what the cap could simulate (never below
    /// [`FixedClock::MIN_DILATION`], so it always recovers), so following
    /// frames run smoothly in slow motion instead of in bursts of
    /// `max_steps_per_frame`, then recovers by 5% per frame once frames fit
    /// again.
    SlowDown,
    /// Keep it as a debt and run it over the next frames, at most
    /// `max_steps_per_frame` steps per frame, until the game has caught up.
    /// The debt is bounded: beyond [`FixedClock::MAX_DEBT_FRAMES`] frames'
    /// worth of capped steps it is dropped (and reported as dropped).
    CatchUp,
}

/// Settings of a [`FixedClock`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClockConfig {
    /// The fixed step (default: 60 Hz).
    pub rate: Rate,
    /// Longest frame duration counted, in seconds; longer frames count as this
    /// (default: `0.25`, as bevy_time's maximum delta; at most
    /// [`FixedClock::MAX_FRAME_TIME`]).
    pub max_frame_time: f64,
    /// Most steps one frame may run (default: `8`, as Godot's
    /// `max_physics_steps_per_frame`).
    pub max_steps_per_frame: u32,
    /// What happens to time beyond the step cap (default: [`HitchPolicy::Drop`]).
    pub hitch_policy: HitchPolicy,
    /// Game seconds per real second: 0.25 is slow motion, 2 fast forward
    /// (default: `1.0`; from [`FixedClock::MIN_TIME_SCALE`] to
    /// [`FixedClock::MAX_TIME_SCALE`]). Changes how many steps run, never the
    /// step size.
    pub time_scale: f64,
}

impl Default for ClockConfig {
    fn default() -> Self {
        Self {
            rate: Rate::default(),
            max_frame_time: 0.25,
            max_steps_per_frame: 8,
            hitch_policy: HitchPolicy::Drop,
            time_scale: 1.0,
        }
    }
}

/// A rejected frame duration or setting.
#[derive(Clone, Debug, PartialEq)]
pub enum ClockError {
    /// A frame duration that is negative, NaN or infinite.
    InvalidFrameTime {
        /// The value given, in seconds.
        value: f64,
    },
    /// A rate or step that is zero, negative, not finite or out of range.
    InvalidRate {
        /// Which quantity.
        what: &'static str,
        /// The value given.
        value: f64,
        /// The accepted range.
        expected: &'static str,
    },
    /// A setting out of range.
    InvalidSetting {
        /// The field.
        field: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        expected: &'static str,
    },
}

impl fmt::Display for ClockError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidFrameTime { value } => {
                write!(
                    f,
                    "invalid frame duration: {} s (must be finite and not negative)",
                    Number(*value)
                )
            }
            Self::InvalidRate { what, value, expected } => {
                write!(f, "invalid {what}: {} (accepted: {expected})", Number(*value))
            }
            Self::InvalidSetting { field, value, expected } => {
                write!(
                    f,
                    "invalid clock setting {field}: {} (expected {expected})",
                    Number(*value)
                )
            }
        }
    }
}

impl std::error::Error for ClockError {}

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
    epoch_units: u128,
    epoch_tick: u64,
    rate: Rate,
}

/// `a * m / d` for `d > 0`, rounded to nearest (halves up), exact for any
/// `u128` operands (the result saturates only past `u128`). The units of
/// a rate from [`Rate::hz_f64`] pass 2^64 (a step's denominator reaches
/// about 1e12, times 1e9 units a second), so `rest * m` needs 256 bits.
fn mul_div_round(a: u128, m: u128, d: u128) -> u128 {
    let (whole, rest) = (a / d, a % d);
    // rest < d, so rest * m / d < m fits; only the product is wide.
    whole
        .saturating_mul(m)
        .saturating_add(wide_div_round(widening_mul(rest, m), d))
}

/// The 256-bit product `a * b`, as its `(high, low)` 128-bit halves.
fn widening_mul(a: u128, b: u128) -> (u128, u128) {
    const LOW: u128 = u64::MAX as u128;
    let (a1, a0) = (a >> 64, a & LOW);
    let (b1, b0) = (b >> 64, b & LOW);
    let (p00, p01, p10, p11) = (a0 * b0, a0 * b1, a1 * b0, a1 * b1);
    // Below 3 * 2^64: no overflow.
    let middle = (p00 >> 64) + (p01 & LOW) + (p10 & LOW);
    let low = (p00 & LOW) | (middle << 64);
    let high = p11 + (p01 >> 64) + (p10 >> 64) + (middle >> 64);
    (high, low)
}

/// `(n + d / 2) / d` for a 256-bit `n = (high, low)` below `d * (2^128 - 1)`
/// (so the quotient fits `u128`): binary long division, 128 rounds, run
/// only when the rate changes.
fn wide_div_round((high, low): (u128, u128), d: u128) -> u128 {
    let (low, carry) = low.overflowing_add(d / 2);
    // n + d/2 < d * 2^128, so the high half stays below d.
    let mut remainder = high + u128::from(carry);
    let mut quotient = 0u128;
    for bit in (0..128).rev() {
        // remainder < d; doubling it may pass 2^128 (`overflow`), and then
        // it is surely at least d, and the difference fits again.
        let overflow = remainder >> 127 == 1;
        remainder = (remainder << 1) | ((low >> bit) & 1);
        quotient <<= 1;
        if overflow || remainder >= d {
            remainder = remainder.wrapping_sub(d);
            quotient |= 1;
        }
    }
    quotient
}

impl Timeline {
    /// Units of `1 / (1e9 denom)` seconds in one step: `numer * 1e9`.
    fn step_units(&self) -> u128 {
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
    fn rebased(&self, tick: u64, rate: Rate) -> Self {
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

/// One fixed step to run: which tick, at what time, with what `dt`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedStep {
    /// The step's index since the clock started (0, 1, 2, ...).
    pub tick: u64,
    /// Simulated time at the start of the step, in seconds.
    pub time: f64,
    /// The step, in seconds.
    pub dt: f64,
}

/// What one call to [`FixedClock::advance`] decided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Fixed steps to run this frame.
    pub steps: u32,
    /// Interpolation factor in `[0, 1)`: how far real time is past the last
    /// step, as a fraction of a step. Render `previous + alpha * (current - previous)`.
    pub alpha: f64,
    /// Real seconds this frame that will never be simulated (hitches and the
    /// step cap under [`HitchPolicy::Drop`] and [`HitchPolicy::SlowDown`]).
    pub dropped: f64,
    /// Simulated seconds per real second this frame (1 at normal speed, the
    /// time scale in slow motion, lower when the hitch guard acted; 0 for a
    /// zero-length frame).
    pub effective_speed: f64,
    /// The tick of the first step to run.
    pub first_tick: u64,
    timeline: Timeline,
}

impl Frame {
    /// The steps to run, in order, with their ticks and times.
    pub fn fixed_steps(&self) -> impl Iterator<Item = FixedStep> + '_ {
        let dt = self.timeline.rate.step_seconds();
        (self.first_tick..self.first_tick + u64::from(self.steps)).map(move |tick| FixedStep {
            tick,
            time: self.timeline.time_of(tick),
            dt,
        })
    }
}

/// The fixed-step accumulator clock. See the [module docs](self).
#[derive(Clone, Debug)]
pub struct FixedClock {
    config: ClockConfig,
    timeline: Timeline,
    /// Accumulated, not yet simulated time, in units of `1 / (1e9 * denom)` s.
    accumulator: u128,
    tick: u64,
    paused: bool,
    single_steps: u32,
    /// Speed factor of [`HitchPolicy::SlowDown`], in `(0, 1]`.
    dilation: f64,
    /// Scaled time accepted into the accumulator and not dropped, in ns.
    accepted_nanos: u128,
    /// Real time dropped in total, in seconds.
    dropped_total: f64,
    /// Steps the last frame ran (what [`defer`](Self::defer) may give back).
    last_steps: u32,
}

impl Default for FixedClock {
    fn default() -> Self {
        Self::from_valid(ClockConfig::default())
    }
}

impl FixedClock {
    /// The largest time scale: a million game seconds per real second. The
    /// limit keeps the accumulator's integer arithmetic exact (1e30 once
    /// overflowed it); raise the rate rather than the scale past it.
    pub const MAX_TIME_SCALE: f64 = 1e6;
    /// The smallest time scale (pause instead of scaling towards zero).
    pub const MIN_TIME_SCALE: f64 = 1e-6;
    /// The longest `max_frame_time`, in seconds: an hour.
    pub const MAX_FRAME_TIME: f64 = 3600.0;
    /// The shortest `max_frame_time`, in seconds: a nanosecond, the clock's
    /// resolution (a shorter cap would count every frame as nothing).
    pub const MIN_FRAME_TIME: f64 = 1e-9;
    /// The lowest speed factor [`HitchPolicy::SlowDown`] goes to, so that it
    /// always recovers (an extreme time scale once drove it to 0 for good).
    pub const MIN_DILATION: f64 = 1e-3;
    /// [`HitchPolicy::CatchUp`] keeps at most this many frames' worth of
    /// capped steps (`max_steps_per_frame` each) as debt; the rest is dropped.
    pub const MAX_DEBT_FRAMES: u128 = 60;

    /// A clock with `config`, at tick 0 and time 0.
    ///
    /// # Errors
    /// [`ClockError::InvalidSetting`] for a `max_frame_time` outside
    /// [`MIN_FRAME_TIME`](Self::MIN_FRAME_TIME) to
    /// [`MAX_FRAME_TIME`](Self::MAX_FRAME_TIME),
    /// a `time_scale` outside [`MIN_TIME_SCALE`](Self::MIN_TIME_SCALE) to
    /// [`MAX_TIME_SCALE`](Self::MAX_TIME_SCALE), or a zero `max_steps_per_frame`.
    pub fn new(config: ClockConfig) -> Result<Self, ClockError> {
        check_max_frame_time(config.max_frame_time)?;
        check_time_scale(config.time_scale)?;
        if config.max_steps_per_frame == 0 {
            return Err(ClockError::InvalidSetting {
                field: "max_steps_per_frame",
                value: 0.0,
                expected: "at least 1",
            });
        }
        Ok(Self::from_valid(config))
    }

    fn from_valid(config: ClockConfig) -> Self {
        Self {
            config,
            timeline: Timeline {
                epoch_units: 0,
                epoch_tick: 0,
                rate: config.rate,
            },
            accumulator: 0,
            tick: 0,
            paused: false,
            single_steps: 0,
            dilation: 1.0,
            accepted_nanos: 0,
            dropped_total: 0.0,
            last_steps: 0,
        }
    }

    /// Feeds one frame's real duration, in seconds, and says how many steps to run.
    ///
    /// # Errors
    /// [`ClockError::InvalidFrameTime`] for a negative, NaN or infinite
    /// duration; the clock is unchanged.
    pub fn advance(&mut self, real_seconds: f64) -> Result<Frame, ClockError> {
        if !real_seconds.is_finite() || real_seconds < 0.0 {
            return Err(ClockError::InvalidFrameTime { value: real_seconds });
        }
        let first_tick = self.tick;
        let step_units = self.step_units();
        let cap = self.config.max_steps_per_frame;
        if self.paused {
            // Queued single steps run at most `cap` a frame, like any steps.
            let steps = self.single_steps.min(cap);
            self.single_steps -= steps;
            self.tick += u64::from(steps);
            return Ok(self.frame(steps, 0.0, real_seconds, first_tick));
        }
        let counted = real_seconds.min(self.config.max_frame_time);
        let mut dropped = real_seconds - counted;
        let speed = self.config.time_scale * self.dilation;
        // Straight into accumulator units (1 / (1e9 denom) s), rounded: a
        // display frame of exactly 1/30 s is then exactly two 60 Hz steps,
        // where whole nanoseconds (33 333 333) would fall a third of a
        // nanosecond short and run 1, 2, 2, 1, ... steps. Bounded: at most
        // an hour times a million times 1e9 times a denominator below 2^32,
        // about 2^95 units.
        let (_, denom) = self.timeline.rate.fraction();
        let units = (counted * speed * 1e9 * denom as f64).round() as u128;
        self.accumulator = self.accumulator.saturating_add(units);
        self.accepted_nanos = self.accepted_nanos.saturating_add(units.div_ceil(u128::from(denom)));

        let needed = self.accumulator / step_units;
        let cap = u128::from(cap);
        let steps = needed.min(cap);
        self.accumulator -= steps * step_units;
        if needed > cap {
            let excess_steps = match self.config.hitch_policy {
                // Keep the debt, up to its bound.
                HitchPolicy::CatchUp => (needed - cap).saturating_sub(cap.saturating_mul(Self::MAX_DEBT_FRAMES)),
                HitchPolicy::Drop | HitchPolicy::SlowDown => needed - cap,
            };
            let excess = excess_steps * step_units;
            self.accumulator -= excess;
            let excess_nanos = excess / u128::from(denom);
            self.accepted_nanos = self.accepted_nanos.saturating_sub(excess_nanos);
            dropped += excess_nanos as f64 / 1e9 / speed;
            if self.config.hitch_policy == HitchPolicy::SlowDown {
                self.dilation = (self.dilation * cap as f64 / needed as f64).max(Self::MIN_DILATION);
            }
        } else if self.config.hitch_policy == HitchPolicy::SlowDown {
            self.dilation = (self.dilation * 1.05).min(1.0);
        }
        self.dropped_total += dropped;
        self.tick += steps as u64;
        Ok(self.frame(steps as u32, dropped, real_seconds, first_tick))
    }

    /// [`advance`](Self::advance) with a [`Duration`] (which cannot be negative or NaN).
    pub fn advance_duration(&mut self, real: Duration) -> Frame {
        let frame = self.advance(real.as_secs_f64());
        frame.unwrap_or_else(|_| unreachable!("a Duration is finite and not negative"))
    }

    /// Runs `n` steps now, outside the real-time flow (for tests and tools):
    /// the accumulator and alpha are untouched.
    pub fn step(&mut self, n: u32) -> Frame {
        let first_tick = self.tick;
        self.tick += u64::from(n);
        self.frame(n, 0.0, 0.0, first_tick)
    }

    /// Gives back `steps` of the last frame's steps that were not run (a
    /// rollback session waiting for the other player): their time goes back
    /// into the accumulator and is due again next frame, up to one frame's
    /// cap of steps (`max_steps_per_frame`); past that it is dropped, as a
    /// hitch would be. Returns the real seconds dropped.
    pub fn defer(&mut self, steps: u32) -> f64 {
        // Only the last frame's steps: earlier ones have run.
        let steps = steps.min(self.last_steps);
        self.last_steps -= steps;
        self.tick -= u64::from(steps);
        let step_units = self.step_units();
        let before = self.accumulator;
        let wanted = before + u128::from(steps) * step_units;
        // At most a frame's cap of steps stays due (or what was due before,
        // catch-up debt included).
        let bound = (u128::from(self.config.max_steps_per_frame) * step_units + before % step_units).max(before);
        self.accumulator = wanted.min(bound);
        let dropped_units = wanted - self.accumulator;
        let (_, denom) = self.timeline.rate.fraction();
        let dropped_nanos = dropped_units / u128::from(denom);
        self.accepted_nanos = self.accepted_nanos.saturating_sub(dropped_nanos);
        let dropped = dropped_nanos as f64 / 1e9 / (self.config.time_scale * self.dilation);
        self.dropped_total += dropped;
        dropped
    }

    fn frame(&mut self, steps: u32, dropped: f64, real_seconds: f64, first_tick: u64) -> Frame {
        self.last_steps = steps;
        let simulated = f64::from(steps) * self.timeline.rate.step_seconds();
        Frame {
            steps,
            alpha: self.alpha(),
            dropped,
            effective_speed: if real_seconds > 0.0 {
                simulated / real_seconds
            } else {
                0.0
            },
            first_tick,
            timeline: self.timeline,
        }
    }

    fn step_units(&self) -> u128 {
        self.timeline.step_units()
    }

    /// The interpolation factor now, in `[0, 1)`.
    #[must_use]
    pub fn alpha(&self) -> f64 {
        let step = self.step_units();
        (self.accumulator % step) as f64 / step as f64
    }

    /// Stops accepting time: frames run no steps and alpha stays put.
    pub fn pause(&mut self) {
        self.paused = true;
    }

    /// Accepts time again (the paused time is not caught up).
    pub fn resume(&mut self) {
        self.paused = false;
        self.single_steps = 0;
    }

    /// Whether the clock is paused.
    #[must_use]
    pub fn is_paused(&self) -> bool {
        self.paused
    }

    /// While paused, makes the next frame run exactly one more step (queued
    /// steps run at most `max_steps_per_frame` a frame, the rest on the
    /// following frames). Ignored (returns false) while running, where steps
    /// come from real time.
    pub fn single_step(&mut self) -> bool {
        if self.paused {
            self.single_steps = self.single_steps.saturating_add(1);
        }
        self.paused
    }

    /// Changes the step. Simulated time stays continuous: steps after the
    /// change add the new step to the time reached so far. Accumulated time
    /// carries over (rounded down to the new units, under a nanosecond).
    pub fn set_rate(&mut self, rate: Rate) {
        let (_, old_denom) = self.timeline.rate.fraction();
        let (_, new_denom) = rate.fraction();
        // Round down, as documented: the carried time never runs ahead.
        let (whole, rest) = (
            self.accumulator / u128::from(old_denom),
            self.accumulator % u128::from(old_denom),
        );
        self.accumulator = whole
            .saturating_mul(u128::from(new_denom))
            .saturating_add(rest * u128::from(new_denom) / u128::from(old_denom));
        self.timeline = self.timeline.rebased(self.tick, rate);
        self.config.rate = rate;
    }

    /// Sets the hitch guard's cap at run time: a frame longer than
    /// `seconds` counts as `seconds` (as Bevy's `Time::set_max_delta`).
    ///
    /// # Errors
    /// [`ClockError::InvalidSetting`] for a cap outside
    /// [`MIN_FRAME_TIME`](Self::MIN_FRAME_TIME) to
    /// [`MAX_FRAME_TIME`](Self::MAX_FRAME_TIME); the clock is unchanged.
    pub fn set_max_frame_time(&mut self, seconds: f64) -> Result<(), ClockError> {
        check_max_frame_time(seconds)?;
        self.config.max_frame_time = seconds;
        Ok(())
    }

    /// Sets the time scale (game seconds per real second).
    ///
    /// # Errors
    /// [`ClockError::InvalidSetting`] for a scale outside
    /// [`MIN_TIME_SCALE`](Self::MIN_TIME_SCALE) to
    /// [`MAX_TIME_SCALE`](Self::MAX_TIME_SCALE) (pause instead of scaling to zero).
    pub fn set_time_scale(&mut self, scale: f64) -> Result<(), ClockError> {
        check_time_scale(scale)?;
        self.config.time_scale = scale;
        Ok(())
    }

    /// Sets the hitch policy.
    pub fn set_hitch_policy(&mut self, policy: HitchPolicy) {
        self.config.hitch_policy = policy;
        self.dilation = 1.0;
    }

    /// The settings in force.
    #[must_use]
    pub fn config(&self) -> &ClockConfig {
        &self.config
    }

    /// The next tick to run (= steps run so far).
    #[must_use]
    pub fn tick(&self) -> u64 {
        self.tick
    }

    /// Simulated time, in seconds.
    #[must_use]
    pub fn time(&self) -> f64 {
        self.timeline.time_of(self.tick)
    }

    /// Simulated time exactly, as `(numer, denom)` seconds in lowest terms.
    #[must_use]
    pub fn exact_time(&self) -> (u128, u128) {
        self.timeline.exact_time_of(self.tick)
    }

    /// The step, in seconds.
    #[must_use]
    pub fn dt(&self) -> f64 {
        self.timeline.rate.step_seconds()
    }

    /// The mapping from ticks to times.
    #[must_use]
    pub fn timeline(&self) -> Timeline {
        self.timeline
    }

    /// Scaled time accepted and not dropped, in seconds: what simulated time
    /// follows, within one step (more under [`HitchPolicy::CatchUp`] debt).
    #[must_use]
    pub fn accepted_time(&self) -> f64 {
        self.accepted_nanos as f64 / 1e9
    }

    /// Accumulated time not yet simulated, in seconds (below one step, except
    /// for a [`HitchPolicy::CatchUp`] debt).
    #[must_use]
    pub fn backlog(&self) -> f64 {
        let (_, denom) = self.timeline.rate.fraction();
        self.accumulator as f64 / (1e9 * denom as f64)
    }

    /// Real seconds dropped since the clock started.
    #[must_use]
    pub fn dropped_total(&self) -> f64 {
        self.dropped_total
    }
}

fn check_range(field: &'static str, value: f64, min: f64, max: f64, expected: &'static str) -> Result<(), ClockError> {
    if value.is_finite() && (min..=max).contains(&value) {
        Ok(())
    } else {
        Err(ClockError::InvalidSetting { field, value, expected })
    }
}

fn check_max_frame_time(seconds: f64) -> Result<(), ClockError> {
    check_range(
        "max_frame_time",
        seconds,
        FixedClock::MIN_FRAME_TIME,
        FixedClock::MAX_FRAME_TIME,
        "from 1e-9 (a nanosecond) to 3600 seconds",
    )
}

fn check_time_scale(scale: f64) -> Result<(), ClockError> {
    check_range(
        "time_scale",
        scale,
        FixedClock::MIN_TIME_SCALE,
        FixedClock::MAX_TIME_SCALE,
        "from 1e-6 to 1e6 game seconds per real second",
    )
}

#[cfg(test)]
mod tests;
