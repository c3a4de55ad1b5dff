//! A recording of a run's input, by tick: what `--record` writes and
//! `--replay` plays back, bit for bit whatever the frame timing.

use core::fmt;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::tick::TickInput;
use crate::clock::Rate;

/// A control that changed the simulation during a recorded run, replayed
/// at its tick.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum RecordedControl {
    /// The world at `world` (its place on the stage, from 0) switched to
    /// the integrator `name`.
    Integrator {
        /// The world's place on the stage.
        world: usize,
        /// The integrator's registry name.
        name: String,
    },
}

/// A recording that could not be read or written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RecordingError {
    /// The file exists and overwriting was not asked for.
    Exists(PathBuf),
    /// The file could not be read, parsed or written.
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong (with the line and column of a malformed file).
        message: String,
    },
}

impl RecordingError {
    fn io(path: &Path, error: &dyn fmt::Display) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            message: error.to_string(),
        }
    }
}

impl fmt::Display for RecordingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Exists(path) => write!(f, "{}: exists; pass --force to overwrite it", path.display()),
            Self::Io { path, message } => write!(f, "{}: {message}", path.display()),
        }
    }
}

impl std::error::Error for RecordingError {}

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
    /// `(tick, control)` for every control that changed the simulation
    /// (an integrator switched from a key or the panel), applied before
    /// that tick's input, in order. Absent in recordings without any.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub controls: Vec<(u64, RecordedControl)>,
    /// The inputs of players 1, 2, ... of a networked match, each in the
    /// form of `inputs` (which holds player 0's). Absent in one-player
    /// recordings.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub other_players: Vec<Vec<(u64, TickInput)>>,
    /// The checksum of the recorded run's state at its end (after `ticks`
    /// steps), which a replay compares with its own there. Absent in
    /// recordings made before it was kept, and where the state could not
    /// be had (a GPU world in a page).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checksum: Option<u64>,
}

impl Recording {
    /// The most players a recording holds (and a game has): 8.
    pub const MAX_PLAYERS: usize = 8;

    /// An empty recording of `game` at `hz` steps per second.
    #[must_use]
    pub fn new(game: &str, hz: f64, seed: u64, integrator: Option<String>) -> Self {
        Self {
            game: game.to_owned(),
            hz,
            seed,
            integrator,
            ticks: 0,
            inputs: Vec::new(),
            controls: Vec::new(),
            other_players: Vec::new(),
            checksum: None,
        }
    }

    /// Players whose input the recording holds (1, or more for a match).
    #[must_use]
    pub fn players(&self) -> usize {
        1 + self.other_players.len()
    }

    /// The recorded inputs of `player` (0 is `inputs`), if it has any.
    #[must_use]
    pub fn inputs_of(&self, player: usize) -> Option<&[(u64, TickInput)]> {
        match player {
            0 => Some(&self.inputs),
            _ => self.other_players.get(player - 1).map(Vec::as_slice),
        }
    }

    /// The mutable inputs of `player`, adding empty lists up to it.
    pub fn inputs_of_mut(&mut self, player: usize) -> &mut Vec<(u64, TickInput)> {
        match player {
            0 => &mut self.inputs,
            _ => {
                if self.other_players.len() < player {
                    self.other_players.resize_with(player, Vec::new);
                }
                &mut self.other_players[player - 1]
            }
        }
    }

    /// Player 0's recorded input of `tick` (see [`input_of`](Self::input_of)).
    #[must_use]
    pub fn input_at(&self, cursor: &mut usize, tick: u64, carried: TickInput) -> TickInput {
        self.input_of(0, cursor, tick, carried)
    }

    /// The recorded input of `player` at `tick`, or `carried` (the last
    /// tick's held keys) if the recording has none for it (the default
    /// input for a player it does not hold). `cursor` is where the
    /// previous call stopped: ask ticks in increasing order, from 0.
    #[must_use]
    pub fn input_of(&self, player: usize, cursor: &mut usize, tick: u64, carried: TickInput) -> TickInput {
        let Some(inputs) = self.inputs_of(player) else {
            return TickInput::default();
        };
        let mut input = carried;
        while let Some((at, recorded)) = inputs.get(*cursor) {
            if *at > tick {
                break;
            }
            if *at == tick {
                input = *recorded;
            }
            *cursor += 1;
        }
        input
    }

    /// Reads a recording written by a run with `--record`.
    ///
    /// # Errors
    /// [`RecordingError::Io`] naming the file, with the line and column of a
    /// malformed one.
    pub fn load(path: &Path) -> Result<Self, RecordingError> {
        let text = crate::text_file::read_limited(path, Self::MAX_FILE_BYTES, "Recording::MAX_FILE_BYTES")
            .map_err(|e| RecordingError::io(path, &e))?;
        Self::parse(&text, path)
    }

    /// Parses and range-checks recording text; `path` names it in errors.
    ///
    /// # Errors
    /// [`RecordingError::Io`] naming `path`, with the line and column of the fault.
    pub fn parse(text: &str, path: &Path) -> Result<Self, RecordingError> {
        let recording: Self = ron::from_str(text).map_err(|e| RecordingError::Io {
            path: path.to_path_buf(),
            message: format!(
                "line {}, column {}: {} (not a Tickwork input recording?)",
                e.span.start.line, e.span.start.col, e.code
            ),
        })?;
        recording.check().map_err(|(field, message)| {
            let (line, column) = field_position(text, field);
            RecordingError::Io {
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
        if self.players() > Self::MAX_PLAYERS {
            return Err((
                "other_players",
                format!(
                    "{} players, past the limit of {} (Recording::MAX_PLAYERS)",
                    self.players(),
                    Self::MAX_PLAYERS
                ),
            ));
        }
        for player in 0..self.players() {
            let field = if player == 0 { "inputs" } else { "other_players" };
            let who = if player == 0 {
                String::new()
            } else {
                format!("player {player}: ")
            };
            let inputs = self.inputs_of(player).unwrap_or_default();
            let mut previous = None;
            for (k, (tick, input)) in inputs.iter().enumerate() {
                if *tick >= self.ticks || previous.is_some_and(|p| *tick <= p) {
                    return Err((
                        field,
                        format!(
                            "{who}entry {k} is at tick {tick}: ticks must rise and stay below the recording's {} ticks",
                            self.ticks
                        ),
                    ));
                }
                previous = Some(*tick);
                if input.pointer.is_some_and(|p| !p.iter().all(|c| c.is_finite())) {
                    return Err((
                        field,
                        format!(
                            "{who}entry {k}: the pointer must be a finite world point, got {:?}",
                            input.pointer
                        ),
                    ));
                }
            }
        }
        let mut previous = 0;
        for (k, (tick, control)) in self.controls.iter().enumerate() {
            // A control may come after the last tick (a switch just
            // before the run ended), never later.
            if *tick > self.ticks || *tick < previous {
                return Err((
                    "controls",
                    format!(
                        "entry {k} is at tick {tick}: ticks must not fall and must stay at or below the recording's \
                         {} ticks",
                        self.ticks
                    ),
                ));
            }
            previous = *tick;
            let RecordedControl::Integrator { name, .. } = control;
            if let Err(unknown) = tickwork_integrators::find(name) {
                return Err(("controls", format!("entry {k}: {unknown}")));
            }
        }
        Ok(())
    }

    /// Writes the recording as RON.
    ///
    /// # Errors
    /// [`RecordingError::Exists`] if the file exists and `overwrite` is off,
    /// [`RecordingError::Io`] if it cannot be written.
    pub fn save(&self, path: &Path, overwrite: bool) -> Result<(), RecordingError> {
        if path.exists() && !overwrite {
            return Err(RecordingError::Exists(path.to_path_buf()));
        }
        let text = ron::ser::to_string_pretty(
            self,
            ron::ser::PrettyConfig::default().struct_names(true).depth_limit(2),
        )
        .map_err(|e| RecordingError::io(path, &e))?;
        crate::platform::write_text(path, &text).map_err(|e| RecordingError::io(path, &e))
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
