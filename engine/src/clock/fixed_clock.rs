//! The fixed-step accumulator clock itself: frame durations poured in,
//! whole steps drained, the hitch guard, time scale, pause and single
//! steps, and changes of rate that keep time continuous. See the
//! [module docs](super) for why it counts integers.

use std::time::Duration;

use super::frame::Frame;
use super::timeline::Timeline;
use super::{ClockConfig, ClockError, HitchPolicy, Rate};

/// The fixed-step accumulator clock. See the [module docs](super).
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
