//! The page's runner: [`run`](crate::app::run) in a browser, where a game plays
//! on a canvas and its `main` returns before the first frame.
//!
//! A page differs from a native run in what it can do, not in what it
//! simulates: the options come from the URL (parsed by the same
//! [`RunOptions`] parser), a `replay` is a URL the page fetches, the GPU
//! arrives from futures the browser resolves, and the loop runs on the
//! browser's animation frames. With `frames`, the frames are driven by a
//! simulated display (60 Hz unless `display_hz` says otherwise), not the
//! wall clock, as off-screen: after that many frames the page holds the
//! last one and prints the line a native off-screen run prints,
//! `tickwork: <game>: the final state at tick N has checksum X` (or, for a
//! replay that reached its end, `the replay ended at tick N with checksum
//! X` and whether that matches the recording),
//! which the browser tests wait for. A match meets the other player in a
//! signalling server's room (`room=`, `page_match.rs`). What a page cannot
//! do (a match over UDP, frames written to files) is refused with a
//! message on the page.

use crate::app::api::error::RunError;
use crate::app::api::game::Game;
use crate::app::runner::native::{RunSummary, renderer_config};
use crate::app::runner::options::RunOptions;
use crate::app::runner::window::{WindowOptions, spawn_window};
use crate::app::session::game_session::GameSession;
use crate::app::session::source::FrameSource;
use crate::input::{Recording, RecordingError};
use crate::platform::{complain, say, web};

/// Starts `game` in the page (see the module). Returns at once: the page
/// runs on the browser's event loop, and says how the run ends on the
/// console.
///
/// # Errors
/// What a page cannot do (networking, off-screen files, a sync test
/// without a recording to fetch is fine, so only the first two).
pub(crate) fn run_in_page<G: Game + Clone + 'static>(game: G, options: RunOptions) -> Result<RunSummary, RunError> {
    web::install_panic_hook();
    #[cfg(feature = "netcode")]
    if options.network().is_some() {
        return Err(RunError::Limit(
            "a networked match over UDP (--host, --join) needs sockets a browser does not have: in a page, meet \
             the other player in a signalling server's room with room=ws://HOST:PORT/ROOM (`tickwork signal`)"
                .into(),
        ));
    }
    if options.headless || options.out.is_some() || options.gif.is_some() {
        return Err(RunError::Limit(
            "a page draws on its canvas: headless, out and gif write frames to files, which only the native build \
             does"
                .into(),
        ));
    }
    crate::platform::spawn_local(async move {
        if let Err(error) = start(game, options).await {
            complain(&format!("error: {error}"));
        }
    });
    // The run goes on in the page; what it does, it prints.
    Ok(RunSummary::nothing_yet(true))
}

/// Fetches the replay, makes the session and starts the canvas.
async fn start<G: Game + Clone + 'static>(game: G, options: RunOptions) -> Result<(), RunError> {
    let replay = match &options.replay {
        Some(url) => {
            let name = url.to_string_lossy();
            let text = web::fetch_text(&name, Recording::MAX_FILE_BYTES, "Recording::MAX_FILE_BYTES")
                .await
                .map_err(|message| RecordingError::Io {
                    path: url.clone(),
                    message,
                })?;
            Some(Recording::parse(&text, url)?)
        }
        None => None,
    };
    // A page reads no files: the game's assets are fetched before setup.
    web::fetch_assets(game.assets())
        .await
        .map_err(|message| RunError::Game(format!("an asset the game lists (Game::assets): {message}").into()))?;
    #[cfg(feature = "webrtc")]
    if let Some(url) = options.room.clone() {
        let backends = backends(options.backend.as_deref())?;
        return super::page_match::start(game, &url, options, backends).await;
    }
    #[cfg(feature = "netcode")]
    let sync_inputs = options.sync_test.and(replay.clone());
    // (A page's recording is a download: nothing to overwrite.)
    // Mutable for the sync test (netcode).
    #[cfg_attr(not(feature = "netcode"), allow(unused_mut))]
    let mut session = GameSession::new(game, crate::app::runner::native::session_options(&options, replay))?;
    #[cfg(feature = "netcode")]
    if let Some(distance) = options.sync_test {
        crate::app::runner::native::sync_test_run(&mut session, distance, &options, sync_inputs.as_ref())?;
        return Ok(());
    }
    // A browser plays a page's sound only after the user's first key
    // press, click or touch: the device opens then (PageRun::input).
    #[cfg(feature = "audio")]
    say("tickwork: sound starts at the first key press, click or touch (the browser's rule)");
    let panel = !options.no_panel && (options.panel || session.stage().panel);
    let (width, height) = options.size.unwrap_or((1280, 720));
    let renderer = renderer_config(session.stage(), height);
    let window = WindowOptions {
        width,
        height,
        fill_page: options.size.is_none(),
        // Frames counted by the page: driven by a simulated display.
        display_hz: options.display_hz.or(options.frames.map(|_| 60.0)),
        panel,
        renderer,
        backends: Some(backends(options.backend.as_deref())?),
        ..WindowOptions::default()
    };
    // The page lives as long as the run: the session is the loop's for good.
    let source: &'static mut PageRun<G> = Box::leak(Box::new(PageRun {
        session,
        frames: options.frames,
        shown: 0,
        ended: false,
        started: None,
        heard: false,
    }));
    spawn_window(
        source,
        window,
        Box::new(|result| {
            if let Err(error) = result {
                complain(&format!("error: {error}"));
            }
        }),
    )
}

/// The backends a page tries: `webgpu`, `webgl2`, or both (WebGPU first).
fn backends(name: Option<&str>) -> Result<wgpu::Backends, RunError> {
    match name {
        None => Ok(wgpu::Backends::BROWSER_WEBGPU | wgpu::Backends::GL),
        Some("webgpu") => Ok(wgpu::Backends::BROWSER_WEBGPU),
        Some("webgl2") => Ok(wgpu::Backends::GL),
        Some(other) => Err(RunError::Limit(format!(
            "backend {other:?} is not one a page has: webgpu or webgl2"
        ))),
    }
}

/// A game's session in a page: counts the frames and ends the run after
/// `frames` of them, holding the last.
struct PageRun<G: Game> {
    session: GameSession<G>,
    frames: Option<u64>,
    shown: u64,
    ended: bool,
    /// When the first frame was advanced: the page's frame time is
    /// reported at the end (wall time, every frame drawn and presented).
    started: Option<crate::platform::Instant>,
    /// Whether the audio device was opened (at the first press).
    heard: bool,
}

impl<G: Game> PageRun<G> {
    /// Says how the run ended, as a native off-screen run does, and offers
    /// the recording.
    fn end(&mut self) -> Result<(), RunError> {
        self.ended = true;
        let title = self.session.game().title().to_owned();
        let ticks = FrameSource::ticks(&self.session);
        if let Some(path) = self.session.save_recording()? {
            say(&format!(
                "tickwork: recorded {ticks} ticks of input to {} (offered as a download)",
                path.display()
            ));
        }
        // A world on the GPU comes back only where the page may wait. A
        // replay that reached its end has said so, with its checksum.
        let replayed = matches!(self.session.replay(), Some((_, true)));
        match self.session.read_back() {
            _ if replayed => {}
            Ok(()) => say(&format!(
                "tickwork: {}: the final state at tick {ticks} has checksum {:016x}",
                title,
                self.session.checksum()
            )),
            Err(why) => say(&format!(
                "tickwork: {title}: the final state at tick {ticks} stays on the GPU, without a checksum: {why}"
            )),
        }
        if let Some(outcome) = self.session.outcome() {
            say(&format!("{title}: {outcome}"));
        }
        if let Some(started) = self.started {
            let seconds = started.elapsed().as_secs_f64();
            say(&format!(
                "tickwork: {}: {} frames in {seconds:.2} s of wall time, {:.1} ms a frame",
                title,
                self.shown,
                1e3 * seconds / self.shown.max(1) as f64
            ));
        }
        Ok(())
    }
}

impl<G: Game> FrameSource for PageRun<G> {
    fn title(&self) -> String {
        self.session.title()
    }

    fn advance(&mut self, seconds: f64) -> Result<(), RunError> {
        if self.ended {
            return Ok(());
        }
        self.started.get_or_insert_with(crate::platform::Instant::now);
        self.session.advance(seconds)?;
        self.shown += 1;
        if self.frames.is_some_and(|frames| self.shown >= frames) {
            self.end()?;
        }
        Ok(())
    }

    fn control(&mut self, control: crate::app::Control) -> Result<(), RunError> {
        self.session.control(control)?;
        // The page says when its clock stops or goes on (a browser test
        // waits on it; the console shows what a click on the panel did).
        if control == crate::app::Control::TogglePause {
            let ticks = FrameSource::ticks(&self.session);
            let state = if self.session.clock().is_paused() {
                "paused"
            } else {
                "resumed"
            };
            say(&format!("tickwork: {state} at tick {ticks}"));
        }
        Ok(())
    }

    fn takes_input(&self) -> bool {
        self.session.takes_input()
    }

    fn claimed_keys(&self) -> crate::input::KeySet {
        self.session.claimed_keys()
    }

    fn input(&mut self, event: crate::input::InputEvent, arrival: f64) {
        // A press is the user's gesture a browser wants before sound.
        if !self.heard && matches!(event, crate::input::InputEvent::Key { down: true, .. }) {
            self.heard = true;
            #[cfg(feature = "audio")]
            self.session.open_audio_device();
        }
        self.session.input(event, arrival);
    }

    fn ticks(&self) -> u64 {
        self.session.ticks()
    }

    fn interpolation(&self) -> Option<crate::interpolation::Interpolation> {
        self.session.interpolation()
    }

    fn finished(&self) -> bool {
        self.session.finished()
    }

    fn camera_mut(&mut self) -> &mut crate::render::Camera {
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
        render: &mut dyn FnMut(&crate::render::FrameView<'_>) -> Result<(), crate::render::RenderError>,
    ) -> Result<(), RunError> {
        self.session.with_view(hud, size, render)
    }

    #[cfg(feature = "panel")]
    fn panel(&self, ctx: &egui::Context, chosen: &mut Vec<crate::app::Control>) {
        self.session.panel(ctx, chosen);
    }
}
