//! Why a run stopped: [`RunError`], and [`PlaybackError`] for a scene's
//! playback. The runners and sources return them; this file depends on no
//! other module of `app/` but `api/game.rs` (for [`GameError`]).

use std::fmt;
use std::path::{Path, PathBuf};

use crate::app::api::game::GameError;
use crate::clock::ClockError;
use crate::render::RenderError;
use crate::scene::SceneError;
use crate::step::SimulationError;
use tickwork_integrators::UnknownMethod;

/// Why playback stopped.
#[derive(Debug)]
pub enum PlaybackError {
    /// The scene could not be loaded or built.
    Scene(SceneError),
    /// The clock refused a frame duration or setting.
    Clock(ClockError),
    /// A step failed (non-finite state, integrator failure).
    Simulation(SimulationError),
    /// An integrator name that is not registered.
    Integrator(UnknownMethod),
    /// The world steps on the GPU, and the GPU step refused it or failed.
    Gpu(crate::gpu_step::GpuStepError),
}

impl fmt::Display for PlaybackError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Scene(e) => e.fmt(f),
            Self::Clock(e) => e.fmt(f),
            Self::Simulation(e) => e.fmt(f),
            Self::Integrator(e) => e.fmt(f),
            Self::Gpu(e) => e.fmt(f),
        }
    }
}

/// The message is the inner error's; `source()` is the inner error itself,
/// so a caller can downcast it or walk its chain.
impl std::error::Error for PlaybackError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Scene(e) => Some(e),
            Self::Clock(e) => Some(e),
            Self::Simulation(e) => Some(e),
            Self::Integrator(e) => Some(e),
            Self::Gpu(e) => Some(e),
        }
    }
}

impl From<ClockError> for PlaybackError {
    fn from(e: ClockError) -> Self {
        Self::Clock(e)
    }
}
impl From<SimulationError> for PlaybackError {
    fn from(e: SimulationError) -> Self {
        Self::Simulation(e)
    }
}
impl From<UnknownMethod> for PlaybackError {
    fn from(e: UnknownMethod) -> Self {
        Self::Integrator(e)
    }
}

/// Why a run (off-screen or in a window) stopped early.
#[derive(Debug)]
pub enum RunError {
    /// The world or clock failed.
    Playback(PlaybackError),
    /// The GPU, a target or a surface failed.
    Render(RenderError),
    /// No window can be opened (no display, or the event loop failed).
    Window(String),
    /// An output file exists and overwriting was not asked for.
    Exists(PathBuf),
    /// The game failed (its set-up, a step, its own error).
    Game(GameError),
    /// A networked match failed: the other player not found, gone, or out
    /// of step (a desync, with the tick and both checksums).
    Network(String),
    /// A request past one of the engine's limits: the message names the
    /// limit and what to do instead.
    Limit(String),
    /// A file could not be written.
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Playback(e) => e.fmt(f),
            Self::Render(e) => e.fmt(f),
            Self::Game(e) => e.fmt(f),
            Self::Window(message) => write!(f, "cannot open a window: {message}"),
            Self::Limit(message) => f.write_str(message),
            Self::Network(message) => write!(f, "network: {message}"),
            Self::Exists(path) => write!(f, "{}: exists; pass --force to overwrite it", path.display()),
            Self::Io { path, message } => write!(f, "{}: {message}", path.display()),
        }
    }
}

/// The message of a wrapping variant is the inner error's; `source()` is
/// the inner error itself, so a caller can downcast it or walk its chain.
impl std::error::Error for RunError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Playback(e) => Some(e),
            Self::Render(e) => Some(e),
            Self::Game(e) => Some(e),
            Self::Window(_) | Self::Exists(_) | Self::Network(_) | Self::Limit(_) | Self::Io { .. } => None,
        }
    }
}

/// A scene's playback failing inside a game: [`GameError::Engine`].
impl From<PlaybackError> for GameError {
    fn from(e: PlaybackError) -> Self {
        Self::Engine(Box::new(e))
    }
}

/// A run started inside a game failing: the game's own error back as it
/// was, anything else as [`GameError::Engine`].
impl From<RunError> for GameError {
    fn from(e: RunError) -> Self {
        match e {
            RunError::Game(e) => e,
            other => Self::Engine(Box::new(other)),
        }
    }
}

impl From<PlaybackError> for RunError {
    fn from(e: PlaybackError) -> Self {
        Self::Playback(e)
    }
}

impl From<RenderError> for RunError {
    fn from(e: RenderError) -> Self {
        Self::Render(e)
    }
}

impl From<UnknownMethod> for RunError {
    fn from(e: UnknownMethod) -> Self {
        Self::Game(e.into())
    }
}

impl From<crate::input::RecordingError> for RunError {
    fn from(e: crate::input::RecordingError) -> Self {
        match e {
            crate::input::RecordingError::Exists(path) => Self::Exists(path),
            crate::input::RecordingError::Io { path, message } => Self::Io { path, message },
        }
    }
}

impl From<ClockError> for RunError {
    fn from(e: ClockError) -> Self {
        Self::Playback(PlaybackError::Clock(e))
    }
}

impl RunError {
    /// A file at `path` could not be written: [`RunError::Io`] with `error`'s message.
    pub(crate) fn io(path: &Path, error: &dyn std::fmt::Display) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            message: error.to_string(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clock::Rate;
    use std::error::Error as _;

    #[test]
    fn a_wrapper_keeps_its_inner_error_as_its_source() {
        let clock = Rate::hz(0).expect_err("0 Hz is refused");
        let run = RunError::from(PlaybackError::from(clock.clone()));
        // The message is passed through, and the chain reaches the clock's error.
        assert_eq!(run.to_string(), clock.to_string());
        let playback = run.source().expect("the playback error");
        assert!(playback.downcast_ref::<PlaybackError>().is_some(), "{playback:?}");
        let inner = playback.source().expect("the clock's error");
        assert_eq!(inner.downcast_ref::<ClockError>(), Some(&clock));
        assert!(RunError::Limit("a limit".into()).source().is_none());
    }
}
