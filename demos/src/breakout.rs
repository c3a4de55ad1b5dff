//! Breakout, written only against Tickwork's public API: Left/Right (or
//! A/D, the mouse, a gamepad's stick or D-pad) move the paddle, Space, a
//! click or the pad's South button serves, Enter or Start plays again.
//! Clear the 40 bricks before the ball gets past you three times.
//!
//! The ball is a sprite and the hits are sounds, loaded from `assets/` (a
//! page fetches them first: [`Game::assets`]).
//!
//! The paddle is a kinematic box (moved by its velocity each step, it hands
//! the ball its speed); bricks are solid boxes that report contacts, and a
//! brick goes when the ball touches it. `--autopilot` lets the game play
//! itself (the demo's golden frame and replays use it).

use tickwork::prelude::*;

/// The arena's half width and height (m); the paddle's centre height.
const ARENA: (f32, f32) = (8.0, 12.0);
const PADDLE_Y: f32 = 1.0;
/// The paddle's half extents and top speed (m, m/s).
const PADDLE: Vec2 = Vec2::new(1.2, 0.2);
const PADDLE_SPEED: f32 = 10.0;
/// The ball's radius and speed (m, m/s), and where it rides the paddle.
const BALL: (f32, f32) = (0.2, 8.0);
const RIDE: f32 = PADDLE_Y + PADDLE.y + BALL.0 + 0.05;
/// Bricks per row; the rows' colours, top row (50 points a brick) first.
const COLUMNS: usize = 8;
const ROWS: [[u8; 4]; 5] = [
    [235, 90, 80, 255],
    [245, 160, 60, 255],
    [235, 215, 80, 255],
    [110, 205, 95, 255],
    [80, 160, 240, 255],
];
/// The files the game loads, relative to the workspace (natively) or the
/// page's asset root (in a page).
const BALL_PNG: &str = "assets/sprites/ball.png";
const BRICK_WAV: &str = "assets/sounds/brick.wav";
const PADDLE_WAV: &str = "assets/sounds/paddle.wav";
const LOST_WAV: &str = "assets/sounds/lost.wav";
/// A bounce with no loss and no friction: the ball keeps its speed.
const ELASTIC: Material = Material {
    restitution: 1.0,
    friction: 0.0,
};

/// How the game stands.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Play {
    /// The ball rides the paddle until served.
    #[default]
    Serving,
    /// The ball is in play.
    Playing,
    /// Every brick is gone.
    Won,
    /// The last ball got past the paddle.
    Lost,
}

/// What the game loaded in `setup`: the ball's sprite and the sounds.
#[derive(Clone, Debug)]
struct Loaded {
    ball: Texture,
    brick: Sound,
    paddle: Sound,
    lost: Sound,
}

/// The Breakout game.
#[derive(Clone, Debug, Default)]
pub struct Breakout {
    /// Whether the game moves the paddle and serves itself.
    pub autopilot: bool,
    /// How the game stands.
    pub play: Play,
    /// Score so far: 10 points a brick in the bottom row to 50 in the top.
    pub score: u32,
    /// Balls left.
    pub lives: u32,
    /// The ball.
    pub ball: Entity,
    court: WorldId,
    paddle: ColliderId,
    /// The bricks left: each one's collider and row.
    pub bricks: Vec<(ColliderId, usize)>,
    loaded: Option<Loaded>,
}

impl Breakout {
    /// A game, played by its autopilot if `autopilot`.
    #[must_use]
    pub fn new(autopilot: bool) -> Self {
        Self {
            autopilot,
            ..Self::default()
        }
    }

    /// A fresh court of the run's seed and integrator: walls, bricks, the
    /// paddle, the ball on it.
    fn build(&mut self, settings: &Settings, stage: &mut Stage) -> Result<(), GameError> {
        let mut court = World::new(settings.world_config())?;
        let (half, top) = ARENA;
        // Open at the bottom: the walls' box reaches far below the paddle.
        let (low, high) = (Vec3::new(-half, -20.0, -1.0), Vec3::new(half, top, 1.0));
        court.add_collider(BoxCollider::container(low, high, ELASTIC));
        self.bricks.clear();
        let width = 2.0 * half / COLUMNS as f32;
        for row in 0..ROWS.len() {
            for column in 0..COLUMNS {
                let min = Vec3::new(-half + column as f32 * width + 0.08, top - 2.1 - 0.6 * row as f32, -1.0);
                let max = min + Vec3::new(width - 0.16, 0.45, 2.0);
                let brick = court.add_collider(BoxCollider::solid(min, max, ELASTIC));
                court.report_contacts(brick)?;
                self.bricks.push((brick, row));
            }
        }
        let centre = Vec2::new(0.0, PADDLE_Y);
        let (low, high) = ((centre - PADDLE).extend(-1.0), (centre + PADDLE).extend(1.0));
        self.paddle = court.add_collider(BoxCollider::solid(low, high, ELASTIC));
        court.report_contacts(self.paddle)?;
        self.ball = court.spawn(Particle {
            position: Vec3::new(0.0, RIDE, 0.0),
            radius: BALL.0,
            colour: [245, 245, 250, 255],
            ..Particle::default()
        })?;
        stage.worlds.clear();
        let court = stage.add_world("court", court);
        self.court = match &self.loaded {
            Some(loaded) => court.sprites(&loaded.ball).id(),
            None => court.id(),
        };
        (self.score, self.lives, self.play) = (0, 3, Play::Serving);
        Ok(())
    }
}

impl Game for Breakout {
    fn title(&self) -> &str {
        "breakout"
    }

    fn assets(&self) -> &[&str] {
        &[BALL_PNG, BRICK_WAV, PADDLE_WAV, LOST_WAV]
    }

    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        self.loaded = Some(Loaded {
            ball: Texture::load(BALL_PNG)?,
            brick: Sound::load(BRICK_WAV)?,
            paddle: Sound::load(PADDLE_WAV)?,
            lost: Sound::load(LOST_WAV)?,
        });
        stage.camera = Camera::TwoD {
            center: Vec2::new(0.0, 6.0),
            height: 13.0,
        };
        stage.background = [16, 18, 30, 255];
        self.build(settings, stage)
    }

    fn fixed_update(&mut self, stage: &mut Stage, step: &FixedStep, input: &TickInput) -> Result<(), GameError> {
        let pad = input.pad(0);
        match self.play {
            Play::Won | Play::Lost if input.pressed(Key::Enter) || pad.pressed(PadButton::Start) => {
                return self.build(&stage.settings().clone(), stage);
            }
            Play::Won | Play::Lost => return Ok(()),
            Play::Serving | Play::Playing => {}
        }
        let Some(loaded) = &self.loaded else {
            return Err("breakout: fixed_update before setup".into());
        };
        let world = stage.world_mut(self.court)?;
        let mut paddle = *world.collider::<BoxCollider>(self.paddle)?;
        let x = paddle.centre().x;
        // Bricks the ball touched in the last step go; where it met the
        // paddle aims it (the ends send it out at 60 degrees).
        let mut sounds = Vec::new();
        for k in 0..world.contacts().len() {
            let Contact { touched, point, .. } = world.contacts()[k];
            let hit = self.bricks.iter().position(|(b, _)| touched == Touched::Collider(*b));
            if touched == Touched::Collider(self.paddle) {
                let angle = ((point.x - x) / PADDLE.x).clamp(-1.0, 1.0) * 60f32.to_radians();
                world.set_velocity(self.ball, BALL.1 * Vec3::new(math::sin(angle), math::cos(angle), 0.0))?;
                sounds.push(&loaded.paddle);
            } else if let Some(k) = hit {
                let (brick, row) = self.bricks.remove(k);
                world.remove_collider(brick)?;
                self.score += 10 * (ROWS.len() - row) as u32;
                sounds.push(&loaded.brick);
            }
        }
        let ball = world.position(self.ball)?;
        // Where the paddle heads: the autopilot's aim, the keys, D-pad or
        // stick while held, else the pointer.
        let held = |a, b, c| f32::from(u8::from(input.held(a) || input.held(b) || pad.held(c)));
        let stick = pad.axis(PadAxis::LeftX);
        let keys = (held(Key::Right, Key::D, PadButton::DPadRight) - held(Key::Left, Key::A, PadButton::DPadLeft)
            + stick)
            .clamp(-1.0, 1.0);
        let dt = step.dt as f32;
        let towards = |t: f32| ((t - x) / dt).clamp(-PADDLE_SPEED, PADDLE_SPEED);
        let speed = match input.pointer_at() {
            _ if self.autopilot => towards(ball.x + 0.6 * math::sin(step.tick as f32 * 0.013)),
            Some(pointer) if keys == 0.0 => towards(pointer.x),
            _ => PADDLE_SPEED * keys,
        };
        // Stop at the walls.
        let reach = ARENA.0 - PADDLE.x;
        paddle.velocity.x = ((x + speed * dt).clamp(-reach, reach) - x) / dt;
        *world.collider_mut::<BoxCollider>(self.paddle)? = paddle;
        match self.play {
            Play::Serving
                if self.autopilot
                    || input.pressed(Key::Space)
                    || input.pressed(Key::MouseLeft)
                    || pad.pressed(PadButton::South) =>
            {
                world.set_velocity(self.ball, BALL.1 * Vec3::new(0.5, 0.866, 0.0))?;
                self.play = Play::Playing;
            }
            // Riding along at the paddle's speed, so it is drawn smoothly.
            Play::Serving => world.set_velocity(self.ball, paddle.velocity)?,
            _ if self.bricks.is_empty() => self.play = Play::Won,
            _ if ball.y < -0.5 => {
                self.lives -= 1;
                sounds.push(&loaded.lost);
                world.teleport(self.ball, Vec3::new(x, RIDE, 0.0))?;
                world.set_velocity(self.ball, Vec3::ZERO)?;
                self.play = if self.lives == 0 { Play::Lost } else { Play::Serving };
            }
            _ => {}
        }
        for sound in sounds {
            stage.play(sound);
        }
        Ok(())
    }

    fn draw(&self, stage: &Stage, alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        let world = stage.world(self.court)?;
        for &(id, row) in &self.bricks {
            let brick = world.collider::<BoxCollider>(id)?;
            draw.rect(brick.min.truncate(), brick.max.truncate(), ROWS[row]);
        }
        let paddle = world.collider::<BoxCollider>(self.paddle)?;
        let (min, max) = paddle.interpolated(alpha, stage.rate.step_seconds() as f32);
        draw.rect(min.truncate(), max.truncate(), [225, 225, 235, 255]);
        let (x, y) = ARENA;
        let walls = [(-x, 0.0), (-x, y), (x, y), (x, 0.0)].map(|(x, y)| Vec3::new(x, y, 0.0));
        draw.polyline(&walls, [90, 95, 120, 255], false);
        draw.hud = format!("score {}   balls {}", self.score, self.lives);
        let (message, colour) = match self.play {
            Play::Won => ("YOU WIN", [120, 230, 120, 255]),
            Play::Lost => ("GAME OVER", [240, 100, 90, 255]),
            Play::Serving if !self.autopilot => ("Space to serve", [200, 200, 210, 255]),
            _ => return Ok(()),
        };
        draw.text(message, Vec3::new(0.0, 4.5, 0.0)).size(48.0).colour(colour);
        Ok(())
    }

    fn state_hash(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut hasher = StableHasher::new();
        (self.play, self.score, self.lives, &self.bricks).hash(&mut hasher);
        hasher.finish()
    }

    fn outcome(&self, _stage: &Stage) -> Option<String> {
        let how = match self.play {
            Play::Won => "won",
            Play::Lost => "lost",
            Play::Serving | Play::Playing => "stopped",
        };
        let (score, left) = (self.score, self.bricks.len());
        Some(format!("{how} with {score} points, {left} bricks left"))
    }
}
