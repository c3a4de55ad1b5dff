//! A game in play: its stage, the clock, the keyboard state turned into
//! per-tick input, and the recording or replay of that input.
//!
//! Per frame: the clock turns the frame's duration into fixed steps; each
//! step takes the tick's input (live keys, or the replayed recording), calls
//! [`Game::fixed_update`], then steps every world of the stage and samples
//! its energy. [`Game::update`] then runs once for the frame.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::draw::{Draw, Viewport};
use super::game::{Game, GameError, Key, KeySet, Settings, TickInput};
use super::stage::{OnFailure, Stage};
use super::{Control, FrameSource, RunError};
use crate::clock::{ClockConfig, FixedClock, Frame, Rate};
use crate::render::{Camera, FrameView, RenderError, WorldView};
use tickwork_integrators::{METHODS, UnknownMethod, build};

/// Worlds up to this many particles sample their energy every step; larger
/// ones every 30 steps (an energy sum costs as much as a step).
const ENERGY_EVERY_STEP: usize = 4_000;

/// The inputs of a run, by tick, with what a replay needs to repeat it.
/// A misspelt field is an error (`integrater: Some("rk4")` once left the
/// replay on the default integrator in silence).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Recording {
    /// The game's title.
    pub game: String,
    /// Fixed steps per second of the recorded run.
    pub hz: f64,
    /// The seed of the recorded run.
    pub seed: u64,
    /// `--integrator` of the recorded run.
    pub integrator: Option<String>,
    /// Ticks the recording covers.
    pub ticks: u64,
    /// `(tick, input)` for every tick whose input differs from the previous
    /// tick's carried over (keys held unchanged, none newly pressed).
    pub inputs: Vec<(u64, TickInput)>,
}

impl Recording {
    /// Reads a recording written by a run with `--record`.
    ///
    /// # Errors
    /// [`RunError::Io`] naming the file, with the line and column of a
    /// malformed one.
    pub fn load(path: &Path) -> Result<Self, RunError> {
        let text = crate::text_file::read_limited(path, Self::MAX_FILE_BYTES, "Recording::MAX_FILE_BYTES")
            .map_err(|e| RunError::io(path, &e))?;
        Self::parse(&text, path)
    }

    /// Parses and range-checks recording text; `path` names it in errors.
    ///
    /// # Errors
    /// [`RunError::Io`] naming `path`, with the line and column of the fault.
    pub fn parse(text: &str, path: &Path) -> Result<Self, RunError> {
        let recording: Self = ron::from_str(text).map_err(|e| RunError::Io {
            path: path.to_path_buf(),
            message: format!(
                "line {}, column {}: {} (not a Tickwork input recording?)",
                e.span.start.line, e.span.start.col, e.code
            ),
        })?;
        recording.check().map_err(|(field, message)| {
            let (line, column) = field_position(text, field);
            RunError::Io {
                path: path.to_path_buf(),
                message: format!("line {line}, column {column}: {field}: {message}"),
            }
        })?;
        Ok(recording)
    }

    /// The largest recording read: 256 MiB (hours of input changing every
    /// tick; a recording stores only the ticks whose input changed).
    pub const MAX_FILE_BYTES: u64 = 256 << 20;

    /// The most ticks a recording may cover: a billion (over six months at
    /// 60 Hz). Past it a replay could not be drawn in any reasonable number
    /// of frames; record shorter runs.
    pub const MAX_TICKS: u64 = 1_000_000_000;

    /// Range-checks every field: the field's name and what is wrong.
    fn check(&self) -> Result<(), (&'static str, String)> {
        Rate::hz_f64(self.hz).map_err(|e| match e {
            crate::clock::ClockError::InvalidRate { expected, .. } => (
                "hz",
                format!(
                    "{} steps per second (accepted: {expected})",
                    crate::clock::Number(self.hz)
                ),
            ),
            other => ("hz", other.to_string()),
        })?;
        if self.ticks > Self::MAX_TICKS {
            return Err((
                "ticks",
                format!(
                    "{} is past the limit of {} recorded ticks (Recording::MAX_TICKS); record a shorter run",
                    self.ticks,
                    Self::MAX_TICKS
                ),
            ));
        }
        let mut previous = None;
        for (k, (tick, _)) in self.inputs.iter().enumerate() {
            if *tick >= self.ticks || previous.is_some_and(|p| *tick <= p) {
                return Err((
                    "inputs",
                    format!(
                        "entry {k} is at tick {tick}: ticks must rise and stay below the recording's {} ticks",
                        self.ticks
                    ),
                ));
            }
            previous = Some(*tick);
        }
        Ok(())
    }

    /// Writes the recording as RON.
    ///
    /// # Errors
    /// [`RunError::Exists`] if the file exists and `overwrite` is off,
    /// [`RunError::Io`] if it cannot be written.
    pub fn save(&self, path: &Path, overwrite: bool) -> Result<(), RunError> {
        if path.exists() && !overwrite {
            return Err(RunError::Exists(path.to_path_buf()));
        }
        let text = ron::ser::to_string_pretty(
            self,
            ron::ser::PrettyConfig::default().struct_names(true).depth_limit(2),
        )
        .map_err(|e| RunError::io(path, &e))?;
        std::fs::write(path, text).map_err(|e| RunError::io(path, &e))
    }
}

/// Line and column (from 1) of the first `field:` in a RON text, or of the
/// start when it is not found.
fn field_position(text: &str, field: &str) -> (usize, usize) {
    let key = format!("{field}:");
    let offset = text
        .match_indices(&key)
        .find(|(i, _)| {
            text[..*i]
                .chars()
                .next_back()
                .is_none_or(|c| !(c.is_alphanumeric() || c == '_'))
        })
        .map_or(0, |(i, _)| i);
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |n| n + 1) + 1;
    (line, column)
}

/// Where the session's per-tick input comes from.
#[derive(Debug)]
enum InputMode {
    /// The keyboard; recorded if `record` is set.
    Live { record: Option<(Recording, PathBuf)> },
    /// A recording, replayed from `cursor`.
    Replay { recording: Recording, cursor: usize },
}

/// What a [`GameSession`] is started with.
#[derive(Clone, Debug)]
pub struct SessionOptions {
    /// Passed to [`Game::setup`].
    pub settings: Settings,
    /// Fixed steps per second, overriding the stage's rate (default: none).
    pub hz: Option<f64>,
    /// Simulated seconds per real second (default 1).
    pub time_scale: f64,
    /// Record inputs to this file at the end of the run (default: none).
    pub record: Option<PathBuf>,
    /// Replay this recording instead of the keyboard (default: none).
    pub replay: Option<Recording>,
    /// Overwrite the recording file if it exists (default false).
    pub overwrite: bool,
}

impl Default for SessionOptions {
    fn default() -> Self {
        Self {
            settings: Settings {
                integrator: None,
                seed: 0,
            },
            hz: None,
            time_scale: 1.0,
            record: None,
            replay: None,
            overwrite: false,
        }
    }
}

/// A game, its stage and its clock: the per-frame path both runners share.
pub struct GameSession<G: Game> {
    game: G,
    stage: Stage,
    options: SessionOptions,
    clock: FixedClock,
    last: Frame,
    /// Keys down now, and keys pressed since the last step began.
    held: KeySet,
    pressed: KeySet,
    /// The last step's input, carried into the next.
    input: TickInput,
    mode: InputMode,
    draw: Draw,
    frame_rate: super::playback::FrameRate,
    /// Whether the replay has run out (reported once).
    replay_done: bool,
    /// Drawn when the stage has no world (a game of lines only).
    empty: crate::world::World,
}

impl<G: Game> std::fmt::Debug for GameSession<G> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GameSession")
            .field("game", &self.game.title())
            .field("tick", &self.clock.tick())
            .field("worlds", &self.stage.worlds.len())
            .finish_non_exhaustive()
    }
}

impl<G: Game> GameSession<G> {
    /// Sets `game` up on a fresh stage.
    ///
    /// # Errors
    /// [`RunError::Game`] for a set-up that fails or an unknown integrator,
    /// [`RunError::Playback`] for a rate or time scale the clock refuses,
    /// [`RunError::Exists`] if the recording file exists (and overwriting
    /// was not asked for: checked now, not after the run).
    pub fn new(game: G, mut options: SessionOptions) -> Result<Self, RunError> {
        if let Some(recording) = &options.replay {
            if recording.game != game.title() {
                return Err(RunError::Game(GameError::Message(format!(
                    "the recording is of \"{}\", not \"{}\"",
                    recording.game,
                    game.title()
                ))));
            }
            // A replay repeats the recorded run's rate, seed and integrator.
            let conflicts = [
                ("--hz", options.hz.is_some_and(|hz| hz != recording.hz)),
                (
                    "--seed",
                    options.settings.seed != 0 && options.settings.seed != recording.seed,
                ),
                (
                    "--integrator",
                    options.settings.integrator.is_some() && options.settings.integrator != recording.integrator,
                ),
            ];
            if let Some((flag, _)) = conflicts.iter().find(|c| c.1) {
                return Err(RunError::Game(GameError::Message(format!(
                    "{flag} differs from the recording's (hz {}, seed {}, integrator {}); a replay runs with the \
                     recorded settings",
                    recording.hz,
                    recording.seed,
                    recording.integrator.as_deref().unwrap_or("default")
                ))));
            }
            options.hz = Some(recording.hz);
            options.settings.seed = recording.seed;
            options.settings.integrator.clone_from(&recording.integrator);
        }
        if let Some(path) = &options.record
            && path.exists()
            && !options.overwrite
        {
            return Err(RunError::Exists(path.clone()));
        }
        if let Some(names) = &options.settings.integrator {
            for name in names.split(',') {
                build::<glam::Vec3A>(name.trim()).map_err(|e| RunError::Game(GameError::Message(e.to_string())))?;
            }
        }
        let mode = match options.replay.take() {
            Some(recording) => InputMode::Replay { recording, cursor: 0 },
            None => InputMode::Live { record: None },
        };
        // Replaced by `restart` with the stage's rate; the time scale carries over.
        let mut clock = FixedClock::new(ClockConfig {
            time_scale: options.time_scale,
            ..ClockConfig::default()
        })?;
        let last = clock.advance(0.0)?;
        let mut session = Self {
            game,
            stage: Stage::default(),
            options,
            clock,
            last,
            held: KeySet::EMPTY,
            pressed: KeySet::EMPTY,
            input: TickInput::default(),
            mode,
            draw: Draw::default(),
            frame_rate: super::playback::FrameRate::default(),
            replay_done: false,
            empty: crate::world::World::default(),
        };
        session.restart()?;
        Ok(session)
    }

    /// Builds the stage afresh and restarts the clock (and the recording).
    fn restart(&mut self) -> Result<(), RunError> {
        let mut stage = Stage::default();
        self.game
            .setup(&mut stage, &self.options.settings)
            .map_err(RunError::Game)?;
        let rate = match self.options.hz {
            Some(hz) => Rate::hz_f64(hz)?,
            None => stage.rate,
        };
        stage.rate = rate;
        if let Some(name) = &self.options.settings.integrator {
            for shown in stage.worlds.iter_mut().filter(|w| !w.fixed_integrator) {
                shown
                    .world
                    .set_integrator(name)
                    .map_err(|e| RunError::Game(GameError::Message(e.to_string())))?;
            }
        }
        for shown in &mut stage.worlds {
            shown.energy.sample(&mut shown.world);
        }
        self.clock = FixedClock::new(ClockConfig {
            rate,
            time_scale: self.clock.config().time_scale,
            ..ClockConfig::default()
        })?;
        self.last = self.clock.advance(0.0)?;
        self.stage = stage;
        self.input = TickInput::default();
        match &mut self.mode {
            InputMode::Live { record } => {
                *record = self.options.record.clone().map(|path| {
                    (
                        Recording {
                            game: self.game.title().to_owned(),
                            hz: rate.hz_value(),
                            seed: self.options.settings.seed,
                            integrator: self.options.settings.integrator.clone(),
                            ticks: 0,
                            inputs: Vec::new(),
                        },
                        path,
                    )
                });
            }
            InputMode::Replay { cursor, .. } => *cursor = 0,
        }
        self.replay_done = false;
        Ok(())
    }

    /// The game.
    pub fn game(&self) -> &G {
        &self.game
    }

    /// The stage.
    pub fn stage(&self) -> &Stage {
        &self.stage
    }

    /// The stage, to change between frames.
    pub fn stage_mut(&mut self) -> &mut Stage {
        &mut self.stage
    }

    /// The clock.
    pub fn clock(&self) -> &FixedClock {
        &self.clock
    }

    /// The clock, for the panel's rate and time scale.
    pub(super) fn clock_mut(&mut self) -> &mut FixedClock {
        &mut self.clock
    }

    /// The last frame's report.
    pub fn last_frame(&self) -> &Frame {
        &self.last
    }

    /// Whether the keys are being recorded (the panel then keeps the rate,
    /// which a recording stores once).
    pub fn is_recording(&self) -> bool {
        matches!(self.mode, InputMode::Live { record: Some(_) })
    }

    /// The recording being replayed, if any, and whether it has run out.
    pub fn replay(&self) -> Option<(&Recording, bool)> {
        match &self.mode {
            InputMode::Replay { recording, .. } => Some((recording, self.replay_done)),
            InputMode::Live { .. } => None,
        }
    }

    /// A key went down (`down`) or up, from the window; ignored while a
    /// recording is replayed.
    pub fn key(&mut self, key: Key, down: bool) {
        if matches!(self.mode, InputMode::Replay { .. }) {
            return;
        }
        if down {
            if !self.held.contains(key) {
                self.pressed.insert(key);
            }
            self.held.insert(key);
        } else {
            self.held.remove(key);
        }
    }

    /// The input of `tick`: replayed, or taken from the keyboard (and recorded).
    fn tick_input(&mut self, tick: u64) -> TickInput {
        let carried = self.input.carried();
        let input = match &mut self.mode {
            InputMode::Replay { recording, cursor } => {
                let mut input = carried;
                while let Some((at, recorded)) = recording.inputs.get(*cursor) {
                    if *at > tick {
                        break;
                    }
                    if *at == tick {
                        input = *recorded;
                    }
                    *cursor += 1;
                }
                if tick >= recording.ticks && !self.replay_done {
                    self.replay_done = true;
                    println!("tickwork: the replay ended at tick {tick}; the keyboard is ignored");
                }
                input
            }
            InputMode::Live { record } => {
                let input = TickInput {
                    held: self.held,
                    pressed: self.pressed,
                };
                self.pressed = KeySet::EMPTY;
                if let Some((recording, _)) = record {
                    if input != carried {
                        recording.inputs.push((tick, input));
                    }
                    recording.ticks = tick + 1;
                }
                input
            }
        };
        self.input = input;
        input
    }

    /// Writes the recording, if one was asked for; returns its path.
    ///
    /// # Errors
    /// [`RunError::Exists`] or [`RunError::Io`] for the file.
    pub fn save_recording(&self) -> Result<Option<PathBuf>, RunError> {
        match &self.mode {
            InputMode::Live {
                record: Some((recording, path)),
            } => {
                recording.save(path, self.options.overwrite)?;
                Ok(Some(path.clone()))
            }
            _ => Ok(None),
        }
    }

    /// The game's outcome line, if it has one.
    pub fn outcome(&self) -> Option<String> {
        self.game.outcome(&self.stage)
    }

    /// Applies a control to every world whose integrator is not the game's.
    fn set_integrators(&mut self, choose: impl Fn(&str) -> Option<&'static str>) -> Result<(), RunError> {
        if !self.stage.switch_integrators {
            return Ok(());
        }
        for shown in self.stage.worlds.iter_mut().filter(|w| !w.fixed_integrator) {
            if let Some(name) = choose(shown.world.integrator().info().name) {
                shown
                    .world
                    .set_integrator(name)
                    .map_err(|e| RunError::Game(GameError::Message(e.to_string())))?;
                shown.failure = None;
            }
        }
        Ok(())
    }

    /// Smoothed frames per second.
    pub fn fps(&self) -> f64 {
        self.frame_rate.fps()
    }
}

impl<G: Game> FrameSource for GameSession<G> {
    fn title(&self) -> String {
        self.game.title().to_owned()
    }

    fn advance(&mut self, seconds: f64) -> Result<(), RunError> {
        let frame = self.clock.advance(seconds)?;
        self.frame_rate.record(seconds);
        for step in frame.fixed_steps() {
            let input = self.tick_input(step.tick);
            self.game
                .fixed_update(&mut self.stage, &step, &input)
                .map_err(RunError::Game)?;
            for shown in &mut self.stage.worlds {
                if shown.failure.is_some() {
                    continue;
                }
                if shown.on_failure == OnFailure::Freeze {
                    match &mut shown.last_good {
                        Some(snapshot) => shown.world.snapshot_into(snapshot),
                        None => shown.last_good = Some(shown.world.snapshot()),
                    }
                }
                if let Err(error) = shown.world.step(step) {
                    match (shown.on_failure, &shown.last_good) {
                        (OnFailure::Freeze, Some(snapshot)) => {
                            shown.world.restore(snapshot);
                            shown.failure = Some(format!("failed at t = {:.2} s: {error}", step.time));
                            continue;
                        }
                        _ => {
                            return Err(RunError::Game(GameError::Simulation {
                                world: shown.label.clone(),
                                error,
                            }));
                        }
                    }
                }
                shown.trails.record(&shown.world);
                if shown.world.len() <= ENERGY_EVERY_STEP || step.tick % 30 == 0 {
                    shown.energy.sample(&mut shown.world);
                }
            }
        }
        self.last = frame;
        self.game.update(&mut self.stage, &self.last);
        Ok(())
    }

    fn control(&mut self, control: Control) -> Result<(), RunError> {
        match control {
            Control::TogglePause | Control::SingleStep | Control::Faster | Control::Slower => {
                super::playback::clock_control(&mut self.clock, control)?;
            }
            Control::NextIntegrator => self.set_integrators(|current| {
                let index = METHODS.iter().position(|m| m.name == current).map_or(0, |i| i + 1);
                Some(METHODS[index % METHODS.len()].name)
            })?,
            Control::Integrator(n) => {
                let Some(info) = METHODS.get(n) else {
                    return Err(RunError::Game(GameError::Message(
                        UnknownMethod::new(&format!("#{}", n + 1)).to_string(),
                    )));
                };
                self.set_integrators(|_| Some(info.name))?;
            }
            Control::Reset => self.restart()?,
        }
        Ok(())
    }

    fn key(&mut self, key: Key, down: bool) -> bool {
        GameSession::key(self, key, down);
        true
    }

    fn ticks(&self) -> u64 {
        self.clock.tick()
    }

    fn camera_mut(&mut self) -> &mut Camera {
        &mut self.stage.camera
    }

    fn with_view(
        &mut self,
        hud: bool,
        (width, height): (u32, u32),
        render: &mut dyn FnMut(&FrameView<'_>) -> Result<(), RenderError>,
    ) -> Result<(), RunError> {
        let alpha = self.last.alpha as f32;
        self.draw.clear(Viewport {
            width,
            height,
            pixels_per_metre: self.stage.camera.matrices(width, height).pixels_per_unit,
        });
        self.game
            .draw(&self.stage, alpha, &mut self.draw)
            .map_err(RunError::Game)?;
        if !hud {
            self.draw.hud.clear();
            self.draw.hud_colours.clear();
        }
        let (first, rest) = match self.stage.worlds.split_first() {
            Some((first, rest)) => (Some(first), rest),
            None => (None, &[][..]),
        };
        let others: Vec<WorldView<'_>> = rest
            .iter()
            .map(|w| WorldView {
                world: &w.world,
                trails: Some(&w.trails),
            })
            .collect();
        let view = FrameView {
            trails: first.map(|w| &w.trails),
            others: &others,
            lines: &self.draw.lines,
            triangles: &self.draw.triangles,
            texts: &self.draw.texts,
            hud: &self.draw.hud,
            hud_colours: &self.draw.hud_colours,
            ..FrameView::new(first.map_or(&self.empty, |w| &w.world), alpha, self.stage.camera)
        };
        render(&view)?;
        Ok(())
    }

    fn panel(&mut self, ctx: &egui::Context) -> Result<(), RunError> {
        super::panel::show(self, ctx)
    }
}
