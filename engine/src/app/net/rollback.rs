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

use crate::app::api::error::RunError;
use crate::app::api::game::{Game, GameError};
use crate::app::session::game_session::GameSession;
use crate::app::session::source::FrameSource;
use crate::clock::FixedStep;
use crate::input::{KeySet, MAX_PADS, PadButtons, PadInput, TickInput};
use crate::world::Snapshot;
use serde::{Deserialize, Serialize};

/// A game's simulated state at a tick boundary.
#[derive(Clone, Debug)]
pub struct SavedTick<G> {
    game: G,
    worlds: Vec<Snapshot>,
    failures: Vec<Option<String>>,
}

/// A player's [`TickInput`] as GGRS sends it: of one fixed size, since
/// GGRS splits a packet's inputs by size (a `TickInput`'s serde form lists
/// key names and leaves out an absent pointer, so its size varies).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WireInput {
    held: u64,
    pressed: u64,
    released: u64,
    /// The pointer's bits, so that GGRS's comparison of a prediction with
    /// the real input is of bits (as `==` on floats is not: `-0.0 == 0.0`
    /// would keep a prediction that runs differently, and NaN would never
    /// match).
    pointer: [u32; 2],
    has_pointer: bool,
    /// Each pad's held, pressed and released buttons as bits, then its
    /// quantised axes (fixed size, as GGRS needs).
    pads: [([u16; 3], [i16; 6]); MAX_PADS],
}

impl From<TickInput> for WireInput {
    /// A pointer that is not finite is sent as none; `-0.0` as `0.0`.
    fn from(input: TickInput) -> Self {
        let pointer = input.pointer.filter(|p| p.iter().all(|c| c.is_finite()));
        Self {
            held: input.held.bits(),
            pressed: input.pressed.bits(),
            released: input.released.bits(),
            pointer: pointer.unwrap_or_default().map(|c| (c + 0.0).to_bits()),
            has_pointer: pointer.is_some(),
            pads: input
                .pads
                .map(|p| ([p.held.bits(), p.pressed.bits(), p.released.bits()], p.axes)),
        }
    }
}

impl From<WireInput> for TickInput {
    /// Unknown key bits are dropped and a pointer that is not finite is
    /// none, the same on every machine (the bytes are the same).
    fn from(wire: WireInput) -> Self {
        Self {
            held: KeySet::from_bits(wire.held),
            pressed: KeySet::from_bits(wire.pressed),
            released: KeySet::from_bits(wire.released),
            pointer: Some(wire.pointer.map(f32::from_bits))
                .filter(|p| wire.has_pointer && p.iter().all(|c| c.is_finite())),
            pads: wire.pads.map(|([held, pressed, released], axes)| PadInput {
                held: PadButtons::from_bits(held),
                pressed: PadButtons::from_bits(pressed),
                released: PadButtons::from_bits(released),
                axes,
            }),
        }
    }
}

/// GGRS's configuration for a Tickwork game: the input is a player's
/// [`TickInput`] (as a [`WireInput`]), the state a [`SavedTick`].
#[derive(Debug)]
pub struct Rollback<G>(PhantomData<G>);

impl<G: Game + Clone + 'static> Config for Rollback<G> {
    type Input = WireInput;
    type InputPredictor = PredictRepeatLast;
    /// Optional so that a save can take the slot's earlier state out and
    /// copy into its buffers (GGRS reuses its slots; no world is allocated
    /// again once every slot has held one).
    type State = Option<SavedTick<G>>;
    type Address = super::link::PeerAddress;
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
        if let Some(shown) = worlds.iter().find(|w| crate::app::api::backend::on_gpu(&w.world)) {
            return Err(RunError::Game(GameError::Message(format!(
                "world \"{}\" steps on the GPU, which a rollback session does not take yet (its state would \
                 have to come back every tick): run it without --gpu",
                shown.label
            ))));
        }
        for ((shown, snapshot), failure) in worlds.iter_mut().zip(&saved.worlds).zip(&saved.failures) {
            shown.world.restore(snapshot);
            shown.failure.clone_from(failure);
        }
        self.game_mut().clone_from(&saved.game);
        Ok(())
    }

    /// Runs fixed step number `tick` with every player's input, outside
    /// the clock (a rollback session decides which tick runs and with what).
    ///
    /// # Errors
    /// [`RunError::Game`] if the game or a world fails.
    pub fn step_tick(&mut self, tick: u64, inputs: &[TickInput]) -> Result<(), RunError> {
        let timeline = self.clock().timeline();
        let step = FixedStep {
            tick,
            time: timeline.time_of(tick),
            dt: self.clock().dt(),
        };
        self.run_tick(step, inputs)
    }
}

/// Where a rollback session stands and what it did: the next tick to run,
/// the rollbacks and the ticks simulated again.
#[derive(Debug)]
pub(crate) struct RollbackCursor {
    /// The session's tick at GGRS's frame 0.
    start: u64,
    /// The next tick to run (the stage's state is at its start).
    pub tick: u64,
    /// The furthest tick run so far.
    furthest: u64,
    /// States loaded (each a rollback).
    pub rollbacks: u64,
    /// Ticks run again after a rollback.
    pub resimulated: u64,
    /// Every player's input of the tick being run (reused).
    inputs: Vec<TickInput>,
}

impl RollbackCursor {
    /// A cursor whose GGRS frame 0 is the session's tick `start`.
    pub(crate) fn new(start: u64) -> Self {
        Self {
            start,
            tick: start,
            furthest: start,
            rollbacks: 0,
            resimulated: 0,
            inputs: Vec::new(),
        }
    }

    /// The session's tick of GGRS frame `frame`.
    fn tick_of(&self, frame: ggrs::Frame) -> Result<u64, RunError> {
        u64::try_from(frame)
            .map(|f| self.start + f)
            .map_err(|_| RunError::Game(GameError::Message(format!("rollback: GGRS asked for frame {frame}"))))
    }
}

/// Fulfils GGRS's requests in order: saves the state (with its checksum)
/// into the slot's reused buffers, loads a saved one, or runs a tick with
/// the players' inputs. `saved(tick, state, checksum)` sees every save,
/// `advanced(tick, inputs)` every tick run.
pub(crate) fn fulfil<G: Game + Clone + 'static>(
    session: &mut GameSession<G>,
    requests: Vec<GgrsRequest<Rollback<G>>>,
    cursor: &mut RollbackCursor,
    mut saved: impl FnMut(u64, &SavedTick<G>, u64),
    mut advanced: impl FnMut(u64, &[TickInput]),
) -> Result<(), RunError> {
    for request in requests {
        match request {
            GgrsRequest::SaveGameState { cell, frame } => {
                let checksum = session.checksum();
                let earlier = cell.data().and_then(|mut slot| slot.as_mut_dangerous().take());
                let state = match earlier {
                    Some(mut state) => {
                        session.save_tick_into(&mut state);
                        state
                    }
                    None => session.save_tick(),
                };
                saved(cursor.tick_of(frame)?, &state, checksum);
                cell.save(frame, Some(Some(state)), Some(u128::from(checksum)));
            }
            GgrsRequest::LoadGameState { cell, frame } => {
                let missing = || {
                    RunError::Game(GameError::Message(format!(
                        "rollback: no state was saved for frame {frame}"
                    )))
                };
                let slot = cell.data().ok_or_else(missing)?;
                session.load_tick(slot.as_ref().ok_or_else(missing)?)?;
                cursor.tick = cursor.tick_of(frame)?;
                cursor.rollbacks += 1;
            }
            GgrsRequest::AdvanceFrame { inputs } => {
                cursor.inputs.clear();
                cursor
                    .inputs
                    .extend(inputs.iter().map(|(input, _)| TickInput::from(*input)));
                session.step_tick(cursor.tick, &cursor.inputs)?;
                advanced(cursor.tick, &cursor.inputs);
                if cursor.tick < cursor.furthest {
                    cursor.resimulated += 1;
                }
                cursor.tick += 1;
                cursor.furthest = cursor.furthest.max(cursor.tick);
            }
        }
    }
    Ok(())
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
/// re-simulating with the same inputs; `input(tick, player)` gives each
/// player's input of each tick, for every player of the game.
///
/// # Errors
/// [`RunError::Game`] naming the first tick whose re-simulated state
/// differs, or a game or world failure; [`RunError::Limit`] for a check
/// distance out of range.
pub fn sync_test<G: Game + Clone + 'static>(
    session: &mut GameSession<G>,
    check_distance: usize,
    ticks: u64,
    mut input: impl FnMut(u64, usize) -> TickInput,
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
    let players = session.players();
    let mut rollback = SessionBuilder::<Rollback<G>>::new()
        .with_num_players(players)
        .map_err(ggrs)?
        .with_check_distance(check_distance)
        .with_max_prediction_window(check_distance + 1)
        .start_synctest_session()
        .map_err(ggrs)?;
    // GGRS counts frames from 0; the session's ticks go on from where it is.
    let mut cursor = RollbackCursor::new(FrameSource::ticks(session));
    for _ in 0..ticks {
        let tick = cursor.tick;
        for player in 0..players {
            rollback
                .add_local_input(player, input(tick, player).into())
                .map_err(ggrs)?;
        }
        let requests = rollback.advance_frame().map_err(ggrs)?;
        fulfil(session, requests, &mut cursor, |_, _, _| {}, |_, _| {})?;
    }
    Ok(SyncTestReport {
        ticks,
        check_distance,
        checksum: session.checksum(),
    })
}
