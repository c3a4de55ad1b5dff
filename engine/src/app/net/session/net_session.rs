//! [`NetSession`]: a game of two players over the network, each machine
//! running the whole simulation under GGRS's `P2PSession`.
//!
//! Per displayed frame: GGRS reads the network; the clock says how many
//! ticks are due; for each, this machine's input goes to GGRS, which
//! answers with requests (roll back to a saved tick, run ticks again with
//! the inputs that arrived, save, run the new tick with the remote input
//! predicted). When GGRS has to wait for the other player (this side is
//! a prediction window ahead), the due ticks go back to the clock
//! ([`FixedClock::defer`](crate::clock::FixedClock::defer)) and run on a
//! later frame: no time is lost, no tick is run twice from the clock.
//! GGRS's advice to let the other side catch up (`WaitRecommendation`)
//! skips that many due ticks instead.
//!
//! A match of `--frames N` ticks ends when this side knows tick N's state
//! for certain (every input before it confirmed and any rollback through
//! it done) and the other side says it does too (or has gone).

use std::cell::RefCell;
use std::rc::Rc;
use std::time::Duration;

use crate::platform::Instant;

use ggrs::{GgrsError, GgrsEvent, P2PSession, SessionState};

use crate::app::net::guard::guarded;
use crate::app::net::link::PeerAddress;
use crate::app::net::match_report::MatchReport;
use crate::app::net::rollback::{Rollback, RollbackCursor, SavedTick, fulfil};
use crate::app::net::transport::Shared;
use crate::app::{Control, FrameSource, Game, GameSession, RunError};
use crate::input::{InputEvent, Recording, TickInput};
use crate::interpolation::Interpolation;
use crate::render::{Camera, FrameView, RenderError};

/// A local player's input read from a recording instead of the keyboard.
#[derive(Debug)]
pub(super) struct Script {
    pub(super) recording: Recording,
    pub(super) cursor: usize,
    pub(super) input: TickInput,
}

/// A game in a networked match: each frame, the ticks the clock says are
/// due go to GGRS with this machine's input, and GGRS's requests (save,
/// load, run a tick with both players' inputs) are fulfilled on the
/// [`GameSession`]; ticks GGRS cannot run yet go back to the clock.
pub struct NetSession<G: Game + Clone + 'static> {
    pub(super) session: GameSession<G>,
    pub(super) p2p: P2PSession<Rollback<G>>,
    /// Why GGRS is no longer trusted: it panicked in a call ([`guarded`]).
    pub(super) broken: Option<String>,
    pub(super) local: usize,
    pub(super) remote: PeerAddress,
    pub(super) shared: Rc<RefCell<Shared>>,
    pub(super) cursor: RollbackCursor,
    /// This side's input given to GGRS for a tick not yet run.
    pub(super) pending: Option<TickInput>,
    pub(super) script: Option<Script>,
    /// Every player's input of every tick run, `players` a tick: after the
    /// match, the confirmed inputs (a misprediction was run again).
    pub(super) played: Vec<TickInput>,
    /// Ticks whose inputs are all confirmed and were run with them.
    pub(super) certain_ticks: u64,
    pub(super) skip: u32,
    pub(super) end: Option<u64>,
    /// The last save of tick `end`, and its checksum.
    pub(super) final_state: Option<(SavedTick<G>, u64)>,
    pub(super) settled: bool,
    pub(super) remote_gone: bool,
    /// GGRS runs only confirmed ticks and asks for no saves (no prediction).
    pub(super) lockstep: bool,
    pub(super) waits: u64,
    pub(super) skipped: u64,
    pub(super) started: Instant,
    pub(super) wait: Duration,
}

impl<G: Game + Clone + 'static> std::fmt::Debug for NetSession<G> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NetSession")
            .field("session", &self.session)
            .field("local", &self.local)
            .field("remote", &self.remote)
            .field("tick", &self.cursor.tick)
            .finish_non_exhaustive()
    }
}

pub(super) fn ggrs_error(error: GgrsError) -> RunError {
    RunError::Network(format!("GGRS: {error}"))
}

impl<G: Game + Clone + 'static> NetSession<G> {
    /// A call into GGRS, [`guarded`]: after a panic in one, GGRS's state is
    /// not trusted, and this and every later call give that error.
    fn guard<T>(&mut self, what: &str, call: impl FnOnce(&mut P2PSession<Rollback<G>>) -> T) -> Result<T, RunError> {
        if let Some(why) = &self.broken {
            return Err(RunError::Network(why.clone()));
        }
        let p2p = &mut self.p2p;
        guarded(what, || call(p2p)).inspect_err(|error| self.broken = Some(error.to_string()))
    }

    /// The game session underneath (the stage, the clock, the game).
    #[must_use]
    pub fn session(&self) -> &GameSession<G> {
        &self.session
    }

    /// This side's player number (the host 0, the joiner 1).
    #[must_use]
    pub fn local_player(&self) -> usize {
        self.local
    }

    /// Ends the match at tick `ticks` (else it runs until the window closes).
    pub fn end_at(&mut self, ticks: u64) {
        self.end = Some(ticks);
    }

    /// Whether the match is over: this side knows the final state, and the
    /// other says so too or has gone.
    #[must_use]
    pub fn is_over(&self) -> bool {
        self.settled && (self.remote_gone || self.shared.borrow().remote_done.is_some())
    }

    /// This side's input of the tick ending at simulated time `end`.
    fn next_local_input(&mut self, end: f64) -> TickInput {
        let tick = self.cursor.tick;
        match &mut self.script {
            Some(script) => {
                script.input = script
                    .recording
                    .input_at(&mut script.cursor, tick, script.input.carried());
                script.input
            }
            None => self.session.local_input(end),
        }
    }

    /// The HUD's line for the match: this side's player, the other's
    /// address, the round trip GGRS measures, and the rollbacks so far.
    fn hud_line(&self) -> String {
        let ping = match self.p2p.network_stats(1 - self.local) {
            Ok(stats) => format!("ping {} ms", stats.ping),
            Err(_) => "ping not measured yet".to_owned(),
        };
        format!(
            "player {} vs {}, {ping}, {} rollbacks",
            self.local + 1,
            self.remote,
            self.cursor.rollbacks
        )
    }

    /// Reads GGRS's events: a desync or a lost peer ends the match.
    fn handle_events(&mut self) -> Result<(), RunError> {
        let tick = self.cursor.tick;
        let left = self.shared.borrow().remote_left.clone();
        if let Some(why) = left {
            if !self.settled {
                return Err(RunError::Network(format!(
                    "the other player ({}) left at tick {tick}: {why}; the match ends",
                    self.remote
                )));
            }
            self.remote_gone = true;
        }
        let events: Vec<_> = self.guard("reading its events", |p2p| p2p.events().collect())?;
        for event in events {
            match event {
                GgrsEvent::Synchronized { addr } => crate::say!("tickwork: connected to {addr}"),
                GgrsEvent::WaitRecommendation { skip_frames } => self.skip += skip_frames,
                GgrsEvent::NetworkInterrupted {
                    addr,
                    disconnect_timeout,
                } if !self.settled => {
                    crate::say!(
                        "tickwork: no word from {addr}; it is dropped in {disconnect_timeout} ms unless it answers"
                    );
                }
                GgrsEvent::Disconnected { .. } if self.settled => self.remote_gone = true,
                GgrsEvent::Disconnected { addr } => {
                    return Err(RunError::Network(format!(
                        "the other player ({addr}) disconnected at tick {tick}"
                    )));
                }
                GgrsEvent::DesyncDetected {
                    frame,
                    local_checksum,
                    remote_checksum,
                    addr,
                } => {
                    return Err(RunError::Network(format!(
                        "desync at tick {frame}: this side's checksum is {local_checksum:016x}, the other's ({addr}) \
                         {remote_checksum:016x}; the two simulations differ (something the game does is not \
                         deterministic or not in its saved state: run it with --sync-test to find it)"
                    )));
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Gives GGRS this side's input for the next tick and fulfils its
    /// requests; false if GGRS is waiting (not synchronised yet, or a
    /// prediction window ahead), so the tick did not run.
    fn try_tick(&mut self, end_time: f64) -> Result<bool, RunError> {
        if self.p2p.current_state() != SessionState::Running {
            if self.started.elapsed() > self.wait {
                return Err(RunError::Network(format!(
                    "could not synchronise with {} within {} s (NetOptions::wait_seconds; raise it with \
                     --wait-seconds)",
                    self.remote,
                    self.wait.as_secs_f64()
                )));
            }
            return Ok(false);
        }
        let input = match self.pending {
            Some(input) => input,
            None => self.next_local_input(end_time),
        };
        self.pending = Some(input);
        let local = self.local;
        guarded("taking this side's input", || {
            self.p2p.add_local_input(local, input.into())
        })?
        .map_err(ggrs_error)?;
        // Whether tick `end`'s state is certain once this call's rollback
        // (if any) is done: every input before it confirmed.
        let end = self.end;
        let confirmed = u64::try_from(self.p2p.confirmed_frame()).map_or(0, |f| f + 1);
        let certain_before = confirmed.min(self.cursor.tick);
        let certain = end.is_some_and(|end| certain_before >= end);
        let frame = self.p2p.current_frame();
        let requests = self
            .guard("advancing a frame", |p2p| p2p.advance_frame())?
            .map_err(ggrs_error)?;
        // A rollback re-runs ticks even when the new one waits: only the
        // frame count says whether this tick ran.
        let advanced = self.p2p.current_frame() > frame;
        let players = 2;
        let (final_state, played) = (&mut self.final_state, &mut self.played);
        fulfil(
            &mut self.session,
            requests,
            &mut self.cursor,
            |tick, state, checksum| {
                if Some(tick) == end {
                    match final_state {
                        Some((kept, sum)) => {
                            kept.clone_from(state);
                            *sum = checksum;
                        }
                        None => *final_state = Some((state.clone(), checksum)),
                    }
                }
            },
            |tick, inputs| {
                let at = usize::try_from(tick).unwrap_or(usize::MAX).saturating_mul(players);
                if played.len() < at + players {
                    played.resize(at + players, TickInput::default());
                }
                played[at..at + players].copy_from_slice(inputs);
            },
        )?;
        self.certain_ticks = self.certain_ticks.max(certain_before);
        let mut certain = certain && self.final_state.is_some();
        if self.lockstep && end == Some(self.cursor.tick) && self.final_state.is_none() {
            // Lockstep asks for no saves; every tick it runs is confirmed.
            self.final_state = Some((self.session.save_tick(), self.session.checksum()));
            self.certain_ticks = self.cursor.tick;
            certain = true;
        }
        if certain && !self.settled {
            self.settled = true;
            let (tick, checksum) = (
                end.unwrap_or(self.cursor.tick),
                self.final_state.as_ref().map_or(0, |f| f.1),
            );
            self.shared.borrow_mut().local_done = Some((tick, checksum));
            // Say so now: the other side may be waiting only for this.
            self.guard("reading the network", |p2p| p2p.poll_remote_clients())?;
        }
        if advanced {
            self.pending = None;
        } else {
            self.waits += 1;
        }
        Ok(advanced)
    }

    /// Plays the match without a window until it is over at tick `ticks`,
    /// in real time (a frame whenever a tick is due), and puts the stage
    /// at the final state.
    ///
    /// # Errors
    /// [`RunError::Network`] for a desync, a lost or silent peer; a game
    /// or world failure.
    pub fn play_headless(&mut self, ticks: u64) -> Result<MatchReport, RunError> {
        self.end_at(ticks);
        let dt = Duration::from_secs_f64(self.session.clock().dt());
        let mut last = Instant::now();
        while !self.is_over() {
            let now = Instant::now();
            self.advance((now - last).as_secs_f64())?;
            last = now;
            // Frame pacing, as a display's vsync would: the next tick is due
            // a step after this one; GGRS is read again then.
            std::thread::sleep(dt.saturating_sub(last.elapsed()).min(Duration::from_millis(4)));
        }
        self.report()
    }

    /// Puts the stage at the final state of a match that is over
    /// ([`is_over`](Self::is_over)) and reports it.
    ///
    /// # Errors
    /// [`RunError::Network`] if the match is not over, or the other side
    /// ended it at another state (a desync in its last ticks).
    pub fn report(&mut self) -> Result<MatchReport, RunError> {
        let (state, checksum) = self
            .final_state
            .as_ref()
            .ok_or_else(|| RunError::Network("the match ended before its final state was known".into()))?;
        let checksum = *checksum;
        let remote = self.shared.borrow().remote_done;
        if let Some((tick, theirs)) = remote.filter(|&(_, theirs)| theirs != checksum) {
            return Err(RunError::Network(format!(
                "desync at tick {tick}, the match's last: this side's checksum is {checksum:016x}, the other's \
                 ({}) {theirs:016x}; the two simulations differ (something the game does is not deterministic or \
                 not in its saved state: run it with --sync-test to find it)",
                self.remote
            )));
        }
        let state = state.clone();
        self.session.load_tick(&state)?;
        Ok(MatchReport {
            ticks: self.end.unwrap_or(self.cursor.tick),
            checksum,
            rollbacks: self.cursor.rollbacks,
            resimulated: self.cursor.resimulated,
            waits: self.waits,
            skipped: self.skipped,
            dropped: self.shared.borrow().dropped,
            outcome: self.session.outcome(),
        })
    }

    /// Both players' inputs up to the end of the match, as a recording
    /// that `--replay` plays back to the same final state.
    #[must_use]
    pub fn recording(&self) -> Recording {
        let clock = self.session.clock();
        let settings = self.session.stage().settings();
        let mut recording = Recording::new(
            self.session.game().title(),
            clock.timeline().rate().hz_value(),
            settings.seed,
            settings.integrator.clone(),
        );
        let players = 2;
        let certain = match self.end {
            Some(end) if self.settled => end,
            _ => self.certain_ticks,
        };
        let ticks = certain.min((self.played.len() / players) as u64);
        recording.ticks = ticks;
        for player in 0..players {
            let inputs = recording.inputs_of_mut(player);
            let mut carried = TickInput::default();
            for tick in 0..ticks {
                let input = self.played[tick as usize * players + player];
                if input != carried {
                    inputs.push((tick, input));
                }
                carried = input.carried();
            }
        }
        recording
    }
}

impl<G: Game + Clone + 'static> FrameSource for NetSession<G> {
    fn title(&self) -> String {
        format!("{} (player {})", self.session.game().title(), self.local + 1)
    }

    fn advance(&mut self, seconds: f64) -> Result<(), RunError> {
        self.guard("reading the network", |p2p| p2p.poll_remote_clients())?;
        self.handle_events()?;
        let frame = self.session.advance_clock(seconds)?;
        let mut ran = 0;
        for step in frame.fixed_steps() {
            if self.skip > 0 {
                // Not run and not given back: this side slows down by a tick.
                self.skip -= 1;
                self.skipped += 1;
                ran += 1;
                continue;
            }
            if !self.try_tick(step.time + step.dt)? {
                break;
            }
            ran += 1;
        }
        if ran < frame.steps {
            self.session.clock_mut().defer(frame.steps - ran);
        }
        self.session.finish_frame(frame);
        // The last advance's events too (a desync found in it).
        self.handle_events()
    }

    fn control(&mut self, control: Control) -> Result<(), RunError> {
        // Both sides must run the same ticks with the same integrators.
        crate::say!("tickwork: {control:?} is not available in a networked match");
        Ok(())
    }

    fn takes_input(&self) -> bool {
        self.script.is_none()
    }

    fn input(&mut self, event: InputEvent, arrival: f64) {
        self.session.input(event, arrival);
    }

    fn ticks(&self) -> u64 {
        self.cursor.tick
    }

    fn finished(&self) -> bool {
        self.is_over()
    }

    fn interpolation(&self) -> Option<Interpolation> {
        self.session.interpolation()
    }

    fn camera_mut(&mut self) -> &mut Camera {
        self.session.camera_mut()
    }

    fn attach_gpu(&mut self, gpu: &crate::render::Gpu) {
        self.session.attach_gpu(gpu);
    }

    fn needs_gpu(&self) -> bool {
        self.session.needs_gpu()
    }

    fn with_view(
        &mut self,
        hud: bool,
        size: (u32, u32),
        render: &mut dyn FnMut(&FrameView<'_>) -> Result<(), RenderError>,
    ) -> Result<(), RunError> {
        if !hud {
            return self.session.with_view(hud, size, render);
        }
        // The match's line under the game's HUD: who, the ping, rollbacks.
        let line = self.hud_line();
        self.session.with_view(hud, size, &mut |view| {
            let mut text = String::with_capacity(view.hud.len() + line.len() + 1);
            text.push_str(view.hud);
            if !text.is_empty() && !text.ends_with('\n') {
                text.push('\n');
            }
            text.push_str(&line);
            render(&FrameView { hud: &text, ..*view })
        })
    }
}
