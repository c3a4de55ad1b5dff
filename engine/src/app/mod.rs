//! Running worlds for a viewer: a [`Game`] in a [`GameSession`], or a
//! scene in a [`Playback`], both [`FrameSource`]s; and the two runners that
//! show them, off-screen ([`OffscreenRun`]) and in a window ([`run_window`]),
//! which share the per-frame path. [`run`] picks one for a game.

// One folder for each layer, and for each feature its own: `api/` (the
// game API), `session/` (what is shown frame by frame), `runner/` (how:
// off-screen, `window/`, a page), `net/` (`netcode`), `audio/` (`audio`),
// `panel.rs` (`panel`). engine/tests/modules.rs keeps them acyclic and each
// feature's crates inside its folder.
mod api;
#[cfg(feature = "audio")]
mod audio;
#[cfg(feature = "netcode")]
mod net;
#[cfg(feature = "panel")]
mod panel;
mod runner;
mod session;

/// The input types a game meets, from [`crate::input`], where they live.
pub use crate::input::{InputEvent, Key, KeySet, Recording, RecordingError, TickInput};
pub use api::control::Control;
pub use api::draw::{Draw, DrawPoint, Viewport};
pub use api::error::{PlaybackError, RunError};
pub use api::game::{Game, GameError};
pub use api::stage::{ReadBackError, Settings, Stage, StageError, WorldBuilder, WorldId};
pub use api::stage_world::{EnergyTrace, OnFailure, StageWorld};
#[cfg(feature = "audio")]
pub use audio::mixer::{LOGGED_SOUNDS, Played};
#[cfg(feature = "audio")]
pub use audio::sound::{Sound, SoundError};
/// The command-line parser [`RunOptions`] is written for, re-exported so a
/// game flattens [`RunOptions`] into its own options with the same version.
#[cfg(feature = "cli")]
pub use clap;
#[cfg(feature = "netcode")]
pub use net::{
    ImpairedSocket, Impairment, ImpairmentCounts, Lobby, MAX_DECODED_INPUT_BYTES, MatchReport, NetOptions, NetSession,
    Peer, PeerAddress, Welcome, decode_peer_message,
};
#[cfg(feature = "netcode")]
pub use net::{MAX_CHECK_DISTANCE, Rollback, SavedTick, SyncTestReport, WireInput, sync_test};
#[cfg(feature = "netcode")]
pub use runner::native::MAX_SYNC_TEST_TICKS;
pub use runner::native::{RunSummary, exit_code, renderer_config};
pub use runner::offscreen::{FrameOutput, MAX_OFFSCREEN_FRAMES, OffscreenRun, OffscreenSummary};
#[cfg(feature = "cli")]
pub use runner::options::parse_args;
pub use runner::options::{MAX_DISPLAY_HZ, MIN_DISPLAY_HZ, RunOptions, display_hz, non_negative_seconds, parse_size};
pub use runner::start::run;
#[cfg(feature = "window")]
pub use runner::window::{WindowOptions, WindowSummary, run_window};
pub use session::game_session::GameSession;
pub use session::options::SessionOptions;
pub use session::playback::Playback;
pub use session::source::FrameSource;
