//! A mass-spring cloth pinned at two corners, in a gusting wind, three
//! times side by side: explicit Euler, implicit Euler and Newmark
//! (average acceleration). At the stiff setting (the default) the
//! springs' frequency is far beyond explicit Euler's stability limit
//! (omega dt > 2): it blows up in a fraction of a second and freezes there,
//! while the two implicit methods stay stable. S toggles stiff and soft;
//! Tab, 1-9 or the panel switch the integrators live (a frozen cloth
//! resumes with its new method).

use std::fmt::Write;
use std::process::ExitCode;

use tickwork::prelude::*;

/// Particles across and down, their spacing (m) and mass (kg).
const COLUMNS: usize = 14;
const ROWS: usize = 11;
const SPACING: f32 = 0.26;
const MASS: f32 = 0.02;

/// The three cloths: integrator and horizontal offset.
const CLOTHS: [(&str, f32); 3] = [("explicit_euler", -4.6), ("implicit_euler", 0.0), ("newmark_beta", 4.6)];

#[derive(Clone)]
struct Cloth {
    stiff: bool,
}

impl Cloth {
    /// Spring stiffness (N/m): omega = sqrt(k / m) is 200 rad/s when stiff
    /// (omega dt = 3.3 at 60 Hz), 40 rad/s when soft.
    fn stiffness(&self) -> f32 {
        if self.stiff { 800.0 } else { 32.0 }
    }

    fn build(&self, name: &str, x0: f32, seed: u64) -> Result<World, GameError> {
        let config = WorldConfig {
            integrator: name.to_owned(),
            seed,
            ..WorldConfig::default()
        };
        let mut world = World::new(config)?;
        world.add_force(Gravity::EARTH);
        world.add_force(Wind {
            velocity: Vec3::new(0.0, 0.0, 3.0),
            rate: 0.4,
        });
        let mut grid = Vec::with_capacity(COLUMNS * ROWS);
        for row in 0..ROWS {
            for column in 0..COLUMNS {
                let pinned = row == 0 && (column == 0 || column == COLUMNS - 1);
                let shade = (200 - 8 * row) as u8;
                let particle = Particle {
                    position: Vec3::new(
                        x0 + (column as f32 - (COLUMNS - 1) as f32 / 2.0) * SPACING,
                        3.0 - row as f32 * SPACING,
                        0.0,
                    ),
                    mass: MASS,
                    immovable: pinned,
                    radius: if pinned { 0.06 } else { 0.035 },
                    colour: if pinned {
                        [255, 220, 120, 255]
                    } else {
                        [shade, shade, 255, 255]
                    },
                    ..Particle::default()
                };
                grid.push(world.spawn(particle)?);
            }
        }
        let k = self.stiffness();
        let mut springs = Springs::default();
        let at = |row: usize, column: usize| grid[row * COLUMNS + column];
        // Structural springs along rows and columns, shear springs on both
        // diagonals; damping of a tenth of critical for one spring.
        let damping = 0.1 * 2.0 * (k * MASS).sqrt();
        for row in 0..ROWS {
            for column in 0..COLUMNS {
                let mut link = |r: usize, c: usize, length: f32| {
                    springs.push(Spring {
                        a: SpringEnd::Entity(at(row, column)),
                        b: SpringEnd::Entity(at(r, c)),
                        stiffness: k,
                        rest_length: length,
                        damping,
                    });
                };
                if column + 1 < COLUMNS {
                    link(row, column + 1, SPACING);
                }
                if row + 1 < ROWS {
                    link(row + 1, column, SPACING);
                }
                if row + 1 < ROWS && column + 1 < COLUMNS {
                    link(row + 1, column + 1, SPACING * std::f32::consts::SQRT_2);
                }
                if row + 1 < ROWS && column > 0 {
                    link(row + 1, column - 1, SPACING * std::f32::consts::SQRT_2);
                }
            }
        }
        world.add_force(springs);
        Ok(world)
    }
}

impl Game for Cloth {
    fn title(&self) -> &str {
        "cloth"
    }

    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        for (name, x0) in CLOTHS {
            let world = self.build(name, x0, settings.seed)?;
            stage.add_world(name, world).on_failure(OnFailure::Freeze);
        }
        stage.panel = true;
        stage.switch_integrators = true;
        stage.camera = Camera::Orbit {
            target: Vec3::new(0.0, 1.8, 0.0),
            distance: 10.5,
            yaw: 0.0,
            pitch: 12.0,
            fov_y: 45.0,
        };
        Ok(())
    }

    fn fixed_update(&mut self, stage: &mut Stage, step: &FixedStep, input: &TickInput) -> Result<(), GameError> {
        if input.pressed(Key::S) {
            self.stiff = !self.stiff;
            // A new stiffness means new cloths, each keeping its integrator.
            for shown in &mut stage.worlds {
                let x0 = CLOTHS.iter().find(|c| c.0 == shown.label).map_or(0.0, |c| c.1);
                let name = shown.world.integrator().info().name;
                shown.world = self.build(name, x0, step.tick)?;
                shown.failure = None;
            }
        }
        // Gusts: the wind's strength follows a slow sine of the tick.
        let gust = 3.0 + 2.5 * math::sin(step.time as f32 * 1.3);
        for shown in &mut stage.worlds {
            if let Some(wind) = shown.world.force_mut::<Wind>() {
                wind.velocity = Vec3::new(0.0, 0.0, gust);
            }
        }
        Ok(())
    }

    fn draw(&self, stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        let k = self.stiffness();
        let omega_dt = (k / MASS).sqrt() * stage.rate.step_seconds() as f32;
        let _ = writeln!(
            draw.hud,
            "{} cloth: k = {k} N/m, omega dt = {omega_dt:.2}  (S: stiff/soft)",
            if self.stiff { "Stiff" } else { "Soft" },
        );
        for shown in &stage.worlds {
            if shown.failure.is_some() {
                // A red cross where the blown-up cloth hung.
                let x0 = CLOTHS.iter().find(|c| c.0 == shown.label).map_or(0.0, |c| c.1);
                let (w, top, bottom) = (
                    SPACING * (COLUMNS - 1) as f32 / 2.0,
                    3.0,
                    3.0 - SPACING * (ROWS - 1) as f32,
                );
                let red = [255, 70, 60, 255];
                draw.line(Vec3::new(x0 - w, top, 0.0), Vec3::new(x0 + w, bottom, 0.0), red);
                draw.line(Vec3::new(x0 + w, top, 0.0), Vec3::new(x0 - w, bottom, 0.0), red);
            }
            draw.colour(shown.colour);
            let _ = match &shown.failure {
                Some(why) => writeln!(
                    draw.hud,
                    "{}: BLEW UP, {}",
                    shown.label,
                    why.split(':').next().unwrap_or(why)
                ),
                None => writeln!(
                    draw.hud,
                    "{}: stable, energy {:+.1e}",
                    shown.world.integrator().info().name,
                    shown.energy.latest()
                ),
            };
        }
        Ok(())
    }

    fn outcome(&self, stage: &Stage) -> Option<String> {
        let states: Vec<String> = stage
            .worlds
            .iter()
            .map(|w| match &w.failure {
                Some(why) => format!("{} blew up ({why})", w.label),
                None => format!("{} stable", w.label),
            })
            .collect();
        Some(states.join(", "))
    }
}

fn main() -> ExitCode {
    exit_code(run(Cloth { stiff: true }, RunOptions::from_args()))
}
