//! A game in play: its stage, the clock, the player's input turned into
//! per-tick input, and the recording or replay of that input.
//!
//! Per frame: the clock turns the frame's duration into fixed steps and the
//! frame's input events get their simulated times; each step applies the
//! recorded controls of its tick (replay), takes the tick's input (the
//! events of its time window, or the recording's), calls
//! [`Game::fixed_update`], then steps every world of the stage and samples
//! its energy. [`Game::update`] then runs once for the frame.

use std::path::PathBuf;

use crate::app::api::backend::{StepFailure, on_gpu};
use crate::app::api::control::{Control, chosen_integrator};
use crate::app::api::draw::Draw;
use crate::app::api::error::RunError;
use crate::app::api::game::{Game, GameError};
use crate::app::api::stage::Stage;
#[cfg(feature = "audio")]
use crate::app::audio::mixer::{Audio, Played};
use crate::app::session::frame_rate::FrameRate;
use crate::app::session::options::SessionOptions;
use crate::app::session::source::FrameSource;
use crate::clock::{ClockConfig, FixedClock, Frame, Rate};
use crate::input::{InputEvent, InputQueue, Key, RecordedControl, Recording, TickInput};
use crate::world::Backend;
use tickwork_integrators::build;

/// Where the session's per-tick input comes from.
#[derive(Debug)]
pub(super) enum InputMode {
    /// The player; recorded if `record` is set.
    Live { record: Option<(Recording, PathBuf)> },
    /// A recording, replayed from `cursors` (inputs, by player) and
    /// `next_control`.
    Replay {
        recording: Recording,
        cursors: Vec<usize>,
        next_control: usize,
    },
}

/// A game, its stage and its clock: the per-frame path both runners share.
pub struct GameSession<G: Game> {
    pub(super) game: G,
    pub(super) stage: Stage,
    pub(super) options: SessionOptions,
    pub(super) clock: FixedClock,
    pub(super) last: Frame,
    /// The player's events, waiting for the steps of their time.
    pub(super) queue: InputQueue,
    /// The last step's input of every player, carried into the next.
    pub(super) inputs: Vec<TickInput>,
    pub(super) mode: InputMode,
    pub(super) draw: Draw,
    pub(super) frame_rate: FrameRate,
    /// Whether the replay has run out (reported once).
    pub(super) replay_done: bool,
    /// Drawn when the stage has no world (a game of lines only).
    pub(super) empty: crate::world::World,
    /// The sounds started, and the device they play on, if any.
    #[cfg(feature = "audio")]
    pub(super) audio: Audio,
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
            options.settings.networked = recording.players() > 1;
        }
        let players = game.players();
        let recorded = options.replay.as_ref().map_or(1, Recording::players);
        if !(1..=Recording::MAX_PLAYERS).contains(&players) || recorded > players {
            return Err(RunError::Game(GameError::Message(format!(
                "\"{}\" has {players} players{}: a game has 1 to {} (Recording::MAX_PLAYERS)",
                game.title(),
                if recorded > players {
                    format!(", but the recording holds {recorded}")
                } else {
                    String::new()
                },
                Recording::MAX_PLAYERS
            ))));
        }
        if let Some(path) = &options.record
            && path.exists()
            && !options.overwrite
        {
            return Err(RunError::Exists(path.clone()));
        }
        if let Some(names) = &options.settings.integrator {
            for name in names.split(',') {
                build::<glam::Vec3A>(name.trim())?;
            }
        }
        let mode = match options.replay.take() {
            Some(recording) => InputMode::Replay {
                recording,
                cursors: vec![0; players],
                next_control: 0,
            },
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
            queue: InputQueue::default(),
            inputs: vec![TickInput::default(); players],
            mode,
            draw: Draw::default(),
            frame_rate: FrameRate::default(),
            replay_done: false,
            empty: crate::world::World::default(),
            #[cfg(feature = "audio")]
            audio: Audio::silent(),
        };
        session.restart()?;
        Ok(session)
    }

    /// Refuses `--integrator` that no world of `stage` takes: every world
    /// fixes its integrator and `names` are not the ones they run (a game
    /// that races the named integrators, such as orbits, runs exactly
    /// those; any other would ignore the option silently).
    pub(super) fn check_fixed_integrators(&self, stage: &Stage, names: &str) -> Result<(), RunError> {
        // A stage without worlds (yet) fixes nothing.
        if stage.worlds.is_empty() || stage.worlds.iter().any(|w| !w.fixed_integrator) {
            return Ok(());
        }
        for name in names.split(',') {
            let wanted = tickwork_integrators::find(name.trim())?.name;
            if !stage.worlds.iter().any(|w| w.world.integrator().info().name == wanted) {
                let labels: Vec<String> = stage.worlds.iter().map(|w| format!("\"{}\"", w.label)).collect();
                return Err(RunError::Game(GameError::Message(format!(
                    "--integrator {names}: {} fixes the integrator of each of its worlds ({}), so the option \
                     would be ignored; run it without --integrator",
                    self.game.title(),
                    labels.join(", ")
                ))));
            }
        }
        Ok(())
    }

    /// Builds the stage afresh and restarts the clock (and the recording).
    pub(super) fn restart(&mut self) -> Result<(), RunError> {
        let mut stage = Stage {
            settings: self.options.settings.clone(),
            ..Stage::default()
        };
        self.game
            .setup(&mut stage, &self.options.settings)
            .map_err(RunError::Game)?;
        let rate = match self.options.hz {
            Some(hz) => Rate::hz_f64(hz)?,
            None => stage.rate,
        };
        stage.rate = rate;
        if let Some(name) = &self.options.settings.integrator {
            let names = name.split(',').count();
            for shown in stage.worlds.iter_mut().filter(|w| !w.fixed_integrator) {
                if names > 1 {
                    // A list is for a game that races integrators, one world
                    // each (it fixes them itself); this world takes one.
                    return Err(RunError::Game(GameError::Message(format!(
                        "--integrator {name} names {names} integrators, but {}'s world \"{}\" runs one: give one \
                         name (a list is for a game that races integrators, such as orbits)",
                        self.game.title(),
                        shown.label
                    ))));
                }
                shown.world.set_integrator(name.trim())?;
            }
            self.check_fixed_integrators(&stage, name)?;
        }
        for shown in &mut stage.worlds {
            if self.options.settings.gpu {
                shown.world.set_backend(Backend::Gpu);
            }
            shown
                .energy
                .sample(&mut shown.world)
                .map_err(|e| RunError::Playback(e.into()))?;
        }
        // The GPU the worlds on it step on stays the runner's.
        stage.gpu = self.stage.gpu.take();
        self.clock = FixedClock::new(ClockConfig {
            rate,
            time_scale: self.clock.config().time_scale,
            ..ClockConfig::default()
        })?;
        self.last = self.clock.advance(0.0)?;
        self.stage = stage;
        self.inputs.fill(TickInput::default());
        self.queue.restart();
        #[cfg(feature = "audio")]
        self.audio.forget();
        match &mut self.mode {
            InputMode::Live { record } => {
                *record = self.options.record.clone().map(|path| {
                    (
                        Recording::new(
                            self.game.title(),
                            rate.hz_value(),
                            self.options.settings.seed,
                            self.options.settings.integrator.clone(),
                        ),
                        path,
                    )
                });
            }
            InputMode::Replay {
                cursors, next_control, ..
            } => {
                cursors.fill(0);
                *next_control = 0;
            }
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

    /// A key went down (`down`) or up at the start of the coming frame
    /// (for tests and tools; the window stamps its events with
    /// [`input`](FrameSource::input)); ignored while a recording is replayed.
    pub fn key(&mut self, key: Key, down: bool) {
        FrameSource::input(self, InputEvent::Key { key, down }, 0.0);
    }

    /// The present in simulated seconds: the clock's time plus its backlog.
    pub(super) fn present(&self) -> f64 {
        self.clock.time() + self.clock.backlog()
    }

    /// This machine's input of the step ending at simulated time `end`,
    /// from the window's events (a networked session sends it to the
    /// other players rather than recording it here).
    #[cfg(feature = "netcode")]
    pub(crate) fn local_input(&mut self, end: f64) -> TickInput {
        self.queue.tick(end)
    }

    /// One fixed step of the game: [`Game::fixed_update_players`] with
    /// every player's input, then every world of the stage.
    pub(crate) fn run_tick(&mut self, step: crate::clock::FixedStep, inputs: &[TickInput]) -> Result<(), RunError> {
        #[cfg(feature = "audio")]
        self.stage.sounds_due.clear();
        self.game
            .fixed_update_players(&mut self.stage, &step, inputs)
            .map_err(RunError::Game)?;
        #[cfg(feature = "audio")]
        self.audio.tick(step.tick, &self.stage.sounds_due);
        let gpu = &mut self.stage.gpu;
        for shown in &mut self.stage.worlds {
            shown.step(gpu, step).map_err(|failure| {
                RunError::Game(match failure {
                    StepFailure::Simulation(error) => GameError::Simulation {
                        world: shown.label.clone(),
                        error,
                    },
                    StepFailure::Gpu(error) => GameError::Message(format!("world \"{}\": {error}", shown.label)),
                })
            })?;
        }
        Ok(())
    }

    /// Feeds a frame of `seconds` to the clock, gives the frame's input
    /// events their simulated times, and says which steps are due.
    pub(crate) fn advance_clock(&mut self, seconds: f64) -> Result<Frame, RunError> {
        let from = self.present();
        let frame = self.clock.advance(seconds)?;
        self.queue.stamp(from, self.present());
        self.frame_rate.record(seconds);
        Ok(frame)
    }

    /// Ends a frame whose steps ran: [`Game::update`] once.
    pub(crate) fn finish_frame(&mut self, frame: Frame) {
        self.last = frame;
        self.game.update(&mut self.stage, &self.last);
    }

    /// The sounds the game's ticks started, oldest first (the last
    /// [`LOGGED_SOUNDS`](crate::app::LOGGED_SOUNDS)): each once, at the tick that
    /// asked for it, however often a rollback ran that tick.
    #[cfg(feature = "audio")]
    pub fn played_sounds(&self) -> impl Iterator<Item = &Played> {
        self.audio.played()
    }

    /// Opens the machine's audio device for the sounds to come and says so
    /// in one line (`tickwork: sound plays through the audio device`);
    /// where there is none (or the build has no device support), says that
    /// instead and goes on silently. The window calls it at the start, a
    /// page at the first key press, click or touch (a browser lets a page
    /// play sound only after one); headless runs and replays stay silent.
    #[cfg(feature = "audio")]
    pub fn open_audio_device(&mut self) {
        match self.audio.open_device() {
            Ok(()) => crate::platform::say("tickwork: sound plays through the audio device"),
            Err(why) => crate::platform::say(&format!("tickwork: sound is silent: {why}")),
        }
    }

    /// The clock, to give back steps a rollback session could not run.
    #[cfg(feature = "netcode")]
    pub(crate) fn clock_mut(&mut self) -> &mut FixedClock {
        &mut self.clock
    }

    /// Reads every world on the GPU back into its [`World`](crate::World)
    /// (see [`Stage::read_back`]), so that [`checksum`](Self::checksum)
    /// and the game's outcome cover their state: a copy of each one's
    /// state and a wait for the GPU. Nothing for worlds on the CPU.
    ///
    /// # Errors
    /// [`RunError::Game`] if a read-back fails.
    pub fn read_back(&mut self) -> Result<(), RunError> {
        self.stage.read_back_all().map_err(|e| RunError::Game(e.into()))
    }

    /// The checksum of every world's state, in stage order, and of the
    /// game's own ([`Game::state_hash`]); a world on the GPU's as of its
    /// last [`read_back`](Self::read_back).
    #[must_use]
    pub fn checksum(&self) -> u64 {
        checksum_of(&self.game, &self.stage)
    }

    /// Players the game has.
    #[must_use]
    pub fn players(&self) -> usize {
        self.inputs.len()
    }

    /// The game, to save and load it (rollback).
    #[cfg(feature = "netcode")]
    pub(crate) fn game_mut(&mut self) -> &mut G {
        &mut self.game
    }

    /// Writes the recording, if one was asked for, with the checksum of
    /// the state at its end (worlds on the GPU read back first, where that
    /// can be waited for; none where it cannot); returns its path.
    ///
    /// # Errors
    /// [`RunError::Exists`] or [`RunError::Io`] for the file.
    pub fn save_recording(&mut self) -> Result<Option<PathBuf>, RunError> {
        // The state at the recording's end, for a replay to compare with:
        // worlds on the GPU read back first (where that can be waited for).
        let checksum = match &self.mode {
            InputMode::Live { record: Some(_) } => self.read_back().ok().map(|()| self.checksum()),
            _ => None,
        };
        match &mut self.mode {
            InputMode::Live {
                record: Some((recording, path)),
            } => {
                recording.checksum = checksum;
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

    /// Applies an integrator control to every world the viewer may switch
    /// (the stage allows it, the game does not fix the world's); records
    /// each switch before the next tick. A replay keeps its recorded
    /// integrators.
    pub(super) fn switch_integrators(&mut self, control: Control) -> Result<(), RunError> {
        // Checked first, so a bad number is an error wherever it is sent.
        chosen_integrator(control, usize::MAX, "", false)?;
        if !self.stage.switch_integrators {
            return Ok(());
        }
        let tick = self.clock.tick();
        let record = match &mut self.mode {
            InputMode::Replay { .. } => {
                crate::say!("tickwork: a replay keeps the recorded integrators; the switch is ignored");
                return Ok(());
            }
            InputMode::Live { record } => record.as_mut().map(|(recording, _)| recording),
        };
        let mut record = record;
        for (index, shown) in self.stage.worlds.iter_mut().enumerate() {
            if shown.fixed_integrator {
                continue;
            }
            let gpu = on_gpu(&shown.world);
            if let Some(name) = chosen_integrator(control, index, shown.world.integrator().info().name, gpu)? {
                shown.world.set_integrator(name)?;
                shown.failure = None;
                if let Some(recording) = record.as_deref_mut() {
                    recording.controls.push((
                        tick,
                        RecordedControl::Integrator {
                            world: index,
                            name: name.to_owned(),
                        },
                    ));
                }
            }
        }
        Ok(())
    }

    /// Smoothed frames per second.
    pub fn fps(&self) -> f64 {
        self.frame_rate.fps()
    }
}

/// The game's [`Game::state_hash`] and every world's
/// [`World::state_hash`](crate::World::state_hash), in stage order, mixed
/// by FNV-1a over the words.
fn checksum_of(game: &impl Game, stage: &Stage) -> u64 {
    let worlds = stage.worlds.iter().map(|w| w.world.state_hash());
    core::iter::once(game.state_hash())
        .chain(worlds)
        .fold(0xcbf2_9ce4_8422_2325_u64, |h, x| {
            (h ^ x).wrapping_mul(0x0000_0100_0000_01b3)
        })
}
