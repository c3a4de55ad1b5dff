//! A platformer on a level made in Tiled (`assets/maps/level.tmx`), on the
//! public API only: Left/Right (A/D, a pad) run, Space (Up, W, the pad's
//! South) jumps, higher while held. Take the coins, ride the ferry over the
//! spikes, reach the flag. The ground is the map's solid layer as merged
//! boxes, coins, spikes and flag its objects as sensors; the hero a
//! kinematic character, animated and flipped, followed by the camera.

use tickwork::prelude::*;

const MAP: &str = "assets/maps/level.tmx";
const TSX: &str = "assets/maps/tiles.tsx";
const TILES: &str = "assets/maps/tiles.png";
const HERO: &str = "assets/sprites/hero.png";
/// A coin taken, a jump, a death.
const SOUNDS: [&str; 3] = [
    "assets/sounds/brick.wav",
    "assets/sounds/paddle.wav",
    "assets/sounds/lost.wav",
];
/// Run and jump speeds, and what a released jump keeps rising at (m/s).
const RUN: f32 = 6.0;
const JUMP: f32 = 13.0;
const CUT: f32 = 4.0;

/// What `setup` loads: the map and its layers' handles, images, sounds.
#[derive(Clone, Debug)]
struct Loaded {
    map: TileMap,
    layers: [TileLayerId; 2],
    tiles: Texture,
    hero: Texture,
    run: Animation,
    sounds: [Sound; 3],
    /// The camera's rule: a 2 x 1.5 m dead zone, smoothing, the level's bounds.
    follow: Follow,
}

/// The platformer.
#[derive(Clone, Debug, Default)]
pub struct Platformer {
    /// Whether the game plays itself.
    pub autopilot: bool,
    /// Coins taken.
    pub coins: u32,
    /// Times the hero died (spikes, a fall).
    pub deaths: u32,
    /// The tick the flag was reached at.
    pub finished: Option<u64>,
    level: WorldId,
    hero: CharacterId,
    /// The coins left: each sensor and where it is drawn.
    coins_left: Vec<(SensorId, Vec2)>,
    hazards: Vec<SensorId>,
    flag: SensorId,
    ferry: ColliderId,
    /// The ferry's leftmost and rightmost x, and its speed.
    ferry_run: (f32, f32, f32),
    spawn: Vec2,
    /// Steps spent running (the animation's clock) and facing left.
    running: u64,
    facing_left: bool,
    loaded: Option<Loaded>,
}

impl Platformer {
    /// A game, played by itself if `autopilot`.
    #[must_use]
    pub fn new(autopilot: bool) -> Self {
        Self {
            autopilot,
            ..Self::default()
        }
    }

    /// The autopilot's run and jump: wait for the ferry at the pit, ride it,
    /// else run right and jump at a wall or an edge.
    fn pilot(&self, world: &World, hero: &Character) -> Result<(f32, bool), GameError> {
        let ferry = world.collider::<BoxCollider>(self.ferry)?;
        let x = hero.position.x;
        let on_ferry = hero.ground().is_some_and(|g| g.collider == self.ferry);
        Ok(match () {
            _ if on_ferry && ferry.max.x > 30.9 => (RUN, false),
            _ if on_ferry && x < ferry.max.x - 0.4 => (RUN / 2.0, false),
            _ if on_ferry => (0.0, false),
            _ if (20.0..21.0).contains(&x) && ferry.min.x >= 21.3 => (0.0, false),
            _ => (
                RUN,
                hero.grounded() && (hero.wall().is_some() || [6.3, 11.6].iter().any(|e| (x - e).abs() < 0.12)),
            ),
        })
    }
}

impl Game for Platformer {
    fn title(&self) -> &str {
        "platformer"
    }

    fn assets(&self) -> &[&str] {
        &[MAP, TSX, TILES, HERO, SOUNDS[0], SOUNDS[1], SOUNDS[2]]
    }

    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        let map = TileMap::load(MAP)?;
        let layers = [map.tile_layer("ground")?, map.tile_layer("decor")?];
        let mut world = World::new(settings.world_config())?;
        map.add_colliders(&mut world, layers[0], Material::default())?;
        let ferry = map.object("ferry")?;
        let (min, max) = ferry.area().ok_or("the ferry is an area")?;
        let speed = ferry.number("speed").unwrap_or(1.0);
        self.ferry_run = (min.x, min.x + ferry.number("travel").unwrap_or(4.0), speed);
        self.ferry = world.add_collider(BoxCollider {
            velocity: Vec3::new(speed, 0.0, 0.0),
            ..BoxCollider::solid(min.extend(-0.5), max.extend(0.5), Material::default())
        });
        (self.coins_left, self.hazards) = (Vec::new(), Vec::new());
        for object in map.objects("objects")? {
            if !["coin", "hazard", "goal"].contains(&object.class.as_str()) {
                continue;
            }
            let sensor = world.add_sensor(object.sensor(1.0)?)?;
            match object.class.as_str() {
                "coin" => self.coins_left.push((sensor, object.position)),
                "hazard" => self.hazards.push(sensor),
                _ => self.flag = sensor,
            }
        }
        self.spawn = map.object("player")?.position + Vec2::new(0.0, 0.5);
        self.hero = world.add_character(Character::new(self.spawn, CharacterConfig::default()))?;
        let follow = Follow {
            dead_zone: Vec2::new(2.0, 1.5),
            smoothing: 0.2,
            bounds: Some(map.bounds()),
        };
        stage.camera = Camera::Field {
            center: self.spawn,
            size: Vec2::new(16.0, 9.0),
            fit: Fit::Letterbox,
        };
        stage.camera.follow(&follow, self.spawn)?;
        stage.background = [92, 148, 220, 255];
        stage.worlds.clear();
        self.level = stage.add_world("level", world).id();
        (self.coins, self.deaths, self.finished, self.running) = (0, 0, None, 0);
        self.loaded = Some(Loaded {
            tiles: Texture::load(TILES)?,
            hero: Texture::load(HERO)?,
            run: Animation::row([16, 0], [16, 24], 4, 5)?,
            sounds: [
                Sound::load(SOUNDS[0])?,
                Sound::load(SOUNDS[1])?,
                Sound::load(SOUNDS[2])?,
            ],
            map,
            layers,
            follow,
        });
        Ok(())
    }

    fn fixed_update(&mut self, stage: &mut Stage, _step: &FixedStep, input: &TickInput) -> Result<(), GameError> {
        let Some(loaded) = &self.loaded else {
            return Err("platformer: fixed_update before setup".into());
        };
        let [coin, jump, hurt] = &loaded.sounds;
        let low = loaded.map.bounds().0;
        let world = stage.world_mut(self.level)?;
        // The ferry turns at the ends of its run.
        let (left, right, speed) = self.ferry_run;
        let ferry = world.collider_mut::<BoxCollider>(self.ferry)?;
        if ferry.min.x >= right {
            ferry.velocity.x = -speed;
        } else if ferry.min.x <= left {
            ferry.velocity.x = speed;
        }
        let touching: Vec<SensorId> = world.sensors_touching(self.hero)?.collect();
        let mut sounds = Vec::new();
        for (k, (sensor, _)) in self.coins_left.clone().iter().enumerate().rev() {
            if touching.contains(sensor) {
                world.remove_sensor(*sensor)?;
                self.coins_left.remove(k);
                self.coins += 1;
                sounds.push(coin);
            }
        }
        if self.finished.is_none() && touching.contains(&self.flag) {
            self.finished = Some(world.tick());
        }
        let hero = world.character(self.hero)?.clone();
        let dead = touching.iter().any(|s| self.hazards.contains(s)) || hero.position.y < low.y - 2.0;
        let pad = input.pad(0);
        let held = |keys: [Key; 2], button| input.held(keys[0]) || input.held(keys[1]) || pad.held(button);
        let (run, jumps) = if self.autopilot {
            self.pilot(world, &hero)?
        } else {
            let axis = f32::from(u8::from(held([Key::Right, Key::D], PadButton::DPadRight)))
                - f32::from(u8::from(held([Key::Left, Key::A], PadButton::DPadLeft)))
                + pad.axis(PadAxis::LeftX);
            let pressed =
                [Key::Space, Key::Up, Key::W].iter().any(|k| input.pressed(*k)) || pad.pressed(PadButton::South);
            (RUN * axis.clamp(-1.0, 1.0), pressed)
        };
        let character = world.character_mut(self.hero)?;
        if dead {
            sounds.push(hurt);
            self.deaths += 1;
            *character = Character::new(self.spawn, character.config);
        } else if self.finished.is_some() {
            character.stop();
        } else {
            character.run(run);
            if jumps {
                character.jump(JUMP);
            }
            let holding = self.autopilot || held([Key::Space, Key::Up], PadButton::South) || input.held(Key::W);
            if !holding {
                character.cut_jump(CUT);
            }
        }
        sounds.extend(hero.jumped().then_some(jump));
        self.running = u64::from(run != 0.0 && hero.grounded()) * (self.running + 1);
        self.facing_left = if run == 0.0 { self.facing_left } else { run < 0.0 };
        stage.camera.follow(&loaded.follow, hero.position)?;
        for sound in sounds {
            stage.play(sound);
        }
        Ok(())
    }

    fn draw(&self, stage: &Stage, alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        let Some(loaded) = &self.loaded else {
            return Ok(());
        };
        for &layer in &loaded.layers {
            draw.tiles(&loaded.map, layer);
        }
        let world = stage.world(self.level)?;
        for (_, at) in &self.coins_left {
            draw.sprite(&loaded.tiles, *at, Vec2::ONE).region([0, 16, 16, 16]);
        }
        let ferry = world.collider::<BoxCollider>(self.ferry)?;
        let (min, max) = ferry.interpolated(alpha, stage.rate.step_seconds() as f32);
        for k in 0..3 {
            let at = Vec2::new(min.x + 0.5 + k as f32, max.y - 0.5);
            draw.sprite(&loaded.tiles, at, Vec2::ONE).region([32, 16, 16, 16]);
        }
        let hero = world.character(self.hero)?;
        let at = hero.drawn_position(alpha) + Vec2::new(0.0, 0.3);
        let sprite = draw.sprite(&loaded.hero, at, Vec2::new(1.0, 1.5));
        match (hero.grounded(), self.running) {
            (false, _) => sprite.region([80, 0, 16, 24]),
            (true, 0) => sprite.region([0, 0, 16, 24]),
            (true, ticks) => sprite.animate(&loaded.run, ticks),
        }
        .flip_x(self.facing_left);
        draw.hud = format!("coins {}   deaths {}", self.coins, self.deaths);
        if let (Some(_), Some((low, high))) = (self.finished, stage.visible()) {
            let centre = ((low + high) / 2.0).extend(0.0);
            draw.text("LEVEL CLEAR", centre)
                .size_of_frame(0.12)
                .colour([255, 240, 120, 255]);
        }
        Ok(())
    }

    fn state_hash(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut hasher = StableHasher::new();
        (self.coins, self.deaths, self.finished, self.running, self.facing_left).hash(&mut hasher);
        self.coins_left.iter().for_each(|(s, _)| s.hash(&mut hasher));
        hasher.finish()
    }

    fn outcome(&self, _stage: &Stage) -> Option<String> {
        let how = self.finished.map_or("stopped before the flag".into(), |t| {
            format!("reached the flag at tick {t}")
        });
        Some(format!("{how} with {} coins and {} deaths", self.coins, self.deaths))
    }
}
