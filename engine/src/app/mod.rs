//! Running worlds for a viewer: a [`Game`] in a [`GameSession`], or a
//! scene in a [`Playback`], both [`FrameSource`]s; and the two runners that
//! show them, off-screen ([`OffscreenRun`]) and in a window ([`run_window`]),
//! which share the per-frame path. [`run`] picks one for a game.

#[cfg(feature = "audio")]
mod audio;
mod backend;
mod control;
mod draw;
mod error;
mod frame_rate;
mod game;
#[cfg(feature = "netcode")]
mod network;
mod offscreen;
mod options;
// The page's runner: only the browser build has one (its canvas is a
// window's).
#[cfg(all(target_arch = "wasm32", feature = "window"))]
mod page;
#[cfg(feature = "panel")]
mod panel;
mod playback;
#[cfg(feature = "netcode")]
mod rollback;
mod run;
mod session;
mod session_options;
#[cfg(feature = "audio")]
mod sound;
mod source;
mod stage;
mod start;
#[cfg(feature = "window")]
mod window;

/// The input types a game meets, from [`crate::input`], where they live.
pub use crate::input::{InputEvent, Key, KeySet, Recording, RecordingError, TickInput};
#[cfg(feature = "audio")]
pub use audio::{LOGGED_SOUNDS, Played};
/// The command-line parser [`RunOptions`] is written for, re-exported so a
/// game flattens [`RunOptions`] into its own options with the same version.
#[cfg(feature = "cli")]
pub use clap;
pub use control::Control;
pub use draw::{Draw, DrawPoint, Viewport};
pub use error::{PlaybackError, RunError};
pub use game::{Game, GameError};
#[cfg(feature = "netcode")]
pub use network::{
    ImpairedSocket, Impairment, ImpairmentCounts, Lobby, MatchReport, NetOptions, NetSession, Peer, Welcome,
};
pub use offscreen::{FrameOutput, MAX_OFFSCREEN_FRAMES, OffscreenRun, OffscreenSummary};
#[cfg(feature = "cli")]
pub use options::parse_args;
pub use options::{MAX_DISPLAY_HZ, MIN_DISPLAY_HZ, RunOptions, display_hz, non_negative_seconds, parse_size};
pub use playback::Playback;
#[cfg(feature = "netcode")]
pub use rollback::{MAX_CHECK_DISTANCE, Rollback, SavedTick, SyncTestReport, WireInput, sync_test};
#[cfg(feature = "netcode")]
pub use run::MAX_SYNC_TEST_TICKS;
pub use run::{RunSummary, exit_code, renderer_config};
pub use session::GameSession;
pub use session_options::SessionOptions;
#[cfg(feature = "audio")]
pub use sound::{Sound, SoundError};
pub use source::FrameSource;
pub use stage::{
    EnergyTrace, OnFailure, ReadBackError, Settings, Stage, StageError, StageWorld, WorldBuilder, WorldId,
};
pub use start::run;
#[cfg(feature = "window")]
pub use window::{WindowOptions, WindowSummary, run_window};
