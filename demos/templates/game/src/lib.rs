//! @NAME@: keep the ball in the air. Space kicks it up, Left and Right push
//! it. The game is a library, so its tests drive it as the window does.

use tickwork::prelude::*;

/// The game's state: handles kept from `setup`, and the score.
#[derive(Clone, Default)]
pub struct @TYPE@ {
    court: WorldId,
    ball: Entity,
    /// Kicks so far.
    pub kicks: u32,
}

impl Game for @TYPE@ {
    fn title(&self) -> &str {
        "@NAME@"
    }

    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        let mut world = World::new(settings.world_config())?;
        world.add_force(Gravity::EARTH);
        world.add_collider(Plane::floor(0.0, Material { restitution: 0.6, friction: 0.1 }));
        self.ball = world.spawn(Particle { position: Vec3::new(0.0, 3.0, 0.0), radius: 0.3, ..Particle::default() })?;
        self.court = stage.add_world("court", world).follow(self.ball, [120, 200, 255, 255]).id();
        self.kicks = 0;
        stage.camera = Camera::TwoD { center: Vec2::new(0.0, 4.0), height: 9.0 };
        Ok(())
    }

    fn fixed_update(&mut self, stage: &mut Stage, _step: &FixedStep, input: &TickInput) -> Result<(), GameError> {
        let world = stage.world_mut(self.court)?;
        let mut velocity = world.velocity(self.ball)?;
        if input.pressed(Key::Space) {
            velocity.y = 7.0;
            self.kicks += 1;
        }
        if input.held(Key::Left) {
            velocity.x -= 0.1;
        }
        if input.held(Key::Right) {
            velocity.x += 0.1;
        }
        world.set_velocity(self.ball, velocity)?;
        Ok(())
    }

    fn draw(&self, _stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        draw.rect(Vec2::new(-8.0, -0.5), Vec2::new(8.0, 0.0), [70, 90, 60, 255]);
        // A dot a kick along the top (`draw.text` comes with the `text` feature).
        for kick in 0..self.kicks.min(30) {
            let x = -7.5 + 0.5 * kick as f32;
            draw.rect(Vec2::new(x, 7.7), Vec2::new(x + 0.3, 8.0), [255, 210, 90, 255]);
        }
        Ok(())
    }

    // The kicks are simulated state the world does not hold: in the checksum.
    fn state_hash(&self) -> u64 {
        u64::from(self.kicks)
    }

    fn outcome(&self, _stage: &Stage) -> Option<String> {
        Some(format!("{} kicks", self.kicks))
    }
}
