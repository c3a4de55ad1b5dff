//! Where frame durations come from: the real clock, or a simulated display.

use crate::platform::Instant;

/// A source of frame durations, in seconds, for [`FixedClock::advance`](super::FixedClock::advance).
///
/// The clock itself never reads the time, so the same loop runs from the real
/// clock in a window and from a simulated cadence in tests and off-screen
/// renders.
pub trait TimeSource {
    /// The duration of the frame that just ended, in seconds.
    fn next_frame(&mut self) -> f64;
}

/// Real time: the `Instant` elapsed since the previous call.
#[derive(Clone, Copy, Debug)]
pub struct RealTime {
    last: Instant,
}

impl Default for RealTime {
    fn default() -> Self {
        Self { last: Instant::now() }
    }
}

impl TimeSource for RealTime {
    fn next_frame(&mut self) -> f64 {
        let now = Instant::now();
        let elapsed = now.duration_since(self.last).as_secs_f64();
        self.last = now;
        elapsed
    }
}

/// A display refreshing at a fixed rate: every frame lasts `1 / hz` seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedCadence {
    /// Frame duration in seconds.
    pub seconds: f64,
}

impl FixedCadence {
    /// A display at `hz` frames per second.
    #[must_use]
    pub fn hz(hz: f64) -> Self {
        Self { seconds: 1.0 / hz }
    }
}

impl TimeSource for FixedCadence {
    fn next_frame(&mut self) -> f64 {
        self.seconds
    }
}

/// A display whose frame times jitter: each frame lasts `mean * (1 + u)` with
/// `u` uniform in `[-spread, spread]`, from a seeded generator (SplitMix64),
/// so a jittery run is reproducible.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JitteryCadence {
    /// Mean frame duration in seconds.
    pub mean: f64,
    /// Relative spread, in `[0, 1)` (default in [`JitteryCadence::new`]: 0.5).
    pub spread: f64,
    state: u64,
}

impl JitteryCadence {
    /// Frames of `mean` seconds, +-50%, from `seed`.
    #[must_use]
    pub fn new(mean: f64, seed: u64) -> Self {
        Self {
            mean,
            spread: 0.5,
            state: seed,
        }
    }
}

impl TimeSource for JitteryCadence {
    fn next_frame(&mut self) -> f64 {
        // SplitMix64: a full-period 64-bit generator, enough for test jitter.
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        let unit = (z >> 11) as f64 / (1u64 << 53) as f64; // [0, 1)
        self.mean * (1.0 + self.spread * (2.0 * unit - 1.0))
    }
}

/// A recorded sequence of frame durations, repeated when exhausted.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordedFrames {
    durations: Vec<f64>,
    next: usize,
}

impl RecordedFrames {
    /// Plays `durations` in order (an empty list gives zero-length frames).
    #[must_use]
    pub fn new(durations: Vec<f64>) -> Self {
        Self { durations, next: 0 }
    }
}

impl TimeSource for RecordedFrames {
    fn next_frame(&mut self) -> f64 {
        if self.durations.is_empty() {
            return 0.0;
        }
        let value = self.durations[self.next % self.durations.len()];
        self.next += 1;
        value
    }
}
