//! The game API: a [`Game`] builds a [`Stage`] of worlds, reacts to each
//! fixed step's [`TickInput`], and adds lines and HUD text to each frame.
//!
//! The runner ([`run`](super::run)) owns the clock: it calls
//! [`Game::fixed_update`] once per fixed step with that tick's input, then
//! steps every world of the stage; [`Game::update`] once per displayed
//! frame; and [`Game::draw`] before drawing. Because a step sees only the
//! stage and its tick's input, a recording of inputs by tick replays a game
//! bit for bit, whatever the frame timing.

use std::fmt;

use serde::{Deserialize, Serialize};

use super::draw::Draw;
use super::stage::Stage;
use crate::clock::{FixedStep, Frame};
use crate::step::SimulationError;

/// The keys a game can read. Keys outside this set drive the runner's
/// controls (P pause, Period step, `+`/`-` time scale, Tab and 1-9
/// integrator, F1 panel, F5 restart, F12 screenshot, Escape quit).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[allow(missing_docs)]
pub enum Key {
    Left,
    Right,
    Up,
    Down,
    Space,
    Enter,
    Shift,
    W,
    A,
    S,
    D,
    Q,
    E,
    R,
    F,
    Z,
    X,
    C,
}

impl Key {
    /// Every key, in bit order.
    pub const ALL: [Key; 18] = [
        Key::Left,
        Key::Right,
        Key::Up,
        Key::Down,
        Key::Space,
        Key::Enter,
        Key::Shift,
        Key::W,
        Key::A,
        Key::S,
        Key::D,
        Key::Q,
        Key::E,
        Key::R,
        Key::F,
        Key::Z,
        Key::X,
        Key::C,
    ];

    fn bit(self) -> u32 {
        1 << (self as u32)
    }
}

/// A set of [`Key`]s (a bit mask), written in recordings as a list of names.
#[derive(Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(from = "Vec<Key>", into = "Vec<Key>")]
pub struct KeySet(u32);

impl KeySet {
    /// No keys.
    pub const EMPTY: Self = Self(0);

    /// Whether `key` is in the set.
    #[must_use]
    pub fn contains(self, key: Key) -> bool {
        self.0 & key.bit() != 0
    }

    /// Adds `key`.
    pub fn insert(&mut self, key: Key) {
        self.0 |= key.bit();
    }

    /// Removes `key`.
    pub fn remove(&mut self, key: Key) {
        self.0 &= !key.bit();
    }

    /// Whether the set is empty.
    #[must_use]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The keys in the set, in [`Key::ALL`] order.
    pub fn iter(self) -> impl Iterator<Item = Key> {
        Key::ALL.into_iter().filter(move |k| self.contains(*k))
    }
}

impl From<Vec<Key>> for KeySet {
    fn from(keys: Vec<Key>) -> Self {
        let mut set = Self::EMPTY;
        for key in keys {
            set.insert(key);
        }
        set
    }
}

impl From<KeySet> for Vec<Key> {
    fn from(set: KeySet) -> Self {
        set.iter().collect()
    }
}

impl fmt::Debug for KeySet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_set().entries(self.iter()).finish()
    }
}

/// What one fixed step sees of the keyboard.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TickInput {
    /// Keys down during this step (thrust while held).
    #[serde(default)]
    pub held: KeySet,
    /// Keys pressed since the previous step began: seen by exactly one step,
    /// even if released before it ran (fire, restart).
    #[serde(default)]
    pub pressed: KeySet,
}

impl TickInput {
    /// Whether `key` is held during this step.
    #[must_use]
    pub fn held(&self, key: Key) -> bool {
        self.held.contains(key)
    }

    /// Whether `key` went down since the previous step.
    #[must_use]
    pub fn pressed(&self, key: Key) -> bool {
        self.pressed.contains(key)
    }

    /// The input of the following step if nothing changes: the same keys
    /// held, none newly pressed.
    #[must_use]
    pub fn carried(&self) -> Self {
        Self {
            held: self.held,
            pressed: KeySet::EMPTY,
        }
    }
}

/// What [`Game::setup`] is told by the command line.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// `--integrator`, as given (the runner also applies it to every world
    /// that does not fix its own integrator; default: none).
    pub integrator: Option<String>,
    /// `--seed` (default 0).
    pub seed: u64,
}

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
}

impl fmt::Display for GameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Simulation { world, error } => write!(f, "world \"{world}\": {error}"),
            Self::Engine(error) => write!(f, "{error}"),
            Self::Message(message) => f.write_str(message),
        }
    }
}

impl std::error::Error for GameError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Simulation { error, .. } => Some(error),
            Self::Engine(error) => Some(error.as_ref()),
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

/// `From` for each engine error a game's code can meet, into
/// [`GameError::Engine`].
macro_rules! engine_errors {
    ($($error:ty),* $(,)?) => {
        $(impl From<$error> for GameError {
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
    super::stage::StageError,
    crate::world::WorldError,
    crate::scene::SceneError,
    crate::clock::ClockError,
    crate::input::InputLogError,
    crate::headless::HeadlessError,
    tickwork_integrators::UnknownMethod,
    tickwork_integrators::StepError,
    SimulationError,
);

/// A game: what it builds, how it reacts to each tick's input, and what it
/// draws. Only [`title`](Game::title) and [`setup`](Game::setup) are required.
pub trait Game {
    /// The name: window title, output folder, recordings.
    fn title(&self) -> &str;

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

    /// A line printed when a run ends (score, outcome); none by default.
    fn outcome(&self, stage: &Stage) -> Option<String> {
        let _ = stage;
        None
    }
}
