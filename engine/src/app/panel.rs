//! The window's control panel (egui, toggled with F1): clock controls,
//! each world's integrator and particle count, and a live plot of each
//! world's relative energy error. Drawn over the frame after it is
//! rendered, so off-screen frames and golden images never contain it.
//!
//! The panel reads what a source shows it ([`ClockRow`], [`WorldRow`]) and
//! returns the [`Control`]s chosen in it; the runner applies them between
//! frames, like the keys' controls. It knows no source type.

use egui_plot::{Legend, Line, Plot, PlotPoints};

use crate::app::api::control::{Control, next_time_scale};
use crate::app::api::stage_world::EnergyTrace;
use crate::clock::FixedClock;
use crate::world::Colour;
use tickwork_integrators::METHODS;

/// `log10 |e|`, floored at 1e-16 (round-off) so exact zeros plot.
fn log_error(e: f64) -> f64 {
    crate::math::log10(e.abs().max(1e-16))
}

fn plot_points(trace: &EnergyTrace) -> PlotPoints<'static> {
    trace.samples().map(|(t, e)| [t, log_error(e)]).collect()
}

/// What the panel shows of one world.
pub(super) struct WorldRow<'a> {
    pub(super) label: &'a str,
    pub(super) colour: Colour,
    pub(super) integrator: &'static str,
    /// Whether the integrator stays as it is (the game fixes it).
    pub(super) fixed: bool,
    pub(super) particles: usize,
    pub(super) energy: &'a EnergyTrace,
    /// Whether its particles step on the GPU (their energy stays there).
    pub(super) on_gpu: bool,
}

/// What the panel shows of the clock.
pub(super) struct ClockRow {
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

impl ClockRow {
    /// The row of `clock`, at `fps` with `steps` in the last frame.
    pub(super) fn of(clock: &FixedClock, fps: f64, steps: u32, rate_fixed: bool) -> Self {
        Self {
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
}

/// Lays the panel out; adds the controls chosen in it to `actions`.
pub(super) fn lay_out(ctx: &egui::Context, clock: &ClockRow, worlds: &[WorldRow<'_>], actions: &mut Vec<Control>) {
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
                    actions.push(Control::TogglePause);
                }
                if ui.add_enabled(clock.paused, egui::Button::new("Step (.)")).clicked() {
                    actions.push(Control::SingleStep);
                }
                if ui.button("Restart (F5)").clicked() {
                    actions.push(Control::Reset);
                }
            });
            ui.horizontal(|ui| {
                ui.label("time scale");
                if ui.button("-").clicked() {
                    actions.push(Control::TimeScale(next_time_scale(scale, false)));
                }
                let response = ui.add(
                    egui::DragValue::new(&mut scale)
                        .range(1.0 / 16.0..=16.0)
                        .speed(0.01)
                        .suffix("x"),
                );
                if response.changed() {
                    actions.push(Control::TimeScale(scale));
                }
                if ui.button("+").clicked() {
                    actions.push(Control::TimeScale(next_time_scale(scale, true)));
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
                    actions.push(Control::Rate(hz));
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
                    let name = ui.colored_label(egui::Color32::from_rgb(r, g, b), row.label).id;
                    ui.add_enabled_ui(!row.fixed, |ui| {
                        // Named by its world's label, for screen readers (and tests).
                        egui::ComboBox::from_id_salt(("integrator", index))
                            .selected_text(row.integrator)
                            .show_ui(ui, |ui| {
                                for (number, method) in METHODS.iter().enumerate() {
                                    if ui
                                        .selectable_label(method.name == row.integrator, method.name)
                                        .clicked()
                                        && method.name != row.integrator
                                    {
                                        actions.push(Control::WorldIntegrator {
                                            world: index,
                                            method: number,
                                        });
                                    }
                                }
                            })
                            .response
                            .labelled_by(name);
                    });
                    ui.label(row.particles.to_string());
                    if row.on_gpu {
                        ui.label("on the GPU");
                    } else {
                        ui.label(format!("{:+.2e}", row.energy.latest()));
                    }
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
}
