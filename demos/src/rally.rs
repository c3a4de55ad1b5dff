//! Rally, a game of two players: each moves a paddle with Up/Down (or W/S)
//! and returns the ball; a ball past a paddle is a point for the other
//! side, and the first to five points wins. Enter plays again.
//!
//! Played over the network (`--host PORT` on one machine, `--join ADDR` on
//! the other), each machine runs the whole match under GGRS rollback;
//! alone, the right paddle follows the ball by itself, a little slower
//! than a player can. The paddles are kinematic boxes that report
//! contacts; where the ball meets a paddle aims it (the ends send it out
//! at 50 degrees) and every return is 4% faster.

use tickwork::prelude::*;

/// The court's half width and height (m); the paddles' distance from the centre.
const COURT: (f32, f32) = (8.0, 9.0);
const PADDLE_X: f32 = 7.2;
/// The paddles' half extents (m) and top speed (m/s); the computer's speed.
const PADDLE: Vec2 = Vec2::new(0.2, 1.1);
const PADDLE_SPEED: f32 = 10.0;
const COMPUTER_SPEED: f32 = 6.5;
/// The ball's radius, serve speed and top speed (m, m/s).
const BALL: (f32, f32, f32) = (0.2, 8.0, 18.0);
/// Points to win; ticks the ball waits at the centre before a serve.
const TO_WIN: u32 = 5;
const SERVE_WAIT: u32 = 45;
/// A bounce with no loss and no friction: the ball keeps its speed.
const ELASTIC: Material = Material {
    restitution: 1.0,
    friction: 0.0,
};
/// The two sides' colours: left, right.
const COLOURS: [[u8; 4]; 2] = [[110, 190, 250, 255], [250, 150, 90, 255]];

/// How the match stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Play {
    /// The ball waits at the centre for `wait` more ticks, then goes
    /// towards `side` (0 left, 1 right).
    Serving {
        /// Ticks until the serve.
        wait: u32,
        /// Where the serve goes.
        side: usize,
    },
    /// The ball is in play.
    Rallying,
    /// A side reached five points.
    Over,
}

impl Default for Play {
    fn default() -> Self {
        Self::Serving {
            wait: SERVE_WAIT,
            side: 1,
        }
    }
}

/// The Rally game.
#[derive(Clone, Debug, Default)]
pub struct Rally {
    /// How the match stands.
    pub play: Play,
    /// Points of the left and the right side.
    pub score: [u32; 2],
    /// Whether the right paddle plays itself (a run without a second player).
    pub computer: bool,
    /// The ball.
    pub ball: Entity,
    /// The ball's speed now (m/s).
    pub speed: f32,
    court: WorldId,
    paddles: [ColliderId; 2],
}

impl Rally {
    /// A fresh court: walls above and below, the paddles, the ball.
    fn build(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        let mut court = World::new(WorldConfig {
            seed: settings.seed,
            ..WorldConfig::default()
        })?;
        let (half, top) = COURT;
        // Open at the sides: the walls' box reaches far past the paddles.
        court.add_collider(BoxCollider::container(
            Vec3::new(-10.0 * half, 0.0, -1.0),
            Vec3::new(10.0 * half, top, 1.0),
            ELASTIC,
        ));
        for (k, x) in [-PADDLE_X, PADDLE_X].into_iter().enumerate() {
            let centre = Vec3::new(x, top / 2.0, 0.0);
            let extent = Vec3::new(PADDLE.x, PADDLE.y, 1.0);
            self.paddles[k] = court.add_collider(BoxCollider::solid(centre - extent, centre + extent, ELASTIC));
            court.report_contacts(self.paddles[k])?;
        }
        self.ball = court.spawn(Particle {
            position: Vec3::new(0.0, top / 2.0, 0.0),
            radius: BALL.0,
            colour: [245, 245, 250, 255],
            ..Particle::default()
        })?;
        match stage.world_mut(self.court) {
            Ok(world) => *world = court,
            Err(_) => self.court = stage.add_world("court", court).id(),
        }
        self.computer = !settings.networked;
        (self.score, self.play, self.speed) = ([0, 0], Play::default(), BALL.1);
        Ok(())
    }

    /// Aims the ball off the paddle it touched in the last step.
    fn returns(&mut self, world: &mut World) -> Result<(), GameError> {
        for k in 0..world.contacts().len() {
            let contact = world.contacts()[k];
            let Touched::Collider(id) = contact.touched else {
                continue;
            };
            let Some(side) = self.paddles.iter().position(|p| *p == id) else {
                continue;
            };
            let paddle = world.collider::<BoxCollider>(id)?.centre();
            let angle = ((contact.point.y - paddle.y) / PADDLE.y).clamp(-1.0, 1.0) * 50f32.to_radians();
            let away = if side == 0 { 1.0 } else { -1.0 };
            self.speed = (self.speed * 1.04).min(BALL.2);
            world.set_velocity(
                self.ball,
                self.speed * Vec3::new(away * math::cos(angle), math::sin(angle), 0.0),
            )?;
        }
        Ok(())
    }

    /// The paddle speed a side asks for: its keys, or the computer's chase.
    fn paddle_speed(&self, side: usize, input: &TickInput, paddle_y: f32, ball: Vec3) -> f32 {
        if side == 1 && self.computer {
            return (ball.y - paddle_y).clamp(-COMPUTER_SPEED, COMPUTER_SPEED);
        }
        let held = |a, b| f32::from(u8::from(input.held(a) || input.held(b)));
        PADDLE_SPEED * (held(Key::Up, Key::W) - held(Key::Down, Key::S))
    }
}

impl Game for Rally {
    fn title(&self) -> &str {
        "rally"
    }

    fn players(&self) -> usize {
        2
    }

    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        stage.camera = Camera::TwoD {
            center: Vec2::new(0.0, COURT.1 / 2.0),
            height: COURT.1 + 1.0,
        };
        stage.background = [14, 20, 26, 255];
        self.build(stage, settings)
    }

    fn fixed_update_players(
        &mut self,
        stage: &mut Stage,
        step: &FixedStep,
        inputs: &[TickInput],
    ) -> Result<(), GameError> {
        let none = TickInput::default();
        let input = |side: usize| inputs.get(side).unwrap_or(&none);
        if self.play == Play::Over {
            if input(0).pressed(Key::Enter) || input(1).pressed(Key::Enter) {
                let settings = stage.settings().clone();
                self.build(stage, &settings)?;
            }
            return Ok(());
        }
        let world = stage.world_mut(self.court)?;
        self.returns(world)?;
        let ball = world.position(self.ball)?;
        let dt = step.dt as f32;
        for side in 0..2 {
            let mut paddle = *world.collider::<BoxCollider>(self.paddles[side])?;
            let y = paddle.centre().y;
            let speed = self.paddle_speed(side, input(side), y, ball);
            // Stop at the walls.
            let reach = (PADDLE.y, COURT.1 - PADDLE.y);
            paddle.velocity.y = ((y + speed * dt).clamp(reach.0, reach.1) - y) / dt;
            *world.collider_mut::<BoxCollider>(self.paddles[side])? = paddle;
        }
        match self.play {
            Play::Serving { wait: 0, side } => {
                // A different angle each point, the same on every machine.
                let points = self.score[0] + self.score[1];
                let angle = (f32::from(u8::try_from(points % 5).unwrap_or(0)) - 2.0) * 12f32.to_radians();
                let towards = if side == 0 { -1.0 } else { 1.0 };
                world.set_velocity(
                    self.ball,
                    self.speed * Vec3::new(towards * math::cos(angle), math::sin(angle), 0.0),
                )?;
                self.play = Play::Rallying;
            }
            Play::Serving { wait, side } => {
                self.play = Play::Serving { wait: wait - 1, side };
            }
            Play::Rallying if ball.x.abs() > COURT.0 + 1.0 => {
                // Past the left paddle: a point for the right, who serves
                // to the left; and the other way round.
                let winner = usize::from(ball.x < 0.0);
                self.score[winner] += 1;
                world.teleport(self.ball, Vec3::new(0.0, COURT.1 / 2.0, 0.0))?;
                world.set_velocity(self.ball, Vec3::ZERO)?;
                self.speed = BALL.1;
                self.play = if self.score[winner] >= TO_WIN {
                    Play::Over
                } else {
                    Play::Serving {
                        wait: SERVE_WAIT,
                        side: 1 - winner,
                    }
                };
            }
            Play::Rallying | Play::Over => {}
        }
        Ok(())
    }

    fn draw(&self, stage: &Stage, alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        let world = stage.world(self.court)?;
        let dt = stage.rate.step_seconds() as f32;
        for (side, id) in self.paddles.iter().enumerate() {
            let (min, max) = world.collider::<BoxCollider>(*id)?.interpolated(alpha, dt);
            draw.rect(min.truncate(), max.truncate(), COLOURS[side]);
        }
        let (half, top) = COURT;
        for y in (0..9).map(|k| k as f32 + 0.25) {
            draw.line(Vec3::new(0.0, y, 0.0), Vec3::new(0.0, y + 0.5, 0.0), [70, 80, 95, 255]);
        }
        draw.line(
            Vec3::new(-half, 0.0, 0.0),
            Vec3::new(half, 0.0, 0.0),
            [90, 100, 120, 255],
        );
        draw.line(
            Vec3::new(-half, top, 0.0),
            Vec3::new(half, top, 0.0),
            [90, 100, 120, 255],
        );
        for ((score, colour), x) in self.score.iter().zip(COLOURS).zip([-2.0, 2.0]) {
            draw.text(score.to_string(), Vec3::new(x, top - 1.0, 0.0))
                .size(40.0)
                .colour(colour)
                .anchor(Anchor::Centre);
        }
        draw.hud = if self.computer {
            "Up/Down or W/S: left paddle   (alone: the right one plays itself; --host / --join for two)".into()
        } else {
            "Up/Down or W/S: your paddle".into()
        };
        if self.play == Play::Over {
            let winner = usize::from(self.score[1] > self.score[0]);
            let message = if winner == 0 { "LEFT WINS" } else { "RIGHT WINS" };
            draw.text(message, Vec3::new(0.0, top / 2.0, 0.0))
                .size(48.0)
                .colour(COLOURS[winner])
                .anchor(Anchor::Centre);
        }
        Ok(())
    }

    fn state_hash(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut hasher = StableHasher::new();
        (self.play, self.score, self.computer, self.speed.to_bits()).hash(&mut hasher);
        hasher.finish()
    }

    fn outcome(&self, _stage: &Stage) -> Option<String> {
        let [left, right] = self.score;
        let how = match self.play {
            Play::Over if left > right => "left wins",
            Play::Over => "right wins",
            _ => "unfinished",
        };
        Some(format!("left {left} : {right} right ({how})"))
    }
}
