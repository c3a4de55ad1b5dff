//! The window's control panel (egui, toggled with F1): clock controls,
//! each world's integrator and particle count, and a live plot of each
//! world's relative energy error. Drawn over the frame after it is
//! rendered, so off-screen frames and golden images never contain it.

use egui_plot::{Legend, Line, Plot, PlotPoints};

use super::game::{EnergyTrace, Game};
use super::playback::next_time_scale;
use super::session::GameSession;
use super::{Control, FrameSource, RunError};
use crate::clock::Rate;
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

/// Lays out the panel for `session` and applies what was chosen.
pub(super) fn show<G: Game>(session: &mut GameSession<G>, ctx: &egui::Context) -> Result<(), RunError> {
    let mut actions = Vec::new();
    let fps = session.fps();
    let clock = session.clock();
    let paused = clock.is_paused();
    let mut scale = clock.config().time_scale;
    let mut hz = clock.config().rate.hz_value();
    let steps = session.last_frame().steps;
    let dropped = clock.dropped_total();
    let recording = session.is_recording();
    egui::Window::new("Tickwork")
        .default_pos([12.0, 80.0])
        .default_width(340.0)
        .show(ctx, |ui| {
            ui.label(format!(
                "{fps:.0} fps  |  {steps} steps this frame  |  dropped {dropped:.3} s  |  t = {:.2} s",
                session.clock().time()
            ));
            ui.horizontal(|ui| {
                if ui.button(if paused { "Resume (P)" } else { "Pause (P)" }).clicked() {
                    actions.push(Action::Control(Control::TogglePause));
                }
                if ui.add_enabled(paused, egui::Button::new("Step (.)")).clicked() {
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
                    !recording,
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
                for (index, shown) in session.stage().worlds.iter().enumerate() {
                    let [r, g, b, _] = shown.colour;
                    ui.colored_label(egui::Color32::from_rgb(r, g, b), &shown.label);
                    let current = shown.world.integrator().info().name;
                    ui.add_enabled_ui(!shown.fixed_integrator, |ui| {
                        egui::ComboBox::from_id_salt(("integrator", index))
                            .selected_text(current)
                            .show_ui(ui, |ui| {
                                for method in METHODS {
                                    if ui.selectable_label(method.name == current, method.name).clicked()
                                        && method.name != current
                                    {
                                        actions.push(Action::Integrator {
                                            world: index,
                                            name: method.name,
                                        });
                                    }
                                }
                            });
                    });
                    ui.label(shown.world.len().to_string());
                    ui.label(format!("{:+.2e}", shown.energy.latest()));
                    ui.end_row();
                }
            });
            ui.label("log10 |relative energy error|");
            Plot::new("energy")
                .height(160.0)
                .legend(Legend::default())
                .show(ui, |plot| {
                    for shown in &session.stage().worlds {
                        let [r, g, b, _] = shown.colour;
                        plot.line(
                            Line::new(shown.label.clone(), plot_points(&shown.energy))
                                .color(egui::Color32::from_rgb(r, g, b)),
                        );
                    }
                });
        });
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
                        .map_err(|e| RunError::Game(super::GameError::Game(e.to_string())))?;
                    shown.failure = None;
                }
            }
        }
    }
    Ok(())
}
