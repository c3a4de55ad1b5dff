//! The game API: a [`Game`] builds a [`Stage`] of worlds, reacts to each
//! fixed step's [`TickInput`], and adds lines and HUD text to each frame.
//!
//! The runner ([`run`](crate::app::run)) owns the clock: it calls
//! [`Game::fixed_update`] once per fixed step with that tick's input, then
//! steps every world of the stage; [`Game::update`] once per displayed
//! frame; and [`Game::draw`] before drawing. Because a step sees only the
//! stage and its tick's input, a recording of inputs by tick replays a game
//! bit for bit, whatever the frame timing.

use std::fmt;

use crate::app::api::draw::Draw;
use crate::app::api::stage::{Settings, Stage};
use crate::clock::{FixedStep, Frame};
use crate::input::TickInput;
use crate::step::SimulationError;

/// Why a game stopped. Every engine error converts into it, so `?` works on
/// any engine call inside a [`Game`]'s hooks; so do a `String` or `&str`, a
/// game's own message.
#[derive(Debug)]
pub enum GameError {
    /// A world's step failed; the world's label says which.
    Simulation {
        /// The world's label.
        world: String,
        /// What failed.
        error: SimulationError,
    },
    /// An engine call failed (a spawn, a handle, a scene, a method name, a
    /// rate): the error itself says what and where.
    Engine(Box<dyn std::error::Error + Send + Sync + 'static>),
    /// The game's own message (a bad setting, a world that could not be built).
    Message(String),
    /// The game's own error of another type ([`GameError::other`]; `?` on
    /// a file read or a number parse lands here too).
    Other(Box<dyn std::error::Error + Send + Sync + 'static>),
}

impl GameError {
    /// Wraps a game's own error type, keeping it as the source.
    pub fn other(error: impl std::error::Error + Send + Sync + 'static) -> Self {
        Self::Other(Box::new(error))
    }
}

impl fmt::Display for GameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Simulation { world, error } => write!(f, "world \"{world}\": {error}"),
            Self::Engine(error) | Self::Other(error) => write!(f, "{error}"),
            Self::Message(message) => f.write_str(message),
        }
    }
}

impl std::error::Error for GameError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Simulation { error, .. } => Some(error),
            Self::Engine(error) | Self::Other(error) => Some(error.as_ref()),
            Self::Message(_) => None,
        }
    }
}

impl From<String> for GameError {
    fn from(message: String) -> Self {
        Self::Message(message)
    }
}

impl From<&str> for GameError {
    fn from(message: &str) -> Self {
        Self::Message(message.to_owned())
    }
}

/// A game's file reads and number parses, into [`GameError::Other`].
macro_rules! other_errors {
    ($($error:ty),* $(,)?) => {
        $(impl From<$error> for GameError {
            fn from(error: $error) -> Self {
                Self::other(error)
            }
        })*
    };
}

other_errors!(std::io::Error, std::num::ParseIntError, std::num::ParseFloatError);

/// `From` for each engine error a game's code can meet, into
/// [`GameError::Engine`].
macro_rules! engine_errors {
    ($($(#[$meta:meta])* $error:ty),* $(,)?) => {
        $($(#[$meta])* impl From<$error> for GameError {
            fn from(error: $error) -> Self {
                Self::Engine(Box::new(error))
            }
        })*
    };
}

engine_errors!(
    crate::world::SpawnError,
    crate::world::EntityError,
    crate::colliders::ColliderError,
    crate::app::api::stage::StageError,
    crate::app::api::stage::ReadBackError,
    crate::gpu_step::GpuStepError,
    crate::world::WorldError,
    crate::scene::SceneError,
    crate::clock::ClockError,
    crate::input::RecordingError,
    crate::headless::HeadlessError,
    tickwork_integrators::UnknownMethod,
    tickwork_integrators::StepError,
    SimulationError,
    crate::render::RenderError,
    crate::render::GoldenError,
    crate::render::TextureError,
    #[cfg(feature = "audio")]
    crate::app::audio::sound::SoundError,
    crate::sensor::SensorError,
    crate::character::CharacterError,
    #[cfg(feature = "tiled")]
    crate::tilemap::MapError,
);
// `PlaybackError` and `RunError` convert too: their `From` impls are in
// `error.rs`, beside them (this file is imported by it, not the reverse).

/// A game: what it builds, how it reacts to each tick's input, and what it
/// draws. Only [`title`](Game::title) and [`setup`](Game::setup) are required.
pub trait Game {
    /// The name: window title, output folder, recordings.
    fn title(&self) -> &str;

    /// The asset files [`setup`](Game::setup) loads (textures, sounds),
    /// by the paths it gives [`Texture::load`](crate::render::Texture::load)
    /// and [`Sound::load`](crate::app::Sound::load): a page, which cannot read
    /// files, fetches each before setup (a missing one stops the page with
    /// its URL). Natively files are read when loaded and this list is not
    /// needed; none by default.
    fn assets(&self) -> &[&str] {
        &[]
    }

    /// Builds the stage: worlds, trails, camera, rate. Called at the start
    /// and again on restart (F5), with a fresh stage.
    ///
    /// # Errors
    /// A [`GameError`] stops the run with its message.
    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError>;

    /// Once per fixed step, before the stage's worlds are stepped, with the
    /// keys of this tick. The deterministic part of a game lives here.
    ///
    /// # Errors
    /// A [`GameError`] stops the run with its message.
    fn fixed_update(&mut self, stage: &mut Stage, step: &FixedStep, input: &TickInput) -> Result<(), GameError> {
        let _ = (stage, step, input);
        Ok(())
    }

    /// How many players the game has (default 1; at most
    /// [`Recording::MAX_PLAYERS`](crate::input::Recording::MAX_PLAYERS)).
    /// Player 0 plays from this machine; in a networked match each player
    /// plays from their own, and [`fixed_update_players`](Game::fixed_update_players)
    /// sees local and remote players alike.
    fn players(&self) -> usize {
        1
    }

    /// Once per fixed step with every player's input of the tick, by player
    /// number (`inputs.len()` is [`players`](Game::players)). The default
    /// gives player 0's to [`fixed_update`](Game::fixed_update): a game of
    /// one player implements that one instead.
    ///
    /// # Errors
    /// A [`GameError`] stops the run with its message.
    fn fixed_update_players(
        &mut self,
        stage: &mut Stage,
        step: &FixedStep,
        inputs: &[TickInput],
    ) -> Result<(), GameError> {
        let input = inputs.first().copied().unwrap_or_default();
        self.fixed_update(stage, step, &input)
    }

    /// Once per displayed frame, after its fixed steps (camera, cosmetics;
    /// frame timing varies, so nothing here may change the simulation).
    fn update(&mut self, stage: &mut Stage, frame: &Frame) {
        let _ = (stage, frame);
    }

    /// What the game draws over its worlds this frame (shapes, lines,
    /// text, the HUD); `alpha` is the interpolation factor the worlds are
    /// drawn at, and `draw` knows the frame's size and scale.
    ///
    /// # Errors
    /// A [`GameError`] stops the run with its message.
    fn draw(&self, stage: &Stage, alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        let _ = (stage, alpha, draw);
        Ok(())
    }

    /// A hash of the game's own simulated state that its worlds do not
    /// hold (score, lives, which bricks are left), mixed into the rollback
    /// checksum so that a sync test also sees it diverge. Default 0: the
    /// game's state shows only through its worlds. Hash with
    /// [`StableHasher`](crate::StableHasher), which gives the same on every
    /// machine (peers of a match compare these).
    fn state_hash(&self) -> u64 {
        0
    }

    /// A line printed when a run ends (score, outcome); none by default.
    fn outcome(&self, stage: &Stage) -> Option<String> {
        let _ = stage;
        None
    }
}
