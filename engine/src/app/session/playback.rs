//! Playback: a world driven by a fixed clock from any time source, with the
//! controls a viewer needs (pause, single step, time scale, integrator
//! switching, reset) and the HUD line that reports them.
//!
//! The window and the off-screen renderer both call [`Playback::advance`]
//! once per frame with the frame's duration and draw [`Playback::view`],
//! so a render test sees exactly what a window shows for the same frame
//! durations.

use std::fmt;

use crate::clock::{ClockConfig, FixedClock, Frame, Rate};
use crate::render::{Camera, FrameView, Trails};
use crate::scene::Scene;
use crate::world::{Backend, Snapshot, World};

use crate::app::api::backend::{StepFailure, Stepper, on_gpu};
use crate::app::api::control::{Control, chosen_integrator, clock_control};
use crate::app::api::error::{PlaybackError, RunError};
use crate::app::api::stage_world::{ENERGY_EVERY_STEP_UP_TO, EnergyTrace};
#[cfg(feature = "panel")]
use crate::app::panel::{ClockRow, WorldRow};
use crate::app::session::frame_rate::FrameRate;
use crate::app::session::source::FrameSource;
use crate::render::Gpu;

/// A world, its clock, its initial state and what the viewer shows.
pub struct Playback {
    world: World,
    initial: Snapshot,
    clock: FixedClock,
    /// What the camera looks at; the window's mouse moves it.
    pub camera: Camera,
    trails: Trails,
    title: String,
    last: Frame,
    frame_rate: FrameRate,
    steps_total: u64,
    energy: Option<(u64, f64)>,
    initial_energy: f64,
    initial_len: usize,
    /// The HUD text, reused between frames.
    hud: String,
    /// Relative energy error, sampled once per frame that stepped (the panel's plot).
    energy_trace: EnergyTrace,
    /// Where the world steps (its GPU copy, where its backend is the GPU).
    stepper: Stepper,
    /// The runner's GPU, for a world on the GPU.
    gpu: Option<Gpu>,
    /// Drawn in place of a world on the GPU (its particles come from the
    /// GPU's buffers).
    empty: World,
}

impl fmt::Debug for Playback {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Playback")
            .field("title", &self.title)
            .field("tick", &self.world.tick())
            .finish_non_exhaustive()
    }
}

impl Playback {
    /// Plays `world` at `rate`, seen through `camera`.
    ///
    /// # Errors
    /// [`PlaybackError::Clock`] for a rate the clock refuses.
    pub fn new(mut world: World, rate: Rate, camera: Camera, title: impl Into<String>) -> Result<Self, PlaybackError> {
        let mut clock = FixedClock::new(ClockConfig {
            rate,
            ..ClockConfig::default()
        })?;
        let last = clock.advance(0.0)?;
        let initial_energy = world.energy()?.total();
        let world_len = world.len();
        Ok(Self {
            initial: world.snapshot(),
            world,
            clock,
            camera,
            trails: Trails::new(240),
            title: title.into(),
            last,
            frame_rate: FrameRate::default(),
            steps_total: 0,
            energy: None,
            initial_energy,
            initial_len: world_len,
            hud: String::new(),
            energy_trace: EnergyTrace::default(),
            stepper: Stepper::default(),
            gpu: None,
            empty: World::default(),
        })
    }

    /// Plays a scene file at its rate through its camera hint, with its
    /// integrator or `integrator` if given; with 8 particles or fewer, each
    /// leaves a trail.
    ///
    /// # Errors
    /// [`PlaybackError::Scene`] for a scene that does not load or build,
    /// [`PlaybackError::Integrator`] for an unknown integrator name.
    pub fn from_scene(scene: &Scene, integrator: Option<&str>) -> Result<Self, PlaybackError> {
        Self::from_scene_on(scene, integrator, None)
    }

    /// [`from_scene`](Self::from_scene), on `backend` instead of the
    /// scene's (`--gpu`) if given.
    ///
    /// # Errors
    /// As [`from_scene`](Self::from_scene).
    pub fn from_scene_on(
        scene: &Scene,
        integrator: Option<&str>,
        backend: Option<Backend>,
    ) -> Result<Self, PlaybackError> {
        let (mut world, entities) = scene.build().map_err(PlaybackError::Scene)?;
        if let Some(name) = integrator {
            world.set_integrator(name)?;
        }
        if let Some(backend) = backend {
            world.set_backend(backend);
        }
        let rate = scene.rate().map_err(PlaybackError::Scene)?;
        let mut playback = Self::new(world, rate, Camera::from_hint(&scene.spec.camera), scene.name())?;
        if entities.len() <= 8 {
            for entity in entities {
                if let Ok(row) = playback.world.row(entity) {
                    let colour = playback.world.particles().colour[row];
                    playback.trails.follow(entity, colour);
                }
            }
        }
        Ok(playback)
    }

    /// The title shown in the HUD and the window's title bar (the scene's name).
    #[must_use]
    pub fn title(&self) -> &str {
        &self.title
    }

    /// The world (read only: change it through fixed steps or controls).
    #[must_use]
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The world, to change between frames (a game's per-frame update).
    pub fn world_mut(&mut self) -> &mut World {
        &mut self.world
    }

    /// The clock.
    #[must_use]
    pub fn clock(&self) -> &FixedClock {
        &self.clock
    }

    /// Smoothed frames per second.
    #[must_use]
    pub fn fps(&self) -> f64 {
        self.frame_rate.fps()
    }

    /// The relative energy error over recent frames (the panel's plot).
    #[must_use]
    pub fn energy_trace(&self) -> &EnergyTrace {
        &self.energy_trace
    }

    /// The trails drawn.
    pub fn trails_mut(&mut self) -> &mut Trails {
        &mut self.trails
    }

    /// The last frame's report (steps, alpha, dropped time).
    #[must_use]
    pub fn last_frame(&self) -> &Frame {
        &self.last
    }

    /// Advances by one displayed frame of `seconds` and runs the fixed steps
    /// it is due, recording trails after each.
    ///
    /// # Errors
    /// [`PlaybackError::Clock`] for a NaN, infinite or negative duration;
    /// [`PlaybackError::Simulation`] if a step fails.
    pub fn advance(&mut self, seconds: f64) -> Result<&Frame, PlaybackError> {
        let frame = self.clock.advance(seconds)?;
        self.frame_rate.record(seconds);
        for step in frame.fixed_steps() {
            self.stepper
                .step(&mut self.gpu, &mut self.world, step)
                .map_err(|failure| match failure {
                    StepFailure::Simulation(error) => PlaybackError::Simulation(error),
                    StepFailure::Gpu(error) => PlaybackError::Gpu(error),
                })?;
            self.steps_total += 1;
            if self.stepper.on_gpu().is_none() {
                self.trails.record(&self.world);
            }
        }
        // (A world on the GPU has its energy there.)
        if self.stepper.on_gpu().is_none() && (frame.steps > 0 || self.energy_trace.samples().next().is_none()) {
            self.energy_trace.sample(&mut self.world)?;
        }
        self.last = frame;
        Ok(&self.last)
    }

    /// Applies a viewer control now (the runners call this between
    /// frames, at a tick boundary).
    ///
    /// # Errors
    /// [`PlaybackError::Integrator`] for an integrator number beyond the
    /// registry; [`PlaybackError::Clock`] for a time scale or rate the
    /// clock refuses.
    pub fn control(&mut self, control: Control) -> Result<(), PlaybackError> {
        if clock_control(&mut self.clock, control)? {
            return Ok(());
        }
        if control == Control::Reset {
            let integrator = self.world.integrator().info().name;
            self.world.restore(&self.initial);
            self.stepper.forget();
            // Keep the integrator the viewer chose.
            self.world.set_integrator(integrator)?;
            self.trails.clear_points();
            self.energy = None;
            self.energy_trace = EnergyTrace::default();
        } else if let Some(name) =
            chosen_integrator(control, 0, self.world.integrator().info().name, on_gpu(&self.world))?
        {
            self.world.set_integrator(name)?;
        }
        Ok(())
    }

    /// The frame to draw: the world at the last frame's alpha, with trails
    /// and `hud` as the HUD text.
    #[must_use]
    pub fn view<'a>(&'a self, hud: &'a str) -> FrameView<'a> {
        // A world on the GPU is drawn from its buffers (see `with_view`).
        let world = if self.stepper.on_gpu().is_some() {
            &self.empty
        } else {
            &self.world
        };
        FrameView {
            trails: Some(&self.trails),
            hud,
            ..FrameView::new(world, self.last.alpha as f32, self.camera)
        }
    }

    /// Reads a world on the GPU back into [`world`](Self::world) (its
    /// positions and velocities live there): a copy of its state and a
    /// wait for the GPU. Nothing for a world on the CPU.
    ///
    /// # Errors
    /// [`PlaybackError::Gpu`] if the read-back fails.
    pub fn read_back(&mut self) -> Result<(), PlaybackError> {
        self.stepper
            .sync(self.gpu.as_ref(), &mut self.world)
            .map_err(PlaybackError::Gpu)
    }

    /// The HUD text: fps, steps this frame, dropped time, integrator, time
    /// scale, particle count, energy and its drift since the start.
    pub fn hud_text(&mut self, out: &mut String) {
        use std::fmt::Write;
        let tick = self.world.tick();
        if let Some(on_gpu) = self.stepper.on_gpu() {
            out.clear();
            let _ = write!(
                out,
                "{}  |  {} on the GPU{}\n{:.0} fps  |  {} steps this frame  |  dropped {:.3} s  |  x{}\n{} \
                 particles  |  t = {:.2} s",
                self.title,
                on_gpu.method(),
                if self.clock.is_paused() { "  |  paused" } else { "" },
                self.fps(),
                self.last.steps,
                self.clock.dropped_total(),
                self.clock.config().time_scale,
                self.world.len(),
                self.world.time()
            );
            return;
        }
        let stale = match self.energy {
            None => true,
            Some((at, _)) => at != tick && (self.world.len() <= ENERGY_EVERY_STEP_UP_TO || tick >= at + 30),
        };
        if stale {
            // A world grown past its pair limit has no energy to show (its
            // step refuses it too, and says so).
            self.energy = self.world.energy().ok().map(|e| (tick, e.total()));
        }
        let energy = self.energy.map(|(_, e)| e);
        // Drift relative to the start, when that means something: same
        // particles, non-zero initial energy.
        let drift = energy
            .filter(|_| self.world.len() == self.initial_len && self.initial_energy.abs() > 1e-9)
            .map(|energy| (energy - self.initial_energy) / self.initial_energy.abs());
        let fps = self.fps();
        out.clear();
        let _ = writeln!(
            out,
            "{}  |  {}{}",
            self.title,
            self.world.integrator().info().name,
            if self.clock.is_paused() { "  |  paused" } else { "" }
        );
        let _ = writeln!(
            out,
            "{fps:.0} fps  |  {} steps this frame  |  dropped {:.3} s  |  x{}",
            self.last.steps,
            self.clock.dropped_total(),
            self.clock.config().time_scale
        );
        let _ = write!(
            out,
            "{} particles  |  t = {:.2} s  |  ",
            self.world.len(),
            self.world.time()
        );
        let _ = match energy {
            Some(energy) => write!(out, "energy {energy:.4} J"),
            None => write!(out, "energy: past WorldConfig::max_pairs"),
        };
        if let Some(drift) = drift {
            let _ = write!(out, " (drift {drift:+.2e})");
        }
    }
}

impl FrameSource for Playback {
    fn title(&self) -> String {
        self.title.clone()
    }

    fn advance(&mut self, seconds: f64) -> Result<(), RunError> {
        Playback::advance(self, seconds)?;
        Ok(())
    }

    fn control(&mut self, control: Control) -> Result<(), RunError> {
        Ok(Playback::control(self, control)?)
    }

    fn ticks(&self) -> u64 {
        self.world.tick()
    }

    #[cfg(feature = "panel")]
    fn panel(&self, ctx: &egui::Context, chosen: &mut Vec<Control>) {
        let clock = ClockRow::of(&self.clock, self.fps(), self.last.steps, false);
        let rows = [WorldRow {
            label: &self.title,
            colour: [235, 235, 235, 255],
            integrator: self.world.integrator().info().name,
            fixed: false,
            particles: self.world.len(),
            energy: &self.energy_trace,
            on_gpu: on_gpu(&self.world),
        }];
        crate::app::panel::lay_out(ctx, &clock, &rows, chosen);
    }

    fn camera_mut(&mut self) -> &mut Camera {
        &mut self.camera
    }

    fn needs_gpu(&self) -> bool {
        on_gpu(&self.world)
    }

    fn attach_gpu(&mut self, gpu: &Gpu) {
        // The first GPU given stays: the world's buffers live on it.
        if self.gpu.is_none() {
            self.gpu = Some(gpu.clone());
        }
    }

    fn with_view(
        &mut self,
        hud: bool,
        _size: (u32, u32),
        render: &mut dyn FnMut(&FrameView<'_>) -> Result<(), crate::render::RenderError>,
    ) -> Result<(), RunError> {
        let mut text = std::mem::take(&mut self.hud);
        if hud {
            self.hud_text(&mut text);
        } else {
            text.clear();
        }
        let gpu_particles = self.stepper.particles();
        let result = render(&FrameView {
            gpu_particles: gpu_particles.as_slice(),
            ..self.view(&text)
        });
        self.hud = text;
        Ok(result?)
    }
}
