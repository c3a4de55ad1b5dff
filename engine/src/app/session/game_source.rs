//! A [`GameSession`] as the runners see it ([`FrameSource`]): a frame's
//! fixed steps, the controls, and the frame's view (the game's drawing, its
//! worlds, sprites for particles).

use crate::app::api::backend::on_gpu;
use crate::app::api::control::{Control, clock_control};
use crate::app::api::draw::{Draw, Viewport};
use crate::app::api::error::RunError;
use crate::app::api::game::{Game, GameError};
use crate::app::api::stage_world::StageWorld;
#[cfg(feature = "panel")]
use crate::app::panel::{ClockRow, WorldRow};
use crate::app::session::game_session::{GameSession, InputMode};
use crate::app::session::source::FrameSource;
use crate::clock::Rate;
use crate::input::InputEvent;
use crate::interpolation::Interpolation;
use crate::render::{Camera, FrameView, RenderError, WorldView};

impl<G: Game> FrameSource for GameSession<G> {
    fn title(&self) -> String {
        self.game.title().to_owned()
    }

    fn advance(&mut self, seconds: f64) -> Result<(), RunError> {
        let mut frame = self.advance_clock(seconds)?;
        // A replay runs its recording's ticks and no more: the steps past
        // its end go back to the clock, which the end pauses.
        if let Some(end) = self.replay_end() {
            let past = (frame.first_tick + u64::from(frame.steps)).saturating_sub(end.max(frame.first_tick));
            let past = u32::try_from(past).unwrap_or(frame.steps).min(frame.steps);
            if past > 0 {
                self.clock.defer(past);
                frame.steps -= past;
            }
        }
        self.end_replay_if_due(frame.first_tick)?;
        for step in frame.fixed_steps() {
            self.replay_controls(step.tick)?;
            self.take_tick_inputs(step.tick, step.time + step.dt);
            let inputs = core::mem::take(&mut self.inputs);
            let ran = self.run_tick(step, &inputs);
            self.inputs = inputs;
            ran?;
            self.end_replay_if_due(step.tick + 1)?;
        }
        self.finish_frame(frame);
        Ok(())
    }

    fn control(&mut self, control: Control) -> Result<(), RunError> {
        if let Control::Rate(hz) = control {
            // A recording stores one rate (the panel greys it out then).
            if self.is_recording() || self.replay().is_some() {
                crate::say!("tickwork: the rate stays as it is while recording or replaying ({hz} Hz ignored)");
                return Ok(());
            }
            self.stage.rate = Rate::hz_f64(hz)?;
        }
        if clock_control(&mut self.clock, control)? {
            return Ok(());
        }
        match control {
            Control::Reset => self.restart(),
            other => self.switch_integrators(other),
        }
    }

    fn takes_input(&self) -> bool {
        true
    }

    fn claimed_keys(&self) -> crate::input::KeySet {
        self.stage.claimed_keys
    }

    fn input(&mut self, event: InputEvent, arrival: f64) {
        if matches!(self.mode, InputMode::Live { .. }) {
            self.queue.push(event, arrival);
        }
    }

    fn ticks(&self) -> u64 {
        self.clock.tick()
    }

    fn interpolation(&self) -> Option<Interpolation> {
        // The step in seconds of game time, as the worlds take it.
        self.stage.hermite.then(|| Interpolation::Hermite {
            dt: self.clock.dt() as f32,
        })
    }

    fn camera_mut(&mut self) -> &mut Camera {
        &mut self.stage.camera
    }

    fn needs_gpu(&self) -> bool {
        self.stage.worlds.iter().any(|w| on_gpu(&w.world))
    }

    fn attach_gpu(&mut self, gpu: &crate::render::Gpu) {
        // The first GPU given stays: the worlds' buffers live on it.
        if self.stage.gpu.is_none() {
            self.stage.gpu = Some(gpu.clone());
        }
    }

    fn with_view(
        &mut self,
        hud: bool,
        (width, height): (u32, u32),
        render: &mut dyn FnMut(&FrameView<'_>) -> Result<(), RenderError>,
    ) -> Result<(), RunError> {
        let alpha = self.last.alpha as f32;
        let viewport = Viewport {
            width,
            height,
            pixels_per_metre: self.stage.camera.matrices(width, height).pixels_per_unit,
        };
        self.stage.viewport = viewport;
        self.draw.clear(viewport);
        self.game
            .draw(&self.stage, alpha, &mut self.draw)
            .map_err(RunError::Game)?;
        if let Some(problem) = self.draw.problem() {
            return Err(RunError::Game(GameError::Message(problem.to_owned())));
        }
        if !hud {
            self.draw.hud.clear();
            self.draw.hud_colours.clear();
        }
        let (first, rest) = match self.stage.worlds.split_first() {
            Some((first, rest)) => (Some(first), rest),
            None => (None, &[][..]),
        };
        // A world on the GPU is drawn from its buffers, not its columns.
        let empty = &self.empty;
        fn columns<'a>(w: &'a StageWorld, empty: &'a crate::world::World) -> &'a crate::world::World {
            if w.gpu_particles().is_some() { empty } else { &w.world }
        }
        let gpu_particles: Vec<crate::render::GpuParticles<'_>> = self
            .stage
            .worlds
            .iter()
            .filter_map(|w| {
                w.gpu_particles()
                    .map(|g| crate::render::GpuParticles { layer: w.layer, ..g })
            })
            .collect();
        for shown in &self.stage.worlds {
            if let Some(texture) = &shown.sprite {
                let layer = shown.layer.unwrap_or(self.draw.particles_on());
                particle_sprites(&shown.world, texture, alpha, layer, &mut self.draw);
            }
        }
        let others: Vec<WorldView<'_>> = rest
            .iter()
            .map(|w| WorldView {
                world: columns(w, empty),
                trails: Some(&w.trails),
                as_sprites: w.sprite.is_some(),
                layer: w.layer,
            })
            .collect();
        let view = FrameView {
            trails: first.map(|w| &w.trails),
            as_sprites: first.is_some_and(|w| w.sprite.is_some()),
            layer: first.and_then(|w| w.layer),
            others: &others,
            lines: &self.draw.lines,
            triangles: &self.draw.triangles,
            batches: &self.draw.batches,
            sprites: &self.draw.sprites,
            particle_layer: self.draw.particles_on(),
            texts: &self.draw.texts,
            hud: &self.draw.hud,
            hud_colours: &self.draw.hud_colours,
            gpu_particles: &gpu_particles,
            ..FrameView::new(first.map_or(empty, |w| columns(w, empty)), alpha, self.stage.camera)
        };
        render(&view)?;
        Ok(())
    }

    #[cfg(feature = "panel")]
    fn panel(&self, ctx: &egui::Context, chosen: &mut Vec<Control>) {
        let rate_fixed = self.is_recording() || self.replay().is_some();
        let clock = ClockRow::of(&self.clock, self.fps(), self.last.steps, rate_fixed);
        let rows: Vec<WorldRow<'_>> = self
            .stage
            .worlds
            .iter()
            .map(|w| WorldRow {
                label: &w.label,
                colour: w.colour,
                integrator: w.world.integrator().info().name,
                fixed: w.fixed_integrator || !self.stage.switch_integrators,
                particles: w.world.len(),
                energy: &w.energy,
                on_gpu: on_gpu(&w.world),
            })
            .collect();
        crate::app::panel::lay_out(ctx, &clock, &rows, chosen);
    }
}

/// A world's particles as sprites of `texture` on `layer`: each at its
/// drawn position, as wide as its disc, tinted by its colour, turned by
/// its heading (if the world has headings).
fn particle_sprites(
    world: &crate::world::World,
    texture: &crate::render::Texture,
    alpha: f32,
    layer: i32,
    draw: &mut Draw,
) {
    let p = world.particles();
    let headings = world.column::<crate::world::Heading>().ok();
    let previous_layer = draw.current_layer();
    draw.layer(layer);
    for row in 0..p.len() {
        let (from, to) = (p.previous_position.row(row), p.position.row(row));
        let at = from + (to - from) * alpha;
        let size = glam::Vec2::splat(2.0 * p.radius[row]);
        let sprite = draw.sprite(texture, glam::Vec2::new(at.x, at.y), size);
        sprite.tint(p.colour[row]);
        if let Some(h) = headings.and_then(|h| h.get(row)) {
            sprite.rotation(h.interpolated(alpha));
        }
    }
    draw.layer(previous_layer);
}
