//! What the clock hands the game each frame: a [`Frame`] (how many steps,
//! the interpolation factor, what was dropped) and its [`FixedStep`]s.

use super::timeline::Timeline;

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

/// What one call to [`FixedClock::advance`](super::FixedClock::advance) decided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Fixed steps to run this frame.
    pub steps: u32,
    /// Interpolation factor in `[0, 1)`: how far real time is past the last
    /// step, as a fraction of a step. Render `previous + alpha * (current - previous)`.
    pub alpha: f64,
    /// Real seconds this frame that will never be simulated (hitches and the
    /// step cap under [`HitchPolicy::Drop`](super::HitchPolicy::Drop) and
    /// [`HitchPolicy::SlowDown`](super::HitchPolicy::SlowDown)).
    pub dropped: f64,
    /// Simulated seconds per real second this frame (1 at normal speed, the
    /// time scale in slow motion, lower when the hitch guard acted; 0 for a
    /// zero-length frame).
    pub effective_speed: f64,
    /// The tick of the first step to run.
    pub first_tick: u64,
    pub(super) timeline: Timeline,
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
