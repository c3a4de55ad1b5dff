//! A game run natively ([`run`](crate::app::run) hands it here): in a window
//! when a display is available, off-screen otherwise, with the shared
//! command-line options; and [`exit_code`] for a game's `main`.

use std::path::{Path, PathBuf};

use crate::app::api::error::RunError;
use crate::app::api::game::Game;
#[cfg(feature = "netcode")]
use crate::app::api::game::GameError;
use crate::app::api::stage::{Settings, Stage};
#[cfg(feature = "netcode")]
use crate::app::net::rollback::sync_test;
#[cfg(feature = "netcode")]
use crate::app::net::{Lobby, MatchReport, NetOptions, NetSession, Peer};
use crate::app::runner::offscreen::{FrameOutput, MAX_OFFSCREEN_FRAMES, OffscreenRun, check_output};
use crate::app::runner::options::RunOptions;
#[cfg(feature = "window")]
use crate::app::runner::window::{WindowOptions, display_available, run_window};
use crate::app::session::game_session::GameSession;
use crate::app::session::options::SessionOptions;
use crate::app::session::source::FrameSource;
use crate::clock::FixedCadence;
use crate::input::Recording;
use crate::render::{Gpu, RendererConfig};

/// What a run did.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSummary {
    /// Whether it ran in a window (else off-screen).
    pub windowed: bool,
    /// Frames shown or drawn.
    pub frames: u64,
    /// Fixed steps run.
    pub ticks: u64,
    /// Off-screen: the frames' directory.
    pub out: Option<PathBuf>,
    /// Off-screen: the GIF.
    pub gif: Option<PathBuf>,
    /// The recording written, if any.
    pub recording: Option<PathBuf>,
    /// The game's outcome line, if it has one.
    pub outcome: Option<String>,
    /// The checksum of the final state (every world and the game's own),
    /// for comparing runs: printed by off-screen runs, sync tests and
    /// headless matches.
    pub checksum: Option<u64>,
}

impl RunSummary {
    /// A run that has done nothing yet.
    pub(crate) fn nothing_yet(windowed: bool) -> Self {
        Self {
            windowed,
            frames: 0,
            ticks: 0,
            out: None,
            gif: None,
            recording: None,
            outcome: None,
            checksum: None,
        }
    }
}

/// The renderer settings [`run`](crate::app::run) draws a stage's frames `height` pixels
/// tall with (for a test that draws a game as `run` does): the stage's
/// background, and its HUD size from 540 px up, shrinking with smaller
/// frames down to 10/16 of it, so a legend that fits a window fits a small
/// GIF.
#[must_use]
pub fn renderer_config(stage: &Stage, height: u32) -> RendererConfig {
    RendererConfig {
        background: stage.background,
        hud_size: stage.hud_size * (height as f32 / 540.0).clamp(10.0 / 16.0, 1.0),
        ..RendererConfig::default()
    }
}

/// A title as a file name: lower-case ASCII letters, digits and dashes.
fn slug(title: &str) -> String {
    title
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect()
}

/// `tickwork-out/<slug>`, or `-2`, `-3`, ... if that holds earlier frames.
fn fresh_output_dir(title: &str) -> PathBuf {
    let slug = slug(title);
    let base = Path::new("tickwork-out");
    (1..)
        .map(|k| {
            if k == 1 {
                base.join(&slug)
            } else {
                base.join(format!("{slug}-{k}"))
            }
        })
        .find(|dir| !dir.exists())
        .unwrap_or_else(|| base.join(&slug))
}

/// Whether a file can be written at `path`: not a directory, in a directory
/// that exists, and new unless `overwrite`.
fn check_output_file(path: &std::path::Path, overwrite: bool) -> Result<(), RunError> {
    let io = |message: String| RunError::Io {
        path: path.to_path_buf(),
        message,
    };
    if path.is_dir() {
        return Err(io("is a directory; name a file".into()));
    }
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty())
        && !parent.is_dir()
    {
        return Err(io(format!("the directory {} does not exist", parent.display())));
    }
    if path.exists() && !overwrite {
        return Err(RunError::Exists(path.to_path_buf()));
    }
    Ok(())
}

/// [`run`](crate::app::run) natively: a window or off-screen frames.
#[cfg_attr(target_arch = "wasm32", allow(dead_code))]
pub(crate) fn run_native<G: Game + Clone + 'static>(game: G, options: RunOptions) -> Result<RunSummary, RunError> {
    if options.backend.is_some() {
        return Err(RunError::Limit(
            "--backend chooses a page's graphics backend (webgpu or webgl2); natively, WGPU_BACKEND chooses \
             (vulkan, gl, ...)"
                .into(),
        ));
    }
    // Before any thread starts (a game's `main` calls `run` first).
    crate::render::quiet_device_select_layer();
    // Parallel steps from this thread then allocate nothing. An existing
    // pool (the game used rayon first) is fine: steps run on it.
    let _ = crate::threads::join_thread_pool();
    // Where the recording goes is checked before the run: a run that failed
    // to save at its end lost all the input it had taken.
    if let Some(path) = &options.record {
        check_output_file(path, options.force)?;
    }
    // So are the GIF, the frames' directory and their count.
    if let Some(path) = &options.gif {
        check_output_file(path, options.force)?;
    }
    // Without the `window` feature every native run is off-screen.
    #[cfg(feature = "window")]
    let windowed = !options.headless && display_available();
    #[cfg(not(feature = "window"))]
    let windowed = false;
    if !windowed {
        check_output(options.frames.unwrap_or(0), options.out.as_deref())?;
    }
    let replay = options.replay.as_deref().map(Recording::load).transpose()?;
    #[cfg(feature = "netcode")]
    if let Some(meeting) = Meeting::of(&options) {
        if replay.is_some() {
            return Err(RunError::Limit(
                "--replay plays a whole run back alone; in a match, --script plays this side's input from a recording"
                    .into(),
            ));
        }
        let script = options.script.as_deref().map(Recording::load).transpose()?;
        return network_run(game, meeting, &options.net_options(), &options, windowed, script);
    }
    #[cfg(feature = "netcode")]
    if options.script.is_some() {
        return Err(RunError::Limit(
            "--script plays one side of a networked match: pass --host PORT, --join ADDR or --room URL with it (to \
             play a recording back alone, use --replay)"
                .into(),
        ));
    }
    let replay_ticks = replay.as_ref().map(|r| (r.ticks, r.hz));
    // A sync test drives the ticks itself, with the recording's inputs.
    #[cfg(feature = "netcode")]
    let replay_inputs = options.sync_test.and(replay.clone());
    let mut session = GameSession::new(game, session_options(&options, replay))?;
    let title = session.game().title().to_owned();
    #[cfg(feature = "netcode")]
    if let Some(distance) = options.sync_test {
        return sync_test_run(&mut session, distance, &options, replay_inputs.as_ref());
    }
    let mut summary = RunSummary::nothing_yet(windowed);
    let shown = show(&mut session, &options, replay_ticks, &mut summary);
    // The input so far is kept even when the run failed (a recording of the
    // failure is what a bug report needs).
    summary.ticks = FrameSource::ticks(&session);
    summary.recording = session.save_recording()?;
    if let Some(path) = &summary.recording {
        crate::say!(
            "tickwork: recorded {} ticks of input to {}",
            summary.ticks,
            path.display()
        );
    }
    shown?;
    // Worlds on the GPU come back for the checksum and the outcome.
    session.read_back()?;
    if !summary.windowed {
        let checksum = session.checksum();
        // A replay that reached its end has said so, with this checksum.
        if !matches!(session.replay(), Some((_, true))) {
            crate::say!(
                "tickwork: {title}: the final state at tick {} has checksum {checksum:016x}",
                summary.ticks
            );
        }
        summary.checksum = Some(checksum);
    }
    summary.outcome = session.outcome();
    if let Some(outcome) = &summary.outcome {
        crate::say!("{title}: {outcome}");
    }
    Ok(summary)
}

/// The session a run alone asks for: `options`' settings, rate, time
/// scale and recording, playing `replay` if given.
pub(crate) fn session_options(options: &RunOptions, replay: Option<Recording>) -> SessionOptions {
    SessionOptions {
        settings: Settings {
            integrator: options.integrator.clone(),
            seed: options.seed,
            networked: false,
            gpu: options.gpu,
        },
        hz: options.hz,
        time_scale: options.time_scale,
        record: options.record.clone(),
        replay,
        overwrite: options.force,
    }
}

/// The ticks a headless match plays without `--frames`: 600 (ten seconds
/// at 60 Hz).
#[cfg(feature = "netcode")]
pub const DEFAULT_MATCH_TICKS: u64 = 600;

/// Where the other player of a match is found.
#[cfg(feature = "netcode")]
enum Meeting {
    /// `--host` or `--join`: over UDP.
    Udp(Peer),
    /// `--room`: in a signalling server's room, over WebRTC.
    #[cfg(feature = "webrtc")]
    Room(String),
}

#[cfg(feature = "netcode")]
impl Meeting {
    /// The meeting `options` ask for, if any.
    fn of(options: &RunOptions) -> Option<Self> {
        #[cfg(feature = "webrtc")]
        if let Some(url) = &options.room {
            return Some(Self::Room(url.clone()));
        }
        options.network().map(|(peer, _)| Self::Udp(peer))
    }
}

#[cfg(feature = "netcode")]
/// `--host`, `--join` or `--room`: finds the other player, then plays the
/// match in the window, or headless for `--frames` ticks; saves both
/// players' inputs with `--record`.
fn network_run<G: Game + Clone + 'static>(
    game: G,
    meeting: Meeting,
    net: &NetOptions,
    options: &RunOptions,
    windowed: bool,
    script: Option<Recording>,
) -> Result<RunSummary, RunError> {
    let title = game.title().to_owned();
    let session_options = SessionOptions {
        settings: Settings {
            integrator: options.integrator.clone(),
            seed: options.seed,
            networked: true,
            gpu: options.gpu,
        },
        hz: options.hz,
        time_scale: 1.0,
        record: None,
        replay: None,
        overwrite: options.force,
    };
    let mut session = match meeting {
        Meeting::Udp(peer) => {
            let lobby = Lobby::bind(peer)?;
            match peer {
                Peer::Host { .. } => crate::say!(
                    "tickwork: {title}: hosting on port {}; the other player joins with --join <this machine's \
                     address>:{}",
                    lobby.local_addr()?.port(),
                    lobby.local_addr()?.port()
                ),
                Peer::Join { host } => crate::say!("tickwork: {title}: joining {host}"),
            }
            NetSession::start(game, lobby, session_options, net, script)?
        }
        // Natively the meeting blocks until it is done.
        #[cfg(feature = "webrtc")]
        Meeting::Room(url) => {
            crate::platform::ready_now(NetSession::start_in_room(game, &url, session_options, net, script))
                .ok_or_else(|| RunError::Network("the meeting in the room did not end".into()))??
        }
    };
    let mut summary = RunSummary::nothing_yet(windowed);
    #[cfg(not(feature = "window"))]
    let played = {
        let _ = windowed;
        let ticks = options.frames.unwrap_or(DEFAULT_MATCH_TICKS);
        session
            .play_headless(ticks)
            .map(|report| summary.checksum = Some(match_ended(&title, report)))
    };
    #[cfg(feature = "window")]
    let played = if windowed {
        // `--frames N` ends the match at tick N (the window closes then).
        if let Some(ticks) = options.frames {
            session.end_at(ticks);
        }
        let (width, height) = options.size.unwrap_or((1280, 720));
        let renderer = renderer_config(session.session().stage(), height);
        run_window(
            &mut session,
            WindowOptions {
                width,
                height,
                display_hz: options.display_hz,
                screenshot_dir: PathBuf::from("."),
                panel: false,
                renderer,
                ..WindowOptions::default()
            },
        )
        .and_then(|window| {
            summary.frames = window.frames;
            if session.is_over() {
                summary.checksum = Some(match_ended(&title, session.report()?));
            }
            Ok(())
        })
    } else {
        let ticks = options.frames.unwrap_or(DEFAULT_MATCH_TICKS);
        session
            .play_headless(ticks)
            .map(|report| summary.checksum = Some(match_ended(&title, report)))
    };
    summary.ticks = FrameSource::ticks(&session);
    // The confirmed inputs are kept even when the match failed.
    if let Some(path) = &options.record {
        let mut recording = session.recording();
        // The match's final state, where it ended (the recording's end).
        recording.checksum = summary.checksum.filter(|_| recording.ticks == summary.ticks);
        recording.save(path, options.force)?;
        crate::say!(
            "tickwork: recorded both players' inputs of {} ticks to {}",
            recording.ticks,
            path.display()
        );
        summary.recording = Some(path.clone());
    }
    played?;
    summary.outcome = session.session().outcome();
    if let Some(outcome) = &summary.outcome {
        crate::say!("{title}: {outcome}");
    }
    Ok(summary)
}

/// Prints how a match ended; returns its checksum.
#[cfg(feature = "netcode")]
pub(crate) fn match_ended(title: &str, report: MatchReport) -> u64 {
    if report.dropped > 0 {
        crate::say!(
            "tickwork: {title}: {} messages from the other player were neither the game's nor GGRS's and were dropped",
            report.dropped
        );
    }
    crate::say!(
        "tickwork: {title}: the match ended at tick {}: checksum {:016x}; {} rollbacks re-ran {} ticks, {} ticks \
         waited for the other player, {} were skipped to let it catch up",
        report.ticks,
        report.checksum,
        report.rollbacks,
        report.resimulated,
        report.waits,
        report.skipped
    );
    report.checksum
}

/// The most ticks `--sync-test` runs: a million (over four hours of play at
/// 60 Hz, each tick simulated up to eight times).
#[cfg(feature = "netcode")]
pub const MAX_SYNC_TEST_TICKS: u64 = 1_000_000;

#[cfg(feature = "netcode")]
/// `--sync-test`: the game headless under a rollback sync test, for
/// `--frames` ticks (default: the recording's, or 300), with the
/// recording's inputs if one is given.
pub(crate) fn sync_test_run<G: Game + Clone + 'static>(
    session: &mut GameSession<G>,
    distance: usize,
    options: &RunOptions,
    recording: Option<&Recording>,
) -> Result<RunSummary, RunError> {
    if let Some(recording) = recording.filter(|r| !r.controls.is_empty()) {
        return Err(RunError::Game(GameError::Message(format!(
            "--sync-test replays a recording's inputs, not its {} integrator switches; record a run without \
             switching integrators to sync-test it",
            recording.controls.len()
        ))));
    }
    let ticks = options.frames.or(recording.map(|r| r.ticks)).unwrap_or(300);
    if ticks > MAX_SYNC_TEST_TICKS {
        return Err(RunError::Limit(format!(
            "--sync-test runs {ticks} ticks, past the limit of {MAX_SYNC_TEST_TICKS} (MAX_SYNC_TEST_TICKS: each tick \
             is simulated {} times); pass a smaller --frames",
            distance + 1
        )));
    }
    let players = session.players();
    let (mut cursors, mut inputs) = (vec![0; players], vec![crate::input::TickInput::default(); players]);
    let report = sync_test(session, distance, ticks, |tick, player| {
        let input = &mut inputs[player];
        *input = match recording {
            Some(recording) => recording.input_of(player, &mut cursors[player], tick, input.carried()),
            None => input.carried(),
        };
        *input
    })?;
    crate::say!(
        "tickwork: {}: sync test passed: {} ticks, each rolled back {} ticks and re-simulated to the same state \
         (checksum {:016x})",
        session.game().title(),
        report.ticks,
        report.check_distance,
        report.checksum
    );
    let outcome = session.outcome();
    if let Some(outcome) = &outcome {
        crate::say!("{}: {outcome}", session.game().title());
    }
    Ok(RunSummary {
        ticks: report.ticks,
        outcome,
        checksum: Some(report.checksum),
        ..RunSummary::nothing_yet(false)
    })
}

/// The window or off-screen part of [`run`](crate::app::run).
fn show<G: Game>(
    session: &mut GameSession<G>,
    options: &RunOptions,
    replay_ticks: Option<(u64, f64)>,
    summary: &mut RunSummary,
) -> Result<(), RunError> {
    let title = session.game().title().to_owned();
    #[cfg(feature = "window")]
    if summary.windowed {
        #[cfg(feature = "audio")]
        session.open_audio_device();
        let (width, height) = options.size.unwrap_or((1280, 720));
        let panel = !options.no_panel && (options.panel || session.stage().panel);
        let renderer = renderer_config(session.stage(), height);
        let window = run_window(
            session,
            WindowOptions {
                width,
                height,
                frames: options.frames,
                hold_seconds: options.hold,
                display_hz: options.display_hz,
                screenshot_dir: PathBuf::from("."),
                panel,
                renderer,
                ..WindowOptions::default()
            },
        )?;
        summary.frames = window.frames;
        return Ok(());
    }
    {
        let (width, height) = options.size.unwrap_or((640, 360));
        let display_hz = options.display_hz.unwrap_or(60.0);
        let frames = match (options.frames, replay_ticks) {
            (Some(frames), _) => frames,
            // Enough frames for every recorded tick: steps per frame are
            // hz * time scale / display rate, at most the clock's cap per
            // frame (past it the clock drops time, not steps of the replay).
            (None, Some((ticks, hz))) => {
                let cap = f64::from(crate::clock::ClockConfig::default().max_steps_per_frame);
                let per_frame = (hz * options.time_scale / display_hz).min(cap);
                let needed = (ticks as f64 / per_frame).ceil() + 1.0;
                if needed.is_nan() || needed > MAX_OFFSCREEN_FRAMES as f64 {
                    return Err(RunError::Io {
                        path: options.replay.clone().unwrap_or_default(),
                        message: format!(
                            "replaying {ticks} ticks at {hz} Hz needs {} frames at {display_hz} frames per second, \
                             past the limit of {MAX_OFFSCREEN_FRAMES} off-screen frames (8 steps a frame at most); replay with a higher \
                             --time-scale or a lower --display-hz, or pass --frames",
                            crate::clock::Number(needed)
                        ),
                    });
                }
                needed as u64
            }
            (None, None) => 300,
        };
        let out = (!options.no_frames).then(|| options.out.clone().unwrap_or_else(|| fresh_output_dir(&title)));
        let gif = match &out {
            Some(out) => options
                .gif
                .clone()
                .or_else(|| Some(out.join(format!("{}.gif", slug(&title))))),
            None => None,
        };
        let gpu = Gpu::headless()?;
        let mut runner = OffscreenRun::new(&gpu, width, height, renderer_config(session.stage(), height))?;
        crate::say!(
            "tickwork: {title}: no display{}; drawing {frames} frames of {width}x{height} off-screen on {}",
            if options.headless { " wanted (--headless)" } else { "" },
            gpu.describe()
        );
        let started = crate::platform::Instant::now();
        let done = runner.run(
            session,
            &mut FixedCadence::hz(display_hz),
            frames,
            &FrameOutput {
                dir: out.clone(),
                gif: gif.clone(),
                overwrite: options.force,
                hud: true,
            },
            &mut |_| {},
        )?;
        summary.frames = done.frames;
        match &out {
            Some(dir) => crate::say!(
                "tickwork: wrote {} frames to {}/ and the GIF {}",
                done.frames,
                dir.display(),
                gif.as_deref().map_or_else(String::new, |g| g.display().to_string())
            ),
            None => {
                let seconds = started.elapsed().as_secs_f64();
                crate::say!(
                    "tickwork: drew {} frames in {seconds:.2} s ({:.2} ms a frame, stepping and drawing, each \
                     frame read back; none written: --no-frames)",
                    done.frames,
                    1000.0 * seconds / done.frames.max(1) as f64
                );
            }
        }
        summary.out = out;
        summary.gif = gif;
    }
    Ok(())
}

/// The exit code of a run for a game's `main`: success, or the error
/// printed to standard error (`error: ...`) and failure.
pub fn exit_code(result: Result<RunSummary, RunError>) -> std::process::ExitCode {
    match result {
        Ok(_) => std::process::ExitCode::SUCCESS,
        Err(error) => {
            crate::complain!("error: {error}");
            std::process::ExitCode::FAILURE
        }
    }
}
