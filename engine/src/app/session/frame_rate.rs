//! The smoothed frame rate the HUD and the panel show.

/// Frames per second for the HUD and the panel, from a smoothed frame time
/// `e <- e + (s - e) / 8` (the first frame sets it).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct FrameRate {
    seconds: f64,
}

impl FrameRate {
    /// Takes a frame of `seconds` into the average.
    pub(crate) fn record(&mut self, seconds: f64) {
        self.seconds = if self.seconds == 0.0 {
            seconds
        } else {
            self.seconds + (seconds - self.seconds) / 8.0
        };
    }

    /// Smoothed frames per second (0 before any frame).
    pub(crate) fn fps(self) -> f64 {
        if self.seconds > 0.0 { 1.0 / self.seconds } else { 0.0 }
    }
}
