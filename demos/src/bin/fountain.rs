//! A fountain of 60 000 particles (`--particles` for more: 10 000 000 with
//! `--gpu` is the GPU step's showcase): three jets (emitters), gravity, air
//! drag (quadratic), a bouncing floor and lifetimes. Left/Right sway the
//! side jets, Up/Down change the pressure, W toggles a cross wind.

use std::fmt::Write;
use std::process::ExitCode;

use clap::Parser;
use tickwork::prelude::*;

/// Seconds each droplet lives: a jet of `rate` per second holds `rate`
/// x 3.4 droplets once the fountain is full (`main` divides by it in f64).
const LIFETIME: f32 = 3.4;

/// The fountain on Tickwork: the shared options and its own `--particles`.
#[derive(Parser)]
struct Options {
    #[command(flatten)]
    run: RunOptions,
    /// Droplets alive once the fountain is full (3 jets of `particles /
    /// (3 x 3.4 s)` each a second); 61 200 by default, 10 000 000 the GPU
    /// step's showcase (with `--gpu`).
    #[arg(long, default_value_t = 61_200, value_parser = clap::value_parser!(u32).range(3..=100_000_000))]
    particles: u32,
}

#[derive(Clone, Default)]
struct Fountain {
    /// Particles per second per jet.
    rate: f32,
    /// Sway of the side jets, radians (Left/Right).
    sway: f32,
    /// Jet speed relative to the start (Up/Down).
    pressure: f32,
    wind: bool,
    /// The fountain's world.
    world: WorldId,
}

impl Fountain {
    /// The three jets for the current sway and pressure.
    fn jets(&self) -> [Emitter; 3] {
        let jet = |x: f32, angle: f32, speed: f32, colour: [u8; 4]| Emitter {
            position: Vec3::new(x, 0.05, 0.0),
            direction: Vec3::new(math::sin(angle), math::cos(angle), 0.0),
            spread: 0.09,
            speed: speed * self.pressure,
            speed_jitter: 0.12,
            rate: self.rate,
            lifetime: LIFETIME,
            colour,
            radius: 0.018,
            mass: 0.001,
            owed: 0.0,
        };
        [
            jet(0.0, 0.0, 10.0, [90, 170, 255, 200]),
            jet(-3.0, 0.45 + self.sway, 8.5, [255, 170, 70, 200]),
            jet(3.0, -0.45 + self.sway, 8.5, [250, 110, 160, 200]),
        ]
    }
}

impl Game for Fountain {
    fn title(&self) -> &str {
        "fountain"
    }

    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        *self = Self {
            pressure: 1.0,
            rate: self.rate,
            ..Self::default()
        };
        let alive = (3.0 * self.rate * LIFETIME) as usize;
        let config = WorldConfig {
            seed: settings.seed,
            // Room for a full fountain and a pressure of 140%.
            max_particles: WorldConfig::default().max_particles.max(2 * alive),
            ..WorldConfig::default()
        };
        let mut world = World::new(config)?;
        world.add_force(Gravity::EARTH);
        // Droplets of 1 g: drag a = -c |v| v with c = 0.02 per metre.
        world.add_force(QuadraticDrag { coefficient: 0.02 });
        world.add_force(Wind {
            velocity: Vec3::ZERO,
            rate: 0.0,
        });
        // At the end of the step: no droplet is fast enough to pass the
        // floor, and `--gpu` then ends in the CPU's checksum bit for bit
        // (the default rule, in the step, is f64 on the CPU, f32 on the GPU).
        world.add_collider(Plane {
            contact: ContactRule::EndOfStep,
            ..Plane::floor(
                0.0,
                Material {
                    restitution: 0.45,
                    friction: 0.15,
                },
            )
        });
        for jet in self.jets() {
            world.add_emitter(jet)?;
        }
        self.world = stage.add_world("fountain", world).id();
        stage.panel = true;
        stage.switch_integrators = true;
        stage.camera = Camera::TwoD {
            center: Vec2::new(0.0, 3.6),
            height: 8.0,
        };
        Ok(())
    }

    fn fixed_update(&mut self, stage: &mut Stage, step: &FixedStep, input: &TickInput) -> Result<(), GameError> {
        let dt = step.dt as f32;
        let turn = f32::from(u8::from(input.held(Key::Right))) - f32::from(u8::from(input.held(Key::Left)));
        let push = f32::from(u8::from(input.held(Key::Up))) - f32::from(u8::from(input.held(Key::Down)));
        self.sway = (self.sway + 0.8 * turn * dt).clamp(-0.6, 0.6);
        self.pressure = (self.pressure + 0.5 * push * dt).clamp(0.4, 1.4);
        if input.pressed(Key::W) {
            self.wind = !self.wind;
        }
        let world = stage.world_mut(self.world)?;
        for (emitter, jet) in world.emitters_mut().iter_mut().zip(self.jets()) {
            *emitter = Emitter {
                owed: emitter.owed,
                ..jet
            };
        }
        if let Some(wind) = world.force_mut::<Wind>() {
            *wind = if self.wind {
                Wind {
                    velocity: Vec3::new(6.0, 0.0, 0.0),
                    rate: 0.6,
                }
            } else {
                Wind {
                    velocity: Vec3::ZERO,
                    rate: 0.0,
                }
            };
        }
        Ok(())
    }

    fn draw(&self, stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        draw.line(
            Vec3::new(-8.0, 0.0, 0.0),
            Vec3::new(8.0, 0.0, 0.0),
            [110, 110, 130, 255],
        );
        let _ = writeln!(
            draw.hud,
            "{} droplets  |  pressure {:.0}%  |  wind {}  (Left/Right sway, Up/Down pressure, W wind)",
            stage.world(self.world)?.len(),
            self.pressure * 100.0,
            if self.wind { "on" } else { "off" }
        );
        Ok(())
    }

    fn outcome(&self, stage: &Stage) -> Option<String> {
        Some(format!("{} droplets alive", stage.world(self.world).ok()?.len()))
    }
}

fn main() -> ExitCode {
    let options = parse_args::<Options>();
    let fountain = Fountain {
        // In f64, so that 61 200 gives exactly the 6 000 a second it always had.
        rate: (f64::from(options.particles) / (3.0 * 3.4)) as f32,
        ..Fountain::default()
    };
    exit_code(run(fountain, options.run))
}
