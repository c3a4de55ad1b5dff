//! A session's input by tick: the player's (recorded where asked) or a
//! recording's, with its controls at their ticks, and the replay's end at
//! the recording's last tick.

use crate::app::api::error::RunError;
use crate::app::api::game::{Game, GameError};
use crate::app::session::game_session::{GameSession, InputMode};
use crate::input::RecordedControl;

impl<G: Game> GameSession<G> {
    /// Takes the inputs of the step `tick` ending at simulated time `end`
    /// into `self.inputs`: replayed, or the player's events of its time
    /// window (and recorded) for player 0 and the default for the others.
    pub(super) fn take_tick_inputs(&mut self, tick: u64, end: f64) {
        match &mut self.mode {
            InputMode::Replay { recording, cursors, .. } => {
                for (player, (input, cursor)) in self.inputs.iter_mut().zip(cursors.iter_mut()).enumerate() {
                    *input = recording.input_of(player, cursor, tick, input.carried());
                }
            }
            InputMode::Live { record } => {
                let carried = self.inputs[0].carried();
                let input = self.queue.tick(end);
                if let Some((recording, _)) = record {
                    if input != carried {
                        recording.inputs.push((tick, input));
                    }
                    recording.ticks = tick + 1;
                }
                self.inputs[0] = input;
            }
        }
    }

    /// The tick a replay ends at (the recording's length); `None` live.
    pub(super) fn replay_end(&self) -> Option<u64> {
        match &self.mode {
            InputMode::Replay { recording, .. } => Some(recording.ticks),
            InputMode::Live { .. } => None,
        }
    }

    /// Ends a replay once `ran` ticks (all of the recording's) have run: the clock
    /// stops there (a window then holds the recorded run's last state) and
    /// one line says the tick, the checksum and whether it matches the
    /// recording's. Worlds on the GPU are read back first where that can be
    /// waited for.
    pub(super) fn end_replay_if_due(&mut self, ran: u64) -> Result<(), RunError> {
        let (Some(end), false) = (self.replay_end(), self.replay_done) else {
            return Ok(());
        };
        let tick = ran;
        if tick < end {
            return Ok(());
        }
        self.replay_done = true;
        self.clock.pause();
        let title = self.game.title().to_owned();
        if let Err(why) = self.read_back() {
            crate::say!(
                "tickwork: {title}: the replay ended at tick {tick}; its state stays on the GPU, without a \
                 checksum: {why}"
            );
            return Ok(());
        }
        let now = self.checksum();
        let recorded = match &self.mode {
            InputMode::Replay { recording, .. } => recording.checksum,
            InputMode::Live { .. } => None,
        };
        let verdict = match recorded {
            Some(recorded) if recorded == now => "it matches the recording".to_owned(),
            Some(recorded) => format!("the recording ended with checksum {recorded:016x}: this run differs from it"),
            None => "the recording keeps no checksum to compare".to_owned(),
        };
        crate::say!("tickwork: {title}: the replay ended at tick {tick} with checksum {now:016x}: {verdict}");
        Ok(())
    }

    /// Replays the recorded controls of `tick` (before its input).
    pub(super) fn replay_controls(&mut self, tick: u64) -> Result<(), RunError> {
        let InputMode::Replay {
            recording,
            next_control,
            ..
        } = &mut self.mode
        else {
            return Ok(());
        };
        while let Some((at, control)) = recording.controls.get(*next_control) {
            if *at > tick {
                break;
            }
            *next_control += 1;
            let RecordedControl::Integrator { world, name } = control;
            let Some(shown) = self.stage.worlds.get_mut(*world) else {
                return Err(RunError::Game(GameError::Message(format!(
                    "the recording switches the integrator of world {world} at tick {at}, but the stage has {} \
                     worlds",
                    self.stage.worlds.len()
                ))));
            };
            shown.world.set_integrator(name)?;
            shown.failure = None;
        }
        Ok(())
    }
}
