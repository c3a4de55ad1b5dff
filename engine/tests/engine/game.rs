//! The game API without a window or GPU: per-tick input, worlds that stop
//! or freeze on failure, integrator controls, restart, recordings.

use glam::Vec3;
use tickwork_engine::app::{
    Control, FrameSource, Game, GameError, GameSession, Key, OnFailure, Playback, Recording, RunError, SessionOptions,
    Settings, Stage, TickInput, WorldId,
};
use tickwork_engine::render::{GoldenImages, RenderError, RgbaImage};
use tickwork_engine::{Entity, FixedStep, Gravity, Particle, Scene, Spring, SpringEnd, Springs, World, WorldConfig};

/// Logs the input of every tick; one falling ball per world.
#[derive(Default)]
struct Probe {
    seen: Vec<(u64, TickInput)>,
    worlds: Vec<(&'static str, bool, OnFailure)>,
    setups: u32,
    /// Each world and its ball, from the last set-up.
    balls: Vec<(WorldId, Entity)>,
}

impl Game for Probe {
    fn title(&self) -> &str {
        "probe"
    }

    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        self.setups += 1;
        stage.switch_integrators = true;
        self.balls.clear();
        for &(name, fixed, on_failure) in &self.worlds {
            let mut world = World::new(WorldConfig {
                integrator: name.into(),
                seed: settings.seed,
                ..WorldConfig::default()
            })?;
            world.add_force(Gravity::EARTH);
            let ball = world.spawn(Particle::default())?;
            let added = stage.add_world(name, world).on_failure(on_failure);
            let id = if fixed { added.fixed_integrator() } else { added }.id();
            self.balls.push((id, ball));
        }
        Ok(())
    }

    fn fixed_update(&mut self, _stage: &mut Stage, step: &FixedStep, input: &TickInput) -> Result<(), GameError> {
        self.seen.push((step.tick, *input));
        Ok(())
    }
}

fn session(worlds: Vec<(&'static str, bool, OnFailure)>) -> GameSession<Probe> {
    GameSession::new(
        Probe {
            worlds,
            ..Probe::default()
        },
        SessionOptions::default(),
    )
    .expect("a session")
}

const STEP: f64 = 1.0 / 60.0;

#[test]
fn a_tap_between_steps_is_seen_by_exactly_one_step_and_held_keys_by_each() {
    let mut game = session(vec![("semi_implicit_euler", false, OnFailure::Stop)]);
    // Tapped during a frame too short for a step: it waits for the next one.
    game.key(Key::Space, true);
    game.key(Key::Space, false);
    game.advance(STEP / 4.0).expect("no step");
    game.key(Key::Up, true);
    game.advance(STEP * 0.75 + 2.0 * STEP).expect("three steps");
    game.key(Key::Up, false);
    game.advance(STEP).expect("one step");
    let seen = &game.game().seen;
    assert_eq!(seen.len(), 4);
    assert!(seen[0].1.pressed(Key::Space) && !seen[0].1.held(Key::Space), "{seen:?}");
    assert!(seen[0].1.pressed(Key::Up) && seen[0].1.held(Key::Up));
    for (_, input) in &seen[1..3] {
        assert!(
            input.held(Key::Up) && !input.pressed(Key::Up) && !input.pressed(Key::Space),
            "{seen:?}"
        );
    }
    // The tick Up's release arrived in sees it released, and nothing else
    // (before releases were latched this tick's input was the default).
    let mut up = tickwork_engine::KeySet::EMPTY;
    up.insert(Key::Up);
    assert_eq!(
        seen[3].1,
        TickInput {
            released: up,
            ..TickInput::default()
        }
    );
    assert!(
        seen[0].1.released(Key::Space),
        "the tap's release, in its press's tick: {seen:?}"
    );
    assert_eq!(seen.iter().map(|s| s.0).collect::<Vec<_>>(), [0, 1, 2, 3]);
}

#[test]
fn integrator_controls_change_only_the_worlds_the_game_does_not_fix() {
    let mut game = session(vec![
        ("rk4", true, OnFailure::Stop),
        ("semi_implicit_euler", false, OnFailure::Stop),
    ]);
    game.control(Control::NextIntegrator).expect("switches");
    let names: Vec<&str> = game
        .stage()
        .worlds
        .iter()
        .map(|w| w.world.integrator().info().name)
        .collect();
    // The fixed world keeps rk4; the other moves to the registry's next.
    let methods = tickwork_engine::integrators::METHODS;
    let next = methods
        .iter()
        .position(|m| m.name == "semi_implicit_euler")
        .expect("registered")
        + 1;
    assert_eq!(names, ["rk4", methods[next % methods.len()].name]);
    let error = game.control(Control::Integrator(40)).expect_err("no method 41");
    assert!(error.to_string().contains("#41"), "{error}");
}

#[test]
fn restart_sets_the_game_up_again_at_tick_zero() {
    let mut game = session(vec![("leapfrog", false, OnFailure::Stop)]);
    for _ in 0..30 {
        game.advance(STEP).expect("steps");
    }
    assert_eq!(game.ticks(), 30);
    game.control(Control::Reset).expect("restarts");
    assert_eq!(game.ticks(), 0);
    assert_eq!(game.game().setups, 2);
    let (id, ball) = game.game().balls[0];
    let world = game.stage().world(id).expect("on the stage");
    assert_eq!(world.tick(), 0);
    assert_eq!(world.position(ball).ok(), Some(Vec3::ZERO));
}

/// A spring of 1e6 N/m on a 1 g particle: explicit Euler blows up at once.
fn explosive(stage: &mut Stage, on_failure: OnFailure) -> WorldId {
    let mut world = World::new(WorldConfig {
        integrator: "explicit_euler".into(),
        ..WorldConfig::default()
    })
    .expect("a world");
    let ball = world
        .spawn(Particle {
            position: Vec3::X,
            mass: 0.001,
            ..Particle::default()
        })
        .expect("spawns");
    world.add_force(Springs::new(vec![Spring {
        a: SpringEnd::Anchor(Vec3::ZERO),
        b: SpringEnd::Entity(ball),
        stiffness: 1e6,
        rest_length: 0.5,
        damping: 0.0,
    }]));
    stage.add_world("explosive", world).on_failure(on_failure).id()
}

/// An explosive world and a calm one, kept by id.
struct Explosive {
    on_failure: OnFailure,
    worlds: Option<(WorldId, WorldId)>,
}

impl Explosive {
    fn new(on_failure: OnFailure) -> Self {
        Self {
            on_failure,
            worlds: None,
        }
    }
}

impl Game for Explosive {
    fn title(&self) -> &str {
        "explosive"
    }

    fn setup(&mut self, stage: &mut Stage, _settings: &Settings) -> Result<(), GameError> {
        stage.switch_integrators = true;
        let explosive = explosive(stage, self.on_failure);
        let mut calm = World::default();
        calm.spawn(Particle::default())?;
        self.worlds = Some((explosive, stage.add_world("calm", calm).id()));
        Ok(())
    }
}

#[test]
fn a_failing_world_stops_the_run_naming_it_or_freezes_while_the_others_go_on() {
    let mut stop = GameSession::new(Explosive::new(OnFailure::Stop), SessionOptions::default()).expect("a session");
    let error = (0..600)
        .find_map(|_| stop.advance(STEP).err())
        .expect("explicit Euler blows up");
    let message = error.to_string();
    assert!(matches!(error, RunError::Game(GameError::Simulation { .. })));
    assert!(message.starts_with("world \"explosive\": step "), "{message}");
    assert!(message.contains("non-finite"), "{message}");

    let mut freeze = GameSession::new(Explosive::new(OnFailure::Freeze), SessionOptions::default()).expect("a session");
    for _ in 0..600 {
        freeze.advance(STEP).expect("a frozen world does not stop the run");
    }
    let (explosive, calm) = freeze.game().worlds.expect("set up");
    let frozen = freeze.stage().shown(explosive).expect("on the stage");
    let why = frozen.failure.as_deref().expect("it failed");
    assert!(why.starts_with("failed at t = "), "{why}");
    // Back to the last finite state, stopped there; the calm world ran on.
    let particles = frozen.world.particles();
    assert!(particles.position.iter().all(|p| p.is_finite()));
    assert!(frozen.world.tick() < 600);
    assert_eq!(freeze.stage().world(calm).expect("on the stage").tick(), 600);
    // Switching its method resumes it.
    let implicit = tickwork_engine::integrators::METHODS
        .iter()
        .position(|m| m.name == "implicit_euler")
        .expect("registered");
    freeze.control(Control::Integrator(implicit)).expect("implicit Euler");
    assert!(freeze.stage().shown(explosive).expect("on the stage").failure.is_none());
}

#[test]
fn a_replay_refuses_settings_that_differ_from_the_recording() {
    let recording = Recording {
        game: "probe".into(),
        hz: 60.0,
        seed: 4,
        integrator: None,
        ticks: 10,
        inputs: vec![],
        controls: vec![],
        other_players: vec![],
        checksum: None,
    };
    let options = |seed| SessionOptions {
        settings: Settings {
            integrator: None,
            seed,
            networked: false,
            gpu: false,
        },
        replay: Some(recording.clone()),
        ..SessionOptions::default()
    };
    let error = GameSession::new(Probe::default(), options(5)).expect_err("seed 5 is not 4");
    assert!(
        error
            .to_string()
            .starts_with("--seed differs from the recording's (hz 60, seed 4"),
        "{error}"
    );
    GameSession::new(Probe::default(), options(4)).expect("the recorded seed is fine");
    let unknown = GameSession::new(
        Probe::default(),
        SessionOptions {
            settings: Settings {
                integrator: Some("rk5".into()),
                ..Settings::default()
            },
            ..SessionOptions::default()
        },
    )
    .expect_err("no rk5");
    assert!(unknown.to_string().contains("rk5"), "{unknown}");
}

#[test]
fn engine_errors_convert_into_game_errors_with_their_messages() {
    use std::error::Error as _;
    fn build(method: &str) -> Result<World, GameError> {
        Ok(World::new(WorldConfig {
            integrator: method.into(),
            ..WorldConfig::default()
        })?)
    }
    fn despawn_twice() -> Result<(), GameError> {
        let mut world = World::default();
        let ball = world.spawn(Particle::default())?;
        world.despawn(ball)?;
        world.despawn(ball)?;
        Ok(())
    }
    let unknown = World::new(WorldConfig {
        integrator: "nope".into(),
        ..WorldConfig::default()
    })
    .expect_err("not a method");
    let converted = build("nope").expect_err("not a method");
    assert!(matches!(converted, GameError::Engine(_)), "{converted:?}");
    assert_eq!(converted.to_string(), unknown.to_string());
    assert_eq!(
        converted.source().map(ToString::to_string),
        Some(unknown.to_string()),
        "the engine error is the source"
    );
    let twice = despawn_twice().expect_err("gone");
    assert!(twice.to_string().contains("despawned"), "{twice}");
    let message: GameError = "no such level".into();
    assert_eq!(message.to_string(), "no such level");
    assert!(message.source().is_none());
    // A game's own reads and parses convert too, keeping their source.
    fn level(text: &str) -> Result<u32, GameError> {
        Ok(text.trim().parse::<u32>()?)
    }
    let parse = level("three").expect_err("not a number");
    assert!(matches!(parse, GameError::Other(_)), "{parse:?}");
    assert_eq!(parse.to_string(), "invalid digit found in string");
    assert!(parse.source().is_some());
    #[derive(Debug)]
    struct Tilt;
    impl std::fmt::Display for Tilt {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("the table tilted")
        }
    }
    impl std::error::Error for Tilt {}
    assert_eq!(GameError::other(Tilt).to_string(), "the table tilted");
    // The render side's errors, a scene's playback and a run started from
    // a game convert with their messages as the source too.
    fn engine<E: std::error::Error + 'static>(error: E, convert: fn(E) -> GameError) {
        let message = error.to_string();
        let converted = convert(error);
        assert!(matches!(converted, GameError::Engine(_)), "{converted:?}");
        assert_eq!(converted.to_string(), message);
        assert_eq!(converted.source().map(ToString::to_string), Some(message));
    }
    fn draw_too_big() -> Result<(), GameError> {
        Err(RenderError::Size {
            width: 0,
            height: 9,
            max: 8192,
        })?
    }
    let render = draw_too_big().expect_err("a 0x9 target");
    assert_eq!(
        render.to_string(),
        "cannot render a 0x9 image: both sides must be between 1 and 8192 pixels"
    );
    engine(RenderError::Config("HUD size 0".into()), |e| -> GameError { e.into() });
    let dir = std::env::temp_dir().join(format!("tickwork-game-errors-{}", std::process::id()));
    fn check_golden(dir: &std::path::Path) -> Result<(), GameError> {
        let golden = GoldenImages::new(dir.join("golden"), dir.join("out"));
        golden.check("absent", &RgbaImage::new(2, 2))?;
        Ok(())
    }
    let missing = check_golden(&dir).expect_err("no golden image");
    assert!(matches!(missing, GameError::Engine(_)), "{missing:?}");
    assert!(missing.to_string().contains("TICKWORK_BLESS=1"), "{missing}");
    assert_eq!(missing.source().map(ToString::to_string), Some(missing.to_string()));
    let _ = std::fs::remove_dir_all(&dir);
    fn play(integrator: &str) -> Result<Playback, GameError> {
        let scene = Scene::load(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../assets/scenes/kepler.ron"
        )))?;
        Ok(Playback::from_scene(&scene, Some(integrator))?)
    }
    let playback = play("rk5").expect_err("no rk5");
    assert!(playback.to_string().contains("rk5"), "{playback}");
    assert_eq!(playback.source().map(ToString::to_string), Some(playback.to_string()));
    play("rk4").expect("rk4 plays the scene");
    engine(RunError::Limit("--frames 2000000 is past the limit".into()), |e| {
        e.into()
    });
    // A run's own game error comes back as the game's, not wrapped.
    let game: GameError = RunError::Game(GameError::Message("the table tilted".into())).into();
    assert!(
        matches!(&game, GameError::Message(m) if m == "the table tilted"),
        "{game:?}"
    );
}

/// Lays out `session`'s control panel in a headless egui, opens the
/// integrator menu of world number `world` and clicks `method` in it;
/// returns the controls the panel gave back.
#[cfg(feature = "panel")]
fn choose_in_panel(session: &GameSession<Probe>, world: usize, method: &str) -> Vec<Control> {
    use egui_kittest::Harness;
    use egui_kittest::kittest::Queryable;
    let chosen = std::cell::RefCell::new(Vec::new());
    let mut harness = Harness::builder()
        .with_size(egui::vec2(900.0, 700.0))
        .build_ui(|ui| session.panel(ui.ctx(), &mut chosen.borrow_mut()));
    let menus: Vec<_> = harness.get_all_by_role(egui::accesskit::Role::ComboBox).collect();
    assert_eq!(
        menus.len(),
        session.stage().worlds.len(),
        "one integrator menu per world"
    );
    menus[world].click();
    harness.run();
    // Far down the list of 22, out of the menu's view: clicked as a screen
    // reader would, not at a pixel.
    harness.get_by_label(method).click_accesskit();
    harness.run();
    drop(harness);
    chosen.into_inner()
}

/// The world hashes and integrators of a session's stage.
fn stage_state(game: &GameSession<Probe>) -> Vec<(u64, &'static str)> {
    game.stage()
        .worlds
        .iter()
        .map(|w| (w.world.state_hash(), w.world.integrator().info().name))
        .collect()
}

#[cfg(feature = "panel")]
#[test]
fn a_replay_repeats_an_integrator_switch_made_from_the_panel_at_its_tick() {
    let dir = std::env::temp_dir().join(format!("tickwork-game-controls-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("switch.ron");
    let _ = std::fs::remove_file(&path);
    let worlds = vec![
        ("semi_implicit_euler", false, OnFailure::Stop),
        ("semi_implicit_euler", false, OnFailure::Stop),
    ];
    let mut live = GameSession::new(
        Probe {
            worlds: worlds.clone(),
            ..Probe::default()
        },
        SessionOptions {
            record: Some(path.clone()),
            ..SessionOptions::default()
        },
    )
    .expect("a session");
    let rk4 = tickwork_engine::integrators::METHODS
        .iter()
        .position(|m| m.name == "rk4")
        .expect("registered");
    for frame in 0..90u64 {
        if frame == 40 {
            // The second world's integrator menu in the control panel, clicked
            // open and set to rk4; the runner applies what the panel returns
            // between frames, like every control.
            let chosen = choose_in_panel(&live, 1, "rk4");
            assert_eq!(chosen, [Control::WorldIntegrator { world: 1, method: rk4 }]);
            for control in chosen {
                live.control(control).expect("switches");
            }
        }
        live.advance(if frame % 3 == 0 { 0.03 } else { 0.011 }).expect("steps");
    }
    let switched_at = {
        live.save_recording().expect("saved");
        let recording = Recording::load(&path).expect("loads");
        assert_eq!(recording.controls.len(), 1, "{:?}", recording.controls);
        let (tick, control) = recording.controls[0].clone();
        assert_eq!(
            control,
            tickwork_engine::input::RecordedControl::Integrator {
                world: 1,
                name: "rk4".into()
            }
        );
        assert!(tick > 0 && tick < recording.ticks, "mid-run: tick {tick}");
        recording
    };
    let replay = |recording: Recording, frame: f64| {
        let mut game = GameSession::new(
            Probe {
                worlds: worlds.clone(),
                ..Probe::default()
            },
            SessionOptions {
                replay: Some(recording),
                ..SessionOptions::default()
            },
        )
        .expect("a session");
        while game.ticks() < live.ticks() {
            game.advance(frame).expect("steps");
        }
        assert_eq!(game.ticks(), live.ticks(), "frames of {frame} s end on the live tick");
        stage_state(&game)
    };
    let state = stage_state(&live);
    assert_eq!(state[1].1, "rk4");
    assert_ne!(state[0].0, state[1].0, "the switch changed the second world's motion");
    // Replayed with frames of another length: the same switch at the same tick.
    assert_eq!(replay(switched_at.clone(), 1.0 / 60.0), state);
    // Without the recorded control the replay stays on one method: the
    // check is not blind.
    let mut without = switched_at;
    without.controls.clear();
    assert_ne!(replay(without, 1.0 / 60.0), state);
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn several_worlds_are_borrowed_at_once_and_a_bad_set_of_ids_is_an_error() {
    use tickwork_engine::app::StageError;
    let mut stage = Stage::default();
    let ids: Vec<WorldId> = ["left", "middle", "right"]
        .into_iter()
        .map(|label| stage.add_world(label, World::default()).id())
        .collect();
    let (left, middle, right) = (ids[0], ids[1], ids[2]);
    let ball = stage
        .world_mut(left)
        .expect("on the stage")
        .spawn(Particle {
            position: Vec3::new(1.0, 2.0, 3.0),
            ..Particle::default()
        })
        .expect("spawned");
    // A ball passes from the left world to the right one: both changed in
    // one borrow, in the order asked.
    let [to, from] = stage.worlds_mut([right, left]).expect("two worlds");
    let at = from.position(ball).expect("alive");
    from.despawn(ball).expect("alive");
    let arrived = to
        .spawn(Particle {
            position: at,
            ..Particle::default()
        })
        .expect("spawned");
    let lens: Vec<usize> = stage.worlds.iter().map(|w| w.world.len()).collect();
    assert_eq!(lens, [0, 0, 1]);
    let moved = stage.world(right).expect("on the stage").position(arrived);
    assert_eq!(moved.ok(), Some(Vec3::new(1.0, 2.0, 3.0)));
    let [a, b, c] = stage.worlds_mut([middle, right, left]).expect("three worlds");
    assert_eq!((a.len(), b.len(), c.len()), (0, 1, 0));
    // The same world twice would be two mutable borrows of it.
    let twice = stage.worlds_mut([left, middle, left]).expect_err("left twice");
    assert_eq!(twice, StageError::Twice { id: left });
    assert_eq!(twice.to_string(), "world #0 was asked for twice in one worlds_mut");
    // An id from a stage with more worlds is not on this one.
    let mut bigger = Stage::default();
    let far = (0..4)
        .map(|_| bigger.add_world("w", World::default()).id())
        .last()
        .expect("four ids");
    let unknown = stage.worlds_mut([left, far]).expect_err("not on this stage");
    assert_eq!(unknown, StageError::Unknown { id: far, worlds: 3 });
    assert_eq!(unknown.to_string(), "world #3 is not on this stage (it has 3 worlds)");
    // Nothing was changed by the refused borrows.
    assert_eq!(
        stage.worlds.iter().map(|w| w.world.len()).collect::<Vec<_>>(),
        [0, 0, 1]
    );
}

#[test]
fn a_replay_stops_at_the_recordings_end_whatever_the_frames_ask_for() {
    let dir = std::env::temp_dir().join(format!("tickwork-replay-end-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("end.ron");
    let worlds = vec![("semi_implicit_euler", false, OnFailure::Stop)];
    let mut live = GameSession::new(
        Probe {
            worlds: worlds.clone(),
            ..Probe::default()
        },
        SessionOptions {
            record: Some(path.clone()),
            ..SessionOptions::default()
        },
    )
    .expect("a session");
    for frame in 0..40u64 {
        live.key(Key::Space, frame % 7 < 3);
        live.advance(if frame % 3 == 0 { 0.03 } else { 0.011 }).expect("steps");
    }
    live.save_recording().expect("saved");
    let recording = Recording::load(&path).expect("loads");
    assert_eq!(recording.ticks, live.ticks());
    assert_eq!(
        recording.checksum,
        Some(live.checksum()),
        "the recording keeps its end's checksum"
    );
    // Frames of 4.2 steps run past the end in the middle of a frame, and
    // then many more frames follow.
    let mut replay = GameSession::new(
        Probe {
            worlds,
            ..Probe::default()
        },
        SessionOptions {
            replay: Some(recording.clone()),
            ..SessionOptions::default()
        },
    )
    .expect("a session");
    assert!(
        !recording.ticks.is_multiple_of(4),
        "the end falls inside a frame: {}",
        recording.ticks
    );
    for _ in 0..(recording.ticks / 4 + 20) {
        replay.advance(0.07).expect("steps");
    }
    assert_eq!(replay.ticks(), recording.ticks, "no step past the recording's end");
    assert_eq!(
        replay.game().seen.last().map(|(tick, _)| *tick),
        Some(recording.ticks - 1),
        "the game saw the recording's last tick and no later one"
    );
    assert!(matches!(replay.replay(), Some((_, true))), "the replay knows it ended");
    assert!(replay.clock().is_paused(), "its clock stops there");
    assert_eq!(replay.checksum(), live.checksum(), "the recorded run's last state");
    assert_eq!(stage_state(&replay), stage_state(&live));
    // A restart replays it again from the start.
    replay.control(Control::Reset).expect("restarts");
    assert!(matches!(replay.replay(), Some((_, false))));
    replay.advance(0.05).expect("steps");
    assert_eq!(replay.ticks(), 3);
    std::fs::remove_dir_all(&dir).expect("clean up");
}
