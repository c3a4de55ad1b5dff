//! Running a world for a viewer: [`Playback`] (clock, controls, HUD) and
//! the two runners that show it, off-screen ([`OffscreenRun`]) and in a
//! window ([`run_window`]), which share the per-frame path.

mod offscreen;
mod playback;
mod window;

pub use offscreen::{FrameOutput, OffscreenRun, OffscreenSummary};
pub use playback::{Control, Playback, PlaybackError};
// RunError is defined below.
pub use window::{WindowOptions, WindowSummary, run_window};

use std::fmt;
use std::path::PathBuf;

use crate::render::RenderError;

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
            Self::Window(message) => write!(f, "cannot open a window: {message}"),
            Self::Exists(path) => write!(f, "{}: exists; pass --force to overwrite it", path.display()),
            Self::Io { path, message } => write!(f, "{}: {message}", path.display()),
        }
    }
}

impl std::error::Error for RunError {}

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
