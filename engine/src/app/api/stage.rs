//! The stage: the worlds a game shows, each with what the runner keeps for
//! it (label, trails, energy trace, what a failure does), the camera, the
//! step rate and the frame's look. Worlds are reached by the [`WorldId`]
//! their [`Stage::add_world`] returned, several at once with
//! [`Stage::worlds_mut`].

use core::fmt;

use glam::{Vec2, Vec3};

use crate::app::api::backend::Stepper;
use crate::app::api::draw::Viewport;
#[cfg(feature = "audio")]
use crate::app::audio::sound::Sound;
use crate::clock::Rate;
use crate::gpu_step::GpuStepError;
use crate::input::KeySet;
use crate::render::Gpu;
use crate::render::{Camera, Texture, Trails};
use crate::world::{Backend, Colour, Entity, World, WorldConfig};

use crate::app::api::stage_world::{EnergyTrace, OnFailure, StageWorld};

/// A world's handle on its stage, from [`Stage::add_world`]. A restart
/// builds a fresh stage, whose set-up hands out the same ids in the same
/// order; the default id is the first world's (a game with one world can
/// hold a `WorldId::default()` from the start).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct WorldId(usize);

impl WorldId {
    /// The world's place in [`Stage::worlds`].
    #[must_use]
    pub fn index(self) -> usize {
        self.0
    }
}

impl fmt::Display for WorldId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "world #{}", self.0)
    }
}

/// A [`WorldId`] the stage cannot give.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StageError {
    /// No world has this id on this stage (an id past its worlds, such as one
    /// kept from a larger stage; ids are indices, so an id of another stage
    /// that is in range names this stage's world of that index).
    Unknown {
        /// The id.
        id: WorldId,
        /// Worlds on the stage.
        worlds: usize,
    },
    /// The same world asked for twice in one [`Stage::worlds_mut`].
    Twice {
        /// The id.
        id: WorldId,
    },
}

impl fmt::Display for StageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Unknown { id, worlds } => write!(f, "{id} is not on this stage (it has {worlds} worlds)"),
            Self::Twice { id } => write!(f, "{id} was asked for twice in one worlds_mut"),
        }
    }
}

impl std::error::Error for StageError {}

/// Why [`Stage::read_back`] failed.
#[derive(Clone, Debug, PartialEq)]
pub enum ReadBackError {
    /// The id names no world of the stage.
    Stage(StageError),
    /// The world's state could not be read back from the GPU.
    Gpu {
        /// The world's label.
        world: String,
        /// Why.
        error: GpuStepError,
    },
}

impl fmt::Display for ReadBackError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Stage(e) => e.fmt(f),
            Self::Gpu { world, error } => write!(f, "world \"{world}\": {error}"),
        }
    }
}

impl std::error::Error for ReadBackError {}

/// What [`Game::setup`](crate::app::Game::setup) is told by the command line.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Settings {
    /// `--integrator`, as given (the runner also applies it to every world
    /// that does not fix its own integrator, and refuses it if every world
    /// fixes its integrator and a name is not one they run; default: none).
    pub integrator: Option<String>,
    /// `--seed` (default 0).
    pub seed: u64,
    /// Whether every player's input comes from a player: a networked
    /// match, or the replay of one (default false: only player 0's comes
    /// from this machine, and a game of more players drives or idles the
    /// others itself). The same on every peer, so a game may branch on it.
    pub networked: bool,
    /// `--gpu`: every world steps on the GPU (the runner sets each
    /// world's [`WorldConfig::backend`] after set-up; default false).
    pub gpu: bool,
}

impl Settings {
    /// A world configuration with this run's seed and integrator
    /// (`--integrator`'s name; the default method when none, or a list for a
    /// race, was given), so a world the game builds, or builds again on a
    /// restart, runs what the command line asked for.
    #[must_use]
    pub fn world_config(&self) -> WorldConfig {
        let mut config = WorldConfig {
            seed: self.seed,
            ..WorldConfig::default()
        };
        if let Some(name) = self.integrator.as_deref().filter(|names| !names.contains(',')) {
            name.trim().clone_into(&mut config.integrator);
        }
        if self.gpu {
            config.backend = Backend::Gpu;
        }
        config
    }
}

/// The worlds a game shows, the camera and the step rate.
#[derive(Debug)]
pub struct Stage {
    /// The worlds, stepped in order and drawn in one frame (reach one by
    /// the [`WorldId`] [`Stage::add_world`] gave).
    pub worlds: Vec<StageWorld>,
    /// What the view looks at (the window's mouse moves it).
    pub camera: Camera,
    /// Fixed steps per second (default 60 Hz; `--hz` overrides it).
    pub rate: Rate,
    /// The frame's clear colour, sRGB RGBA (default: near-black blue
    /// `[12, 14, 22, 255]`).
    pub background: Colour,
    /// HUD text size in pixels in frames 540 pixels high or more; smaller
    /// frames scale it down to 10/16 of it (default 16).
    pub hud_size: f32,
    /// Whether a window opens with the control panel shown (F1 toggles
    /// it; `--panel` and `--no-panel` override). Default false: a game's
    /// own screen; the physics lab's demos turn it on.
    pub panel: bool,
    /// Whether the viewer may switch the integrator of the worlds whose
    /// integrator is not fixed (Tab, keys 1-9, the panel). Default false: a
    /// game's keys are its own; the lab's demos turn it on.
    pub switch_integrators: bool,
    /// Draw the particles along cubic Hermite curves between steps (the
    /// shader's [`Interpolation::Hermite`](crate::interpolation::Interpolation),
    /// the runner passing the clock's current fixed step each frame)
    /// instead of straight lines: exact on a projectile's arc for methods
    /// whose step lies on it (velocity Verlet, RK4, ...); 12 more bytes
    /// uploaded per particle (default false).
    pub hermite: bool,
    /// What the run was started with (see [`Stage::settings`]).
    pub(crate) settings: Settings,
    /// The last frame drawn's size and scale (see [`Stage::viewport`]).
    pub(crate) viewport: Viewport,
    /// The runner's keys this game takes for itself (default none): P
    /// (pause), Tab and 1-9 (integrator), F1 (panel), F5 (restart), F12
    /// (screenshot), Escape (quit). A claimed key reaches the game; its
    /// control is then Ctrl and the key (Ctrl+Escape quits). Every other
    /// [`Key`](crate::input::Key) is the game's anyway.
    pub claimed_keys: KeySet,
    /// The sounds this tick's `fixed_update` asked for, in order.
    #[cfg(feature = "audio")]
    pub(crate) sounds_due: Vec<Sound>,
    /// The GPU the worlds on the GPU step on: the runner's (the one it
    /// draws with), or one of their own for a run that draws nothing.
    pub(crate) gpu: Option<Gpu>,
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
            background: [12, 14, 22, 255],
            hud_size: 16.0,
            panel: false,
            switch_integrators: false,
            hermite: false,
            settings: Settings::default(),
            viewport: Viewport::default(),
            claimed_keys: KeySet::EMPTY,
            #[cfg(feature = "audio")]
            sounds_due: Vec::new(),
            gpu: None,
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
    /// The command line's settings (seed, integrator), the same ones
    /// [`Game::setup`](crate::app::Game::setup) was given: a game that starts a
    /// level again from `fixed_update` builds it from these.
    #[must_use]
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Plays `sound`: call it from `fixed_update`, so the sound starts at
    /// the tick that asked for it, once, however often a rollback runs that
    /// tick again. It plays on the machine's audio device where there is
    /// one (a window run built with the `audio-device` feature), silently
    /// otherwise; either way [`GameSession::played_sounds`](crate::app::GameSession::played_sounds)
    /// lists it (a test asserts "the explosion started at tick 812").
    #[cfg(feature = "audio")]
    pub fn play(&mut self, sound: &Sound) {
        self.sounds_due.push(sound.clone());
    }

    /// The size and scale of the last frame drawn (before the first, 640 x
    /// 360): where a game's [`update`](crate::app::Game::update) places things
    /// by the window's shape. Not for `fixed_update`, whose results must
    /// not depend on the window (a replay has none).
    #[must_use]
    pub fn viewport(&self) -> Viewport {
        self.viewport
    }

    /// The world point (on the `z = 0` plane) under pixel `pixel` of the
    /// last frame (from its top left): the pointer in world units. `None`
    /// where the camera's view does not meet that plane.
    #[must_use]
    pub fn screen_to_world(&self, pixel: Vec2) -> Option<Vec2> {
        let v = self.viewport;
        self.camera.point_on_plane(pixel.x, pixel.y, v.width, v.height)
    }

    /// The pixel of the last frame (from its top left) at which the world
    /// point `at` is drawn; `None` behind an orbit camera.
    #[must_use]
    pub fn world_to_screen(&self, at: Vec3) -> Option<Vec2> {
        let v = self.viewport;
        self.camera.pixel_of(at, v.width, v.height)
    }

    /// The world rectangle (min, max) a 2D camera shows in the last frame
    /// (the field, for a letterboxed one): where a game wraps its ships
    /// around, or pins a score to a corner. `None` for an orbit camera.
    #[must_use]
    pub fn visible(&self) -> Option<(Vec2, Vec2)> {
        let v = self.viewport;
        self.camera.visible(v.width, v.height)
    }

    /// Adds a world labelled `label`; the builder it returns sets what the
    /// runner keeps for it and gives its [`WorldId`]:
    /// `let moon = stage.add_world("moon", world).follow(lander, colour).id();`
    pub fn add_world(&mut self, label: impl Into<String>, world: World) -> WorldBuilder<'_> {
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
            sprite: None,
            layer: None,
            stepper: Stepper::default(),
        });
        let index = self.worlds.len() - 1;
        WorldBuilder { stage: self, index }
    }

    /// The world `id` with what the runner keeps for it.
    ///
    /// # Errors
    /// [`StageError::Unknown`] for an id past this stage's worlds.
    pub fn shown(&self, id: WorldId) -> Result<&StageWorld, StageError> {
        let worlds = self.worlds.len();
        self.worlds.get(id.0).ok_or(StageError::Unknown { id, worlds })
    }

    /// The world `id` with what the runner keeps for it, to change.
    ///
    /// # Errors
    /// [`StageError::Unknown`] for an id past this stage's worlds.
    pub fn shown_mut(&mut self, id: WorldId) -> Result<&mut StageWorld, StageError> {
        let worlds = self.worlds.len();
        self.worlds.get_mut(id.0).ok_or(StageError::Unknown { id, worlds })
    }

    /// The world `id`.
    ///
    /// # Errors
    /// [`StageError::Unknown`] for an id past this stage's worlds.
    pub fn world(&self, id: WorldId) -> Result<&World, StageError> {
        self.shown(id).map(|shown| &shown.world)
    }

    /// The world `id`, to change.
    ///
    /// # Errors
    /// [`StageError::Unknown`] for an id past this stage's worlds.
    pub fn world_mut(&mut self, id: WorldId) -> Result<&mut World, StageError> {
        self.shown_mut(id).map(|shown| &mut shown.world)
    }

    /// The world `id`, its particles read back first if it steps on the
    /// GPU (their positions and velocities live there): for a game that
    /// reads them (a score from positions, a snapshot). Costs a copy of
    /// the state (48 bytes a particle) and a wait for the GPU; a world on
    /// the CPU is returned as it is.
    ///
    /// # Errors
    /// [`ReadBackError`] for an unknown id or a failed read-back.
    pub fn read_back(&mut self, id: WorldId) -> Result<&World, ReadBackError> {
        let gpu = self.gpu.as_ref();
        let worlds = self.worlds.len();
        let shown = self
            .worlds
            .get_mut(id.0)
            .ok_or(ReadBackError::Stage(StageError::Unknown { id, worlds }))?;
        shown.sync(gpu).map_err(|error| ReadBackError::Gpu {
            world: shown.label.clone(),
            error,
        })?;
        Ok(&shown.world)
    }

    /// Reads every world on the GPU back (see [`read_back`](Self::read_back)).
    pub(crate) fn read_back_all(&mut self) -> Result<(), ReadBackError> {
        let gpu = self.gpu.as_ref();
        for shown in &mut self.worlds {
            shown.sync(gpu).map_err(|error| ReadBackError::Gpu {
                world: shown.label.clone(),
                error,
            })?;
        }
        Ok(())
    }

    /// Several worlds at once, to change together (a ball passing from one
    /// world to another): `let [a, b] = stage.worlds_mut([left, right])?;`
    ///
    /// # Errors
    /// [`StageError`] for an id past this stage's worlds or one given twice.
    pub fn worlds_mut<const N: usize>(&mut self, ids: [WorldId; N]) -> Result<[&mut World; N], StageError> {
        let worlds = self.worlds.len();
        for (k, id) in ids.iter().enumerate() {
            if id.0 >= worlds {
                return Err(StageError::Unknown { id: *id, worlds });
            }
            if ids[..k].contains(id) {
                return Err(StageError::Twice { id: *id });
            }
        }
        let shown = self
            .worlds
            .get_disjoint_mut(ids.map(|id| id.0))
            .map_err(|_| StageError::Twice { id: ids[0] })?;
        Ok(shown.map(|s| &mut s.world))
    }

    /// Draws a trail behind `entity` of world `id`, in `colour`.
    ///
    /// # Errors
    /// [`StageError::Unknown`] for an id past this stage's worlds.
    pub fn follow(&mut self, id: WorldId, entity: Entity, colour: Colour) -> Result<(), StageError> {
        self.shown_mut(id)?.trails.follow(entity, colour);
        Ok(())
    }
}

/// What [`Stage::add_world`] returns: settings for the world just added
/// (each applied at once, so the builder may be dropped after any), then
/// its [`id`](Self::id).
#[derive(Debug)]
pub struct WorldBuilder<'a> {
    stage: &'a mut Stage,
    index: usize,
}

impl WorldBuilder<'_> {
    fn shown(&mut self) -> &mut StageWorld {
        &mut self.stage.worlds[self.index]
    }

    /// Its colour in legends and the panel's energy plot (default: the
    /// next of eight).
    pub fn colour(mut self, colour: Colour) -> Self {
        self.shown().colour = colour;
        self
    }

    /// The integrator belongs to the game (an integrator race):
    /// `--integrator`, the integrator keys and the panel leave it alone.
    pub fn fixed_integrator(mut self) -> Self {
        self.shown().fixed_integrator = true;
        self
    }

    /// What a failed step does (default [`OnFailure::Stop`]).
    pub fn on_failure(mut self, on_failure: OnFailure) -> Self {
        self.shown().on_failure = on_failure;
        self
    }

    /// Trails kept `points` long (default 240).
    pub fn trail_length(mut self, points: usize) -> Self {
        self.shown().trails = Trails::new(points);
        self
    }

    /// Draws its particles as `texture`, each as wide as its disc, tinted
    /// by its colour and turned by its heading (a rain of coins, a field
    /// of asteroids).
    pub fn sprites(mut self, texture: &Texture) -> Self {
        self.shown().sprite = Some(texture.clone());
        self
    }

    /// Draws its particles, trails and outlines after the shapes of
    /// `layer` and before those of higher layers, whatever the frame's
    /// [`Draw::particle_layer`](crate::app::Draw::particle_layer): a background
    /// world of stars under the game's shapes, sparks over them.
    pub fn layer(mut self, layer: i32) -> Self {
        self.shown().layer = Some(layer);
        self
    }

    /// Draws a trail behind `entity` in `colour`.
    pub fn follow(mut self, entity: Entity, colour: Colour) -> Self {
        self.shown().trails.follow(entity, colour);
        self
    }

    /// The world's id, to keep.
    #[must_use]
    pub fn id(self) -> WorldId {
        WorldId(self.index)
    }
}
