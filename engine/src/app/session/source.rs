//! [`FrameSource`]: what the runners show frame by frame, a game's
//! [`GameSession`](crate::app::GameSession) or a scene's
//! [`Playback`](crate::app::Playback).

use crate::app::api::control::Control;
use crate::app::api::error::RunError;
use crate::input::{InputEvent as Event, KeySet};
use crate::interpolation::Interpolation;
use crate::render::{Camera, FrameView, RenderError};

/// Something the runners can show frame by frame: advanced by each frame's
/// duration, steered by controls and keys, drawn through a [`FrameView`].
pub trait FrameSource {
    /// The window title.
    fn title(&self) -> String;

    /// Advances by one displayed frame of `seconds`, running the fixed
    /// steps it is due.
    ///
    /// # Errors
    /// [`RunError`] for a bad duration or a failed step.
    fn advance(&mut self, seconds: f64) -> Result<(), RunError>;

    /// Applies a viewer control now. The runners call it between frames
    /// only (the keys' controls and the panel's alike), so every control
    /// enters the simulation at a tick boundary.
    ///
    /// # Errors
    /// [`RunError`] if the control fails (an integrator number beyond the
    /// registry, a rate the clock refuses).
    fn control(&mut self, control: Control) -> Result<(), RunError>;

    /// Whether the source takes the player's input (game keys, mouse
    /// buttons and pointer); if not, the window maps keys to controls and
    /// the mouse to the camera. Default: not taken.
    fn takes_input(&self) -> bool {
        false
    }

    /// The runner's keys the source takes for itself while it takes input
    /// (see [`Stage::claimed_keys`](crate::app::Stage)); the others stay the
    /// runner's. Default: none.
    fn claimed_keys(&self) -> KeySet {
        KeySet::EMPTY
    }

    /// An input event that arrived at `arrival` in the coming frame (0 at
    /// its start, 1 at its end): see [`crate::input::InputQueue`]. Called
    /// by the runner just before [`advance`](Self::advance). Default: ignored.
    fn input(&mut self, event: Event, arrival: f64) {
        let _ = (event, arrival);
    }

    /// Fixed steps run since the start (or the last reset).
    fn ticks(&self) -> u64;

    /// How the runner's renderer is to place particles between steps this
    /// frame, read before each frame is drawn (the fixed step can change
    /// between frames); `None` (the default) keeps the renderer's own
    /// [`RendererConfig::interpolation`](crate::render::RendererConfig).
    fn interpolation(&self) -> Option<Interpolation> {
        None
    }

    /// Whether the source has come to its end and the window should close
    /// (a networked match over). Default: never.
    fn finished(&self) -> bool {
        false
    }

    /// The camera, for the window's mouse.
    fn camera_mut(&mut self) -> &mut Camera;

    /// The GPU the runner draws with, given before the first frame: worlds
    /// stepped on the GPU step there, so the renderer draws them from
    /// their own buffers. Default: not used.
    fn attach_gpu(&mut self, gpu: &crate::render::Gpu) {
        let _ = gpu;
    }

    /// Whether the source steps a world on the GPU, so that a runner whose
    /// GPU is not there yet (a page's, a window's, which the platform
    /// gives later) holds its frames until it is. Default: no.
    fn needs_gpu(&self) -> bool {
        false
    }

    /// Calls `render` with the view of the current frame, for a target of
    /// `size` pixels (`hud`: with its HUD text).
    ///
    /// # Errors
    /// What `render` returns.
    fn with_view(
        &mut self,
        hud: bool,
        size: (u32, u32),
        render: &mut dyn FnMut(&FrameView<'_>) -> Result<(), RenderError>,
    ) -> Result<(), RunError>;

    /// Lays out the window's control panel, adding the controls chosen in
    /// it to `chosen` (applied by the runner before the next frame's
    /// steps). Default: no panel.
    #[cfg(feature = "panel")]
    fn panel(&self, ctx: &egui::Context, chosen: &mut Vec<Control>) {
        let _ = (ctx, chosen);
    }
}
