//! The clock's settings: the step, the hitch guard and what happens to the
//! time it cuts ([`HitchPolicy`]), and the time scale.

use super::Rate;

/// What to do with time that the step cap did not let a frame simulate.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum HitchPolicy {
    /// Throw it away (default): after a stall the game continues at normal
    /// speed from where it was, and the frame reports the time as dropped.
    #[default]
    Drop,
    /// Throw it away and slow the game down: the clock lowers an internal
    /// speed factor to what the cap could simulate (never below
    /// [`FixedClock::MIN_DILATION`](super::FixedClock::MIN_DILATION), so it
    /// always recovers), so following frames run smoothly in slow motion
    /// instead of in bursts of `max_steps_per_frame`, then recovers by 5% per
    /// frame once frames fit again.
    SlowDown,
    /// Keep it as a debt and run it over the next frames, at most
    /// `max_steps_per_frame` steps per frame, until the game has caught up.
    /// The debt is bounded: beyond
    /// [`FixedClock::MAX_DEBT_FRAMES`](super::FixedClock::MAX_DEBT_FRAMES)
    /// frames' worth of capped steps it is dropped (and reported as dropped).
    CatchUp,
}

/// Settings of a [`FixedClock`](super::FixedClock).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClockConfig {
    /// The fixed step (default: 60 Hz).
    pub rate: Rate,
    /// Longest frame duration counted, in seconds; longer frames count as this
    /// (default: `0.25`, as bevy_time's maximum delta; at most
    /// [`FixedClock::MAX_FRAME_TIME`](super::FixedClock::MAX_FRAME_TIME)).
    pub max_frame_time: f64,
    /// Most steps one frame may run (default: `8`, as Godot's
    /// `max_physics_steps_per_frame`).
    pub max_steps_per_frame: u32,
    /// What happens to time beyond the step cap (default: [`HitchPolicy::Drop`]).
    pub hitch_policy: HitchPolicy,
    /// Game seconds per real second: 0.25 is slow motion, 2 fast forward
    /// (default: `1.0`; from
    /// [`FixedClock::MIN_TIME_SCALE`](super::FixedClock::MIN_TIME_SCALE) to
    /// [`FixedClock::MAX_TIME_SCALE`](super::FixedClock::MAX_TIME_SCALE)).
    /// Changes how many steps run, never the step size.
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
