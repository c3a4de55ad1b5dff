//! Rollback: a game saved, loaded and re-simulated tick by tick under
//! GGRS's SyncTestSession reaches the same states, and a game that keeps
//! simulation state outside what it saves is caught, with the tick.

use std::cell::Cell;
use std::rc::Rc;

use glam::Vec3;
use tickwork_engine::app::{Game, GameError, GameSession, SessionOptions, Settings, Stage, TickInput, sync_test};
use tickwork_engine::{Entity, FixedStep, Gravity, Key, Material, Particle, Plane, World, WorldConfig};

/// Balls bouncing on a floor, kicked by Space; `kicks` counts them in the
/// game's own state. `leak`, when set, is a counter `Clone` shares instead
/// of copying: state outside the snapshot.
#[derive(Clone, Default)]
struct Bouncer {
    method: &'static str,
    balls: Vec<Entity>,
    kicks: u32,
    leak: Option<Rc<Cell<u32>>>,
}

impl Game for Bouncer {
    fn title(&self) -> &str {
        "bouncer"
    }

    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        let mut world = World::new(WorldConfig {
            integrator: self.method.into(),
            seed: settings.seed,
            ..WorldConfig::default()
        })?;
        world.add_force(Gravity::EARTH);
        world.add_collider(Plane::floor(
            0.0,
            Material {
                restitution: 0.7,
                friction: 0.1,
            },
        ));
        self.balls.clear();
        for k in 0..20 {
            self.balls.push(world.spawn(Particle {
                position: Vec3::new(k as f32 * 0.3, 1.0 + 0.1 * k as f32, 0.0),
                radius: 0.1,
                ..Particle::default()
            })?);
        }
        stage.add_world("bouncer", world);
        Ok(())
    }

    fn fixed_update(&mut self, stage: &mut Stage, _step: &FixedStep, input: &TickInput) -> Result<(), GameError> {
        let world = &mut stage.worlds[0].world;
        let mut kick = if input.pressed(Key::Space) { 4.0 } else { 0.0 };
        if let Some(leak) = &self.leak {
            // Counts every call, re-simulations included.
            leak.set(leak.get() + 1);
            kick += 0.001 * leak.get() as f32;
        }
        if kick > 0.0 {
            self.kicks += 1;
            let ball = self.balls[self.kicks as usize % self.balls.len()];
            let v = world.velocity(ball)?;
            world.set_velocity(ball, v + Vec3::new(0.0, kick, 0.0))?;
        }
        Ok(())
    }
}

/// Space pressed every 25th tick (by the only player).
fn kicks(tick: u64, _player: usize) -> TickInput {
    let mut input = TickInput::default();
    if tick % 25 == 3 {
        input.pressed.insert(Key::Space);
        input.held.insert(Key::Space);
    }
    input
}

fn session(game: Bouncer) -> GameSession<Bouncer> {
    GameSession::new(game, SessionOptions::default()).expect("a session")
}

#[test]
fn every_kind_of_method_re_simulates_to_the_same_states() {
    // A pointwise method, one with history, an implicit one, an adaptive one.
    for method in [
        "semi_implicit_euler",
        "adams_bashforth4",
        "implicit_euler",
        "dormand_prince",
    ] {
        let mut rolled = session(Bouncer {
            method,
            ..Bouncer::default()
        });
        let report = sync_test(&mut rolled, 7, 200, kicks).unwrap_or_else(|e| panic!("{method}: {e}"));
        assert_eq!(report.ticks, 200);
        // The same 200 ticks straight through: the same state.
        let mut straight = session(Bouncer {
            method,
            ..Bouncer::default()
        });
        for tick in 0..200 {
            straight.step_tick(tick, &[kicks(tick, 0)]).expect("steps");
        }
        assert_eq!(report.checksum, straight.checksum(), "{method}");
        assert_eq!(
            rolled.game().kicks,
            straight.game().kicks,
            "{method}: the game's own state rolled back too"
        );
        assert_eq!(straight.game().kicks, 8);
    }
}

#[test]
fn state_kept_outside_the_snapshot_fails_the_sync_test_with_its_tick() {
    let mut leaky = session(Bouncer {
        method: "semi_implicit_euler",
        leak: Some(Rc::new(Cell::new(0))),
        ..Bouncer::default()
    });
    let error = sync_test(&mut leaky, 4, 100, kicks)
        .expect_err("the leak is caught")
        .to_string();
    assert!(error.starts_with("sync test failed at tick "), "{error}");
    assert!(error.contains("is not in the saved state"), "{error}");
}

#[test]
fn a_check_distance_past_the_window_is_refused_by_name() {
    let mut game = session(Bouncer {
        method: "rk4",
        ..Bouncer::default()
    });
    let error = sync_test(&mut game, 9, 10, kicks).expect_err("too far").to_string();
    assert_eq!(
        error,
        "--sync-test 9: the check distance must be 1 to 7 ticks (GGRS's prediction window)"
    );
}

/// A score counted in an `Rc` that clones share: no world sees it, only
/// the game's `state_hash`.
#[derive(Clone, Default)]
struct Scorer {
    score: Rc<Cell<u32>>,
}

impl Game for Scorer {
    fn title(&self) -> &str {
        "scorer"
    }

    fn setup(&mut self, stage: &mut Stage, _: &Settings) -> Result<(), GameError> {
        stage.add_world("empty", World::default());
        Ok(())
    }

    fn fixed_update(&mut self, _: &mut Stage, _: &FixedStep, _: &TickInput) -> Result<(), GameError> {
        self.score.set(self.score.get() + 1);
        Ok(())
    }

    fn state_hash(&self) -> u64 {
        u64::from(self.score.get())
    }
}

#[test]
fn a_game_s_own_state_that_diverges_is_caught_through_its_state_hash() {
    let mut game = GameSession::new(Scorer::default(), SessionOptions::default()).expect("a session");
    let error = sync_test(&mut game, 3, 50, |_, _| TickInput::default())
        .expect_err("the shared score is not rolled back")
        .to_string();
    assert!(error.starts_with("sync test failed at tick "), "{error}");
}
