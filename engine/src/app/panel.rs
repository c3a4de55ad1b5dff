//! The window's control panel (egui, toggled with F1): clock controls,
//! each world's integrator and particle count, and a live plot of each
//! world's relative energy error. Drawn over the frame after it is
//! rendered, so off-screen frames and golden images never contain it.

use egui_plot::{Legend, Line, Plot, PlotPoints};

use super::game::Game;
use super::playback::next_time_scale;
use super::playback::{Playback, PlaybackError};
use super::session::GameSession;
use super::stage::EnergyTrace;
use super::{Control, FrameSource, RunError};
use crate::clock::{FixedClock, Rate};
use crate::world::Colour;
use tickwork_integrators::METHODS;

/// Something the panel asked for, applied after the panel is laid out.
enum Action {
    Control(Control),
    TimeScale(f64),
    Rate(f64),
    Integrator { world: usize, name: &'static str },
}

/// `log10 |e|`, floored at 1e-16 (round-off) so exact zeros plot.
fn log_error(e: f64) -> f64 {
    e.abs().max(1e-16).log10()
}

fn plot_points(trace: &EnergyTrace) -> PlotPoints<'static> {
    trace.samples().map(|(t, e)| [t, log_error(e)]).collect()
}

/// What the panel shows of one world.
struct WorldRow<'a> {
    label: &'a str,
    colour: Colour,
    integrator: &'static str,
    fixed: bool,
    particles: usize,
    energy: &'a EnergyTrace,
}

/// What the panel shows of the clock.
struct ClockRow {
    fps: f64,
    steps: u32,
    dropped: f64,
    time: f64,
    paused: bool,
    scale: f64,
    hz: f64,
    /// Whether the rate is fixed (a recording is being made).
    rate_fixed: bool,
}

/// Lays the panel out and returns what was chosen.
fn lay_out(ctx: &egui::Context, clock: &ClockRow, worlds: &[WorldRow<'_>]) -> Vec<Action> {
    let mut actions = Vec::new();
    let (mut scale, mut hz) = (clock.scale, clock.hz);
    egui::Window::new("Tickwork")
        .default_pos([12.0, 80.0])
        .default_width(340.0)
        .show(ctx, |ui| {
            ui.label(format!(
                "{:.0} fps  |  {} steps this frame  |  dropped {:.3} s  |  t = {:.2} s",
                clock.fps, clock.steps, clock.dropped, clock.time
            ));
            ui.horizontal(|ui| {
                if ui
                    .button(if clock.paused { "Resume (P)" } else { "Pause (P)" })
                    .clicked()
                {
                    actions.push(Action::Control(Control::TogglePause));
                }
                if ui.add_enabled(clock.paused, egui::Button::new("Step (.)")).clicked() {
                    actions.push(Action::Control(Control::SingleStep));
                }
                if ui.button("Restart (F5)").clicked() {
                    actions.push(Action::Control(Control::Reset));
                }
            });
            ui.horizontal(|ui| {
                ui.label("time scale");
                if ui.button("-").clicked() {
                    actions.push(Action::TimeScale(next_time_scale(scale, false)));
                }
                let response = ui.add(
                    egui::DragValue::new(&mut scale)
                        .range(1.0 / 16.0..=16.0)
                        .speed(0.01)
                        .suffix("x"),
                );
                if response.changed() {
                    actions.push(Action::TimeScale(scale));
                }
                if ui.button("+").clicked() {
                    actions.push(Action::TimeScale(next_time_scale(scale, true)));
                }
            });
            ui.horizontal(|ui| {
                ui.label("rate");
                // A recording stores one rate: it is fixed while recording.
                let response = ui.add_enabled(
                    !clock.rate_fixed,
                    egui::DragValue::new(&mut hz)
                        .range(1.0..=2000.0)
                        .speed(1.0)
                        .suffix(" Hz"),
                );
                if response.drag_stopped() || (response.changed() && !response.dragged()) {
                    actions.push(Action::Rate(hz));
                }
            });
            ui.separator();
            egui::Grid::new("worlds").striped(true).show(ui, |ui| {
                ui.strong("world");
                ui.strong("integrator");
                ui.strong("particles");
                ui.strong("energy error");
                ui.end_row();
                for (index, row) in worlds.iter().enumerate() {
                    let [r, g, b, _] = row.colour;
                    ui.colored_label(egui::Color32::from_rgb(r, g, b), row.label);
                    ui.add_enabled_ui(!row.fixed, |ui| {
                        egui::ComboBox::from_id_salt(("integrator", index))
                            .selected_text(row.integrator)
                            .show_ui(ui, |ui| {
                                for method in METHODS {
                                    if ui
                                        .selectable_label(method.name == row.integrator, method.name)
                                        .clicked()
                                        && method.name != row.integrator
                                    {
                                        actions.push(Action::Integrator {
                                            world: index,
                                            name: method.name,
                                        });
                                    }
                                }
                            });
                    });
                    ui.label(row.particles.to_string());
                    ui.label(format!("{:+.2e}", row.energy.latest()));
                    ui.end_row();
                }
            });
            ui.label("log10 |relative energy error|");
            Plot::new("energy")
                .height(160.0)
                .legend(Legend::default())
                .show(ui, |plot| {
                    for row in worlds {
                        let [r, g, b, _] = row.colour;
                        plot.line(
                            Line::new(row.label.to_owned(), plot_points(row.energy))
                                .color(egui::Color32::from_rgb(r, g, b)),
                        );
                    }
                });
        });
    actions
}

fn clock_row(clock: &FixedClock, fps: f64, steps: u32, rate_fixed: bool) -> ClockRow {
    ClockRow {
        fps,
        steps,
        dropped: clock.dropped_total(),
        time: clock.time(),
        paused: clock.is_paused(),
        scale: clock.config().time_scale,
        hz: clock.config().rate.hz_value(),
        rate_fixed,
    }
}

/// Lays out the panel for `session` and applies what was chosen.
pub(super) fn show<G: Game>(session: &mut GameSession<G>, ctx: &egui::Context) -> Result<(), RunError> {
    let clock = clock_row(
        session.clock(),
        session.fps(),
        session.last_frame().steps,
        session.is_recording(),
    );
    let rows: Vec<WorldRow<'_>> = session
        .stage()
        .worlds
        .iter()
        .map(|w| WorldRow {
            label: &w.label,
            colour: w.colour,
            integrator: w.world.integrator().info().name,
            fixed: w.fixed_integrator,
            particles: w.world.len(),
            energy: &w.energy,
        })
        .collect();
    let actions = lay_out(ctx, &clock, &rows);
    drop(rows);
    for action in actions {
        match action {
            Action::Control(control) => session.control(control)?,
            Action::TimeScale(scale) => session.clock_mut().set_time_scale(scale)?,
            Action::Rate(hz) => {
                let rate = Rate::hz_f64(hz)?;
                session.clock_mut().set_rate(rate);
                session.stage_mut().rate = rate;
            }
            Action::Integrator { world, name } => {
                if let Some(shown) = session.stage_mut().worlds.get_mut(world) {
                    shown
                        .world
                        .set_integrator(name)
                        .map_err(|e| RunError::Game(super::GameError::Message(e.to_string())))?;
                    shown.failure = None;
                }
            }
        }
    }
    Ok(())
}

/// Lays out the panel for a scene's `playback` (one world) and applies what was chosen.
pub(super) fn show_playback(playback: &mut Playback, ctx: &egui::Context) -> Result<(), RunError> {
    let clock = clock_row(playback.clock(), playback.fps(), playback.last_frame().steps, false);
    let title = playback.title().to_owned();
    let rows = [WorldRow {
        label: &title,
        colour: [235, 235, 235, 255],
        integrator: playback.world().integrator().info().name,
        fixed: false,
        particles: playback.world().len(),
        energy: playback.energy_trace(),
    }];
    let actions = lay_out(ctx, &clock, &rows);
    for action in actions {
        match action {
            Action::Control(control) => playback.control(control)?,
            Action::TimeScale(scale) => playback
                .clock_mut()
                .set_time_scale(scale)
                .map_err(PlaybackError::from)?,
            Action::Rate(hz) => {
                let rate = Rate::hz_f64(hz).map_err(PlaybackError::from)?;
                playback.clock_mut().set_rate(rate);
            }
            Action::Integrator { name, .. } => {
                let index = METHODS.iter().position(|m| m.name == name).unwrap_or(0);
                playback.control(Control::Integrator(index))?;
            }
        }
    }
    Ok(())
}
