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

use crate::clock::{FixedStep, Frame, Rate};
use crate::render::{Camera, Line, Trails};
use crate::step::SimulationError;
use crate::world::{Colour, Entity, World};

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

/// A world on the stage, with what the runner keeps for it.
#[derive(Debug)]
pub struct StageWorld {
    /// Shown in the legend, the panel and error messages.
    pub label: String,
    /// The world.
    pub world: World,
    /// Its trails (none followed by default).
    pub trails: Trails,
    /// Its colour in the panel's energy plot and legends.
    pub colour: Colour,
    /// Whether the integrator belongs to the game (an integrator race), so
    /// `--integrator`, Tab, 1-9 and the panel leave it alone (default false).
    pub fixed_integrator: bool,
    /// Relative energy error since set-up, sampled by the runner.
    pub energy: EnergyTrace,
    /// What a failed step does (default [`OnFailure::Stop`]).
    pub on_failure: OnFailure,
    /// Why the world stopped, under [`OnFailure::Freeze`] (`None` while it runs).
    pub failure: Option<String>,
    /// The state before the current step, kept under [`OnFailure::Freeze`].
    pub(crate) last_good: Option<crate::world::Snapshot>,
}

/// What happens when a world's step fails (an explicit method blowing up
/// on stiff springs, an implicit solve that does not converge).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OnFailure {
    /// The run stops with the error (default): a game's world must not fail.
    #[default]
    Stop,
    /// The world goes back to its state before the failed step and stops
    /// there, with [`StageWorld::failure`] saying why; the others go on
    /// (an integrator race, a stability demonstration). Switching its
    /// integrator resumes it. Costs a snapshot per step.
    Freeze,
}

/// The relative energy error `(E - E0) / |E0|` of a world over recent
/// steps, for plots and legends.
#[derive(Clone, Debug, Default)]
pub struct EnergyTrace {
    initial: Option<f64>,
    /// `(time, relative error)` samples, oldest first, at most [`EnergyTrace::CAPACITY`].
    samples: std::collections::VecDeque<(f64, f64)>,
}

impl EnergyTrace {
    /// Samples kept.
    pub const CAPACITY: usize = 600;

    /// Records the world's energy now (the first call sets `E0`).
    pub fn sample(&mut self, world: &mut World) {
        let energy = world.energy().total();
        let initial = *self.initial.get_or_insert(energy);
        let error = if initial.abs() > 1e-12 {
            (energy - initial) / initial.abs()
        } else {
            energy - initial
        };
        if self.samples.len() == Self::CAPACITY {
            self.samples.pop_front();
        }
        self.samples.push_back((world.time(), error));
    }

    /// The latest relative error (0 before any sample).
    #[must_use]
    pub fn latest(&self) -> f64 {
        self.samples.back().map_or(0.0, |s| s.1)
    }

    /// The samples, oldest first.
    pub fn samples(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.samples.iter().copied()
    }
}

/// The worlds a game shows, the camera and the step rate.
#[derive(Debug)]
pub struct Stage {
    /// The worlds, stepped in order and drawn in one frame.
    pub worlds: Vec<StageWorld>,
    /// What the view looks at (the window's mouse moves it).
    pub camera: Camera,
    /// Fixed steps per second (default 60 Hz; `--hz` overrides it).
    pub rate: Rate,
}

impl Default for Stage {
    fn default() -> Self {
        Self {
            worlds: Vec::new(),
            camera: Camera::TwoD {
                center: glam::Vec2::ZERO,
                height: 10.0,
            },
            rate: Rate::hz(60).unwrap_or_else(|_| unreachable!("60 Hz is a valid rate")),
        }
    }
}

/// Default colours of worlds added without one (the panel's plot lines).
const PALETTE: [Colour; 8] = [
    [240, 90, 80, 255],
    [250, 190, 60, 255],
    [120, 210, 90, 255],
    [70, 200, 220, 255],
    [100, 140, 250, 255],
    [200, 110, 240, 255],
    [240, 120, 190, 255],
    [220, 220, 220, 255],
];

impl Stage {
    /// Adds a world labelled `label` and returns its index in [`Stage::worlds`].
    pub fn add_world(&mut self, label: impl Into<String>, world: World) -> usize {
        let colour = PALETTE[self.worlds.len() % PALETTE.len()];
        self.worlds.push(StageWorld {
            label: label.into(),
            world,
            trails: Trails::new(240),
            colour,
            fixed_integrator: false,
            energy: EnergyTrace::default(),
            on_failure: OnFailure::Stop,
            failure: None,
            last_good: None,
        });
        self.worlds.len() - 1
    }

    /// The world at `index`.
    ///
    /// # Panics
    /// If no world was added at `index` (a bug in the game, not bad input).
    #[must_use]
    pub fn world(&self, index: usize) -> &World {
        &self.worlds[index].world
    }

    /// The world at `index`, to change.
    ///
    /// # Panics
    /// If no world was added at `index`.
    pub fn world_mut(&mut self, index: usize) -> &mut World {
        &mut self.worlds[index].world
    }

    /// Draws a trail behind `entity` of world `index`, in `colour`.
    ///
    /// # Panics
    /// If no world was added at `index`.
    pub fn follow(&mut self, index: usize, entity: Entity, colour: Colour) {
        self.worlds[index].trails.follow(entity, colour);
    }
}

/// What a game draws on top of its worlds this frame.
#[derive(Debug, Default)]
pub struct Draw {
    /// Line segments in world space.
    pub lines: Vec<Line>,
    /// HUD text, top-left (`write!` into it).
    pub hud: String,
    /// Colour changes in `hud`: (byte offset, colour); see [`Draw::colour`].
    pub hud_colours: Vec<(usize, Colour)>,
}

impl Draw {
    /// Adds a segment from `a` to `b`.
    pub fn line(&mut self, a: glam::Vec3, b: glam::Vec3, colour: Colour) {
        self.lines.push(Line { a, b, colour });
    }

    /// Adds segments joining `points` in order; `closed` joins the last to the first.
    pub fn polyline(&mut self, points: &[glam::Vec3], colour: Colour, closed: bool) {
        for pair in points.windows(2) {
            self.line(pair[0], pair[1], colour);
        }
        if closed && points.len() > 2 {
            self.line(points[points.len() - 1], points[0], colour);
        }
    }

    /// HUD text written from now on is drawn in `colour` (a legend's entries).
    pub fn colour(&mut self, colour: Colour) {
        self.hud_colours.push((self.hud.len(), colour));
    }

    pub(crate) fn clear(&mut self) {
        self.lines.clear();
        self.hud.clear();
        self.hud_colours.clear();
    }
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

    /// Lines and HUD text for this frame; `alpha` is the interpolation
    /// factor the worlds are drawn at.
    fn draw(&self, stage: &Stage, alpha: f32, draw: &mut Draw) {
        let _ = (stage, alpha, draw);
    }

    /// A line printed when a run ends (score, outcome); none by default.
    fn outcome(&self, stage: &Stage) -> Option<String> {
        let _ = stage;
        None
    }
}
