//! The window runner: winit 0.30's `ApplicationHandler` around a
//! [`FrameSource`] (a game or a scene's playback), driven by the real clock
//! (or a simulated cadence for tests), drawing through the same
//! [`Renderer`] as the off-screen runner, with the egui control panel on top.
//!
//! Keys: P pause (and Space and R reset for sources without game keys),
//! Period single step, `+`/`-` time scale, Tab or 1-9 integrator, F5 reset,
//! F1 panel, F12 screenshot, Escape close. Which key is the runner's and
//! which the game's follows one rule, stated on [`Key`](crate::input::Key):
//! the runner's own keys stay its own unless the game claims them, and
//! with Ctrl held any key is the runner's.
//! Mouse: a game gets its buttons and the pointer (as a world point);
//! otherwise drag to orbit (3D) or pan (2D). The wheel zooms.
//!
//! Everything the player does is collected during a frame and handed over
//! at the start of the next, before its steps: input events with where in
//! the frame they arrived (the source gives each to the tick of its time),
//! then the controls of keys and panel, applied through
//! [`FrameSource::control`] at that tick boundary.

mod app;
mod gamepads;
mod keys;
mod options;
mod panel;
mod surface;
mod touch;

use winit::event_loop::EventLoop;

use crate::app::api::error::RunError;
use crate::app::session::source::FrameSource;
use app::App;
use app::Connected;
#[cfg(target_arch = "wasm32")]
use app::WhenDone;
pub use app::WindowSummary;
pub use options::WindowOptions;

/// Whether a window can be opened: on Linux and the BSDs, a display server
/// is named (`DISPLAY`, `WAYLAND_DISPLAY` or `WAYLAND_SOCKET`).
pub(crate) fn display_available() -> bool {
    !cfg!(all(unix, not(target_os = "macos")))
        || ["DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET"]
            .iter()
            .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

/// Opens a window and plays `source` in it until it is closed (or
/// `options.frames` have been shown).
///
/// # Errors
/// [`RunError::Window`] if no window can be opened (no display),
/// [`RunError::Render`] for no adapter or a surface that cannot be
/// configured, [`RunError::Playback`] if a step fails.
pub fn run_window(source: &mut dyn FrameSource, options: WindowOptions) -> Result<WindowSummary, RunError> {
    check_options(&options)?;
    if !display_available() {
        return Err(RunError::Window(
            "no display (neither DISPLAY nor WAYLAND_DISPLAY is set): run it in a desktop session or under \
             `xvfb-run`, or draw frames without a window with `tickwork render`"
                .into(),
        ));
    }
    let event_loop = EventLoop::<Connected>::with_user_event()
        .build()
        .map_err(|e| RunError::Window(e.to_string()))?;
    let mut app = App::new(source, options, event_loop.create_proxy(), None);
    event_loop
        .run_app(&mut app)
        .map_err(|e| RunError::Window(e.to_string()))?;
    match app.error {
        Some(error) => Err(error),
        None => Ok(app.summary),
    }
}

/// Checks `options` before a window opens.
fn check_options(options: &WindowOptions) -> Result<(), RunError> {
    if options.width == 0 || options.height == 0 {
        return Err(RunError::Window(format!(
            "the window size must be at least 1x1, got {}x{}",
            options.width, options.height
        )));
    }
    if !(options.hold_seconds.is_finite() && options.hold_seconds >= 0.0) {
        return Err(RunError::Window(format!(
            "hold_seconds must be finite and not negative, got {}",
            options.hold_seconds
        )));
    }
    Ok(())
}

/// The page's window run: plays `source` on a canvas on the browser's
/// event loop and returns at once (a page's loop never returns to its
/// caller); `done` gets the run's result when it ends.
///
/// # Errors
/// As [`run_window`], for what is known before the loop starts.
#[cfg(target_arch = "wasm32")]
pub(crate) fn spawn_window(
    source: &'static mut dyn FrameSource,
    options: WindowOptions,
    done: WhenDone,
) -> Result<(), RunError> {
    use winit::platform::web::EventLoopExtWebSys;
    check_options(&options)?;
    let event_loop = EventLoop::<Connected>::with_user_event()
        .build()
        .map_err(|e| RunError::Window(e.to_string()))?;
    let app = App::new(source, options, event_loop.create_proxy(), Some(done));
    event_loop.spawn_app(app);
    Ok(())
}
