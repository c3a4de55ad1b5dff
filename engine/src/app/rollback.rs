//! Rollback: a game's whole simulated state saved, loaded and stepped one
//! tick at a time with given input, as a rollback session asks (GGRS); and
//! the sync test that runs any game under GGRS's `SyncTestSession`.
//!
//! A sync test steps a tick, then every tick loads the state of
//! `check_distance` ticks ago and steps forward again with the same
//! inputs, comparing each tick's checksum with the first run's. Anything
//! that changes the simulation but is not in the saved state (a game
//! field that `Clone` does not copy, a global, the wall clock) gives
//! different re-simulated states, and the test names the first tick that
//! differs.
//!
//! What is saved: the game itself (`Game + Clone`: a game's own state
//! lives in its fields), every world of the stage (a [`Snapshot`] each),
//! and which worlds froze. The checksum covers every world
//! ([`World::state_hash`](crate::World::state_hash)), in stage order.

use core::marker::PhantomData;

use ggrs::{Config, GgrsError, GgrsRequest, PredictRepeatLast, SessionBuilder};

use super::game::{Game, GameError};
use super::session::GameSession;
use super::{FrameSource, RunError};
use crate::clock::FixedStep;
use crate::input::TickInput;
use crate::world::Snapshot;

/// A game's simulated state at a tick boundary.
#[derive(Clone, Debug)]
pub struct SavedTick<G> {
    game: G,
    worlds: Vec<Snapshot>,
    failures: Vec<Option<String>>,
}

/// GGRS's configuration for a Tickwork game: the input is a player's
/// [`TickInput`], the state a [`SavedTick`].
#[derive(Debug)]
pub struct Rollback<G>(PhantomData<G>);

impl<G: Game + Clone + 'static> Config for Rollback<G> {
    type Input = TickInput;
    type InputPredictor = PredictRepeatLast;
    /// Optional so that a save can take the slot's earlier state out and
    /// copy into its buffers (GGRS reuses its slots; no world is allocated
    /// again once every slot has held one).
    type State = Option<SavedTick<G>>;
    type Address = std::net::SocketAddr;
}

impl<G: Game + Clone> GameSession<G> {
    /// The simulated state now: the game and every world.
    pub fn save_tick(&self) -> SavedTick<G> {
        SavedTick {
            game: self.game().clone(),
            worlds: self.stage().worlds.iter().map(|w| w.world.snapshot()).collect(),
            failures: self.stage().worlds.iter().map(|w| w.failure.clone()).collect(),
        }
    }

    /// Overwrites `saved` with the state now, reusing its buffers (a
    /// world's snapshot copies into the last one's columns).
    pub fn save_tick_into(&self, saved: &mut SavedTick<G>) {
        let worlds = &self.stage().worlds;
        saved.worlds.truncate(worlds.len());
        for (k, shown) in worlds.iter().enumerate() {
            match saved.worlds.get_mut(k) {
                Some(snapshot) => shown.world.snapshot_into(snapshot),
                None => saved.worlds.push(shown.world.snapshot()),
            }
        }
        saved.failures.clear();
        saved.failures.extend(worlds.iter().map(|w| w.failure.clone()));
        saved.game.clone_from(self.game());
    }

    /// Puts a saved state back (the worlds' buffers reused).
    ///
    /// # Errors
    /// [`RunError::Game`] if the stage has another number of worlds than
    /// when the state was saved.
    pub fn load_tick(&mut self, saved: &SavedTick<G>) -> Result<(), RunError> {
        let worlds = &mut self.stage_mut().worlds;
        if worlds.len() != saved.worlds.len() {
            return Err(RunError::Game(GameError::Message(format!(
                "the saved state has {} worlds, the stage {}: a game must not add or remove worlds after set-up \
                 in a rollback session",
                saved.worlds.len(),
                worlds.len()
            ))));
        }
        for ((shown, snapshot), failure) in worlds.iter_mut().zip(&saved.worlds).zip(&saved.failures) {
            shown.world.restore(snapshot);
            shown.failure.clone_from(failure);
        }
        self.game_mut().clone_from(&saved.game);
        Ok(())
    }

    /// Runs fixed step number `tick` with `input`, outside the clock (a
    /// rollback session decides which tick runs and with what).
    ///
    /// # Errors
    /// [`RunError::Game`] if the game or a world fails.
    pub fn step_tick(&mut self, tick: u64, input: &TickInput) -> Result<(), RunError> {
        let timeline = self.clock().timeline();
        let step = FixedStep {
            tick,
            time: timeline.time_of(tick),
            dt: self.clock().dt(),
        };
        self.run_tick(step, input)
    }

    /// The checksum of every world's state, in stage order, and of the
    /// game's own ([`Game::state_hash`]).
    #[must_use]
    pub fn checksum(&self) -> u64 {
        let worlds = self.stage().worlds.iter().map(|w| w.world.state_hash());
        core::iter::once(self.game().state_hash())
            .chain(worlds)
            .fold(0xcbf2_9ce4_8422_2325_u64, |h, x| {
                (h ^ x).wrapping_mul(0x0000_0100_0000_01b3)
            })
    }
}

/// What a sync test did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SyncTestReport {
    /// Ticks run (each also re-simulated `check_distance` times).
    pub ticks: u64,
    /// How far back each tick rolled.
    pub check_distance: usize,
    /// The last tick's checksum.
    pub checksum: u64,
}

/// The most ticks a sync test rolls back: GGRS's prediction window.
pub const MAX_CHECK_DISTANCE: usize = 7;

/// Runs `session` for `ticks` ticks under GGRS's `SyncTestSession`, rolling
/// back `check_distance` ticks (1 to [`MAX_CHECK_DISTANCE`]) every tick and
/// re-simulating with the same inputs; `input(tick)` gives each tick's input.
///
/// # Errors
/// [`RunError::Game`] naming the first tick whose re-simulated state
/// differs, or a game or world failure; [`RunError::Limit`] for a check
/// distance out of range.
pub fn sync_test<G: Game + Clone + 'static>(
    session: &mut GameSession<G>,
    check_distance: usize,
    ticks: u64,
    mut input: impl FnMut(u64) -> TickInput,
) -> Result<SyncTestReport, RunError> {
    if !(1..=MAX_CHECK_DISTANCE).contains(&check_distance) {
        return Err(RunError::Limit(format!(
            "--sync-test {check_distance}: the check distance must be 1 to {MAX_CHECK_DISTANCE} ticks (GGRS's \
             prediction window)"
        )));
    }
    let ggrs = |error: GgrsError| match error {
        GgrsError::MismatchedChecksum {
            current_frame,
            mismatched_frames,
        } => RunError::Game(GameError::Message(format!(
            "sync test failed at tick {current_frame}: re-simulating tick {} from a saved state gave another state \
             than the first run (ticks {mismatched_frames:?} differ); something that changes the simulation is not \
             in the saved state (a game field Clone does not copy, a global, the wall clock, a random generator \
             outside the worlds)",
            mismatched_frames.first().copied().unwrap_or(current_frame)
        ))),
        other => RunError::Game(GameError::Message(format!("sync test: {other}"))),
    };
    let mut rollback = SessionBuilder::<Rollback<G>>::new()
        .with_num_players(1)
        .map_err(ggrs)?
        .with_check_distance(check_distance)
        .with_max_prediction_window(check_distance + 1)
        .start_synctest_session()
        .map_err(ggrs)?;
    // GGRS counts frames from 0; the session's ticks go on from where it is.
    let start = session.ticks();
    let mut tick = start;
    for _ in 0..ticks {
        rollback.add_local_input(0, input(tick)).map_err(ggrs)?;
        for request in rollback.advance_frame().map_err(ggrs)? {
            match request {
                GgrsRequest::SaveGameState { cell, frame } => {
                    let checksum = u128::from(session.checksum());
                    let earlier = cell.data().and_then(|mut slot| slot.as_mut_dangerous().take());
                    let saved = match earlier {
                        Some(mut saved) => {
                            session.save_tick_into(&mut saved);
                            saved
                        }
                        None => session.save_tick(),
                    };
                    cell.save(frame, Some(Some(saved)), Some(checksum));
                }
                GgrsRequest::LoadGameState { cell, frame } => {
                    let missing = || {
                        RunError::Game(GameError::Message(format!(
                            "sync test: no state was saved for tick {frame}"
                        )))
                    };
                    let slot = cell.data().ok_or_else(missing)?;
                    session.load_tick(slot.as_ref().ok_or_else(missing)?)?;
                    tick = start + u64::try_from(frame).map_err(|_| missing())?;
                }
                GgrsRequest::AdvanceFrame { inputs } => {
                    let input = inputs.first().map(|(input, _)| *input).unwrap_or_default();
                    session.step_tick(tick, &input)?;
                    tick += 1;
                }
            }
        }
    }
    Ok(SyncTestReport {
        ticks,
        check_distance,
        checksum: session.checksum(),
    })
}
