//! [`SessionOptions`]: what a [`GameSession`](crate::app::GameSession) is
//! started with (the game's settings, the rate and time scale, and the
//! recording to make or replay), each with its default.

use std::path::PathBuf;

use crate::app::api::stage::Settings;
use crate::input::Recording;

/// What a [`GameSession`](crate::app::GameSession) is started with.
#[derive(Clone, Debug)]
pub struct SessionOptions {
    /// Passed to [`Game::setup`](crate::app::Game::setup).
    pub settings: Settings,
    /// Fixed steps per second, overriding the stage's rate (default: none).
    pub hz: Option<f64>,
    /// Simulated seconds per real second (default 1).
    pub time_scale: f64,
    /// Record inputs to this file at the end of the run (default: none).
    pub record: Option<PathBuf>,
    /// Replay this recording instead of the keyboard (default: none).
    pub replay: Option<Recording>,
    /// Overwrite the recording file if it exists (default false).
    pub overwrite: bool,
}

impl Default for SessionOptions {
    fn default() -> Self {
        Self {
            settings: Settings::default(),
            hz: None,
            time_scale: 1.0,
            record: None,
            replay: None,
            overwrite: false,
        }
    }
}
