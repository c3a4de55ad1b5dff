//! [`WindowOptions`]: what a window run is asked for.

use std::path::PathBuf;

use crate::render::RendererConfig;

/// Window settings.
#[derive(Clone, Debug)]
pub struct WindowOptions {
    /// Inner width in physical pixels (default 1280).
    pub width: u32,
    /// Inner height in physical pixels (default 720).
    pub height: u32,
    /// Wait for the display's refresh (default true); off presents at once
    /// (Mailbox or Immediate, whichever the surface offers).
    pub vsync: bool,
    /// Close after this many frames (default: run until closed).
    pub frames: Option<u64>,
    /// After `frames`, keep showing the last frame this many seconds before
    /// closing (default 0), for an outside screenshot.
    pub hold_seconds: f64,
    /// Frame durations from a simulated display at this rate instead of the
    /// real clock (default: real clock), so a window's frames can be
    /// reproduced off-screen.
    pub display_hz: Option<f64>,
    /// Where F12 screenshots go (default: the current directory).
    pub screenshot_dir: PathBuf,
    /// Draw the HUD (default true).
    pub hud: bool,
    /// Renderer settings (default: [`RendererConfig::default`]).
    pub renderer: RendererConfig,
    /// Show the control panel at the start (default false; F1 toggles it).
    pub panel: bool,
    /// In a page: the canvas fills the page and follows its size (and the
    /// device pixel ratio) instead of `width` x `height` (default false;
    /// ignored natively).
    pub fill_page: bool,
    /// The graphics backends to try (default: `WGPU_BACKEND`'s, or every
    /// one compiled in; in a page WebGPU, then WebGL2).
    pub backends: Option<wgpu::Backends>,
}

impl Default for WindowOptions {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            vsync: true,
            frames: None,
            hold_seconds: 0.0,
            display_hz: None,
            screenshot_dir: PathBuf::from("."),
            hud: true,
            renderer: RendererConfig::default(),
            panel: false,
            fill_page: false,
            backends: None,
        }
    }
}
