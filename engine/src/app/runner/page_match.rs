//! A match in a page (`room=ws://HOST:PORT/ROOM`): the page meets the
//! other player in the signalling server's room, then plays the match on
//! its canvas over WebRTC, a native build or another page on the other
//! side. `script=URL` plays this side from a recording, `frames=N` ends
//! the match at tick N and prints the native line `the match ended at
//! tick N: checksum X`, `record=` offers both players' inputs as a
//! download. The HUD says who is connected, the ping and the rollbacks.

use crate::app::api::error::RunError;
use crate::app::api::game::Game;
use crate::app::net::NetSession;
use crate::app::runner::native::{match_ended, renderer_config};
use crate::app::runner::options::RunOptions;
use crate::app::runner::window::{WindowOptions, spawn_window};
use crate::app::session::source::FrameSource;
use crate::input::{Recording, RecordingError};
use crate::platform::{complain, say, web};

/// Meets the other player in the room at `url` and starts the match on
/// the page's canvas, drawing with `backends`.
pub(super) async fn start<G: Game + Clone + 'static>(
    game: G,
    url: &str,
    options: RunOptions,
    backends: wgpu::Backends,
) -> Result<(), RunError> {
    let script = match &options.script {
        Some(path) => {
            let name = path.to_string_lossy();
            let text = web::fetch_text(&name, Recording::MAX_FILE_BYTES, "Recording::MAX_FILE_BYTES")
                .await
                .map_err(|message| RecordingError::Io {
                    path: path.clone(),
                    message,
                })?;
            Some(Recording::parse(&text, path)?)
        }
        None => None,
    };
    let session_options = crate::app::runner::native::session_options(&options, None);
    let mut session = NetSession::start_in_room(game, url, session_options, &options.net_options(), script).await?;
    if let Some(ticks) = options.frames {
        session.end_at(ticks);
    }
    let (width, height) = options.size.unwrap_or((1280, 720));
    let renderer = renderer_config(session.session().stage(), height);
    let window = WindowOptions {
        width,
        height,
        fill_page: options.size.is_none(),
        // A match runs on the wall clock: the other side does.
        display_hz: None,
        renderer,
        backends: Some(backends),
        ..WindowOptions::default()
    };
    let source: &'static mut PageMatch<G> = Box::leak(Box::new(PageMatch {
        session,
        record: options.record.clone(),
        ended: false,
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

/// A match in a page: says how it ended once it is over.
struct PageMatch<G: Game + Clone + 'static> {
    session: NetSession<G>,
    record: Option<std::path::PathBuf>,
    ended: bool,
}

impl<G: Game + Clone + 'static> PageMatch<G> {
    /// Prints the match's end as a native run does; offers the recording.
    fn end(&mut self) -> Result<(), RunError> {
        self.ended = true;
        let title = self.session.session().game().title().to_owned();
        let report = self.session.report()?;
        let checksum = match_ended(&title, report);
        if let Some(path) = &self.record {
            let mut recording = self.session.recording();
            recording.checksum = Some(checksum);
            // A page's recording is a download: nothing to overwrite.
            recording.save(path, true)?;
            say(&format!(
                "tickwork: recorded both players' inputs of {} ticks to {} (offered as a download)",
                recording.ticks,
                path.display()
            ));
        }
        if let Some(outcome) = self.session.session().outcome() {
            say(&format!("{title}: {outcome}"));
        }
        Ok(())
    }
}

impl<G: Game + Clone + 'static> FrameSource for PageMatch<G> {
    fn title(&self) -> String {
        self.session.title()
    }

    fn advance(&mut self, seconds: f64) -> Result<(), RunError> {
        if self.ended {
            return Ok(());
        }
        self.session.advance(seconds)?;
        if self.session.is_over() {
            self.end()?;
        }
        Ok(())
    }

    fn control(&mut self, control: crate::app::Control) -> Result<(), RunError> {
        self.session.control(control)
    }

    fn takes_input(&self) -> bool {
        self.session.takes_input()
    }

    fn input(&mut self, event: crate::input::InputEvent, arrival: f64) {
        self.session.input(event, arrival);
    }

    fn ticks(&self) -> u64 {
        FrameSource::ticks(&self.session)
    }

    fn interpolation(&self) -> Option<crate::interpolation::Interpolation> {
        self.session.interpolation()
    }

    fn finished(&self) -> bool {
        // The page holds the last frame (the window's end would cancel
        // the recording's download).
        false
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
}
