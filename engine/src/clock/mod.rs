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

mod config;
mod error;
mod fixed_clock;
mod frame;
mod number;
mod rate;
mod time_source;
mod timeline;
mod wide;

pub use config::{ClockConfig, HitchPolicy};
pub use error::ClockError;
pub use fixed_clock::FixedClock;
pub use frame::{FixedStep, Frame};
pub use number::Number;
pub use rate::Rate;
pub use time_source::{FixedCadence, JitteryCadence, RealTime, RecordedFrames, TimeSource};
pub use timeline::Timeline;

#[cfg(test)]
mod tests;
