//! The integrator race: one eccentric Kepler orbit (e = 0.6, period 3 s)
//! run by every integrator at once, each in its own world, colour and
//! trail, with its energy error in the legend. Explicit Euler spirals out,
//! implicit Euler spirals in, the symplectic methods stay on a closed orbit.
//!
//! `cargo run --release` (or `--bin orbits -- --integrator rk4,leapfrog`).

use std::f32::consts::PI;
use std::fmt::Write;
use std::process::ExitCode;

use tickwork::integrators::METHODS;
use tickwork::prelude::*;

/// Semi-major axis (m), eccentricity, period (s).
const A: f32 = 2.0;
const E: f32 = 0.6;
const PERIOD: f32 = 3.0;

#[derive(Clone)]
struct Orbits;

/// Colours around the hue circle, `k` of `n`.
fn hue(k: usize, n: usize) -> [u8; 4] {
    let h = k as f32 / n as f32 * 6.0;
    let x = 1.0 - ((h % 2.0) - 1.0).abs();
    let (r, g, b) = match h as u32 {
        0 => (1.0, x, 0.0),
        1 => (x, 1.0, 0.0),
        2 => (0.0, 1.0, x),
        3 => (0.0, x, 1.0),
        4 => (x, 0.0, 1.0),
        _ => (1.0, 0.0, x),
    };
    let c = |v: f32| (70.0 + 185.0 * v) as u8;
    [c(r), c(g), c(b), 255]
}

impl Game for Orbits {
    fn title(&self) -> &str {
        "orbits"
    }

    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        let names: Vec<&str> = match &settings.integrator {
            Some(list) => list.split(',').map(str::trim).collect(),
            None => METHODS.iter().map(|m| m.name).collect(),
        };
        // Kepler's third law: GM = 4 pi^2 a^3 / T^2; start at perihelion
        // r = a (1 - e) with the vis-viva speed v = sqrt(GM (1 + e) / r).
        let gm = 4.0 * PI * PI * (A * A * A) / (PERIOD * PERIOD);
        let r = A * (1.0 - E);
        let v = (gm * (1.0 + E) / r).sqrt();
        for (k, name) in names.iter().enumerate() {
            let config = WorldConfig {
                integrator: (*name).to_owned(),
                ..WorldConfig::default()
            };
            let mut world = World::new(config)?;
            world.add_force(Attractor {
                position: Vec3::ZERO,
                gm,
                softening: 0.0,
            });
            let colour = hue(k, names.len());
            let planet = world.spawn(Particle {
                position: Vec3::new(r, 0.0, 0.0),
                velocity: Vec3::new(0.0, v, 0.0),
                radius: 0.07,
                colour,
                ..Particle::default()
            })?;
            if k == 0 {
                // The sun: immovable, so no force moves it and it adds no energy.
                world.spawn(Particle {
                    immovable: true,
                    radius: 0.16,
                    colour: [255, 210, 90, 255],
                    ..Particle::default()
                })?;
            }
            stage
                .add_world(*name, world)
                .colour(colour)
                .fixed_integrator()
                .on_failure(OnFailure::Freeze)
                .trail_length(400)
                .follow(planet, colour);
        }
        stage.panel = true;
        // 360 steps per orbit: coarse enough for the first-order methods to
        // show their character within a few periods.
        stage.rate = tickwork::engine::Rate::hz(120)?;
        stage.camera = Camera::TwoD {
            center: Vec2::new(-A * E - 1.4, 0.0),
            height: 2.0 * A * (1.0 - E * E).sqrt() * 1.9,
        };
        Ok(())
    }

    fn draw(&self, stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        let t = stage.worlds.first().map_or(0.0, |w| w.world.time());
        let _ = writeln!(
            draw.hud,
            "Integrator race: one orbit, t = {t:.1} s ({:.1} periods)",
            t / f64::from(PERIOD)
        );
        let _ = writeln!(draw.hud, "relative energy error (E - E0) / |E0|");
        for shown in &stage.worlds {
            draw.colour(shown.colour);
            let _ = match &shown.failure {
                Some(why) => writeln!(
                    draw.hud,
                    "{}  stopped: {}",
                    shown.label,
                    why.split(':').next().unwrap_or(why)
                ),
                None => writeln!(draw.hud, "{}  {:+.1e}", shown.label, shown.energy.latest()),
            };
        }
        Ok(())
    }

    fn outcome(&self, stage: &Stage) -> Option<String> {
        let mut line = String::from("energy error");
        for shown in &stage.worlds {
            let _ = write!(line, " {}={:+.2e}", shown.label, shown.energy.latest());
        }
        Some(line)
    }
}

fn main() -> ExitCode {
    exit_code(run(Orbits, RunOptions::from_args()))
}
