//! Breakout, the game the README promises a newcomer can write: the
//! autopilot clears the bricks through contact events, the last frame
//! matches its golden image, and a recorded game replays to the same state.

use std::path::PathBuf;
use std::process::Command;

use tickwork::engine::app::{FrameSource, GameSession, InputEvent, Recording, SessionOptions};
use tickwork::engine::render::GoldenImages;
use tickwork::prelude::*;
use tickwork_demos::breakout::{Breakout, Play};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn session(game: Breakout, options: SessionOptions) -> GameSession<Breakout> {
    GameSession::new(game, options).expect("a session")
}

#[test]
fn the_autopilot_clears_every_brick_and_scores_each_once() {
    let mut game = session(Breakout::new(true), SessionOptions::default());
    let mut bricks = game.game().bricks.len();
    assert_eq!(bricks, 40);
    while game.game().play != Play::Won && game.ticks() < 60 * 600 {
        game.advance(1.0 / 60.0).expect("steps");
        let left = game.game().bricks.len();
        assert!(left <= bricks, "bricks only go");
        bricks = left;
    }
    assert_eq!(game.game().play, Play::Won, "won by tick {}", game.ticks());
    // Eight bricks a row, 10 points a brick in the bottom row to 50 in the top.
    assert_eq!(game.game().score, 8 * (10 + 20 + 30 + 40 + 50));
    // A sound each brick, and one each return off the paddle.
    let count = |name: &str| game.played_sounds().filter(|p| &*p.sound == name).count();
    assert_eq!(count("brick"), 40);
    assert!(
        count("paddle") >= 2,
        "the paddle sent the ball back: {}",
        count("paddle")
    );
    println!("won at tick {}", game.ticks());
}

fn check_golden(name: &str, image: &image::RgbaImage) {
    let golden = GoldenImages::new(root().join("assets/golden"), root().join("target/golden"));
    if let Err(error) = golden.check(name, image) {
        panic!("{error}");
    }
}

fn scratch(name: &str) -> PathBuf {
    let dir = root().join("target/test-breakout").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

#[test]
fn the_demo_plays_itself_off_screen_to_its_golden_frame() {
    let out = scratch("frames");
    let output = Command::new(env!("CARGO_BIN_EXE_breakout"))
        .args([
            "--headless",
            "--autopilot",
            "--frames",
            "150",
            "--size",
            "480x270",
            "--out",
        ])
        .arg(&out)
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // 150 frames at 60 Hz: 150 steps; a few bricks are gone by then.
    let outcome = stdout
        .lines()
        .find(|l| l.starts_with("breakout: stopped with "))
        .unwrap_or_else(|| panic!("an outcome line:\n{stdout}"));
    assert!(!outcome.contains(" 40 bricks left"), "{outcome}");
    let last = image::open(out.join("frame_00149.png"))
        .expect("the last frame")
        .to_rgba8();
    check_golden("demo_breakout", &last);
}

#[test]
fn a_won_game_says_so_in_the_middle_of_the_court() {
    let mut game = session(Breakout::new(true), SessionOptions::default());
    while game.game().play != Play::Won && game.ticks() < 60 * 600 {
        game.advance(1.0 / 60.0).expect("steps");
    }
    assert_eq!(game.game().play, Play::Won);
    let gpu = tickwork::engine::render::Gpu::headless().expect("a GPU adapter (lavapipe on CI)");
    let config = tickwork::engine::app::renderer_config(game.stage(), 270);
    let mut runner = tickwork::engine::app::OffscreenRun::new(&gpu, 480, 270, config).expect("a runner");
    let frame = runner.draw(&mut game, true).expect("drawn");
    check_golden("breakout_won", &frame);
}

#[test]
fn a_recorded_game_of_keys_and_mouse_replays_to_the_same_state() {
    let path = scratch("record").join("game.ron");
    let mut live = session(
        Breakout::new(false),
        SessionOptions {
            record: Some(path.clone()),
            ..SessionOptions::default()
        },
    );
    // Frames of uneven length; keys, then the mouse, between them.
    for k in 0..900u64 {
        match k {
            10 => live.key(Key::Space, true),
            12 => live.key(Key::Space, false),
            20 => live.key(Key::Right, true),
            60 => live.key(Key::Right, false),
            80 => live.key(Key::Left, true),
            140 => live.key(Key::Left, false),
            _ => {}
        }
        if k >= 200 {
            // The pointer follows the ball, a little late, at 0.7 of the frame.
            let ball = live.stage().worlds[0]
                .world
                .position(live.game().ball)
                .expect("the ball");
            live.input(InputEvent::Pointer(Vec2::new(ball.x, 1.0)), 0.7);
        }
        live.advance(if k % 3 == 0 { 0.027 } else { 0.012 }).expect("steps");
    }
    assert!(live.game().bricks.len() < 40, "the ball hit bricks");
    live.save_recording().expect("saved");
    let recording = Recording::load(&path).expect("loads");
    assert_eq!(recording.ticks, live.ticks());
    let mut replayed = session(
        Breakout::new(false),
        SessionOptions {
            replay: Some(recording),
            ..SessionOptions::default()
        },
    );
    while replayed.ticks() < live.ticks() {
        replayed.advance(1.0 / 60.0).expect("steps");
    }
    assert_eq!(replayed.ticks(), live.ticks());
    assert_eq!(
        (
            replayed.game().score,
            replayed.game().bricks.len(),
            replayed.game().play
        ),
        (live.game().score, live.game().bricks.len(), live.game().play)
    );
    assert_eq!(
        replayed.stage().worlds[0].world.state_hash(),
        live.stage().worlds[0].world.state_hash(),
        "the replay reaches the live run's exact state"
    );
    // A sound for each brick that went and each ball lost, at
    // the ticks they happened: the replay starts the same ones.
    let sounds = |s: &GameSession<Breakout>| -> Vec<(u64, String)> {
        s.played_sounds().map(|p| (p.tick, p.sound.to_string())).collect()
    };
    let played = sounds(&live);
    let count = |name: &str| played.iter().filter(|(_, s)| s == name).count();
    assert_eq!(count("brick"), 40 - live.game().bricks.len(), "{played:?}");
    assert_eq!(count("lost"), 3 - live.game().lives as usize, "{played:?}");
    assert_eq!(
        sounds(&replayed),
        played,
        "the replay plays the live run's sounds at its ticks"
    );
}

#[test]
fn the_integrator_option_takes_one_name_and_says_why_not_a_list() {
    let run = |integrator: &str| {
        GameSession::new(
            Breakout::new(true),
            SessionOptions {
                settings: Settings {
                    integrator: Some(integrator.into()),
                    ..Settings::default()
                },
                ..SessionOptions::default()
            },
        )
    };
    let game = run("rk4").expect("one name");
    assert_eq!(game.stage().worlds[0].world.integrator().info().name, "rk4");
    let error = run("rk4,leapfrog").expect_err("a list").to_string();
    assert_eq!(
        error,
        "--integrator rk4,leapfrog names 2 integrators, but breakout's world \"court\" runs one: give one name (a \
         list is for a game that races integrators, such as orbits)"
    );
}

#[test]
fn enter_after_the_last_brick_builds_a_fresh_court_in_place_of_the_old_one() {
    // With --integrator: the rebuilt court runs it too. (Without drag,
    // implicit-drag Euler steps as semi-implicit Euler does, so the
    // autopilot's game is the same.)
    let mut options = SessionOptions::default();
    options.settings.integrator = Some("implicit_drag_euler".into());
    let mut game = session(Breakout::new(true), options);
    while game.game().play != Play::Won && game.ticks() < 60 * 600 {
        game.advance(1.0 / 60.0).expect("steps");
    }
    assert_eq!(game.game().play, Play::Won, "won by tick {}", game.ticks());
    // Won: the game waits, whatever the ticks, until Enter.
    game.advance(1.0 / 60.0).expect("steps");
    assert_eq!(game.game().play, Play::Won);
    game.key(Key::Enter, true);
    game.advance(1.0 / 60.0).expect("steps");
    let fresh = game.game();
    assert_eq!((fresh.score, fresh.lives, fresh.bricks.len()), (0, 3, 40));
    assert_ne!(fresh.play, Play::Won);
    assert_eq!(game.stage().worlds.len(), 1, "the old court is gone");
    let court = &game.stage().worlds[0].world;
    // The walls, the 40 bricks and the paddle; the ball on the paddle.
    assert_eq!(court.colliders().count(), 42);
    assert_eq!(court.integrator().info().name, "implicit_drag_euler");
    assert!(
        court.position(game.game().ball).is_ok_and(|ball| ball.y < 2.0),
        "the ball is served from the paddle"
    );
}
