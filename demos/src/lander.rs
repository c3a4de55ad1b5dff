//! Lunar lander, a small game written only against Tickwork's public API:
//! rotate with Left/Right, fire the engine with Up (or W or Space), and set
//! down on the pad gently (below 1.5 m/s down, 1 m/s across, 15 degrees of
//! tilt). Landing scores 500 plus 25 per second of fuel left; anything else
//! is a crash. Enter flies again.
//!
//! The ship is one particle under the Moon's gravity and a [`Thrust`] force
//! the game sets each tick from the keys, so every integrator can fly it;
//! crashes scatter debris particles that bounce on the ground.

use std::fmt::Write;

use tickwork::engine::forces::Force;
use tickwork::glam::Vec3A;
use tickwork::prelude::*;

/// The Moon's gravity, m/s^2.
const MOON: f32 = 1.62;
/// Engine acceleration at full thrust, m/s^2.
const ENGINE: f32 = 4.0;
/// Rotation rate, rad/s.
const TURN: f32 = 2.0;
/// Seconds of full thrust in the tank.
const FUEL: f32 = 10.0;
/// The pad: centre x, half width, height (m).
const PAD: (f32, f32, f32) = (3.0, 1.5, 1.0);
/// Landing limits: descent speed, drift speed (m/s), tilt (rad).
const SAFE: (f32, f32, f32) = (1.5, 1.0, 0.26);
/// Half the ship's height: from its centre to the feet (m).
const FEET: f32 = 0.35;

/// The engine: a uniform acceleration the game changes every tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Thrust {
    /// Acceleration, m/s^2.
    pub acceleration: Vec3,
}

impl Force for Thrust {
    fn name(&self) -> &'static str {
        "thrust"
    }

    fn affine_in_velocity(&self) -> Option<(Vec3A, f32)> {
        Some((self.acceleration.into(), 0.0))
    }

    fn accumulate(&self, _t: f32, _first: usize, _x: &[Vec3A], _v: &[Vec3A], _w: &[f32], out: &mut [Vec3A]) {
        let a = Vec3A::from(self.acceleration);
        for out in out {
            *out += a;
        }
    }
}

/// How a flight is going.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Flight {
    /// In the air.
    Flying,
    /// Down on the pad, with this score.
    Landed {
        /// 500 plus 25 per second of fuel left.
        score: u32,
    },
    /// Down anywhere else, or too hard.
    Crashed {
        /// Why.
        reason: &'static str,
    },
}

/// The lander game.
#[derive(Clone, Debug)]
pub struct Lander {
    /// The world, once set up.
    moon: Option<WorldId>,
    ship: Option<Entity>,
    /// Tilt from upright, radians (positive: leaning left, engine pushes right).
    angle: f32,
    fuel: f32,
    thrusting: bool,
    flight: Flight,
    /// Total score over the flights of this run.
    total: u32,
    flights: u32,
    seed: u64,
}

impl Default for Lander {
    fn default() -> Self {
        Self {
            moon: None,
            ship: None,
            angle: 0.0,
            fuel: FUEL,
            thrusting: false,
            flight: Flight::Flying,
            total: 0,
            flights: 0,
            seed: 0,
        }
    }
}

/// Ground height at `x`: rolling hills, flat on the pad.
fn ground(x: f32) -> f32 {
    let (pad, half, height) = PAD;
    if (x - pad).abs() <= half {
        return height;
    }
    0.9 + 0.6 * math::sin(0.9 * x) + 0.35 * math::sin(2.3 * x + 1.0)
}

impl Lander {
    /// The current flight's state.
    #[must_use]
    pub fn flight(&self) -> Flight {
        self.flight
    }

    /// Total score of the run.
    #[must_use]
    pub fn total(&self) -> u32 {
        self.total
    }

    /// A fresh world: the ship high on the left, drifting right.
    fn launch(&mut self, stage: &mut Stage) -> Result<(), GameError> {
        let config = WorldConfig {
            integrator: stage
                .worlds
                .first()
                .map_or("semi_implicit_euler", |w| w.world.integrator().info().name)
                .to_owned(),
            seed: self.seed,
            ..WorldConfig::default()
        };
        let mut world = World::new(config)?;
        world.add_force(Gravity {
            acceleration: Vec3::new(0.0, -MOON, 0.0),
        });
        world.add_force(Thrust::default());
        world.add_collider(Plane::floor(
            0.0,
            Material {
                restitution: 0.3,
                friction: 0.5,
            },
        ));
        let ship = world.spawn(Particle {
            position: Vec3::new(-4.0, 8.0, 0.0),
            velocity: Vec3::new(0.9, 0.0, 0.0),
            radius: 0.16,
            colour: [230, 230, 240, 255],
            ..Particle::default()
        })?;
        match self.moon {
            Some(moon) => *stage.world_mut(moon)? = world,
            None => self.moon = Some(stage.add_world("moon", world).id()),
        }
        self.ship = Some(ship);
        self.angle = 0.0;
        self.fuel = FUEL;
        self.thrusting = false;
        self.flight = Flight::Flying;
        self.flights += 1;
        Ok(())
    }

    /// Touch-down: landed or crashed, by the pad and the limits.
    fn touch_down(&mut self, world: &mut World, ship: Entity) -> Result<(), GameError> {
        let (position, velocity) = (world.position(ship)?, world.velocity(ship)?);
        let on_pad = (position.x - PAD.0).abs() <= PAD.1 - 0.2;
        self.flight = if !on_pad {
            Flight::Crashed {
                reason: "missed the pad",
            }
        } else if -velocity.y > SAFE.0 {
            Flight::Crashed {
                reason: "came down too fast",
            }
        } else if velocity.x.abs() > SAFE.1 {
            Flight::Crashed {
                reason: "drifting sideways",
            }
        } else if self.angle.abs() > SAFE.2 {
            Flight::Crashed { reason: "not upright" }
        } else {
            let score = 500 + (25.0 * self.fuel).round() as u32;
            self.total += score;
            Flight::Landed { score }
        };
        world.despawn(ship)?;
        self.ship = None;
        let resting = Vec3::new(position.x, ground(position.x) + FEET, 0.0);
        match self.flight {
            Flight::Landed { .. } => {
                self.ship = Some(world.spawn(Particle {
                    position: resting,
                    immovable: true,
                    radius: 0.16,
                    colour: [120, 230, 140, 255],
                    ..Particle::default()
                })?);
            }
            _ => {
                // Debris: 40 fragments thrown up and out, from the world's
                // seeded generator, so a replay crashes the same way.
                for k in 0..40 {
                    let angle = std::f32::consts::PI * (0.1 + 0.8 * k as f32 / 39.0);
                    let speed = 1.5 + 2.5 * ((k * 7919 % 40) as f32 / 40.0);
                    world.spawn(Particle {
                        position: resting,
                        velocity: speed * Vec3::new(math::cos(angle), math::sin(angle), 0.0) + 0.3 * velocity,
                        radius: 0.05,
                        mass: 0.05,
                        colour: [255, 150 + (k * 3 % 90) as u8, 60, 255],
                        lifetime: Some(4.0),
                        ..Particle::default()
                    })?;
                }
            }
        }
        if let Some(thrust) = world.force_mut::<Thrust>() {
            thrust.acceleration = Vec3::ZERO;
        }
        self.thrusting = false;
        Ok(())
    }
}

impl Game for Lander {
    fn title(&self) -> &str {
        "lander"
    }

    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        *self = Self {
            seed: settings.seed,
            ..Self::default()
        };
        self.launch(stage)?;
        stage.camera = Camera::TwoD {
            center: Vec2::new(0.0, 4.5),
            height: 10.0,
        };
        Ok(())
    }

    fn fixed_update(&mut self, stage: &mut Stage, step: &FixedStep, input: &TickInput) -> Result<(), GameError> {
        if self.flight != Flight::Flying {
            if input.pressed(Key::Enter) {
                self.launch(stage)?;
            }
            return Ok(());
        }
        let (Some(moon), Some(ship)) = (self.moon, self.ship) else {
            return Ok(());
        };
        let dt = step.dt as f32;
        let world = stage.world_mut(moon)?;
        let turn = f32::from(u8::from(input.held(Key::Left))) - f32::from(u8::from(input.held(Key::Right)));
        self.angle = (self.angle + TURN * turn * dt).clamp(-1.5, 1.5);
        let burn = [Key::Up, Key::W, Key::Space].iter().any(|&k| input.held(k)) && self.fuel > 0.0;
        self.thrusting = burn;
        if burn {
            self.fuel = (self.fuel - dt).max(0.0);
        }
        // The engine pushes along the ship's up axis, tilted by `angle`.
        let up = Vec3::new(-math::sin(self.angle), math::cos(self.angle), 0.0);
        if let Some(thrust) = world.force_mut::<Thrust>() {
            thrust.acceleration = if burn { ENGINE * up } else { Vec3::ZERO };
        }
        let position = world.position(ship)?;
        if position.y - FEET <= ground(position.x) {
            self.touch_down(world, ship)?;
        } else if position.x.abs() > 12.0 || position.y > 30.0 {
            self.flight = Flight::Crashed {
                reason: "lost in space",
            };
        }
        Ok(())
    }

    fn draw(&self, stage: &Stage, alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        let Some(moon) = self.moon else {
            return Ok(());
        };
        // The ground, and the pad in green.
        let hill = |k: u32| {
            let x = -12.0 + 24.0 * k as f32 / 96.0;
            Vec3::new(x, ground(x), 0.0)
        };
        for k in 0..96 {
            draw.line(hill(k), hill(k + 1), [150, 150, 165, 255]);
        }
        let (pad, half, height) = PAD;
        for dy in [0.0, 0.03] {
            draw.line(
                Vec3::new(pad - half, height + dy, 0.0),
                Vec3::new(pad + half, height + dy, 0.0),
                [90, 230, 120, 255],
            );
        }
        let world = stage.world(moon)?;
        if let Some(centre) = self
            .ship
            .and_then(|ship| world.row(ship).ok())
            .map(|row| world.particles().interpolated(row, alpha))
        {
            // Hull and legs, rotated by the tilt.
            let rotate = |p: Vec3| {
                let (s, c) = math::sin_cos(self.angle);
                centre + Vec3::new(c * p.x - s * p.y, s * p.x + c * p.y, 0.0)
            };
            let hull =
                [(-0.25, -0.1), (0.25, -0.1), (0.15, 0.3), (-0.15, 0.3)].map(|(x, y)| rotate(Vec3::new(x, y, 0.0)));
            draw.polyline(&hull, [230, 230, 240, 255], true);
            for side in [-1.0, 1.0] {
                draw.line(
                    rotate(Vec3::new(0.2 * side, -0.1, 0.0)),
                    rotate(Vec3::new(0.35 * side, -FEET, 0.0)),
                    [200, 200, 210, 255],
                );
            }
            if self.thrusting {
                let flame = [(-0.1, -0.12), (0.0, -0.65), (0.1, -0.12)].map(|(x, y)| rotate(Vec3::new(x, y, 0.0)));
                draw.polyline(&flame, [255, 170, 60, 255], false);
            }
        }
        let speed = self
            .ship
            .and_then(|ship| world.velocity(ship).ok())
            .unwrap_or(Vec3::ZERO);
        let altitude = self
            .ship
            .and_then(|ship| world.position(ship).ok())
            .map_or(0.0, |p| p.y - FEET - ground(p.x));
        let _ = writeln!(
            draw.hud,
            "fuel {:.1} s  alt {altitude:.1} m  down {:.1} m/s  across {:+.1} m/s  tilt {:+.0}  score {}",
            self.fuel,
            -speed.y,
            speed.x,
            self.angle.to_degrees(),
            self.total
        );
        match self.flight {
            Flight::Flying => {
                let _ = writeln!(
                    draw.hud,
                    "Left/Right rotate, Up fires the engine: land on the green pad"
                );
            }
            Flight::Landed { score } => {
                draw.colour([120, 240, 140, 255]);
                let _ = writeln!(draw.hud, "LANDED! +{score} points. Enter to fly again");
            }
            Flight::Crashed { reason } => {
                draw.colour([255, 110, 90, 255]);
                let _ = writeln!(draw.hud, "CRASHED: {reason}. Enter to try again");
            }
        }
        Ok(())
    }

    fn outcome(&self, _stage: &Stage) -> Option<String> {
        Some(match self.flight {
            Flight::Flying => format!("flying, fuel {:.2} s, score {}", self.fuel, self.total),
            Flight::Landed { score } => format!("landed, +{score}, score {}", self.total),
            Flight::Crashed { reason } => format!("crashed ({reason}), score {}", self.total),
        })
    }
}
