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
    /// speed factor to what the cap could simulate, so following frames run
    /// smoothly in slow motion instead of in bursts of `max_steps_per_frame`,
    /// then recovers by 5% per frame once frames fit again.
    SlowDown,
    /// Keep it as a debt and run it over the next frames, at most
    /// `max_steps_per_frame` steps per frame, until the game has caught up.
    CatchUp,
}

/// Settings of a [`FixedClock`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClockConfig {
    /// The fixed step (default: 60 Hz).
    pub rate: Rate,
    /// Longest frame duration counted, in seconds; longer frames count as this
    /// (default: `0.25`, as bevy_time's maximum delta).
    pub max_frame_time: f64,
    /// Most steps one frame may run (default: `8`, as Godot's
    /// `max_physics_steps_per_frame`).
    pub max_steps_per_frame: u32,
    /// What happens to time beyond the step cap (default: [`HitchPolicy::Drop`]).
    pub hitch_policy: HitchPolicy,
    /// Game seconds per real second: 0.25 is slow motion, 2 fast forward
    /// (default: `1.0`). Changes how many steps run, never the step size.
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
                write!(f, "invalid frame duration: {value} s (must be finite and not negative)")
            }
            Self::InvalidRate { what, value } => write!(f, "invalid {what}: {value} (must be finite and positive)"),
            Self::InvalidSetting { field, value, expected } => {
                write!(f, "invalid clock setting {field}: {value} (expected {expected})")
            }
        }
    }
}

impl std::error::Error for ClockError {}

/// Maps ticks to exact simulated times: `epoch + (tick - epoch_tick) * step`.
///
/// The epoch moves when the rate changes, so time stays continuous.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timeline {
    epoch_numer: u128,
    epoch_denom: u128,
    epoch_tick: u64,
    rate: Rate,
}

impl Timeline {
    /// The exact simulated time at the start of `tick`, as `(numer, denom)` seconds.
    #[must_use]
    pub fn exact_time_of(&self, tick: u64) -> (u128, u128) {
        let (p, q) = self.rate.fraction();
        let k = u128::from(tick.saturating_sub(self.epoch_tick));
        let numer = self.epoch_numer * u128::from(q) + k * u128::from(p) * self.epoch_denom;
        let denom = self.epoch_denom * u128::from(q);
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
}

impl Default for FixedClock {
    fn default() -> Self {
        Self::from_valid(ClockConfig::default())
    }
}

impl FixedClock {
    /// A clock with `config`, at tick 0 and time 0.
    ///
    /// # Errors
    /// [`ClockError::InvalidSetting`] for a `max_frame_time` or `time_scale`
    /// that is not finite and positive, or a zero `max_steps_per_frame`.
    pub fn new(config: ClockConfig) -> Result<Self, ClockError> {
        check_positive("max_frame_time", config.max_frame_time)?;
        check_positive("time_scale", config.time_scale)?;
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
                epoch_numer: 0,
                epoch_denom: 1,
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
        if self.paused {
            let steps = self.single_steps;
            self.single_steps = 0;
            self.tick += u64::from(steps);
            return Ok(self.frame(steps, 0.0, real_seconds, first_tick));
        }
        let counted = real_seconds.min(self.config.max_frame_time);
        let mut dropped = real_seconds - counted;
        let speed = self.config.time_scale * self.dilation;
        // Straight into accumulator units (1 / (1e9 denom) s), rounded: a
        // display frame of exactly 1/30 s is then exactly two 60 Hz steps,
        // where whole nanoseconds (33 333 333) would fall a third of a
        // nanosecond short and run 1, 2, 2, 1, ... steps.
        let (_, denom) = self.timeline.rate.fraction();
        let units = (counted * speed * 1e9 * denom as f64).round() as u128;
        self.accumulator += units;
        self.accepted_nanos += units.div_ceil(u128::from(denom));

        let needed = self.accumulator / step_units;
        let cap = u128::from(self.config.max_steps_per_frame);
        let steps = needed.min(cap);
        self.accumulator -= steps * step_units;
        if needed > cap {
            let excess = (needed - cap) * step_units;
            match self.config.hitch_policy {
                HitchPolicy::CatchUp => {}
                policy => {
                    self.accumulator -= excess;
                    let excess_nanos = excess / u128::from(denom);
                    self.accepted_nanos -= excess_nanos;
                    dropped += excess_nanos as f64 / 1e9 / speed;
                    if policy == HitchPolicy::SlowDown {
                        self.dilation *= cap as f64 / needed as f64;
                    }
                }
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

    fn frame(&self, steps: u32, dropped: f64, real_seconds: f64, first_tick: u64) -> Frame {
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
        u128::from(self.timeline.rate.fraction().0) * NANOS
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

    /// While paused, makes the next frame run exactly one more step. Ignored
    /// (returns false) while running, where steps come from real time.
    pub fn single_step(&mut self) -> bool {
        if self.paused {
            self.single_steps += 1;
        }
        self.paused
    }

    /// Changes the step. Simulated time stays continuous: steps after the
    /// change add the new step to the time reached so far. Accumulated time
    /// carries over (rounded down to the new units, under a nanosecond).
    pub fn set_rate(&mut self, rate: Rate) {
        let (numer, denom) = self.timeline.exact_time_of(self.tick);
        let (_, old_denom) = self.timeline.rate.fraction();
        let (_, new_denom) = rate.fraction();
        self.accumulator = self.accumulator * u128::from(new_denom) / u128::from(old_denom);
        self.timeline = Timeline {
            epoch_numer: numer,
            epoch_denom: denom,
            epoch_tick: self.tick,
            rate,
        };
        self.config.rate = rate;
    }

    /// Sets the time scale (game seconds per real second).
    ///
    /// # Errors
    /// [`ClockError::InvalidSetting`] for a scale that is not finite and positive
    /// (pause instead of scaling to zero).
    pub fn set_time_scale(&mut self, scale: f64) -> Result<(), ClockError> {
        check_positive("time_scale", scale)?;
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

fn check_positive(field: &'static str, value: f64) -> Result<(), ClockError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ClockError::InvalidSetting {
            field,
            value,
            expected: "a finite number above zero",
        })
    }
}

#[cfg(test)]
mod tests;
