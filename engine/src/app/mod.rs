//! Running worlds for a viewer: a [`Game`] in a [`GameSession`], or a
//! scene in a [`Playback`], both [`FrameSource`]s; and the two runners that
//! show them, off-screen ([`OffscreenRun`]) and in a window ([`run_window`]),
//! which share the per-frame path. [`run`] picks one for a game.

mod control;
mod draw;
mod frame_rate;
mod game;
mod network;
mod offscreen;
mod options;
mod panel;
mod playback;
mod rollback;
mod run;
mod session;
mod stage;
mod window;

/// The input types a game meets, from [`crate::input`], where they live.
pub use crate::input::{InputEvent, Key, KeySet, Recording, RecordingError, TickInput};
/// The command-line parser [`RunOptions`] is written for, re-exported so a
/// game flattens [`RunOptions`] into its own options with the same version.
pub use clap;
pub use control::Control;
pub use draw::{Draw, Viewport};
pub use game::{Game, GameError};
pub use network::{
    ImpairedSocket, Impairment, ImpairmentCounts, Lobby, MatchReport, NetOptions, NetSession, Peer, Welcome,
};
pub use offscreen::{FrameOutput, OffscreenRun, OffscreenSummary};
pub use options::{MAX_DISPLAY_HZ, MIN_DISPLAY_HZ, RunOptions, display_hz, non_negative_seconds, parse_size};
pub use playback::{Playback, PlaybackError};
pub use rollback::{MAX_CHECK_DISTANCE, Rollback, SavedTick, SyncTestReport, WireInput, sync_test};
pub use run::{MAX_OFFSCREEN_FRAMES, MAX_SYNC_TEST_TICKS, RunSummary, exit_code, renderer_config, run};
pub use session::{GameSession, SessionOptions};
pub use stage::{EnergyTrace, OnFailure, Settings, Stage, StageError, StageWorld, WorldBuilder, WorldId};
// RunError and FrameSource are defined below.
pub use window::{WindowOptions, WindowSummary, run_window};

use std::fmt;
use std::path::PathBuf;

use crate::input::InputEvent as Event;
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

    /// Applies a viewer control now. The runners call it between frames
    /// only (the keys' controls and the panel's alike), so every control
    /// enters the simulation at a tick boundary.
    ///
    /// # Errors
    /// [`RunError`] if the control fails (an integrator number beyond the
    /// registry, a rate the clock refuses).
    fn control(&mut self, control: Control) -> Result<(), RunError>;

    /// Whether the source takes the player's input (game keys, mouse
    /// buttons and pointer); if not, the window maps keys to controls and
    /// the mouse to the camera. Default: not taken.
    fn takes_input(&self) -> bool {
        false
    }

    /// An input event that arrived at `arrival` in the coming frame (0 at
    /// its start, 1 at its end): see [`crate::input::InputQueue`]. Called
    /// by the runner just before [`advance`](Self::advance). Default: ignored.
    fn input(&mut self, event: Event, arrival: f64) {
        let _ = (event, arrival);
    }

    /// Fixed steps run since the start (or the last reset).
    fn ticks(&self) -> u64;

    /// Whether the source has come to its end and the window should close
    /// (a networked match over). Default: never.
    fn finished(&self) -> bool {
        false
    }

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

    /// Lays out the window's control panel, adding the controls chosen in
    /// it to `chosen` (applied by the runner before the next frame's
    /// steps). Default: no panel.
    fn panel(&self, ctx: &egui::Context, chosen: &mut Vec<Control>) {
        let _ = (ctx, chosen);
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

impl From<tickwork_integrators::UnknownMethod> for RunError {
    fn from(e: tickwork_integrators::UnknownMethod) -> Self {
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

impl From<crate::clock::ClockError> for RunError {
    fn from(e: crate::clock::ClockError) -> Self {
        Self::Playback(PlaybackError::Clock(e))
    }
}
