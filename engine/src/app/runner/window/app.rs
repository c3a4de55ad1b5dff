//! The window run's application: winit's `ApplicationHandler` holding the
//! source, the window's surface and panel, and what the player did this
//! frame; [`run_window`](super::run_window) and the page's runner drive it.

use crate::platform::Instant;
use std::path::PathBuf;

use winit::application::ApplicationHandler;
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoopProxy};
use winit::keyboard::{Key, NamedKey};
use winit::window::WindowId;

use super::gamepads::Gamepads;
use super::keys::KeyAction;
use super::options::WindowOptions;
use super::panel::draw_panel;
use super::panel::{Panel, PanelTarget};
use super::surface::{WindowState, open, screenshot};
use super::touch::{Mouse, TouchMouse};
use crate::app::api::control::Control;
use crate::app::api::error::RunError;
use crate::app::session::source::FrameSource;
use crate::clock::{RealTime, TimeSource};
use crate::input::{InputEvent, Key as GameKey};
use crate::platform::say;
use crate::render::RenderError;

/// The window's GPU, once found: the event the start-up sends back to the
/// loop (natively at once, in a page when the browser has answered).
pub(crate) struct Connected(Result<(WindowState, Panel), RunError>);

/// Called with the run's result when a page's window run ends (a page's
/// loop never returns to its caller).
pub(crate) type WhenDone = Box<dyn FnOnce(Result<WindowSummary, RunError>)>;

/// What a window run did.
#[derive(Clone, Debug, PartialEq)]
pub struct WindowSummary {
    /// Frames presented.
    pub frames: u64,
    /// The adapter used.
    pub adapter: String,
    /// The surface format and present mode chosen.
    pub surface: String,
    /// Screenshots written.
    pub screenshots: Vec<PathBuf>,
}

impl<'a> App<'a> {
    pub(super) fn new(
        source: &'a mut dyn FrameSource,
        options: WindowOptions,
        proxy: EventLoopProxy<Connected>,
        done: Option<WhenDone>,
    ) -> Self {
        let time: Box<dyn TimeSource> = match options.display_hz {
            Some(hz) => Box::new(crate::clock::FixedCadence::hz(hz)),
            None => Box::new(RealTime::default()),
        };
        let panel_visible = options.panel;
        App {
            source,
            options,
            panel: None,
            panel_visible,
            time,
            state: None,
            connecting: false,
            proxy,
            done,
            error: None,
            summary: WindowSummary {
                frames: 0,
                adapter: String::new(),
                surface: String::new(),
                screenshots: Vec::new(),
            },
            drag: None,
            cursor: (0.0, 0.0),
            touch: TouchMouse::default(),
            events: Vec::new(),
            controls: Vec::new(),
            physical_down: [0; GameKey::ALL.len()],
            ctrl: false,
            gamepads: Gamepads::open(),
            frame_started: Instant::now(),
            hold_started: None,
            screenshot: false,
            announce: None,
        }
    }
}

/// The window run's state: winit's application around the source.
pub(super) struct App<'a> {
    source: &'a mut dyn FrameSource,
    options: WindowOptions,
    panel: Option<Panel>,
    panel_visible: bool,
    time: Box<dyn TimeSource>,
    state: Option<WindowState>,
    /// The GPU is being found (the start-up sends [`Connected`]).
    connecting: bool,
    proxy: EventLoopProxy<Connected>,
    /// A page's run: who gets the result at the end.
    done: Option<WhenDone>,
    pub(super) error: Option<RunError>,
    pub(super) summary: WindowSummary,
    drag: Option<(f64, f64)>,
    cursor: (f64, f64),
    /// Which finger stands for the mouse.
    touch: TouchMouse,
    /// The player's input events of the coming frame, with their arrival.
    events: Vec<(InputEvent, Instant)>,
    /// Controls from keys and the panel, applied before the next frame's steps.
    controls: Vec<Control>,
    /// Physical keys down per game key (two Shift keys are one game key).
    physical_down: [u8; GameKey::ALL.len()],
    /// Whether Ctrl is held: the runner's keys then win over the game's.
    ctrl: bool,
    /// The gamepads polled each frame (none without the `gamepad` feature).
    gamepads: Gamepads,
    /// When the coming frame began (the last `advance`).
    frame_started: Instant,
    hold_started: Option<crate::platform::Instant>,
    screenshot: bool,
    /// A line to print once this many more frames have been presented: the
    /// signal tests and tools wait on (a state change, then two presents,
    /// so the first frame that shows it has surely reached the screen),
    /// instead of sleeping and hoping.
    announce: Option<(String, u8)>,
}

impl App<'_> {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: RunError) {
        self.error.get_or_insert(error);
        event_loop.exit();
    }

    /// The game key `physical` gives the source, if it takes input and
    /// the key is its (a runner's key only when claimed).
    fn game_key_of(&self, physical: winit::keyboard::PhysicalKey) -> Option<GameKey> {
        let claimed = self.source.claimed_keys();
        super::keys::game_key_for(physical, self.source.takes_input(), claimed)
    }

    fn key(&mut self, event: &KeyEvent, event_loop: &ActiveEventLoop) {
        let down = event.state == ElementState::Pressed;
        // With Ctrl held a key is the runner's (Ctrl+P pauses a game that
        // claimed P); without, a game key is the game's, but for the
        // runner's own keys the game did not claim.
        if let Some(key) = self.game_key_of(event.physical_key)
            && !(down && self.ctrl)
        {
            // Releases were forwarded before the panel saw the event.
            if down && !event.repeat {
                let held = &mut self.physical_down[key as usize];
                if *held == 0 {
                    self.events.push((InputEvent::Key { key, down }, Instant::now()));
                }
                *held = held.saturating_add(1);
            }
            return;
        }
        if !down || (event.repeat && !super::keys::repeatable(event.physical_key)) {
            return;
        }
        let control = match super::keys::key_action(&event.logical_key, event.physical_key) {
            Some(KeyAction::Quit) => {
                event_loop.exit();
                None
            }
            Some(KeyAction::Screenshot) => {
                self.screenshot = true;
                None
            }
            Some(KeyAction::TogglePanel) => {
                self.panel_visible = !self.panel_visible;
                let state = if self.panel_visible { "shown" } else { "hidden" };
                say(&format!("tickwork: panel {state} (F1)"));
                self.announce = Some((format!("tickwork: panel {state} (F1) and presented"), 2));
                None
            }
            Some(KeyAction::Control(control)) => Some(control),
            None => None,
        };
        self.controls.extend(control);
    }

    /// Hands the frame's input events and controls to the source: the
    /// start of the next frame is a tick boundary.
    fn hand_over(&mut self) -> Result<(), RunError> {
        // Controls first: a restart forgets the events waiting before it,
        // not this frame's (a key released now must reach the new run).
        for control in self.controls.drain(..) {
            self.source.control(control)?;
        }
        if self.source.takes_input() {
            self.gamepads.poll(&mut self.events);
        }
        let now = Instant::now();
        let span = now.duration_since(self.frame_started).as_secs_f64();
        for (event, at) in self.events.drain(..) {
            let arrival = if span > 0.0 {
                at.duration_since(self.frame_started).as_secs_f64() / span
            } else {
                1.0
            };
            self.source.input(event, arrival);
        }
        self.frame_started = now;
        Ok(())
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<(), RunError> {
        let holding = self.hold_started.is_some();
        self.hand_over()?;
        // A source that steps on the GPU waits for the runner's.
        if !holding && (self.state.is_some() || !self.source.needs_gpu()) {
            let seconds = self.time.next_frame();
            self.source.advance(seconds)?;
        }
        let Some(state) = self.state.as_mut() else {
            return Ok(());
        };
        // Minimised (0x0): nothing to draw, nothing wrong.
        let Some(buffers) = state.buffers.as_ref() else {
            return Ok(());
        };
        let (renderer, gpu) = (&mut state.renderer, &state.gpu);
        if let Some(interpolation) = self.source.interpolation() {
            renderer.set_interpolation(interpolation);
        }
        self.source
            .with_view(self.options.hud, (buffers.width, buffers.height), &mut |view| {
                renderer.prepare(gpu, buffers, view)
            })?;
        let frame = match state.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(frame) | wgpu::CurrentSurfaceTexture::Suboptimal(frame) => frame,
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => return Ok(()),
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                state.surface.configure(&state.gpu.device, &state.config);
                return Ok(());
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                return Err(RenderError::Surface("validation error acquiring the frame".into()).into());
            }
        };
        let output = frame.texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(state.format),
            ..Default::default()
        });
        let mut encoder = state
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("tickwork window"),
            });
        match state
            .relay
            .as_ref()
            .and_then(|relay| relay.view().map(|view| (relay, view)))
        {
            Some((relay, view)) => {
                state.renderer.encode(&mut encoder, buffers, view);
                relay.copy_to(&state.gpu.device, &mut encoder, &output);
            }
            None => state.renderer.encode(&mut encoder, buffers, &output),
        }
        let mut commands = Vec::new();
        if self.panel_visible
            && let Some(panel) = self.panel.as_mut()
        {
            let target = PanelTarget {
                window: &state.window,
                gpu: &state.gpu,
                width: state.config.width,
                height: state.config.height,
            };
            commands = draw_panel(panel, &*self.source, &mut self.controls, &target, &mut encoder, &output);
        }
        commands.push(encoder.finish());
        state.gpu.queue.submit(commands);
        state.window.pre_present_notify();
        state.gpu.queue.present(frame);
        if std::mem::take(&mut self.screenshot) {
            let path = screenshot(state, &mut *self.source, &self.options)?;
            crate::say!("tickwork: screenshot {}", path.display());
            self.summary.screenshots.push(path);
        }
        if !holding {
            self.summary.frames += 1;
        }
        if let Some((line, presents)) = self.announce.as_mut() {
            *presents -= 1;
            if *presents == 0 {
                say(line);
                self.announce = None;
            }
        }
        if self.source.finished() {
            event_loop.exit();
        }
        if let Some(limit) = self.options.frames {
            if self.summary.frames >= limit && self.hold_started.is_none() {
                self.hold_started = Some(crate::platform::Instant::now());
                // Said after the held frame's next present.
                self.announce = Some((
                    format!(
                        "tickwork: frame {limit} shown; holding it {} s",
                        self.options.hold_seconds
                    ),
                    1,
                ));
            }
            if let Some(start) = self.hold_started
                && start.elapsed().as_secs_f64() >= self.options.hold_seconds
            {
                event_loop.exit();
            }
        }
        Ok(())
    }
}

impl ApplicationHandler<Connected> for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_some() {
            return;
        }
        if self.connecting {
            return;
        }
        match open(event_loop, &self.source.title(), &self.options) {
            Ok(opening) => {
                self.connecting = true;
                let (proxy, options) = (self.proxy.clone(), self.options.clone());
                crate::platform::spawn_local(async move {
                    let connected = opening.connect(options).await;
                    // The loop is gone only if the run already ended.
                    let _ = proxy.send_event(Connected(connected));
                });
            }
            Err(error) => self.fail(event_loop, error),
        }
    }

    fn user_event(&mut self, event_loop: &ActiveEventLoop, Connected(connected): Connected) {
        self.connecting = false;
        match connected {
            Ok((state, panel)) => {
                self.source.attach_gpu(&state.gpu);
                self.summary.adapter = state.gpu.describe();
                self.summary.surface = format!("{:?}, {:?}", state.format, state.config.present_mode);
                if crate::platform::IS_WEB {
                    // A page has no terminal that shows the adapter: the
                    // console and the page say which backend draws.
                    say(&format!("tickwork: drawing with {}", self.summary.adapter));
                    crate::platform::show_status(&format!("{} on {}", self.source.title(), self.summary.adapter));
                }
                state.window.request_redraw();
                self.panel = Some(panel);
                self.state = Some(state);
                // The clock starts with the first frame drawn, not before
                // the GPU answered.
                self.frame_started = Instant::now();
            }
            Err(error) => self.fail(event_loop, error),
        }
    }

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(done) = self.done.take() {
            let summary = self.summary.clone();
            done(match self.error.take() {
                Some(error) => Err(error),
                None => Ok(summary),
            });
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        // A finger is the mouse (see `touch`): the game and the panel see
        // the mouse events it stands for, not the touch.
        if let WindowEvent::Touch(touch) = event {
            let location = (touch.location.x, touch.location.y);
            for mouse in self.touch.map(touch.id, touch.phase, location).into_iter().flatten() {
                let device_id = touch.device_id;
                let event = match mouse {
                    Mouse::Move(x, y) => WindowEvent::CursorMoved {
                        device_id,
                        position: winit::dpi::PhysicalPosition::new(x, y),
                    },
                    Mouse::Press | Mouse::Release => WindowEvent::MouseInput {
                        device_id,
                        state: if mouse == Mouse::Press {
                            ElementState::Pressed
                        } else {
                            ElementState::Released
                        },
                        button: MouseButton::Left,
                    },
                };
                self.event(event_loop, event);
            }
            return;
        }
        self.event(event_loop, event);
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(state) = &self.state {
            state.window.request_redraw();
        }
    }
}

impl App<'_> {
    /// A window event other than a touch (which arrives as mouse events).
    fn event(&mut self, event_loop: &ActiveEventLoop, event: WindowEvent) {
        // The runner's own keys (F1, F12, Escape) never go to a text field.
        let runner_key = matches!(
            &event,
            WindowEvent::KeyboardInput { event, .. }
                if matches!(event.logical_key, Key::Named(NamedKey::F1 | NamedKey::F12 | NamedKey::Escape))
        );
        // A release always reaches the game, even one the panel takes (a
        // button let go over it): else the game's key would stay held.
        if self.source.takes_input() {
            let released = match &event {
                WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Released => {
                    self.game_key_of(event.physical_key)
                }
                WindowEvent::MouseInput {
                    state: ElementState::Released,
                    button,
                    ..
                } => match button {
                    MouseButton::Left => Some(GameKey::MouseLeft),
                    MouseButton::Right => Some(GameKey::MouseRight),
                    MouseButton::Middle => Some(GameKey::MouseMiddle),
                    _ => None,
                },
                _ => None,
            };
            if let Some(key) = released {
                // Up only when the last of its physical keys is (left and
                // right Shift are one game key).
                // (A key pressed with Ctrl went to the runner: the game
                // never saw it down, so it sees no release.)
                let down = &mut self.physical_down[key as usize];
                if *down > 0 {
                    *down -= 1;
                    if *down == 0 {
                        self.events.push((InputEvent::Key { key, down: false }, Instant::now()));
                    }
                }
            }
        }
        if self.panel_visible
            && !runner_key
            && let (Some(panel), Some(state)) = (self.panel.as_mut(), self.state.as_ref())
            && panel.takes(&state.window, &event)
        {
            return;
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                if let Some(state) = self.state.as_mut() {
                    match state.resize(size.width, size.height) {
                        Err(error) => self.fail(event_loop, error),
                        // A 0x0 (minimised) window presents nothing: said now.
                        Ok(()) if state.buffers.is_none() => {
                            say(&format!("tickwork: resized to {}x{}", size.width, size.height));
                        }
                        Ok(()) => {
                            self.announce = Some((
                                format!("tickwork: resized to {}x{} and presented", size.width, size.height),
                                2,
                            ));
                        }
                    }
                }
            }
            WindowEvent::ModifiersChanged(modifiers) => self.ctrl = modifiers.state().control_key(),
            WindowEvent::KeyboardInput { event, .. } => self.key(&event, event_loop),
            WindowEvent::MouseInput { state, button, .. } if self.source.takes_input() => {
                let key = match button {
                    MouseButton::Left => GameKey::MouseLeft,
                    MouseButton::Right => GameKey::MouseRight,
                    MouseButton::Middle => GameKey::MouseMiddle,
                    _ => return,
                };
                // Releases were forwarded before the panel saw the event.
                if state == ElementState::Pressed {
                    self.events.push((InputEvent::Key { key, down: true }, Instant::now()));
                }
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.drag = (state == ElementState::Pressed).then_some(self.cursor);
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = (position.x, position.y);
                if self.source.takes_input() {
                    if let Some(size) = self.state.as_ref().map(|s| (s.config.width, s.config.height))
                        && let Some(at) = self.source.camera_mut().point_on_plane(
                            position.x as f32,
                            position.y as f32,
                            size.0,
                            size.1,
                        )
                    {
                        self.events.push((InputEvent::Pointer(at), Instant::now()));
                    }
                } else if let Some((x, y)) = self.drag {
                    // Half a degree per pixel dragged.
                    let (dx, dy) = (position.x - x, position.y - y);
                    self.source.camera_mut().orbit(-0.5 * dx as f32, 0.5 * dy as f32);
                    self.drag = Some(self.cursor);
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.source.camera_mut().zoom(crate::math::powf(1.1_f32, lines));
            }
            WindowEvent::RedrawRequested => {
                if let Err(error) = self.redraw(event_loop) {
                    self.fail(event_loop, error);
                }
            }
            _ => {}
        }
    }
}
