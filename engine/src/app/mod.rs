//! Running worlds for a viewer: a [`Game`] in a [`GameSession`], or a
//! scene in a [`Playback`], both [`FrameSource`]s; and the two runners that
//! show them, off-screen ([`OffscreenRun`]) and in a window ([`run_window`]),
//! which share the per-frame path. [`run`] picks one for a game.

mod draw;
mod game;
mod offscreen;
mod options;
mod panel;
mod playback;
mod session;
mod stage;
mod window;

pub use draw::{Draw, Viewport};
pub use game::{Game, GameError, Key, KeySet, Settings, TickInput};
pub use offscreen::{FrameOutput, OffscreenRun, OffscreenSummary};
pub use options::{
    MAX_DISPLAY_HZ, MAX_OFFSCREEN_FRAMES, MIN_DISPLAY_HZ, RunOptions, RunSummary, display_hz, exit_code,
    non_negative_seconds, parse_size, renderer_config, run,
};
pub use playback::{Control, Playback, PlaybackError};
pub use session::{GameSession, Recording, SessionOptions};
pub use stage::{EnergyTrace, OnFailure, Stage, StageError, StageWorld, WorldBuilder, WorldId};
// RunError and FrameSource are defined below.
pub use window::{WindowOptions, WindowSummary, run_window};

use std::fmt;
use std::path::PathBuf;

use crate::render::{Camera, FrameView, RenderError};

/// Something the runners can show frame by frame: advanced by each frame's
/// duration, steered by controls and keys, drawn through a [`FrameView`].
pub trait FrameSource {
    /// The window title.
    fn title(&self) -> String;

    /// Advances by one displayed frame of `seconds`, running the fixed
    /// steps it is due.
    ///
    /// # Errors
    /// [`RunError`] for a bad duration or a failed step.
    fn advance(&mut self, seconds: f64) -> Result<(), RunError>;

    /// Applies a viewer control.
    ///
    /// # Errors
    /// [`RunError`] if the control fails (an integrator number beyond the registry).
    fn control(&mut self, control: Control) -> Result<(), RunError>;

    /// A game key went down or up; returns whether the source takes game
    /// keys (if not, the window maps them to controls). Default: not taken.
    fn key(&mut self, key: Key, down: bool) -> bool {
        let _ = (key, down);
        false
    }

    /// Fixed steps run since the start (or the last reset).
    fn ticks(&self) -> u64;

    /// The camera, for the window's mouse.
    fn camera_mut(&mut self) -> &mut Camera;

    /// Calls `render` with the view of the current frame, for a target of
    /// `size` pixels (`hud`: with its HUD text).
    ///
    /// # Errors
    /// What `render` returns.
    fn with_view(
        &mut self,
        hud: bool,
        size: (u32, u32),
        render: &mut dyn FnMut(&FrameView<'_>) -> Result<(), RenderError>,
    ) -> Result<(), RunError>;

    /// Fills the window's control panel (default: clock controls only).
    ///
    /// # Errors
    /// [`RunError`] if a control chosen in the panel fails.
    fn panel(&mut self, ctx: &egui::Context) -> Result<(), RunError> {
        let _ = ctx;
        Ok(())
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

impl From<crate::clock::ClockError> for RunError {
    fn from(e: crate::clock::ClockError) -> Self {
        Self::Playback(PlaybackError::Clock(e))
    }
}
